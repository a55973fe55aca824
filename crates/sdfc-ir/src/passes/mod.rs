//! Optimisation passes. The scalar passes rewrite a function in one walk over its nodes that
//! re-adds each to a fresh hash-consed graph ([`cse::rebuild`]), folding ([`fold`]) or
//! simplifying ([`simplify`]) it on the way; then [`dce`] drops what no result needs. The
//! shape pass ([`merge`]) rewrites the shape tree.

pub mod cse;
pub mod dce;
pub mod fold;
pub mod merge;
pub mod relative;
pub mod simplify;

use crate::func::Func;
use cse::{copy, rebuild};

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
