//! The order the encoder emits a function's nodes in: whichever of depth first from the
//! results, the graph's own order and call by call keeps the fewest values live.

use sdfc_ir::graph::{Graph, NodeId};
use sdfc_ir::ops::Op;
use std::collections::BTreeMap;

/// The order to encode a graph's needed nodes in: depth first from the results
/// ([`demand_order`]), or the graph's own order, whichever keeps fewer values live at once.
/// The graph's order wins for a union's material: it was built child by child (distance,
/// running minimum, nearer-material selects), while depth first from the results finishes
/// the distance chain before the selects start and keeps every child's distance live between
/// (the 300-shape grid needed 81 registers so).
pub(super) fn schedule(g: &Graph, results: &[NodeId]) -> Vec<NodeId> {
    let demand = demand_order(g, results);
    let mut needed = vec![false; g.len()];
    for id in &demand {
        needed[id.index()] = true;
    }
    let own: Vec<NodeId> = (0..g.len() as u32)
        .map(NodeId)
        .filter(|id| needed[id.index()])
        .collect();
    let by_call = call_by_call(g, &own);
    [own, by_call].into_iter().fold(demand, |best, order| {
        if max_live(g, &order, results) < max_live(g, &best, results) {
            order
        } else {
            best
        }
    })
}

/// The graph's own order regrouped call by call: each node goes with the last group call
/// (by first appearance) it depends on, so a union's distance, material selects and blends
/// for one child are computed right after that child's call. In the graph's own order every
/// call comes first and their results wait for the select chains, and depth first from the
/// results finishes the albedo chain before the phong chain starts, leaving every child's
/// comparison live: a 1 000-shape grid needed more than 64 registers either way.
fn call_by_call(g: &Graph, own: &[NodeId]) -> Vec<NodeId> {
    let mut calls: BTreeMap<(u32, NodeId), usize> = BTreeMap::new();
    let mut key = vec![0usize; g.len()];
    for (id, node) in g.nodes() {
        key[id.index()] = match node.op {
            Op::Call { func, .. } => {
                let next = calls.len() + 1;
                let point = node.args().first().copied().unwrap_or(NodeId(0));
                *calls.entry((func, point)).or_insert(next)
            }
            _ => node
                .args()
                .iter()
                .map(|a| key[a.index()])
                .max()
                .unwrap_or(0),
        };
    }
    let mut order = own.to_vec();
    // Stable: within one call's nodes the graph's (topological) order stays, and a node's
    // arguments never have a larger key than it.
    order.sort_by_key(|id| key[id.index()]);
    order
}

/// The most values live at once when `order` is encoded (constants count, though they are
/// loaded at use: an estimate to compare orders by).
fn max_live(g: &Graph, order: &[NodeId], results: &[NodeId]) -> usize {
    let mut last = vec![usize::MAX; g.len()];
    for (i, id) in order.iter().enumerate() {
        for a in g.node(*id).args() {
            last[a.index()] = i;
        }
    }
    for r in results {
        last[r.index()] = order.len();
    }
    let mut ends = vec![0usize; order.len() + 1];
    let (mut live, mut most) = (0usize, 0usize);
    for (i, id) in order.iter().enumerate() {
        let l = last[id.index()];
        if l != usize::MAX {
            live += 1;
            ends[l] += 1;
        }
        most = most.max(live);
        live -= ends[i];
    }
    most
}

/// The nodes `results` need, each after its arguments, in the order a depth-first walk from
/// the results first needs them: a value is computed just before its first use, which keeps
/// few registers live (the graph's own order computes, say, every operand of a 300-shape
/// union before the first `min`). As in Sethi-Ullman numbering, the argument that needs the
/// most registers is computed first, so a right-nested `min(a, min(b, ...))` holds one
/// value at a time, not one per level.
fn demand_order(g: &Graph, results: &[NodeId]) -> Vec<NodeId> {
    // Registers each node needs (an estimate: shared arguments are counted on each path).
    let mut need = vec![0u32; g.len()];
    for (id, node) in g.nodes() {
        let mut n: Vec<u32> = node.args().iter().map(|a| need[a.index()]).collect();
        n.sort_unstable_by(|a, b| b.cmp(a));
        need[id.index()] = n
            .iter()
            .enumerate()
            .map(|(i, x)| x + i as u32)
            .max()
            .unwrap_or(0)
            .max(1);
    }
    let ordered_args = |id: NodeId| {
        let mut a: Vec<NodeId> = g.node(id).args().to_vec();
        a.sort_by_key(|x| std::cmp::Reverse(need[x.index()]));
        a
    };
    let mut seen = vec![false; g.len()];
    let mut order = Vec::new();
    let mut stack: Vec<(NodeId, Vec<NodeId>, usize)> = Vec::new();
    for &r in results {
        if seen[r.index()] {
            continue;
        }
        seen[r.index()] = true;
        stack.push((r, ordered_args(r), 0));
        while let Some((id, args, next)) = stack.pop() {
            if let Some(&a) = args.get(next) {
                stack.push((id, args, next + 1));
                if !seen[a.index()] {
                    seen[a.index()] = true;
                    stack.push((a, ordered_args(a), 0));
                }
            } else {
                order.push(id);
            }
        }
    }
    order
}
