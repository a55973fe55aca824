//! Constant folding with f32 semantics: a node whose arguments are all constants becomes the
//! constant the GPU would compute (`+ - * /` and `sqrt` are IEEE f32, correctly rounded; the
//! transcendental functions are computed in f64 and rounded once, at least as accurate as any
//! GPU). A result that is not finite is an error at the node's span.

use crate::eval;
use crate::graph::{Graph, NodeId};
use crate::hash::FxHashMap;
use crate::ops::Op;
use crate::value::{Float, Value};
use sdfc_syntax::span::Span;

/// The message for a constant that folds to infinity or NaN.
pub const NON_FINITE: &str = "this constant expression is not finite (infinity or NaN)";

/// The folded value of `op` on `args` if every argument is a constant and `op` is pure.
pub fn fold_one(g: &Graph, op: Op, ty: crate::types::Ty, args: &[NodeId]) -> Option<Value<f32>> {
    if matches!(op, Op::Const(_)) || op.is_input() {
        return None;
    }
    let vals: Option<Vec<Value<f32>>> = args.iter().map(|a| g.as_const(*a)).collect();
    Some(eval::apply(op, ty, &vals?))
}

/// Adds a node, folding it at once when its arguments are constants (used by passes that
/// build new arithmetic, such as transform merging).
pub fn add_folded(g: &mut Graph, op: Op, args: &[NodeId], span: Span) -> NodeId {
    let n = g.add(op, args, span);
    let node = *g.node(n);
    match fold_one(g, node.op, node.ty, node.args()) {
        Some(v) if v.all_finite() => g.konst(v),
        _ => n,
    }
}

/// The value of a node that depends on constants only, memoised (in f32, as folding
/// computes it).
pub fn const_value(
    g: &Graph,
    id: NodeId,
    memo: &mut FxHashMap<NodeId, Option<Value<f32>>>,
) -> Option<Value<f32>> {
    const_value_in(g, id, memo)
}

/// [`const_value`] computed in `T`: in f64, from the f32 constants the source's numbers
/// became, a value is not rounded at each step (camera-relative offsets near 1e5, where an
/// f32 step is 0.008).
pub fn const_value_in<T: Float>(
    g: &Graph,
    id: NodeId,
    memo: &mut FxHashMap<NodeId, Option<Value<T>>>,
) -> Option<Value<T>> {
    if let Some(v) = memo.get(&id) {
        return *v;
    }
    let node = *g.node(id);
    let out = match node.op {
        Op::Const(c) => Some(c.to_value().cast()),
        op if op.is_input() => None,
        op => {
            let mut args = Vec::new();
            let mut all = true;
            for a in node.args() {
                match const_value_in(g, *a, memo) {
                    Some(v) => args.push(v),
                    None => {
                        all = false;
                        break;
                    }
                }
            }
            all.then(|| eval::apply(op, node.ty, &args))
        }
    };
    memo.insert(id, out);
    out
}
