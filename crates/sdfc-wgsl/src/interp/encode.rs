//! Encodes a compiled program as register-machine bytecode for the interpreter shader.
//!
//! Each SSA node becomes (at most) one instruction `[opcode, dst | imm << 16, a0 | a1 << 16,
//! a2 | a3 << 16]` over `vec4<f32>` registers. Group calls are inlined (once per group and
//! point, with only the results the caller uses). A float or boolean is kept splatted in all
//! four components (booleans as 1.0 / 0.0), so component-wise opcodes broadcast scalars over
//! vectors for free; a mat3 is three registers, its columns, and never an operand of its own.
//! Registers are reused after the last read of their value (linear scan over the straight
//! line code); register 0 holds the point `p` throughout.

use super::allocate::allocate;
use super::opcodes::{builtin_opcode, helper_opcode, Opcode};
use super::peephole::fold;
use super::schedule::schedule;
use sdfc_ir::func::Func;
use sdfc_ir::graph::{Graph, NodeId};
use sdfc_ir::ops::{Builtin, Op, NO_BEST};
use sdfc_ir::types::Ty;
use sdfc_ir::value::Value;
use sdfc_ir::Program;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fmt;

/// Registers of the interpreter's register file (`MAX_REGISTERS` in the shader).
pub const MAX_REGISTERS: u32 = 64;
/// Entries of the constant pool an instruction can name: a 16-bit operand, constants
/// numbered after the registers.
pub const MAX_CONSTANTS: usize = (1 << 16) - MAX_REGISTERS as usize;
/// Instructions of one program (distance and material together).
pub const MAX_INSTRUCTIONS: usize = 1 << 20;
/// Nesting of group calls inlined into one another.
const MAX_INLINE_DEPTH: usize = 64;

/// Why a program cannot be encoded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EncodeError {
    /// The scene needs more than the interpreter's documented limits (registers, constants,
    /// instructions): render it with the specialised shader.
    TooLarge(String),
    /// An operation the interpreter has no opcode for (a helper added to the compiler but not
    /// yet to the interpreter): a gap in sdfc, not a mistake in the scene.
    Unsupported(String),
}

impl fmt::Display for EncodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EncodeError::TooLarge(s) => write!(
                f,
                "the scene is too large for the interpreted marcher: {s} (render it without --interpreted)"
            ),
            EncodeError::Unsupported(s) => {
                write!(f, "the interpreted marcher cannot run this scene: {s}")
            }
        }
    }
}

impl std::error::Error for EncodeError {}

/// A program as bytecode: one instruction list holding the distance function, then the
/// material function, each ending in `ret`.
#[derive(Clone, Debug, PartialEq)]
pub struct Bytecode {
    /// `[opcode, dst | imm << 16, a0 | a1 << 16, a2 | a3 << 16]` per instruction.
    pub code: Vec<[u32; 4]>,
    /// The constant pool, one `vec4<f32>` each (scalars splatted).
    pub consts: Vec<[f32; 4]>,
    /// Instruction range `[start, end)` of the distance function (`ret d`).
    pub distance: [u32; 2],
    /// Instruction range of the distance the march steps with along a ray
    /// (`scene_distance_ray`, after the material function; `distance` where the program has
    /// none, or where the union is read as data, which the specialised shader marches
    /// without it too).
    pub distance_ray: [u32; 2],
    /// Instruction range of the material function (`ret albedo, phong`).
    pub material: [u32; 2],
    /// Registers the code uses (at most [`MAX_REGISTERS`]).
    pub registers: u32,
    /// Instructions before the two functions: the kinds' code of a union read as data
    /// (`encode_instances`); 0 otherwise.
    pub kinds: u32,
    /// The union read as data (the hierarchy and records of `shaders/instances.wgsl`), one
    /// `vec4<u32>` each; empty otherwise.
    pub instances: Vec<[u32; 4]>,
}

/// An SSA value in virtual registers: a vector (or scalar) or a matrix's three columns.
#[derive(Clone, Copy, Debug)]
pub(super) enum Val {
    /// A virtual register, or a constant of the pool ([`const_operand`]).
    Reg(u32),
    Mat([u32; 3]),
    /// An input loaded where it is used (`param`, `time`), not where the graph has it, so
    /// that it does not hold a register all the way from the graph's start.
    Load(Opcode, u32),
}

