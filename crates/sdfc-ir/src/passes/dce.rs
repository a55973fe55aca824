//! Dead code elimination: keeps only the nodes the function's results depend on.

use super::cse::{copy, rebuild};
use crate::func::Func;

pub fn run(f: &Func) -> Func {
    let (graph, results) = rebuild(&f.graph, &f.results, false, |out, id, node, args| {
        copy(out, &f.graph, id, node, args)
    });
    Func {
        name: f.name.clone(),
        kind: f.kind,
        graph,
        results,
    }
}
