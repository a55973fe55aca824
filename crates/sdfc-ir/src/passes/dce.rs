//! Dead code elimination: keeps only the nodes the function's results depend on.

use super::cse::live;
use crate::func::Func;
use crate::graph::{Args, Graph, Node, NodeId};

pub fn run(f: &Func) -> Func {
    let g = &f.graph;
    let live = live(g, &f.results);
    // The live nodes, in order, with their arguments renamed: distinct nodes stay distinct,
    // so they are appended without the hash-consing lookup.
    let mut graph = Graph::with_capacity_untabled(live.iter().filter(|l| **l).count());
    let mut map = vec![NodeId(0); g.len()];
    let mut args = Vec::with_capacity(4);
    for (id, node) in g.nodes() {
        if !live[id.index()] {
            continue;
        }
        args.clear();
        args.extend(node.args().iter().map(|a| map[a.index()]));
        let copy = Node {
            op: node.op,
            args: Args::new(&args),
            ty: node.ty,
        };
        map[id.index()] = graph.push_copy(copy, g.span(id), g.hint(id));
    }
    graph.ill_typed = g.ill_typed.clone();
    Func {
        name: f.name.clone(),
        kind: f.kind,
        graph,
        results: f.results.iter().map(|r| map[r.index()]).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::func::FuncKind;
    use crate::ops::{Builtin, Op};

    #[test]
    fn keeps_live_nodes_and_hash_conses_after() {
        let mut g = Graph::new();
        let p = g.op(Op::Point, &[]);
        g.builtin(Builtin::Abs, &[p]);
        let len = g.builtin(Builtin::Length, &[p]);
        let one = g.f32(1.0);
        let d = g.op(Op::Sub, &[len, one]);
        g.set_hint(d, "d");
        let f = Func {
            name: "f".into(),
            kind: FuncKind::Distance,
            graph: g,
            results: vec![d],
        };
        let mut out = run(&f);
        assert_eq!(out.graph.len(), 4, "the dead abs is gone");
        assert!(!out
            .graph
            .nodes()
            .any(|(_, n)| n.op == Op::Builtin(Builtin::Abs)));
        let r = out.results[0];
        assert_eq!(out.graph.hint(r), "d");
        // A later add of an existing node finds it (the table is filled on demand); a new
        // one is appended.
        let p2 = out.graph.op(Op::Point, &[]);
        let len2 = out.graph.builtin(Builtin::Length, &[p2]);
        let one2 = out.graph.f32(1.0);
        assert_eq!(out.graph.op(Op::Sub, &[len2, one2]), r);
        assert_eq!(out.graph.len(), 4);
        out.graph.builtin(Builtin::Abs, &[p2]);
        assert_eq!(out.graph.len(), 5);
    }
}
