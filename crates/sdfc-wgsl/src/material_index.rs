//! Material choice carried as an index: where a function picks its albedo and phong vectors
//! out of constant materials by one tree of conditions (a hard union of shapes with
//! materials), the WGSL selects one `u32` per condition instead of two vectors, and looks
//! the index's albedo and phong up once at the end. Same values, a third of the material
//! text: the 5 000-shape scene's WGSL shrinks by a third and naga parses it that much faster.

use sdfc_ir::func::{Func, FuncKind};
use sdfc_ir::graph::{Graph, NodeId};
use sdfc_ir::ops::Op;
use sdfc_ir::types::Ty;
use sdfc_ir::value::Value;
use std::collections::HashMap;

/// A material: the bits of its albedo and phong vectors.
pub type Material = ([u32; 4], [u32; 4]);

/// Below this many conditions a function keeps its vector selects: a small scene's WGSL
/// reads more plainly with them, and there is little text to save.
pub const MIN_CONDITIONS: usize = 8;

/// One index expression.
#[derive(Clone, Debug, PartialEq)]
pub enum Index {
    /// A constant material.
    Leaf(Material),
    /// `select(if_false, if_true, cond)` over two earlier index expressions; it can be
    /// emitted once the node `ready` (the last node it replaces) has been.
    Select {
        if_false: usize,
        if_true: usize,
        cond: NodeId,
        ready: NodeId,
    },
}

/// How a function's material is emitted as an index.
#[derive(Debug)]
pub struct Plan {
    /// Index expressions, each after those it reads; the last is the material.
    pub exprs: Vec<Index>,
    /// Per graph node: a vector select the index replaces (not emitted).
    pub replaced: Vec<bool>,
    /// Per graph node: a condition read by one index select only, spelled inline there.
    pub inline: Vec<bool>,
    /// The distinct materials picked, in first-use order: index `i` is `locals[i]`.
    pub locals: Vec<Material>,
}

impl Plan {
    /// The index of a material among [`Plan::locals`] (0 for one it does not pick).
    pub fn local(&self, m: &Material) -> usize {
        self.locals.iter().position(|l| l == m).unwrap_or(0)
    }
}

/// The plan for `f`'s material, where it is a tree of at least [`MIN_CONDITIONS`]
/// conditions over constant materials whose vector selects nothing else reads.
pub fn plan(f: &Func) -> Option<Plan> {
    let (albedo, phong) = match f.kind {
        FuncKind::Group => (*f.results.get(1)?, *f.results.get(2)?),
        FuncKind::Material => (*f.results.first()?, *f.results.get(1)?),
        _ => return None,
    };
    let g = &f.graph;
    // Enough for a chain whose two vectors change together (one index select per condition)
    // and for some duplication where they do not; past it the tree is not worth indexing.
    let selects = g.nodes().filter(|(_, n)| n.op == Op::Select).count();
    let mut b = Builder {
        g,
        memo: HashMap::new(),
        exprs: Vec::new(),
        replaced: vec![false; g.len()],
        budget: 2 * selects + 16,
    };
    b.resolve(albedo, phong)?;
    let conditions = b
        .exprs
        .iter()
        .filter(|e| matches!(e, Index::Select { .. }))
        .count();
    let mut locals: Vec<Material> = Vec::new();
    for e in &b.exprs {
        if let Index::Leaf(m) = e {
            if !locals.contains(m) {
                locals.push(*m);
            }
        }
    }
    // The lookup at the end costs two selects per material after the first: the index
    // must save more than that.
    if conditions < MIN_CONDITIONS || 2 * locals.len().saturating_sub(1) >= conditions {
        return None;
    }
    // Every replaced select must be read only by other replaced selects (or be a root).
    let mut outside_uses = vec![0u32; g.len()];
    for (id, n) in g.nodes() {
        if b.replaced[id.index()] {
            continue;
        }
        for a in n.args() {
            if b.replaced[a.index()] {
                return None;
            }
            outside_uses[a.index()] += 1;
        }
    }
    for r in &f.results {
        if b.replaced[r.index()] && *r != albedo && *r != phong {
            return None;
        }
        outside_uses[r.index()] += 1;
    }
    let mut index_uses = vec![0u32; g.len()];
    for e in &b.exprs {
        if let Index::Select { cond, .. } = e {
            index_uses[cond.index()] += 1;
        }
    }
    let inline = (0..g.len())
        .map(|i| index_uses[i] == 1 && outside_uses[i] == 0)
        .collect();
    Some(Plan {
        exprs: b.exprs,
        replaced: b.replaced,
        inline,
        locals,
    })
}

