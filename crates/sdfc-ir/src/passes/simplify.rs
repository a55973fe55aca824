//! Algebraic simplification with rules that keep every value (compared as IEEE values, so
//! `x + 0 -> x` may turn a `-0` into `+0`, which no distance or colour can observe):
//! `x * 1`, `x / 1`, `x + 0`, `x - 0`, `-(-x)`, `x + -y`, `x - (-c)`, `min(x, x)`, `select(a, a, c)`,
//! selects on a constant condition, identity swizzles and matrices, and the like.

use crate::graph::{Graph, NodeId};
use crate::ops::{Builtin, Op, Swizzle};
use crate::types::Ty;
use crate::value::Value;

/// Whether every component of constant `n` equals `x`.
fn is_splat(g: &Graph, n: NodeId, x: f32) -> bool {
    match g.as_const(n) {
        Some(Value::B(_)) | None => false,
        Some(v) => v.comps().iter().all(|c| *c == x),
    }
}

fn is_identity(g: &Graph, n: NodeId) -> bool {
    matches!(g.as_const(n), Some(Value::M3(m)) if m == [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
}

/// The simpler node equal to `op(args)`, if a rule applies. A rule may only return a node
/// whose type is the type `op(args)` would have.
pub fn simplify(g: &mut Graph, op: Op, a: &[NodeId]) -> Option<NodeId> {
    match op {
        Op::Add if is_splat(g, a[1], 0.0) && g.ty(a[0]).width() >= g.ty(a[1]).width() => Some(a[0]),
        Op::Add if is_splat(g, a[0], 0.0) && g.ty(a[1]).width() >= g.ty(a[0]).width() => Some(a[1]),
        Op::Sub if is_splat(g, a[1], 0.0) && g.ty(a[0]).width() >= g.ty(a[1]).width() => Some(a[0]),
        Op::Mul
            if is_splat(g, a[1], 1.0)
                && g.ty(a[0]).width() >= g.ty(a[1]).width()
                && g.ty(a[0]) != Ty::Mat3 =>
        {
            Some(a[0])
        }
        Op::Mul
            if is_splat(g, a[0], 1.0)
                && g.ty(a[1]).width() >= g.ty(a[0]).width()
                && g.ty(a[0]) != Ty::Mat3 =>
        {
            Some(a[1])
        }
        Op::Mul
            if is_splat(g, a[1], -1.0)
                && g.ty(a[0]).width() >= g.ty(a[1]).width()
                && g.ty(a[0]) != Ty::Mat3 =>
        {
            Some(g.op(Op::Neg, &[a[0]]))
        }
        Op::Div if is_splat(g, a[1], 1.0) && g.ty(a[0]).width() >= g.ty(a[1]).width() => Some(a[0]),
        Op::Neg if g.node(a[0]).op == Op::Neg => Some(g.node(a[0]).args()[0]),
        // x + (-y) == x - y and x - (-y) == x + y exactly in IEEE arithmetic.
        Op::Add if g.node(a[1]).op == Op::Neg => {
            let y = g.node(a[1]).args()[0];
            Some(g.op(Op::Sub, &[a[0], y]))
        }
        Op::Sub if g.node(a[1]).op == Op::Neg => {
            let y = g.node(a[1]).args()[0];
            Some(g.op(Op::Add, &[a[0], y]))
        }
        // x - c == x + (-c) exactly; a scalar constant below zero reads better added.
        Op::Sub if matches!(g.as_const(a[1]), Some(Value::F(c)) if c < 0.0) => {
            let c = match g.as_const(a[1]) {
                Some(Value::F(c)) => -c,
                _ => return None,
            };
            let c = g.f32(c);
            Some(g.op(Op::Add, &[a[0], c]))
        }
        Op::Builtin(Builtin::Min | Builtin::Max) if a[0] == a[1] => Some(a[0]),
        Op::Builtin(Builtin::Abs) if g.node(a[0]).op == Op::Builtin(Builtin::Abs) => Some(a[0]),
        Op::Select if a[0] == a[1] => Some(a[0]),
        Op::Select => match g.as_const(a[2]) {
            Some(Value::B(true)) => Some(a[1]),
            Some(Value::B(false)) => Some(a[0]),
            _ => None,
        },
        Op::MatMul if is_identity(g, a[0]) && g.ty(a[1]) != Ty::Mat3 => Some(a[1]),
        Op::Swizzle(s) => simplify_swizzle(g, s, a[0]),
        Op::MakeVec => {
            // vec3(v.x, v.y, v.z) is v.
            let mut src = None;
            for (i, x) in a.iter().enumerate() {
                let n = g.node(*x);
                match n.op {
                    Op::Swizzle(s) if s.indices() == [i as u8] => {
                        let v = n.args()[0];
                        if src.is_some_and(|s| s != v) {
                            return None;
                        }
                        src = Some(v);
                    }
                    _ => return None,
                }
            }
            src.filter(|v| g.ty(*v).width() == a.len())
        }
        _ => None,
    }
}

fn simplify_swizzle(g: &mut Graph, s: Swizzle, x: NodeId) -> Option<NodeId> {
    let ty = g.ty(x);
    // v.xyz of a vec3 (and v.xy of a vec2) is v.
    if ty != Ty::F32
        && s.len as usize == ty.width()
        && s.indices()
            .iter()
            .enumerate()
            .all(|(i, &k)| i == k as usize)
    {
        return Some(x);
    }
    let node = *g.node(x);
    match node.op {
        // vec3(a, b, c).y is b.
        Op::MakeVec if s.len == 1 => Some(node.args()[s.indices()[0] as usize]),
        // (v.zyx).x is v.z
        Op::Swizzle(inner) if g.ty(node.args()[0]) != Ty::F32 => {
            let idx: Vec<u8> = s
                .indices()
                .iter()
                .map(|&i| inner.indices()[i as usize])
                .collect();
            let src = node.args()[0];
            if idx.len() == g.ty(src).width()
                && idx.iter().enumerate().all(|(i, &k)| i == k as usize)
            {
                return Some(src);
            }
            Some(g.op(Op::Swizzle(Swizzle::new(&idx)), &[src]))
        }
        _ => None,
    }
}
