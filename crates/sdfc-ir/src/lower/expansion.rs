//! The expansion limit: how many shape instances a scene becomes once its shape DAG is
//! unfolded into a tree. A `let` shape used twice is one node in the DAG but is evaluated (and
//! emitted) once per use, so `let s1 = s0 | s0.translate(..)` doubling on each line grows
//! exponentially while the DAG stays tiny. Without this check such a 2 kB file exhausted
//! memory in the SSA lowering.

use crate::scene::limits::MAX_SHAPE_INSTANCES;
use crate::shape::{ShapeId, ShapeKind, ShapeNode};
use sdfc_syntax::diag::Diagnostic;
use sdfc_syntax::span::Span;

/// For every shape node, the number of shape nodes of its unfolded tree, saturating at
/// `u64::MAX`.
pub fn instance_counts(shapes: &[ShapeNode]) -> Vec<u64> {
    let mut count = vec![0u64; shapes.len()];
    for i in post_order(shapes) {
        let below = children(&shapes[i].kind).iter().fold(0u64, |acc, c| {
            acc.saturating_add(count.get(c.index()).copied().unwrap_or(1))
        });
        count[i] = below.saturating_add(1);
    }
    count
}

/// Every shape index once, each after its children. Iterative (an explicit stack), so deep
/// scenes cannot overflow the stack, and independent of the order of `shapes`.
pub fn post_order(shapes: &[ShapeNode]) -> Vec<usize> {
    let mut done = vec![false; shapes.len()];
    let mut order = Vec::with_capacity(shapes.len());
    for start in 0..shapes.len() {
        let mut stack = vec![start];
        while let Some(&i) = stack.last() {
            if done[i] {
                stack.pop();
                continue;
            }
            let pending: Vec<usize> = children(&shapes[i].kind)
                .iter()
                .map(|c| c.index())
                .filter(|&c| c < shapes.len() && !done[c])
                .collect();
            if pending.is_empty() {
                done[i] = true;
                order.push(i);
                stack.pop();
            } else {
                stack.extend(pending);
            }
        }
    }
    order
}

/// The direct children of a shape node.
pub fn children(kind: &ShapeKind) -> &[ShapeId] {
    match kind {
        ShapeKind::Prim { .. } | ShapeKind::Sdf { .. } | ShapeKind::Heightfield { .. } => &[],
        ShapeKind::Displace { child, .. }
        | ShapeKind::Warp { child, .. }
        | ShapeKind::Map { child, .. }
        | ShapeKind::Modify { child, .. }
        | ShapeKind::Material { child, .. } => std::slice::from_ref(child),
        ShapeKind::Combine { children, .. } => children,
    }
}

/// An error at the `scene` item when the unfolded scene is larger than the documented limit.
pub fn check(shapes: &[ShapeNode], root: ShapeId, scene_span: Span) -> Option<Diagnostic> {
    let n = instance_counts(shapes)
        .get(root.index())
        .copied()
        .unwrap_or(0);
    (n > MAX_SHAPE_INSTANCES).then(|| {
        let size = if n == u64::MAX {
            "more than 10^19".to_string()
        } else {
            n.to_string()
        };
        Diagnostic::error(
            scene_span,
            format!(
                "the scene unfolds into {size} shapes, more than the limit of \
                 {MAX_SHAPE_INSTANCES}"
            ),
        )
        .with_label("this scene")
        .with_hint(
            "a shape bound with `let` is copied at each use, so a `let` that uses the previous \
             one twice doubles the scene on every line; for regular copies use `repeat`, which \
             costs one shape",
        )
    })
}
