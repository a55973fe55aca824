//! The interpreter's register machine on the CPU, in f32: what `interpret.wgsl` computes for
//! one lane, for tests that check the encoder without a device (bytecode against the IR's
//! own evaluator) and for telling an encoder fault from a driver's.
//!
//! Component-wise opcodes run on all four lanes; built-ins and distance helpers go through
//! `sdfc_ir::eval::apply`, with the argument swizzles (`a.xyz`, `b.x`, ...) read from the
//! helper's `case` line in the shader, so the two cannot drift apart.

use super::encode::{Bytecode, MAX_REGISTERS};
use super::exec_walk::{Trip, Walk};
use super::listing::arity;
use super::opcodes::{builtin_opcode, decode, helper_opcode, Opcode};
use super::INTERPRET;
use sdfc_ir::eval::apply;
use sdfc_ir::ops::{Builtin, Helper, Op};
use sdfc_ir::types::Ty;
use sdfc_ir::value::Value;

/// Instructions one run may take: far more than any scene's (a union's walk visits each
/// node at most once per call).
const MAX_TRIPS: u64 = 1 << 28;

/// One of the functions of a program.
#[derive(Clone, Copy, Debug)]
pub enum Function {
    Distance,
    /// The march's distance along the unit direction given (`scene_distance_ray`; the
    /// plain distance's code where the program has no ray function).
    DistanceRay([f32; 3]),
    Material,
}

/// Runs `function` of `code` at point `p` with the params' values (`vec4` each, as the data
/// buffer holds them) and the time; returns the `ret`'s two registers (the distance in the
/// first's `x`; the albedo and phong vectors for the material). An opcode this executor
/// does not know is an error.
pub fn run(
    code: &Bytecode,
    function: Function,
    p: [f32; 3],
    params: &[[f32; 4]],
    time: f32,
) -> Result<[[f32; 4]; 2], String> {
    let [start, end] = match function {
        Function::Distance => code.distance,
        Function::DistanceRay(_) => code.distance_ray,
        Function::Material => code.material,
    };
    let ray = match function {
        Function::DistanceRay(rd) => [rd[0], rd[1], rd[2], 0.0],
        _ => [0.0; 4],
    };
    let mut regs = [[0f32; 4]; MAX_REGISTERS as usize];
    regs[0] = [p[0], p[1], p[2], 0.0];
    let last = end.checked_sub(1).ok_or("an empty function")?;
    let mut pc = start;
    let mut walk = Walk::default();
    // A walk jumps back; a fault in it must not loop for ever.
    let mut trips = 0u64;
    while pc < last {
        trips += 1;
        if trips > MAX_TRIPS {
            return Err(format!("more than {MAX_TRIPS} instructions run"));
        }
        let [op, y, z, w] = code.code[pc as usize];
        let (dst, imm) = ((y & 0xffff) as usize, y >> 16);
        let reg = |i: u32| operand(&regs, code, i);
        let (a, b, c, d) = (
            reg(z & 0xffff)?,
            reg(z >> 16)?,
            reg(w & 0xffff)?,
            reg(w >> 16)?,
        );
        let (Some(op), folded) = decode(op) else {
            return Err(format!("unknown opcode {op} at {pc}"));
        };
        // A folded translation: the first argument is `a - d`, as the shader fetches it.
        let a = if folded {
            std::array::from_fn(|i| a[i] - d[i])
        } else {
            a
        };
        let r = match op {
            Opcode::Instances => {
                match walk.trip(code, pc, [a[0], a[1], a[2]], imm, &mut regs[0])? {
                    Trip::Jump(to) => {
                        pc = to;
                        continue;
                    }
                    Trip::Over(r) => Some(r),
                }
            }
            Opcode::InstanceDone => {
                pc = walk.back(a[0], &mut regs[0])?;
                continue;
            }
            Opcode::Arg => Some(walk.arg(code, imm)?),
            Opcode::MaterialRow => Some(
                *code
                    .consts
                    .get((imm + 2 * a[1] as u32) as usize)
                    .ok_or("a material out of range")?,
            ),
            Opcode::Ray => Some(ray),
            _ => execute(op, imm, [a, b, c, d], params, time)
                .ok_or_else(|| format!("{} at {pc}", op.mnemonic()))?,
        };
        // `!(a < b)`, as the shader says it: NaN skips too.
        let less = a[0].partial_cmp(&b[0]) == Some(std::cmp::Ordering::Less);
        if op == Opcode::SkipUnlessLess && !less {
            pc += imm;
        }
        *regs.get_mut(dst).ok_or("a destination out of range")? = r.unwrap_or(regs[dst]);
        pc += 1;
    }
    let [_, _, z, _] = code.code[last as usize];
    Ok([
        operand(&regs, code, z & 0xffff)?,
        operand(&regs, code, z >> 16)?,
    ])
}

/// An operand: a register, or from `MAX_REGISTERS` on a constant of the pool.
fn operand(
    regs: &[[f32; 4]; MAX_REGISTERS as usize],
    code: &Bytecode,
    i: u32,
) -> Result<[f32; 4], &'static str> {
    match i.checked_sub(MAX_REGISTERS) {
        Some(k) => code
            .consts
            .get(k as usize)
            .copied()
            .ok_or("a constant out of range"),
        None => Ok(regs[i as usize]),
    }
}

fn zip(a: [f32; 4], b: [f32; 4], f: impl Fn(f32, f32) -> f32) -> [f32; 4] {
    [0, 1, 2, 3].map(|i| f(a[i], b[i]))
}

fn splat(x: f32) -> [f32; 4] {
    [x; 4]
}

