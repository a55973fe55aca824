//! Common subexpression elimination, and the rewriting walk every scalar pass uses: re-adding
//! each node to a fresh hash-consed graph merges nodes that are (or have become) identical.

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
        live(g, roots)
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

/// Per node: whether any of `roots` depends on it.
pub fn live(g: &Graph, roots: &[NodeId]) -> Vec<bool> {
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