struct Builder<'a> {
    g: &'a Graph,
    memo: HashMap<(NodeId, NodeId), usize>,
    exprs: Vec<Index>,
    replaced: Vec<bool>,
    budget: usize,
}

/// What a pair of (albedo, phong) nodes is.
enum Shape {
    Leaf(Material),
    /// `cond ? pair(if_true) : pair(if_false)`, replacing the `ready` select(s).
    Split {
        cond: NodeId,
        if_false: (NodeId, NodeId),
        if_true: (NodeId, NodeId),
        replaces: [Option<NodeId>; 2],
    },
}

impl Builder<'_> {
    fn v4(&self, id: NodeId) -> Option<[u32; 4]> {
        match self.g.as_const(id)? {
            Value::V4(v) => Some(v.map(f32::to_bits)),
            _ => None,
        }
    }

    /// `[if_false, if_true, cond]` of a select on one boolean.
    fn select(&self, id: NodeId) -> Option<[NodeId; 3]> {
        let n = self.g.node(id);
        match (n.op, n.args()) {
            (Op::Select, &[f, t, c]) if self.g.ty(c) == Ty::Bool => Some([f, t, c]),
            _ => None,
        }
    }

    fn shape(&self, a: NodeId, p: NodeId) -> Option<Shape> {
        if let (Some(ka), Some(kp)) = (self.v4(a), self.v4(p)) {
            return Some(Shape::Leaf((ka, kp)));
        }
        let (sa, sp) = (self.select(a), self.select(p));
        // Split on the later select where both are selects on different conditions (the
        // outer choice of a chain); on a constant's partner where only one is a select.
        let split_albedo = match (sa, sp) {
            (Some([af, at, ca]), Some([pf, pt, cp])) if ca == cp => {
                return Some(Shape::Split {
                    cond: ca,
                    if_false: (af, pf),
                    if_true: (at, pt),
                    replaces: [Some(a), Some(p)],
                });
            }
            (Some(_), Some(_)) => a > p,
            (Some(_), None) => {
                self.v4(p)?;
                true
            }
            (None, Some(_)) => {
                self.v4(a)?;
                false
            }
            (None, None) => return None,
        };
        Some(if split_albedo {
            let [f, t, c] = sa?;
            Shape::Split {
                cond: c,
                if_false: (f, p),
                if_true: (t, p),
                replaces: [Some(a), None],
            }
        } else {
            let [f, t, c] = sp?;
            Shape::Split {
                cond: c,
                if_false: (a, f),
                if_true: (a, t),
                replaces: [None, Some(p)],
            }
        })
    }

    /// The index expression of the pair, children first; an explicit stack, as chains
    /// can be thousands long.
    fn resolve(&mut self, a: NodeId, p: NodeId) -> Option<usize> {
        let mut stack = vec![(a, p, false)];
        while let Some((a, p, expanded)) = stack.pop() {
            if self.memo.contains_key(&(a, p)) {
                continue;
            }
            self.budget = self.budget.checked_sub(1)?;
            match self.shape(a, p)? {
                Shape::Leaf(m) => {
                    self.memo.insert((a, p), self.exprs.len());
                    self.exprs.push(Index::Leaf(m));
                }
                Shape::Split {
                    cond,
                    if_false,
                    if_true,
                    replaces,
                } => {
                    if !expanded {
                        stack.push((a, p, true));
                        stack.push((if_true.0, if_true.1, false));
                        stack.push((if_false.0, if_false.1, false));
                        continue;
                    }
                    let (Some(&f), Some(&t)) = (self.memo.get(&if_false), self.memo.get(&if_true))
                    else {
                        return None;
                    };
                    let mut ready = cond;
                    for r in replaces.into_iter().flatten() {
                        self.replaced[r.index()] = true;
                        ready = ready.max(r);
                    }
                    self.memo.insert((a, p), self.exprs.len());
                    self.exprs.push(Index::Select {
                        if_false: f,
                        if_true: t,
                        cond,
                        ready,
                    });
                }
            }
        }
        self.memo.get(&(a, p)).copied()
    }
}
