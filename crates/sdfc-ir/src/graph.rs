//! The hash-consed expression DAG: typed nodes in topological order, each built once.

use crate::hash::FxHashMap;
use crate::ops::{Builtin, Op};
use crate::types::Ty;
use crate::value::{Const, Value};
use sdfc_syntax::span::Span;

/// Index of a node in its [`Graph`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(pub u32);

impl NodeId {
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Up to four arguments, stored inline so a node key needs no allocation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Args {
    len: u8,
    ids: [NodeId; 4],
}

impl Args {
    pub fn new(ids: &[NodeId]) -> Args {
        let mut a = [NodeId(0); 4];
        let n = ids.len().min(4);
        a[..n].copy_from_slice(&ids[..n]);
        Args {
            len: n as u8,
            ids: a,
        }
    }

    pub fn as_slice(&self) -> &[NodeId] {
        &self.ids[..self.len as usize]
    }
}

/// One node: an operation on earlier nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    pub op: Op,
    pub args: Args,
    pub ty: Ty,
}

impl Node {
    pub fn args(&self) -> &[NodeId] {
        self.args.as_slice()
    }

    pub fn as_const(&self) -> Option<Value<f32>> {
        match self.op {
            Op::Const(c) => Some(c.to_value()),
            _ => None,
        }
    }
}

/// A DAG of typed nodes; `add` returns the existing node for a repeated `(op, args)`.
#[derive(Clone, Debug, Default)]
pub struct Graph {
    nodes: Vec<Node>,
    spans: Vec<Span>,
    hints: Vec<&'static str>,
    table: FxHashMap<(Op, Args), NodeId>,
    /// Set when a node was built with argument types its operation does not take; the
    /// compiler reports it as an internal error instead of panicking.
    pub ill_typed: Option<String>,
}

impl Graph {
    pub fn new() -> Graph {
        Graph::default()
    }

    /// An empty graph with room for `n` nodes and none in its table, for
    /// [`Graph::push_copy`].
    pub fn with_capacity_untabled(n: usize) -> Graph {
        Graph {
            nodes: Vec::with_capacity(n),
            spans: Vec::with_capacity(n),
            hints: Vec::with_capacity(n),
            ..Graph::default()
        }
    }

    /// An empty graph with room for `n` nodes (rebuilding passes know their size).
    pub fn with_capacity(n: usize) -> Graph {
        Graph {
            nodes: Vec::with_capacity(n),
            spans: Vec::with_capacity(n),
            hints: Vec::with_capacity(n),
            table: FxHashMap::with_capacity_and_hasher(n, Default::default()),
            ill_typed: None,
        }
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    pub fn node(&self, id: NodeId) -> &Node {
        &self.nodes[id.index()]
    }

    pub fn nodes(&self) -> impl Iterator<Item = (NodeId, &Node)> {
        self.nodes
            .iter()
            .enumerate()
            .map(|(i, n)| (NodeId(i as u32), n))
    }

    pub fn ty(&self, id: NodeId) -> Ty {
        self.nodes[id.index()].ty
    }

    pub fn span(&self, id: NodeId) -> Span {
        self.spans[id.index()]
    }

    /// The name prefix the emitter uses for this node (`d` distance, `q` point, ...).
    pub fn hint(&self, id: NodeId) -> &'static str {
        self.hints[id.index()]
    }

    pub fn set_hint(&mut self, id: NodeId, hint: &'static str) {
        self.hints[id.index()] = hint;
    }

    pub fn as_const(&self, id: NodeId) -> Option<Value<f32>> {
        self.node(id).as_const()
    }

    pub fn as_scalar_const(&self, id: NodeId) -> Option<f32> {
        self.as_const(id).and_then(|v| v.scalar())
    }