fn truth(b: bool) -> f32 {
    if b {
        1.0
    } else {
        0.0
    }
}

/// One instruction's result (`Some(None)`: it writes its destination back unchanged), or
/// `None` for an opcode this executor cannot run.
fn execute(
    op: Opcode,
    imm: u32,
    [a, b, c, d]: [[f32; 4]; 4],
    params: &[[f32; 4]],
    time: f32,
) -> Option<Option<[f32; 4]>> {
    use Opcode as O;
    let r = match op {
        O::Ret | O::SkipUnlessLess => return Some(None),
        O::Param => *params.get(imm as usize)?,
        O::Time => splat(time),
        O::Mov => a,
        O::Neg => a.map(|x| -x),
        O::Add => zip(a, b, |x, y| x + y),
        O::Sub => zip(a, b, |x, y| x - y),
        O::Mul => zip(a, b, |x, y| x * y),
        O::Div => zip(a, b, |x, y| x / y),
        O::Mod => zip(a, b, |x, y| x - y * (x / y).floor()),
        O::Lt => zip(a, b, |x, y| truth(x < y)),
        O::Le => zip(a, b, |x, y| truth(x <= y)),
        O::Gt => zip(a, b, |x, y| truth(x > y)),
        O::Ge => zip(a, b, |x, y| truth(x >= y)),
        O::Eq => zip(a, b, |x, y| truth(x == y)),
        O::Ne => zip(a, b, |x, y| truth(x != y)),
        O::Select => {
            if c[0] != 0.0 {
                b
            } else {
                a
            }
        }
        O::MakeVec => [a[0], b[0], c[0], d[0]],
        O::Swizzle => [0, 1, 2, 3].map(|i| a[((imm >> (2 * i)) & 3) as usize]),
        O::Mat3Vec => [0, 1, 2, 3].map(|i| {
            if i < 3 {
                a[i] * d[0] + b[i] * d[1] + c[i] * d[2]
            } else {
                0.0
            }
        }),
        O::MatRow => [
            a[imm as usize & 3],
            b[imm as usize & 3],
            c[imm as usize & 3],
            0.0,
        ],
        O::Length2 => splat(len(&a[..2])),
        O::Length3 => splat(len(&a[..3])),
        O::FarCorner => splat(len(&[0, 1, 2].map(|i| a[i].abs() + b[i]))),
        O::Length4 => splat(len(&a)),
        O::Dot2 => splat(dot(&a[..2], &b[..2])),
        O::Dot3 => splat(dot(&a[..3], &b[..3])),
        O::Dot4 => splat(dot(&a, &b)),
        O::Normalize2 => normalized(a, 2),
        O::Normalize3 => normalized(a, 3),
        O::Normalize4 => normalized(a, 4),
        O::Cross => [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
            0.0,
        ],
        _ => {
            if let Some(&h) = Helper::ALL.iter().find(|h| helper_opcode(**h) == Some(op)) {
                helper(op, h, [a, b, c, d])?
            } else {
                let &bi = Builtin::ALL
                    .iter()
                    .find(|b| builtin_opcode(**b) == Some(op))?;
                let args = [a, b, c].map(Value::V4);
                let n = arity(op);
                match apply(Op::Builtin(bi), Ty::Vec4, &args[..n]) {
                    Value::V4(v) => v,
                    Value::F(x) => splat(x),
                    _ => return None,
                }
            }
        }
    };
    Some(Some(r))
}

fn len(v: &[f32]) -> f32 {
    dot(v, v).sqrt()
}

fn dot(a: &[f32], b: &[f32]) -> f32 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn normalized(a: [f32; 4], n: usize) -> [f32; 4] {
    let l = len(&a[..n]);
    [0, 1, 2, 3].map(|i| if i < n { a[i] / l } else { 0.0 })
}

/// A distance helper, its arguments swizzled as its `case` line in the shader spells them;
/// a fractal's case (one iteration per trip, over several lines) reads the point `a.xyz`
/// and scalars `b.x`, `c.x`, `d.x`.
fn helper(op: Opcode, h: Helper, regs: [[f32; 4]; 4]) -> Option<[f32; 4]> {
    let case = format!("case {}:", op.wgsl_name());
    let line = INTERPRET.lines().find(|l| l.contains(&case))?;
    if line.trim_end().ends_with('{') {
        let [a, b, c, d] = regs;
        let scalars = [b[0], c[0], d[0]].map(Value::F);
        let mut args = vec![Value::V3([a[0], a[1], a[2]])];
        args.extend_from_slice(&scalars[..arity(op).checked_sub(1)?]);
        return match apply(Op::Helper(h), Ty::F32, &args) {
            Value::F(x) => Some(splat(x)),
            _ => None,
        };
    }
    let call = &line[line.find('(')? + 1..];
    let call = &call[call.find('(')? + 1..];
    let call = &call[..call.find(')')?];
    let mut args = Vec::new();
    for token in call.split([',', ' ']) {
        let Some((reg, swizzle)) = token.split_once('.') else {
            continue;
        };
        let r = regs[["a", "b", "c", "d"].iter().position(|n| *n == reg)?];
        args.push(match swizzle {
            "x" => Value::F(r[0]),
            "xy" => Value::V2([r[0], r[1]]),
            "xyz" => Value::V3([r[0], r[1], r[2]]),
            _ => return None,
        });
    }
    Some(match apply(Op::Helper(h), Ty::F32, &args) {
        Value::F(x) => splat(x),
        Value::V3(v) => [v[0], v[1], v[2], 0.0],
        _ => return None,
    })
}