/// What a function's `Op::Point` and `Op::Best` stand for where it is inlined.
#[derive(Clone, Copy, Debug)]
pub(super) struct Inputs {
    pub(super) point: Val,
    /// `None`: no best distance to stop at (`NO_BEST`, loaded where it is read).
    pub(super) best: Option<Val>,
}

/// A load is reused while it is at most this many instructions old, else loaded again.
const RELOAD_AFTER: usize = 16;

/// An instruction over virtual registers (infinitely many, each written once).
pub(super) struct VIns {
    pub(super) op: Opcode,
    pub(super) dst: Option<u32>,
    pub(super) args: Vec<u32>,
    pub(super) imm: u32,
    /// The first argument is `args[0] - args[3]` ([`super::opcodes::FOLDED_SUB`],
    /// `peephole::fold_translations`).
    pub(super) folded: bool,
}

/// Encoding state shared by the two functions: the constant pool.
pub(super) struct Encoder<'p> {
    /// The group functions the two call.
    pub(super) groups: &'p [sdfc_ir::func::Func],
    pub(super) consts: Vec<[f32; 4]>,
    pub(super) const_index: HashMap<[u32; 4], u32>,
    /// In a kind's code (`encode_instances`): `Op::Param(i)` is the instance's argument i,
    /// read by `arg` with this immediate, not the scene's param i.
    pub(super) args: Option<Vec<u32>>,
}

/// One function being encoded: its virtual instructions.
pub(super) struct Chunk {
    pub(super) ins: Vec<VIns>,
    next: u32,
    /// The latest load of each input: its register and the instruction it sits at.
    loads: HashMap<(Opcode, u32), (u32, usize)>,
}

impl VIns {
    /// An instruction that writes no register (`ret`, `instance_done`).
    pub(super) fn control(op: Opcode, args: Vec<u32>) -> VIns {
        VIns {
            op,
            dst: None,
            args,
            imm: 0,
            folded: false,
        }
    }
}

/// The point's virtual (and physical) register.
pub(super) const POINT: u32 = 0;

/// Marks a virtual operand that is constant `k` of the pool, not a register.
pub(super) const CONST_OPERAND: u32 = 1 << 31;

/// The virtual operand reading constant `k`. Half the instructions of a large union were
/// `const` loads, each a trip of the shader's loop (and on lavapipe a pass through every
/// case of its switch); an operand names the constant instead, as `MAX_REGISTERS + k` in
/// the bytecode.
fn const_operand(k: u32) -> u32 {
    CONST_OPERAND | k
}

/// Whether a virtual operand is a register (not a constant of the pool).
pub(super) fn is_register(v: u32) -> bool {
    v & CONST_OPERAND == 0
}

/// How many virtual registers the instructions name (the point's included): the size of
/// tables indexed by them.
pub(super) fn virtual_registers(ins: &[VIns]) -> usize {
    ins.iter()
        .flat_map(|x| x.dst.iter().chain(&x.args))
        .filter(|&&v| is_register(v))
        .max()
        .map_or(0, |&v| v as usize)
        .max(POINT as usize)
        + 1
}

impl Chunk {
    pub(super) fn new() -> Chunk {
        Chunk {
            ins: Vec::new(),
            next: POINT + 1,
            loads: HashMap::new(),
        }
    }

    /// A value an instruction can read: a param or the time is loaded here, or its load
    /// reused while recent (a constant is an operand already, [`const_operand`]).
    pub(super) fn materialize(&mut self, v: Val) -> Val {
        match v {
            Val::Load(op, imm) => Val::Reg(self.load(op, imm)),
            _ => v,
        }
    }

    /// The register holding an input: its latest load while recent, else a new load.
    fn load(&mut self, op: Opcode, imm: u32) -> u32 {
        if let Some(&(r, at)) = self.loads.get(&(op, imm)) {
            if self.ins.len() - at <= RELOAD_AFTER {
                return r;
            }
        }
        let at = self.ins.len();
        let r = self.emit(op, &[], imm);
        self.loads.insert((op, imm), (r, at));
        r
    }

    pub(super) fn emit(&mut self, op: Opcode, args: &[u32], imm: u32) -> u32 {
        let dst = self.next;
        self.next += 1;
        self.ins.push(VIns {
            op,
            dst: Some(dst),
            args: args.to_vec(),
            imm,
            folded: false,
        });
        dst
    }
}