    /// Appends a copy of a node of a hash-consed graph whose arguments have been renamed
    /// one-to-one (dead code elimination), so it cannot be a duplicate: no lookup, and the
    /// table is filled only if a later [`Graph::add`] needs it (most graphs after DCE are
    /// only read: lowering the 5 000-shape scene, 36-37 -> 32 ms).
    pub fn push_copy(&mut self, node: Node, span: Span, hint: &'static str) -> NodeId {
        let id = NodeId(self.nodes.len() as u32);
        self.nodes.push(node);
        self.spans.push(span);
        self.hints.push(hint);
        id
    }

    /// Fills the table with the nodes appended by [`Graph::push_copy`].
    fn index_copies(&mut self) {
        if self.table.len() < self.nodes.len() {
            self.table.reserve(self.nodes.len() - self.table.len());
            for (i, n) in self.nodes.iter().enumerate() {
                self.table.insert((n.op, n.args), NodeId(i as u32));
            }
        }
    }

    /// Adds (or finds) a node. The result type is inferred; see [`infer`].
    pub fn add(&mut self, op: Op, args: &[NodeId], span: Span) -> NodeId {
        self.index_copies();
        let key = (op, Args::new(args));
        if let Some(&id) = self.table.get(&key) {
            return id;
        }
        let mut arg_tys = [Ty::F32; 4];
        for (t, a) in arg_tys.iter_mut().zip(args) {
            *t = self.ty(*a);
        }
        let arg_tys = &arg_tys[..args.len().min(4)];
        let ty = match infer(op, arg_tys) {
            Some(t) => t,
            None => {
                if self.ill_typed.is_none() {
                    self.ill_typed = Some(format!("{op:?} applied to {arg_tys:?}"));
                }
                Ty::F32
            }
        };
        self.push(op, key.1, ty, span, key)
    }

    /// Adds an input node whose type is not implied by its operation (`Param`, `LambdaArg`).
    pub fn input(&mut self, op: Op, ty: Ty, span: Span) -> NodeId {
        self.add_typed(op, &[], ty, span)
    }

    /// Adds (or finds) a node whose type the caller knows (inputs, calls).
    pub fn add_typed(&mut self, op: Op, args: &[NodeId], ty: Ty, span: Span) -> NodeId {
        self.index_copies();
        let key = (op, Args::new(args));
        if let Some(&id) = self.table.get(&key) {
            return id;
        }
        self.push(op, key.1, ty, span, key)
    }

    fn push(&mut self, op: Op, args: Args, ty: Ty, span: Span, key: (Op, Args)) -> NodeId {
        let id = NodeId(self.nodes.len() as u32);
        self.nodes.push(Node { op, args, ty });
        self.spans.push(span);
        self.hints.push(default_hint(ty));
        self.table.insert(key, id);
        id
    }

    pub fn konst(&mut self, v: Value<f32>) -> NodeId {
        self.add(Op::Const(Const::from_value(&v)), &[], Span::default())
    }

    pub fn f32(&mut self, x: f32) -> NodeId {
        self.konst(Value::F(x))
    }

    pub fn vec3(&mut self, x: [f32; 3]) -> NodeId {
        self.konst(Value::V3(x))
    }

    /// Shorthands for the common operations, all with the span given.
    pub fn op(&mut self, op: Op, args: &[NodeId]) -> NodeId {
        self.add(op, args, Span::default())
    }

    pub fn builtin(&mut self, b: Builtin, args: &[NodeId]) -> NodeId {
        self.add(Op::Builtin(b), args, Span::default())
    }
}

/// The name prefix of a node of type `ty` that has no more specific hint.
pub fn default_hint(ty: Ty) -> &'static str {
    match ty {
        Ty::F32 => "v",
        Ty::Vec2 => "w",
        Ty::Vec3 => "q",
        Ty::Vec4 => "c",
        Ty::Bool => "b",
        Ty::Mat3 => "m",
    }
}

