//! Shape-level simplification: transform chains merged into one affine map
//! (translate∘translate, rotate∘rotate, scales), identity transforms removed, smooth
//! operators with `k = 0` made hard, nested plain unions and intersections flattened.

use super::fold::{add_folded, const_value};
use crate::graph::{Graph, NodeId};
use crate::hash::FxHashMap;
use crate::ops::Op;
use crate::scene::Scene;
use crate::shape::{CombineOp, PointMap, ShapeId, ShapeKind, ShapeNode};
use crate::value::Value;

pub fn run(scene: &Scene) -> Scene {
    let mut m = Merger {
        old: scene,
        g: scene.values.clone(),
        shapes: Vec::new(),
        map: FxHashMap::default(),
        memo: FxHashMap::default(),
    };
    let root = m.shape(scene.root);
    Scene {
        values: m.g,
        shapes: m.shapes,
        root,
        materials: scene.materials.clone(),
        params: scene.params.clone(),
        lights: scene.lights.clone(),
        camera: scene.camera.clone(),
        render: scene.render.clone(),
    }
}

struct Merger<'s> {
    old: &'s Scene,
    g: Graph,
    shapes: Vec<ShapeNode>,
    map: FxHashMap<ShapeId, ShapeId>,
    memo: FxHashMap<NodeId, Option<Value<f32>>>,
}

/// `(m, o, s)` of an affine map `local = (m p + o) / s`.
type Affine = (Option<NodeId>, Option<NodeId>, Option<NodeId>);

impl Merger<'_> {
    fn konst(&mut self, n: NodeId) -> Option<Value<f32>> {
        const_value(&self.g, n, &mut self.memo)
    }

    fn is_const(&mut self, n: Option<NodeId>, pred: impl Fn(&Value<f32>) -> bool) -> bool {
        match n {
            Some(n) => self.konst(n).is_some_and(|v| pred(&v)),
            None => false,
        }
    }

    fn push(&mut self, kind: ShapeKind, span: sdfc_syntax::span::Span) -> ShapeId {
        self.shapes.push(ShapeNode { kind, span });
        ShapeId(self.shapes.len() as u32 - 1)
    }

    fn shape(&mut self, id: ShapeId) -> ShapeId {
        if let Some(n) = self.map.get(&id) {
            return *n;
        }
        let node = self.old.shape(id).clone();
        let out = match node.kind {
            ShapeKind::Map {
                map: PointMap::Affine { m, o, s },
                child,
            } => {
                let mut aff: Affine = (m, o, s);
                let mut inner = child;
                // Fold the chain below into this one map (inner maps apply after outer ones).
                while let ShapeKind::Map {
                    map: PointMap::Affine { m, o, s },
                    child,
                } = &self.old.shape(inner).kind
                {
                    aff = self.compose((*m, *o, *s), aff, node.span);
                    inner = *child;
                }
                let aff = self.drop_identities(aff);
                let child = self.shape(inner);
                match aff {
                    (None, None, None) => child,
                    (m, o, s) => self.push(
                        ShapeKind::Map {
                            map: PointMap::Affine { m, o, s },
                            child,
                        },
                        node.span,
                    ),
                }
            }
            ShapeKind::Combine {
                op,
                smooth,
                children,
            } => {
                let smooth = smooth.filter(|k| !self.is_const(Some(*k), |v| *v == Value::F(0.0)));
                let mut kids = Vec::new();
                for c in children {
                    let c = self.shape(c);
                    // union(union(a, b), c) is union(a, b, c) when neither is smooth.
                    let flatten =
                        smooth.is_none() && matches!(op, CombineOp::Union | CombineOp::Intersect);
                    match &self.shapes[c.index()].kind {
                        ShapeKind::Combine {
                            op: o2,
                            smooth: None,
                            children: inner,
                        } if flatten && *o2 == op => kids.extend(inner.iter().copied()),
                        _ => kids.push(c),
                    }
                }
                if kids.len() == 1 && matches!(op, CombineOp::Union | CombineOp::Intersect) {
                    kids[0]
                } else {
                    self.push(
                        ShapeKind::Combine {
                            op,
                            smooth,
                            children: kids,
                        },
                        node.span,
                    )
                }
            }
            ShapeKind::Map { map, child } => {
                let child = self.shape(child);
                self.push(ShapeKind::Map { map, child }, node.span)
            }
            ShapeKind::Displace {
                child,
                body,
                lambda,
                lipschitz,
            } => {
                let child = self.shape(child);
                self.push(
                    ShapeKind::Displace {
                        child,
                        body,
                        lambda,
                        lipschitz,
                    },
                    node.span,
                )
            }
            ShapeKind::Modify { modifier, child } => {
                let child = self.shape(child);
                self.push(ShapeKind::Modify { modifier, child }, node.span)
            }
            ShapeKind::Warp {
                map,
                child,
                lipschitz,
            } => {
                let child = self.shape(child);
                self.push(
                    ShapeKind::Warp {
                        map,
                        child,
                        lipschitz,
                    },
                    node.span,
                )
            }
            ShapeKind::Material { material, child } => {
                let child = self.shape(child);
                self.push(ShapeKind::Material { material, child }, node.span)
            }
            kind @ (ShapeKind::Prim { .. }
            | ShapeKind::Sdf { .. }
            | ShapeKind::Heightfield { .. }) => self.push(kind, node.span),
        };
        self.map.insert(id, out);
        out
    }

    /// The map that applies `outer` first, then `inner`:
    /// `(m1 ((m2 p + o2) / s2) + o1) / s1 = (m1 m2 p + m1 o2 + s2 o1) / (s1 s2)`.
    fn compose(&mut self, inner: Affine, outer: Affine, span: sdfc_syntax::span::Span) -> Affine {
        let (m1, o1, s1) = inner;
        let (m2, o2, s2) = outer;
        let m = match (m1, m2) {
            (Some(a), Some(b)) => Some(add_folded(&mut self.g, Op::MatMul, &[a, b], span)),
            (a, b) => a.or(b),
        };
        let o2m = match (m1, o2) {
            (Some(a), Some(b)) => Some(add_folded(&mut self.g, Op::MatMul, &[a, b], span)),
            (_, b) => b,
        };
        let o1s = match (s2, o1) {
            (Some(s), Some(o)) => Some(add_folded(&mut self.g, Op::Mul, &[o, s], span)),
            (_, o) => o,
        };
        let o = match (o2m, o1s) {
            (Some(a), Some(b)) => Some(add_folded(&mut self.g, Op::Add, &[a, b], span)),
            (a, b) => a.or(b),
        };
        let s = match (s1, s2) {
            (Some(a), Some(b)) => Some(add_folded(&mut self.g, Op::Mul, &[a, b], span)),
            (a, b) => a.or(b),
        };
        (m, o, s)
    }

    fn drop_identities(&mut self, (m, o, s): Affine) -> Affine {
        let ident = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let m = m.filter(|m| !self.is_const(Some(*m), |v| *v == Value::M3(ident)));
        let o = o.filter(|o| !self.is_const(Some(*o), |v| v.comps().iter().all(|c| *c == 0.0)));
        let s = s.filter(|s| !self.is_const(Some(*s), |v| *v == Value::F(1.0)));
        (m, o, s)
    }
}