/// Encodes a program; fails cleanly on an operation without an opcode or a scene beyond
/// the limits. The functions are the ones the renderer marches with: camera-relative
/// (`Program::relative`, a point q standing for the world point q + origin) where the camera
/// is far from the origin, as in the specialised shader; a world-space interpreter lost the
/// same precision there that the move to the camera exists to avoid (normals 81 degrees off
/// at 1e5).
pub fn encode(program: &Program) -> Result<Bytecode, EncodeError> {
    let sdfc_ir::SceneFunctions {
        distance,
        distance_ray,
        material,
        groups,
        ..
    } = program.marched();
    let mut e = Encoder {
        groups,
        consts: Vec::new(),
        const_index: HashMap::new(),
        args: None,
    };
    let mut code = Vec::new();
    let mut registers = 1;
    // Outside a culled part there is no caller's best distance to stop at.
    let top = Inputs {
        point: Val::Reg(POINT),
        best: None,
    };

    // A distance function's range; the registers it uses.
    let distance_code = |e: &mut Encoder, code: &mut Vec<[u32; 4]>, f: &Func| {
        let mut chunk = Chunk::new();
        let d = e.func(&mut chunk, f, &f.results, top, 0)?;
        let d = reg(d[0], "the distance")?;
        chunk.ins.push(VIns::control(Opcode::Ret, vec![d]));
        let start = code.len() as u32;
        let used = allocate(&fold(chunk.ins), code)?;
        Ok::<_, EncodeError>(([start, code.len() as u32], used))
    };
    let (distance, used) = distance_code(&mut e, &mut code, distance)?;
    registers = registers.max(used);

    let mut chunk = Chunk::new();
    let m = e.func(&mut chunk, material, &material.results, top, 0)?;
    if m.len() != 2 {
        return Err(EncodeError::Unsupported(format!(
            "the material function returns {} values, not 2",
            m.len()
        )));
    }
    let albedo = reg(m[0], "the albedo")?;
    let phong = reg(m[1], "the phong coefficients")?;
    chunk
        .ins
        .push(VIns::control(Opcode::Ret, vec![albedo, phong]));
    let start = code.len() as u32;
    registers = registers.max(allocate(&fold(chunk.ins), &mut code)?);
    let material = [start, code.len() as u32];
    // The march's ray function repeats the distance's code (its groups inlined again): where
    // that would pass the limits, the march takes the distance instead, as it did before
    // planes and displacements divided by their slopes, rather than the scene failing.
    let (at, pooled) = (code.len(), e.consts.len());
    let distance_ray = match distance_ray.map(|f| distance_code(&mut e, &mut code, f)) {
        Some(Ok((range, used))) if code.len() <= MAX_INSTRUCTIONS => {
            registers = registers.max(used);
            range
        }
        Some(Err(EncodeError::Unsupported(s))) => return Err(EncodeError::Unsupported(s)),
        Some(_) => {
            code.truncate(at);
            e.consts.truncate(pooled);
            e.const_index.retain(|_, i| (*i as usize) < pooled);
            distance
        }
        None => distance,
    };

    if code.len() > MAX_INSTRUCTIONS {
        return Err(EncodeError::TooLarge(format!(
            "{} instructions, at most {MAX_INSTRUCTIONS}",
            code.len()
        )));
    }
    Ok(Bytecode {
        code,
        consts: e.consts,
        distance,
        distance_ray,
        material,
        registers,
        kinds: 0,
        instances: Vec::new(),
    })
}

pub(super) fn reg(v: Val, what: &str) -> Result<u32, EncodeError> {
    match v {
        Val::Reg(r) => Ok(r),
        Val::Mat(_) => Err(EncodeError::Unsupported(format!("{what} is a matrix"))),
        Val::Load(..) => Err(unsupported(format!("{what} was not loaded"))),
    }
}

pub(super) fn unsupported(what: impl fmt::Display) -> EncodeError {
    EncodeError::Unsupported(what.to_string())
}

