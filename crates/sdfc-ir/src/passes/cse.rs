//! Common subexpression elimination: re-adding every node to a fresh hash-consed graph merges
//! the nodes that folding and simplification made identical.

use super::{copy, rebuild};
use crate::func::Func;

pub fn run(f: &Func) -> Func {
    let (graph, results) = rebuild(&f.graph, &f.results, true, |out, id, node, args| {
        copy(out, &f.graph, id, node, args)
    });
    Func {
        name: f.name.clone(),
        kind: f.kind,
        graph,
        results,
    }
}
