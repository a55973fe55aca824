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
/// `u64::MAX`. Iterative (a post-order walk with an explicit stack), so deep scenes cannot
/// overflow the stack, and it does not rely on the order of `shapes`.
pub fn instance_counts(shapes: &[ShapeNode]) -> Vec<u64> {
    const UNKNOWN: u64 = 0;
    let mut count = vec![UNKNOWN; shapes.len()];
    for start in 0..shapes.len() {
        let mut stack = vec![start];
        while let Some(&i) = stack.last() {
            if count[i] != UNKNOWN {
                stack.pop();
                continue;
            }
            let children = children(&shapes[i].kind);
            let pending: Vec<usize> = children
                .iter()
                .map(|c| c.index())
                .filter(|&c| c < shapes.len() && count[c] == UNKNOWN)
                .collect();
            if pending.is_empty() {
                let below = children.iter().fold(0u64, |acc, c| {
                    acc.saturating_add(count.get(c.index()).copied().unwrap_or(1))
                });
                count[i] = below.saturating_add(1);
                stack.pop();
            } else {
                stack.extend(pending);
            }
        }
    }
    count
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
