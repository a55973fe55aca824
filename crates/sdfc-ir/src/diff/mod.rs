//! Forward-mode differentiation of the distance function: `scene_gradient(p)` returns the
//! distance and its gradient with respect to p, for `normals: analytic` (no epsilon).
//!
//! Each node of the distance function is copied into a new graph together with its tangents,
//! its derivatives along x, y and z (three nodes of its own type, `None` where the derivative
//! is zero). The derivative of a distance helper comes from the helper's formula spelled in
//! generic operations (`helpers.rs`), differentiated by the same rules; the value itself stays
//! the helper call, so the gradient function's distance is the distance function's. A group
//! call becomes a call of the group's gradient function.

mod helpers;
mod rules;

use crate::func::{Func, FuncKind};
use crate::graph::{Graph, NodeId};
use crate::hash::FxHashMap;
use crate::ops::Op;
use crate::types::Ty;

/// The derivatives of one node along x, y and z; `None` is zero.
pub(crate) type Tangent = [Option<NodeId>; 3];

/// `scene_gradient` and the gradient functions of the groups it calls.
#[derive(Clone, Debug)]
pub struct Gradient {
    /// Results: the distance, then the gradient's x, y and z components (four f32). Kept
    /// apart so that a consumer of one component (the interpreter's three passes) computes
    /// only its chain.
    pub func: Func,
    /// One per group of the program, in the same order, with the same four results; the
    /// calls in `func` and in these name them as `Op::Call { func: groups.len() + i }` of the
    /// combined list (`[program groups..., gradient groups...]`).
    pub groups: Vec<Func>,
}

impl Gradient {
    /// The group list the gradient functions' calls index: the program's groups, then these.
    pub fn all_groups(&self, groups: &[Func]) -> Vec<Func> {
        groups.iter().chain(&self.groups).cloned().collect()
    }
}

/// Differentiates `distance` (whose calls name `groups`).
pub fn gradient(distance: &Func, groups: &[Func]) -> Gradient {
    let base = groups.len() as u32;
    let grads = groups
        .iter()
        .map(|f| differentiate(f, base, format!("{}_gradient", f.name)))
        .collect();
    Gradient {
        func: differentiate(distance, base, "scene_gradient".into()),
        groups: grads,
    }
}

/// The gradient function of `f`'s first result.
fn differentiate(f: &Func, base: u32, name: String) -> Func {
    let mut d = Differ::new(base);
    let src = &f.graph;
    let root = f.results[0];
    // Only the nodes the distance needs (a group's material part is left behind).
    let mut need = vec![false; src.len()];
    need[root.index()] = true;
    for i in (0..src.len()).rev() {
        if need[i] {
            for a in src.node(NodeId(i as u32)).args() {
                need[a.index()] = true;
            }
        }
    }
    let mut map: Vec<NodeId> = vec![NodeId(0); src.len()];
    for (id, node) in src.nodes() {
        if !need[id.index()] {
            continue;
        }
        let args: Vec<NodeId> = node.args().iter().map(|a| map[a.index()]).collect();
        let new = match node.op {
            Op::Call { func, result: 0 } => d.call(func, args[0]),
            // Only a group's distance is differentiated; other results are not needed.
            Op::Call { .. } => d.g.add_typed(node.op, &args, node.ty, src.span(id)),
            // Gradient functions are called unguarded, with no best distance to cut at.
            Op::Best => d.g.f32(crate::ops::NO_BEST),
            op => d.node_spanned(op, &args, node.ty, src.span(id)),
        };
        d.g.set_hint(new, src.hint(id));
        map[id.index()] = new;
    }
    let value = map[root.index()];
    let t = d.tangent(value);
    let comps = t.map(|c| c.unwrap_or_else(|| d.g.f32(0.0)));
    for c in comps {
        d.g.set_hint(c, "n");
    }
    Func {
        name,
        kind: FuncKind::Gradient,
        graph: d.g,
        results: vec![value, comps[0], comps[1], comps[2]],
    }
}

/// The graph being built and the tangents of its nodes.
pub(crate) struct Differ {
    pub(crate) g: Graph,
    tangents: FxHashMap<NodeId, Tangent>,
    /// Where the gradient groups start in the combined group list.
    base: u32,
}

impl Differ {
    fn new(base: u32) -> Differ {
        Differ {
            g: Graph::new(),
            tangents: FxHashMap::default(),
            base,
        }
    }

    /// Adds (or finds) a node and, the first time, its tangents.
    pub(crate) fn node(&mut self, op: Op, args: &[NodeId]) -> NodeId {
        let id = self.g.op(op, args);
        self.ensure(id);
        id
    }