/// The result type of `op` on arguments of the given types, or `None` where WGSL would
/// reject the combination. Arithmetic broadcasts scalars over vectors.
pub fn infer(op: Op, a: &[Ty]) -> Option<Ty> {
    use Ty::*;
    let float = |t: Ty| t.is_float_like();
    let broadcast = |x: Ty, y: Ty| -> Option<Ty> {
        if !float(x) || !float(y) {
            None
        } else if x == y || y == F32 {
            Some(x)
        } else if x == F32 {
            Some(y)
        } else {
            None
        }
    };
    match op {
        Op::Const(c) => Some(match c {
            Value::F(_) => F32,
            Value::V2(_) => Vec2,
            Value::V3(_) => Vec3,
            Value::V4(_) => Vec4,
            Value::B(_) => Bool,
            Value::M3(_) => Mat3,
        }),
        Op::Point | Op::Ray => Some(Vec3),
        Op::Time | Op::Best => Some(F32),
        Op::Param(_) | Op::LambdaArg { .. } | Op::Call { .. } => None,
        Op::Neg => (a.len() == 1 && float(a[0])).then_some(a[0]),
        Op::Add | Op::Sub | Op::Mul | Op::Div | Op::Mod => {
            if a.len() != 2 {
                return None;
            }
            if op == Op::Mul && a[0] == Mat3 && a[1] == Mat3 {
                return None; // use MatMul
            }
            broadcast(a[0], a[1])
        }
        Op::Lt | Op::Le | Op::Gt | Op::Ge | Op::Eq | Op::Ne => {
            (a.len() == 2 && a[0] == F32 && a[1] == F32).then_some(Bool)
        }
        Op::Select => (a.len() == 3 && a[0] == a[1] && a[2] == Bool).then_some(a[0]),
        Op::MakeVec => (a.len() >= 2 && a.iter().all(|t| *t == F32)).then(|| Ty::vec(a.len()))?,
        Op::Swizzle(s) => {
            let w = a.first()?.width();
            (a.len() == 1
                && a[0] != Mat3
                && a[0] != Bool
                && s.indices().iter().all(|&i| (i as usize) < w))
            .then(|| Ty::vec(s.len as usize))?
        }
        Op::MakeMat3 => (a.len() == 3 && a.iter().all(|t| *t == Vec3)).then_some(Mat3),
        Op::MatMul => match a {
            [Mat3, Mat3] => Some(Mat3),
            [Mat3, Vec3] => Some(Vec3),
            _ => None,
        },
        Op::Transpose => (a == [Mat3]).then_some(Mat3),
        Op::Builtin(b) => infer_builtin(b, a),
        Op::Helper(h) => {
            use crate::ops::Helper::{NoiseGradient, RotateX, RotateY, RotateZ};
            let ok = a.first() == Some(&Vec3) && a.iter().all(|t| float(*t));
            ok.then_some(
                if matches!(h, RotateX | RotateY | RotateZ | NoiseGradient) {
                    Vec3
                } else {
                    F32
                },
            )
        }
    }
}

fn infer_builtin(b: Builtin, a: &[Ty]) -> Option<Ty> {
    use Builtin::*;
    use Ty::*;
    if a.len() != b.arity() || !a.iter().all(|t| t.is_float_like()) {
        return None;
    }
    let same = a.iter().all(|t| *t == a[0]);
    match b {
        Length => Some(F32),
        Distance => same.then_some(F32),
        // WGSL defines `normalize` and `dot` on vectors only.
        Normalize => (a[0] != F32).then_some(a[0]),
        Dot => (same && a[0] != F32).then_some(F32),
        Cross => (a == [Vec3, Vec3]).then_some(Vec3),
        // WGSL's mix, step and smoothstep take the same type throughout (we splat scalars).
        _ => same.then_some(a[0]),
    }
}

impl Graph {
    /// Broadcasts a scalar node to a vector type (a no-op when the types already agree).
    /// A splat is a swizzle of a scalar (`.xxx`); the emitter spells it `vec3<f32>(x)`.
    pub fn splat(&mut self, x: NodeId, ty: Ty) -> NodeId {
        if self.ty(x) == ty || self.ty(x) != Ty::F32 {
            return x;
        }
        let span = self.span(x);
        let swz = crate::ops::Swizzle::new(&vec![0u8; ty.width()]);
        self.add(Op::Swizzle(swz), &[x], span)
    }
}