impl Encoder<'_> {
    /// The pool index of a constant, splatted if scalar.
    fn constant(&mut self, v: [f32; 4]) -> Result<u32, EncodeError> {
        let key = v.map(f32::to_bits);
        if let Some(&i) = self.const_index.get(&key) {
            return Ok(i);
        }
        if self.consts.len() >= MAX_CONSTANTS {
            return Err(EncodeError::TooLarge(format!(
                "more than {MAX_CONSTANTS} distinct constants"
            )));
        }
        let i = self.consts.len() as u32;
        self.consts.push(v);
        self.const_index.insert(key, i);
        Ok(i)
    }

    fn load_const(&mut self, v: &Value<f32>) -> Result<Val, EncodeError> {
        let lanes = |x: &[f32]| {
            let mut a = [0.0; 4];
            a[..x.len()].copy_from_slice(x);
            a
        };
        let vec = match *v {
            Value::F(x) => [x; 4],
            Value::B(b) => [if b { 1.0 } else { 0.0 }; 4],
            Value::V2(x) => lanes(&x),
            Value::V3(x) => lanes(&x),
            Value::V4(x) => x,
            Value::M3(m) => {
                let mut cols = [0; 3];
                for (col, m) in cols.iter_mut().zip(m) {
                    *col = const_operand(self.constant(lanes(&m))?);
                }
                return Ok(Val::Mat(cols));
            }
        };
        Ok(Val::Reg(const_operand(self.constant(vec)?)))
    }

    /// Encodes the nodes of `f` that `results` need, with `point` as `Op::Point`; returns the
    /// results' values.
    pub(super) fn func(
        &mut self,
        c: &mut Chunk,
        f: &Func,
        results: &[NodeId],
        inputs: Inputs,
        depth: usize,
    ) -> Result<Vec<Val>, EncodeError> {
        if depth > MAX_INLINE_DEPTH {
            return Err(EncodeError::TooLarge(format!(
                "group calls nested deeper than {MAX_INLINE_DEPTH}"
            )));
        }
        let g = &f.graph;
        let mut live = vec![false; g.len()];
        for r in results {
            if let Some(l) = live.get_mut(r.index()) {
                *l = true;
            } else {
                return Err(unsupported("a result outside its function"));
            }
        }
        for i in (0..g.len()).rev() {
            if live[i] {
                for a in g.node(NodeId(i as u32)).args() {
                    live[a.index()] = true;
                }
            }
        }
        // Which results each call site (group, point and any guard) needs, so a group is
        // inlined once per site.
        let mut wanted: BTreeMap<(u32, &[NodeId]), BTreeSet<u8>> = BTreeMap::new();
        for (id, node) in g.nodes() {
            if let (true, Op::Call { func, result }) = (live[id.index()], node.op) {
                wanted
                    .entry((func, node.args()))
                    .or_default()
                    .insert(result);
            }
        }
        let mut inlined: BTreeMap<(u32, &[NodeId]), BTreeMap<u8, Val>> = BTreeMap::new();
        let mut vals: Vec<Option<Val>> = vec![None; g.len()];
        for id in schedule(g, results) {
            let node = g.node(id);
            let mut args = Vec::with_capacity(node.args().len());
            for a in node.args() {
                let v = vals[a.index()].ok_or_else(|| unsupported("a node before its argument"))?;
                args.push(c.materialize(v));
            }
            let v = match node.op {
                Op::Call { func, result } => {
                    let key = (func, node.args());
                    if let std::collections::btree_map::Entry::Vacant(slot) = inlined.entry(key) {
                        let Some(group) = self.groups.get(func as usize) else {
                            return Err(unsupported(format!("a call of missing group {func}")));
                        };
                        let want: Vec<u8> = wanted[&key].iter().copied().collect();
                        let mut nodes = Vec::new();
                        for &r in &want {
                            let Some(&n) = group.results.get(r as usize) else {
                                return Err(unsupported(format!("result {r} of group {func}")));
                            };
                            nodes.push(n);
                        }
                        let out = match args[..] {
                            // A culled union's part: run only where its box is nearer than
                            // the best distance so far, and handed that best.
                            [point, bound, best] => {
                                let inputs = Inputs {
                                    point,
                                    best: Some(best),
                                };
                                self.guarded(c, group, &nodes, &want, inputs, bound, depth + 1)?
                            }
                            _ => {
                                let inputs = Inputs {
                                    point: args[0],
                                    best: None,
                                };
                                self.func(c, group, &nodes, inputs, depth + 1)?
                            }
                        };
                        slot.insert(want.into_iter().zip(out).collect());
                    }
                    inlined[&key][&result]
                }
                _ => self.node(c, g, id, &args, inputs)?,
            };
            vals[id.index()] = Some(v);
        }
        let mut out = Vec::with_capacity(results.len());
        for r in results {
            let v = vals[r.index()].ok_or_else(|| unsupported("a result that was not computed"))?;
            out.push(c.materialize(v));
        }
        Ok(out)
    }

    /// A culled union's part, inlined behind a skip: its results are set to the skipped
    /// call's (the box's distance `bound`, zero albedo and phong), then, unless `bound` is
    /// below `inputs.best`, the part's code runs and overwrites them. As the WGSL emitter's
    /// `if bound < best { s = group(p, best) }`.
    #[allow(clippy::too_many_arguments)]
    fn guarded(
        &mut self,
        c: &mut Chunk,
        group: &Func,
        nodes: &[NodeId],
        want: &[u8],
        inputs: Inputs,
        bound: Val,
        depth: usize,
    ) -> Result<Vec<Val>, EncodeError> {
        let bound = reg(bound, "a part's bound")?;
        let best = match inputs.best {
            Some(v) => v,
            None => self.load_const(&Value::F(NO_BEST))?,
        };
        let best = reg(c.materialize(best), "the best distance")?;
        let zero = self.load_const(&Value::V4([0.0; 4]))?;
        let mut results = Vec::with_capacity(want.len());
        for &r in want {
            let skipped = match r {
                0 => bound,
                _ => reg(c.materialize(zero), "zero")?,
            };
            results.push(c.emit(Opcode::Mov, &[skipped], 0));
        }
        let skip = c.ins.len();
        c.ins.push(VIns {
            op: Opcode::SkipUnlessLess,
            dst: None,
            args: vec![bound, best],
            imm: 0,
            folded: false,
        });
        let inputs = Inputs {
            point: inputs.point,
            best: Some(Val::Reg(best)),
        };
        let out = self.func(c, group, nodes, inputs, depth)?;
        for (&dst, v) in results.iter().zip(out) {
            let v = reg(c.materialize(v), "a part's result")?;
            c.ins.push(VIns {
                op: Opcode::Mov,
                dst: Some(dst),
                args: vec![v],
                imm: 0,
                folded: false,
            });
        }
        // A load inside the part is not made where it was skipped.
        c.loads.clear();
        // The offset is a 16-bit immediate; a longer part is run wherever it is reached
        // (its value then is its own, which is also a lower bound: never below its box's).
        let len = c.ins.len() - skip - 1;
        if len <= 0xffff {
            c.ins[skip].imm = len as u32;
        }
        Ok(results.into_iter().map(Val::Reg).collect())
    }

    /// One node (other than a call).
    fn node(
        &mut self,
        c: &mut Chunk,
        g: &Graph,
        id: NodeId,
        a: &[Val],
        inputs: Inputs,
    ) -> Result<Val, EncodeError> {
        let node = g.node(id);
        let arg_ty = |i: usize| g.ty(node.args()[i]);
        let regs = |what: &str| -> Result<Vec<u32>, EncodeError> {
            a.iter().map(|v| reg(*v, what)).collect()
        };
        let simple = |c: &mut Chunk, op: Opcode| -> Result<Val, EncodeError> {
            let r = regs(op.mnemonic())?;
            Ok(Val::Reg(c.emit(op, &r, 0)))
        };
        match node.op {
            Op::Const(k) => self.load_const(&k.to_value()),
            Op::Point => Ok(inputs.point),
            Op::Time => Ok(Val::Load(Opcode::Time, 0)),
            Op::Ray => Ok(Val::Load(Opcode::Ray, 0)),
            // The caller's best distance (`NO_BEST` outside a culled part).
            Op::Best => match inputs.best {
                Some(v) => Ok(v),
                None => self.load_const(&Value::F(NO_BEST)),
            },
            Op::Param(i) => match &self.args {
                Some(args) => match args.get(usize::from(i)) {
                    Some(&imm) => Ok(Val::Load(Opcode::Arg, imm)),
                    None => Err(unsupported(format!("argument {i} of a kind"))),
                },
                None => Ok(Val::Load(Opcode::Param, u32::from(i))),
            },
            // As in the WGSL emitter: only reachable if a lambda argument escaped substitution.
            Op::LambdaArg { .. } => self.load_const(&sdfc_ir::eval::zero_of(node.ty)),
            Op::Call { .. } => Err(unsupported("a nested call")),
            Op::Neg => simple(c, Opcode::Neg),
            Op::Add => simple(c, Opcode::Add),
            Op::Sub => simple(c, Opcode::Sub),
            Op::Div => simple(c, Opcode::Div),
            Op::Mod => simple(c, Opcode::Mod),
            Op::Lt => simple(c, Opcode::Lt),
            Op::Le => simple(c, Opcode::Le),
            Op::Gt => simple(c, Opcode::Gt),
            Op::Ge => simple(c, Opcode::Ge),
            Op::Eq => simple(c, Opcode::Eq),
            Op::Ne => simple(c, Opcode::Ne),
            Op::Mul | Op::MatMul => match (a[0], a[1]) {
                (Val::Reg(x), Val::Reg(y)) => Ok(Val::Reg(c.emit(Opcode::Mul, &[x, y], 0))),
                (Val::Mat(m), Val::Reg(v)) if arg_ty(1) == Ty::Vec3 => {
                    Ok(Val::Reg(c.emit(Opcode::Mat3Vec, &[m[0], m[1], m[2], v], 0)))
                }
                (Val::Mat(m), Val::Mat(n)) => {
                    let cols = n.map(|col| c.emit(Opcode::Mat3Vec, &[m[0], m[1], m[2], col], 0));
                    Ok(Val::Mat(cols))
                }
                _ => Err(unsupported("a matrix multiplied by a scalar")),
            },
            Op::Select => match (a[0], a[1], a[2]) {
                (Val::Reg(x), Val::Reg(y), Val::Reg(z)) => {
                    Ok(Val::Reg(c.emit(Opcode::Select, &[x, y, z], 0)))
                }
                (Val::Mat(x), Val::Mat(y), Val::Reg(z)) => {
                    let cols = [0, 1, 2].map(|i| c.emit(Opcode::Select, &[x[i], y[i], z], 0));
                    Ok(Val::Mat(cols))
                }
                _ => Err(unsupported("a select between a matrix and a vector")),
            },
            Op::MakeVec => {
                if a.len() > 4 || (0..a.len()).any(|i| arg_ty(i) != Ty::F32) {
                    return Err(unsupported("a vector built from vectors"));
                }
                simple(c, Opcode::MakeVec)
            }
            Op::Swizzle(s) => {
                let x = reg(a[0], "a swizzle")?;
                if arg_ty(0) == Ty::F32 {
                    // A splat: the scalar is already in every lane.
                    return Ok(Val::Reg(x));
                }
                let idx = s.indices();
                // A scalar result is splatted like every scalar.
                let lanes: [u8; 4] = if idx.len() == 1 {
                    [idx[0]; 4]
                } else {
                    [0, 1, 2, 3].map(|i| idx.get(i).copied().unwrap_or(0))
                };
                let imm = lanes
                    .iter()
                    .enumerate()
                    .fold(0u32, |acc, (i, &l)| acc | (u32::from(l & 3) << (2 * i)));
                Ok(Val::Reg(c.emit(Opcode::Swizzle, &[x], imm)))
            }
            Op::MakeMat3 => Ok(Val::Mat([
                reg(a[0], "a matrix column")?,
                reg(a[1], "a matrix column")?,
                reg(a[2], "a matrix column")?,
            ])),
            Op::Transpose => match a[0] {
                Val::Mat(m) => {
                    Ok(Val::Mat([0, 1, 2].map(|row| {
                        c.emit(Opcode::MatRow, &[m[0], m[1], m[2]], row)
                    })))
                }
                _ => Err(unsupported("a transpose of a vector")),
            },
            Op::Builtin(b) => {
                let width = arg_ty(0).width();
                let by_width = |ops: [Opcode; 3]| match width {
                    2 => Some(ops[0]),
                    3 => Some(ops[1]),
                    4 => Some(ops[2]),
                    _ => None,
                };
                let op = match b {
                    Builtin::Length if width == 1 => Some(Opcode::Abs),
                    Builtin::Length => {
                        by_width([Opcode::Length2, Opcode::Length3, Opcode::Length4])
                    }
                    Builtin::Distance => {
                        let r = regs("distance")?;
                        let diff = c.emit(Opcode::Sub, &r, 0);
                        let op = if width == 1 {
                            Some(Opcode::Abs)
                        } else {
                            by_width([Opcode::Length2, Opcode::Length3, Opcode::Length4])
                        };
                        let Some(op) = op else {
                            return Err(unsupported("distance of this type"));
                        };
                        return Ok(Val::Reg(c.emit(op, &[diff], 0)));
                    }
                    Builtin::Dot => by_width([Opcode::Dot2, Opcode::Dot3, Opcode::Dot4]),
                    Builtin::Normalize => {
                        by_width([Opcode::Normalize2, Opcode::Normalize3, Opcode::Normalize4])
                    }
                    Builtin::Cross => (width == 3).then_some(Opcode::Cross),
                    _ => builtin_opcode(b),
                };
                match op {
                    Some(op) => simple(c, op),
                    None => Err(unsupported(format!(
                        "built-in `{}` on {:?}",
                        b.name(),
                        arg_ty(0)
                    ))),
                }
            }
            Op::Helper(h) => match helper_opcode(h) {
                Some(op) if a.len() <= 4 => simple(c, op),
                _ => Err(unsupported(format!("helper `{}` has no opcode", h.name()))),
            },
            #[allow(unreachable_patterns)] // operations added after the interpreter
            _ => Err(unsupported(format!(
                "operation {:?} has no opcode",
                node.op
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interp::listing::arity;
    use crate::interp::opcodes::decode;

    /// Every register an instruction reads was written earlier in the same function (or is
    /// the point, register 0): the shader's register file holds whatever an earlier call left
    /// in it, so a read before a write would make the result depend on the lane's history.
    /// A skipped part's code may not run: after it, only what was written before its skip
    /// counts as written.
    fn reads_only_written_registers(name: &str, src: &str, cull: bool) {
        let opts = crate::Options {
            cull,
            ..Default::default()
        };
        let c = crate::compile(src, &opts).unwrap();
        let code = encode(c.program()).unwrap();
        for (func, [start, end]) in [("distance", code.distance), ("material", code.material)] {
            let mut written = vec![false; MAX_REGISTERS as usize];
            written[0] = true;
            // (last instruction a skip jumps over, what was written before the skip)
            let mut skipped: Vec<(u32, Vec<bool>)> = Vec::new();
            for pc in start..end {
                let [op, d, a01, a23] = code.code[pc as usize];
                let (op, folded) = decode(op);
                let op = op.unwrap();
                let args = [a01 & 0xffff, a01 >> 16, a23 & 0xffff, a23 >> 16];
                let read = args[..arity(op)].iter().chain(folded.then_some(&args[3]));
                for &r in read.filter(|&&r| r < MAX_REGISTERS) {
                    assert!(
                        written[r as usize],
                        "{name}: {func} instruction {pc} ({}) reads r{r} before any write\n{}",
                        op.mnemonic(),
                        code.listing()
                    );
                }
                if op != Opcode::Ret {
                    written[(d & 0xffff) as usize] = true;
                }
                if op == Opcode::SkipUnlessLess && d >> 16 > 0 {
                    let last = pc + (d >> 16);
                    assert!(
                        last < end - 1 && skipped.last().is_none_or(|s| last <= s.0),
                        "{name}: the skip at {pc} leaves its part"
                    );
                    skipped.push((last, written.clone()));
                }
                while skipped.last().is_some_and(|s| s.0 == pc) {
                    written = skipped.pop().unwrap().1;
                }
            }
            assert!(skipped.is_empty(), "{name}: a skip past the end");
        }
    }

    /// `arity` says which argument registers each opcode's `case` in the shader reads (`a`
    /// to `d`, in order), so the listing and the test below see what the shader does.
    #[test]
    fn arities_match_the_shader() {
        for op in Opcode::ALL.iter().filter(|o| **o != Opcode::Ret) {
            let case = format!("case {}:", op.wgsl_name());
            let src = super::super::INTERPRET;
            let at = src
                .find(&case)
                .unwrap_or_else(|| panic!("no case for {}", op.mnemonic()));
            // The case's block, to its matching brace (a fractal's case spans lines).
            let open = at + src[at..].find('{').unwrap();
            let mut depth = 0;
            let mut close = open;
            for (i, ch) in src[open..].char_indices() {
                match ch {
                    '{' => depth += 1,
                    '}' => depth -= 1,
                    _ => {}
                }
                if depth == 0 {
                    close = open + i;
                    break;
                }
            }
            let line = &src[at..=close];
            let body = &src[open..=close];
            let words: Vec<&str> = body
                .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .collect();
            let used = ["a", "b", "c", "d"]
                .iter()
                .rposition(|r| words.contains(r))
                .map_or(0, |i| i + 1);
            assert_eq!(arity(*op), used, "{}: {line}", op.mnemonic());
        }
    }

    /// A culled row of 64 spheres, every other one red: eight parts of eight, each split
    /// again, so skips nest.
    fn culled_row() -> String {
        let spheres: Vec<String> = (0..64)
            .map(|i| {
                let red = if i % 2 == 0 { ".material(red)" } else { "" };
                format!("sphere(0.4){red}.translate([{i}, 0, 0])")
            })
            .collect();
        format!(
            "material red {{ color: [0.9, 0.2, 0.1] }}\nscene = union({});\n",
            spheres.join(", ")
        )
    }

    #[test]
    fn a_culled_union_skips_its_parts_and_reads_only_written_registers() {
        let src = culled_row();
        reads_only_written_registers("culled row", &src, true);
        let opts = crate::Options {
            cull: true,
            ..Default::default()
        };
        let code = encode(crate::compile(&src, &opts).unwrap().program()).unwrap();
        let skips: Vec<u32> = code
            .code
            .iter()
            .filter(|c| c[0] == Opcode::SkipUnlessLess.code())
            .map(|c| c[1] >> 16)
            .collect();
        // Eight parts split again, in the distance function and in the material function.
        assert!(
            skips.len() >= 2 * 8,
            "{} skips\n{}",
            skips.len(),
            code.listing()
        );
        assert!(skips.iter().all(|&n| n > 0), "a part too long to skip");
        let plain = encode(crate::compile(&src, &Default::default()).unwrap().program()).unwrap();
        assert!(!plain
            .code
            .iter()
            .any(|c| c[0] == Opcode::SkipUnlessLess.code()));
    }

    #[test]
    fn no_register_is_read_before_it_is_written() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let mut paths = Vec::new();
        for dir in ["examples", "crates/sdfc-render/tests/scenes"] {
            for e in std::fs::read_dir(root.join(dir)).unwrap() {
                let p = e.unwrap().path();
                if p.extension().is_some_and(|e| e == "sdf") {
                    paths.push(p);
                }
            }
        }
        paths.sort();
        assert!(paths.len() > 20, "the scenes are missing");
        for p in paths {
            let src = std::fs::read_to_string(&p).unwrap();
            for cull in [false, true] {
                reads_only_written_registers(&p.display().to_string(), &src, cull);
            }
        }
    }

    /// The distance function's instructions, decoded.
    fn distance_ops(src: &str) -> (Bytecode, Vec<(Option<Opcode>, bool)>) {
        let c = crate::compile(src, &Default::default()).unwrap();
        let code = encode(c.program()).unwrap();
        let [start, end] = code.distance;
        let ops = code.code[start as usize..end as usize]
            .iter()
            .map(|i| decode(i[0]))
            .collect();
        (code, ops)
    }

    /// A shape moved by a constant offset takes the moved point as it fetches its argument:
    /// no `sub` of its own, the same distance. An offset from a param is a register, and
    /// stays an instruction.
    #[test]
    fn a_constant_translation_is_folded_into_its_readers() {
        let (code, ops) = distance_ops("scene = sphere(1).translate([1, 2, 3]);");
        assert!(
            !ops.contains(&(Some(Opcode::Sub), false)),
            "{}",
            code.listing()
        );
        assert!(
            ops.contains(&(Some(Opcode::SdSphere), true)),
            "{}",
            code.listing()
        );
        let at = |code: &Bytecode, p: [f32; 3], params: &[[f32; 4]]| {
            super::super::exec::run(code, super::super::exec::Function::Distance, p, params, 0.0)
                .unwrap()[0][0]
        };
        assert_eq!(at(&code, [1.0, 2.0, 5.0], &[]), 1.0);
        assert_eq!(at(&code, [1.0, 2.0, 3.0], &[]), -1.0);
        let (code, ops) = distance_ops("param o = [1, 2, 3];\nscene = sphere(1).translate(o);");
        assert!(
            ops.contains(&(Some(Opcode::Sub), false)),
            "{}",
            code.listing()
        );
        assert!(ops.iter().all(|o| !o.1), "{}", code.listing());
        assert_eq!(at(&code, [1.0, 2.0, 5.0], &[[1.0, 2.0, 3.0, 0.0]]), 1.0);
    }
}