    fn node_spanned(
        &mut self,
        op: Op,
        args: &[NodeId],
        ty: Ty,
        span: sdfc_syntax::span::Span,
    ) -> NodeId {
        let id = match op {
            Op::Param(_) | Op::LambdaArg { .. } => self.g.add_typed(op, args, ty, span),
            _ => self.g.add(op, args, span),
        };
        self.ensure(id);
        id
    }

    fn ensure(&mut self, id: NodeId) {
        if !self.tangents.contains_key(&id) {
            let t = self.rule(id);
            self.tangents.insert(id, t);
        }
    }

    /// The tangents of a node added through [`Self::node`] (zero for any other).
    pub(crate) fn tangent(&self, id: NodeId) -> Tangent {
        self.tangents.get(&id).copied().unwrap_or([None; 3])
    }

    pub(crate) fn set_tangent(&mut self, id: NodeId, t: Tangent) {
        self.tangents.insert(id, t);
    }

    /// Adds a tangent node, folded where its arguments are constants, and without the
    /// products by zero and one, sums with zero and dot products with an axis that the seeds
    /// of forward mode bring (on finite values, which WGSL assumes, these are exact).
    pub(crate) fn op(&mut self, op: Op, args: &[NodeId]) -> NodeId {
        let zero = |d: &Differ, x: NodeId| d.is_zero(x);
        let one = |d: &Differ, x: NodeId| {
            d.g.as_const(x)
                .is_some_and(|v| v.comps().iter().all(|c| *c == 1.0))
        };
        match (op, args) {
            (Op::Mul, [x, y]) if zero(self, *x) || zero(self, *y) => {
                let n = self.g.op(op, args);
                let ty = self.g.ty(n);
                return self.zero(ty);
            }
            (Op::Mul, [x, y]) if one(self, *x) && self.g.ty(*x) == Ty::F32 => {
                return *y;
            }
            (Op::Mul, [x, y]) | (Op::Add, [x, y]) | (Op::Add, [y, x])
                if (op == Op::Add && zero(self, *y))
                    || (op == Op::Mul && one(self, *y) && self.g.ty(*y) == Ty::F32) =>
            {
                let n = self.g.op(op, args);
                let ty = self.g.ty(n);
                return self.g.splat(*x, ty);
            }
            (Op::Sub, [x, y]) if zero(self, *y) => {
                let n = self.g.op(op, args);
                let ty = self.g.ty(n);
                return self.g.splat(*x, ty);
            }
            (Op::Div, [x, _]) if zero(self, *x) => {
                let n = self.g.op(op, args);
                let ty = self.g.ty(n);
                return self.zero(ty);
            }
            (Op::Builtin(crate::ops::Builtin::Dot), [x, y]) => {
                for (v, e) in [(*x, *y), (*y, *x)] {
                    if let Some(crate::value::Value::V3(c)) = self.g.as_const(e) {
                        if let Some(k) = (0..3)
                            .find(|&k| c[k] == 1.0 && c.iter().filter(|v| **v == 0.0).count() == 2)
                        {
                            let n = *self.g.node(v);
                            if n.op == Op::MakeVec {
                                return n.args()[k];
                            }
                            return self
                                .g
                                .op(Op::Swizzle(crate::ops::Swizzle::new(&[k as u8])), &[v]);
                        }
                    }
                }
            }
            _ => {}
        }
        crate::passes::fold::add_folded(&mut self.g, op, args, Default::default())
    }

    pub(crate) fn bop(&mut self, b: crate::ops::Builtin, args: &[NodeId]) -> NodeId {
        self.op(Op::Builtin(b), args)
    }

    /// Whether a node is a constant zero (of any width).
    pub(crate) fn is_zero(&self, x: NodeId) -> bool {
        self.g
            .as_const(x)
            .is_some_and(|v| v.ty() != Ty::Bool && v.comps().iter().all(|c| *c == 0.0))
    }

    /// A call of group `func`'s gradient function: its distance, with the tangents
    /// `grad . tq_k` where the group's point has tangents `tq`.
    fn call(&mut self, func: u32, q: NodeId) -> NodeId {
        let gf = self.base + func;
        let call = |g: &mut Graph, result: u8, ty: Ty| {
            g.add_typed(Op::Call { func: gf, result }, &[q], ty, Default::default())
        };
        let value = call(&mut self.g, 0, Ty::F32);
        let comps: Vec<NodeId> = (1..4).map(|r| call(&mut self.g, r, Ty::F32)).collect();
        let grad = self.g.op(Op::MakeVec, &comps);
        let tq = self.tangent(q);
        // (`op` reads `dot(grad, e_k)` as component k, so a group called at p itself costs
        // only the component asked for.)
        let t = tq.map(|t| t.map(|t| self.bop(crate::ops::Builtin::Dot, &[grad, t])));
        self.tangents.insert(value, t);
        value
    }
}
