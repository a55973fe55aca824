//! Camera-relative coordinates: the scene moved so that the camera sits at the origin, for a
//! camera far from it. f32 points near 1e5 are 0.008 apart, so a shader that marches in world
//! coordinates there cannot place a surface better than that; moved, the points it works on
//! are small again. The move is folded into the scene's own affine maps where it can be
//! (their offsets are recomputed in f64 and rounded once, so `translate(s, [1e5, ...])` seen
//! from a camera at 1e5 becomes a small exact offset); below a shape whose point map is not
//! affine (repetition, mirrors, lambdas in world space) it stays a runtime addition.

use super::fold::const_value;
use crate::eval::apply;
use crate::graph::NodeId;
use crate::hash::FxHashMap;
use crate::ops::Op;
use crate::scene::{LightKind, Scene};
use crate::shape::{PointMap, ShapeId, ShapeKind, ShapeNode};
use crate::types::Ty;
use crate::value::Value;

/// Cameras at least this far from the origin (in any coordinate) get camera-relative
/// coordinates; nearer ones keep the world coordinates, so the emitted WGSL keeps the
/// scene's constants as written.
pub const FROM: f32 = 1024.0;

/// Whether a scene's camera is far enough out for camera-relative coordinates.
pub fn wanted(scene: &Scene) -> bool {
    scene.camera.position.iter().any(|c| c.abs() >= FROM)
}

/// The scene seen from `origin`: its root at q is the old root at q + origin; point lights
/// move by -origin; the camera is left as it is (the caller puts it at the origin).
pub fn shift(scene: &Scene, origin: [f32; 3]) -> Scene {
    let mut s = Shifter {
        scene: scene.clone(),
        c: origin.map(|x| x as f64),
        memo: FxHashMap::default(),
        values: FxHashMap::default(),
    };
    let root = s.shift(scene.root);
    let mut out = s.scene;
    out.root = root;
    for l in &mut out.lights {
        if let LightKind::Point { position } = &mut l.kind {
            for k in 0..3 {
                position[k] = (position[k] as f64 - origin[k] as f64) as f32;
            }
        }
    }
    out
}

struct Shifter {
    scene: Scene,
    c: [f64; 3],
    memo: FxHashMap<ShapeId, ShapeId>,
    values: FxHashMap<NodeId, Option<Value<f32>>>,
}

impl Shifter {
    fn push(&mut self, kind: ShapeKind, span: sdfc_syntax::span::Span) -> ShapeId {
        self.scene.shapes.push(ShapeNode { kind, span });
        ShapeId(self.scene.shapes.len() as u32 - 1)
    }

    /// The value of a node computed from constants only (as folding computes it, in f32).
    fn konst(&mut self, n: NodeId) -> Option<Value<f64>> {
        const_value(&self.scene.values, n, &mut self.values).map(|v| v.cast())
    }

    /// The shape whose distance at q is `id`'s at q + c.
    fn shift(&mut self, id: ShapeId) -> ShapeId {
        if let Some(s) = self.memo.get(&id) {
            return *s;
        }
        let node = self.scene.shape(id).clone();
        let span = node.span;
        let out = match node.kind {
            ShapeKind::Map {
                map: PointMap::Affine { m, o, s },
                child,
            } => {
                // (m (q + c) + o) / s = (m q + (m c + o)) / s.
                let o = Some(self.offset(m, o, span));
                self.push(
                    ShapeKind::Map {
                        map: PointMap::Affine { m, o, s },
                        child,
                    },
                    span,
                )
            }
            ShapeKind::Combine {
                op,
                smooth,
                children,
            } => {
                let children = children.into_iter().map(|c| self.shift(c)).collect();
                self.push(
                    ShapeKind::Combine {
                        op,
                        smooth,
                        children,
                    },
                    span,
                )
            }
            ShapeKind::Material { material, child } => {
                let child = self.shift(child);
                self.push(ShapeKind::Material { material, child }, span)
            }
            ShapeKind::Modify { modifier, child } => {
                let child = self.shift(child);
                self.push(ShapeKind::Modify { modifier, child }, span)
            }
            _ => {
                let o = Some(self.offset(None, None, span));
                self.push(
                    ShapeKind::Map {
                        map: PointMap::Affine {
                            m: None,
                            o,
                            s: None,
                        },
                        child: id,
                    },
                    span,
                )
            }
        };
        self.memo.insert(id, out);
        out
    }

    /// `m c + o`: computed in f64 and rounded once where m and o are constants, else added
    /// at run time.
    fn offset(
        &mut self,
        m: Option<NodeId>,
        o: Option<NodeId>,
        span: sdfc_syntax::span::Span,
    ) -> NodeId {
        let c = Value::V3(self.c);
        let mk = m.map(|m| self.konst(m));
        let ok = o.map(|o| self.konst(o));
        if !matches!(mk, Some(None)) && !matches!(ok, Some(None)) {
            let mc = match mk.flatten() {
                Some(mv) => apply(Op::MatMul, Ty::Vec3, &[mv, c]),
                None => c,
            };
            let v = match ok.flatten() {
                Some(ov) => apply(Op::Add, Ty::Vec3, &[mc, ov]),
                None => mc,
            };
            return self.scene.values.konst(v.cast());
        }
        let g = &mut self.scene.values;
        let cn = g.konst(Value::V3(self.c.map(|x| x as f32)));
        let mc = match m {
            Some(m) => g.add(Op::MatMul, &[m, cn], span),
            None => cn,
        };
        match o {
            Some(o) => g.add(Op::Add, &[mc, o], span),
            None => mc,
        }
    }
}
