//! Optimisation passes. Scalar passes rewrite a function by walking its nodes in order and
//! re-adding each one to a fresh hash-consed graph (see [`rebuild`]); the shape pass
//! ([`merge`]) rewrites the shape tree.

pub mod cse;
pub mod dce;
pub mod fold;
pub mod merge;
pub mod simplify;

use crate::func::Func;
use crate::graph::{Graph, Node, NodeId};
use crate::ops::Op;

/// Rewrites `g` node by node in index order (a topological order). `f` receives the new
/// graph, the old node, and its arguments already mapped into the new graph, and returns
/// the node that replaces it. With `keep_dead` false, nodes no root depends on are skipped.
pub fn rebuild(
    g: &Graph,
    roots: &[NodeId],
    keep_dead: bool,
    mut f: impl FnMut(&mut Graph, NodeId, &Node, &[NodeId]) -> NodeId,
) -> (Graph, Vec<NodeId>) {
    let live = if keep_dead {
        vec![true; g.len()]
    } else {
        let mut live = vec![false; g.len()];
        for r in roots {
            live[r.index()] = true;
        }
        for i in (0..g.len()).rev() {
            if live[i] {
                for a in g.node(NodeId(i as u32)).args() {
                    live[a.index()] = true;
                }
            }
        }
        live
    };
    let mut out = Graph::with_capacity(g.len());
    let mut map = vec![NodeId(0); g.len()];
    let mut args = Vec::with_capacity(4);
    for (id, node) in g.nodes() {
        if !live[id.index()] {
            continue;
        }
        args.clear();
        args.extend(node.args().iter().map(|a| map[a.index()]));
        let new = f(&mut out, id, node, &args);
        // Keep the more specific name hint of the two.
        if out.hint(new) == crate::graph::default_hint(out.ty(new)) {
            out.set_hint(new, g.hint(id));
        }
        map[id.index()] = new;
    }
    out.ill_typed = g.ill_typed.clone();
    let roots = roots.iter().map(|r| map[r.index()]).collect();
    (out, roots)
}

/// Re-adds a node unchanged (inputs keep their declared type).
pub fn copy(out: &mut Graph, old: &Graph, id: NodeId, node: &Node, args: &[NodeId]) -> NodeId {
    match node.op {
        Op::Param(_) | Op::LambdaArg { .. } | Op::Call { .. } => {
            out.add_typed(node.op, args, node.ty, old.span(id))
        }
        op => out.add(op, args, old.span(id)),
    }
}

/// The scalar pipeline: one rewriting walk in which each node is folded (fold.rs) or else
/// simplified (simplify.rs) as it is re-added to a hash-consed graph, which merges equal
/// nodes (cse.rs); then dead code elimination (dce.rs). Simplification only builds nodes from
/// already-rewritten arguments, so one walk reaches the fixed point of both rule sets for
/// everything but rules that enable each other through several nodes, which none do.
/// Returns the optimised function and the spans of constants that folded to a non-finite value.
pub fn optimise(f: &Func) -> (Func, Vec<(sdfc_syntax::span::Span, String)>) {
    let mut errors: Vec<(sdfc_syntax::span::Span, String)> = Vec::new();
    let (graph, results) = rebuild(&f.graph, &f.results, true, |out, id, node, args| {
        match fold::fold_one(out, node.op, node.ty, args) {
            Some(v) if v.all_finite() => return out.konst(v),
            Some(_) => {
                let span = f.graph.span(id);
                if !errors.iter().any(|(s, _)| *s == span) {
                    errors.push((span, fold::NON_FINITE.to_string()));
                }
            }
            None => {}
        }
        if let Some(n) = simplify::simplify(out, node.op, args) {
            // A rule may expose a constant (e.g. a select on a now-constant condition).
            return n;
        }
        copy(out, &f.graph, id, node, args)
    });
    let folded = Func {
        name: f.name.clone(),
        kind: f.kind,
        graph,
        results,
    };
    (dce::run(&folded), errors)
}
