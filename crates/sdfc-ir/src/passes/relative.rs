//! Camera-relative coordinates: the scene moved so that the camera sits at the origin, for a
//! camera far from it. f32 points near 1e5 are 0.008 apart, so a shader that marches in world
//! coordinates there cannot place a surface better than that; moved, the points it works on
//! are small again. The move goes down the shape tree in f64 and is folded, rounded once,
//! wherever it can be: into an affine map (`translate(s, [1e5, ...])` seen from a camera at
//! 1e5 becomes a small exact offset, and a turned shape's `-R T` is not rounded before the
//! camera's shift is added), into a plane's offset, and through an infinite repetition
//! modulo its period (a repetition is the same after a move by whole periods). Below a shape
//! whose point map is none of these (mirrors, limited repetition, lambdas in world space) it
//! stays a runtime addition.

use super::fold::const_value_in;
use crate::eval::apply;
use crate::graph::NodeId;
use crate::hash::{FxHashMap, FxHashSet};
use crate::lower::expansion::children;
use crate::ops::Op;
use crate::scene::{LightKind, Scene};
use crate::shape::{PointMap, Prim, ShapeId, ShapeKind, ShapeNode};
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
        uses: uses(scene),
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
    /// The camera's position: the move at the root.
    c: [f64; 3],
    /// Shapes already moved, by shape and move (the bits of its three f64s).
    memo: FxHashMap<(ShapeId, [u64; 3]), ShapeId>,
    values: FxHashMap<NodeId, Option<Value<f64>>>,
    /// How many parents each shape has: a move goes on below a map only into a shape used
    /// once, so that a shared shape is never copied once per move (a `let` doubled at each
    /// of 14 levels made 4 MB of WGSL from 81 KB).
    uses: FxHashMap<ShapeId, u32>,
}

/// The number of parents of each shape reachable from the root (the root has none).
fn uses(scene: &Scene) -> FxHashMap<ShapeId, u32> {
    let mut uses: FxHashMap<ShapeId, u32> = FxHashMap::default();
    let mut stack = vec![scene.root];
    let mut seen = FxHashSet::default();
    while let Some(id) = stack.pop() {
        if !seen.insert(id) {
            continue;
        }
        for &c in children(&scene.shape(id).kind) {
            *uses.entry(c).or_default() += 1;
            stack.push(c);
        }
    }
    uses
}

/// The largest move carried below a map: past it the f32 offset it becomes could overflow
/// (a chain of `scale(1e-12)`s divides the move by 1e12 at each); the map folds it instead.
const MAX_MOVE: f64 = 1e12;

impl Shifter {
    fn push(&mut self, kind: ShapeKind, span: sdfc_syntax::span::Span) -> ShapeId {
        self.scene.shapes.push(ShapeNode { kind, span });
        ShapeId(self.scene.shapes.len() as u32 - 1)
    }

    /// The value of a node computed from constants only, in f64: an offset such as
    /// `R (-1e5, -1e5, -1e5)` (a turned shape moved far out) rounded to f32 before the
    /// camera's shift was added would keep its 0.008 error in the small result.
    fn konst(&mut self, n: NodeId) -> Option<Value<f64>> {
        const_value_in(&self.scene.values, n, &mut self.values)
    }

    /// A constant vec3 node, rounded to f32 once.
    fn vec3(&mut self, v: [f64; 3]) -> NodeId {
        self.scene.values.konst(Value::V3(v.map(|x| x as f32)))
    }

    /// `id` seen from the camera: the shape whose distance at q is `id`'s at q + c.
    fn shift(&mut self, id: ShapeId) -> ShapeId {
        let c = self.c;
        self.moved(id, c)
    }

    /// The shape whose distance at q is `id`'s at q + `c`.
    fn moved(&mut self, id: ShapeId, c: [f64; 3]) -> ShapeId {
        if c == [0.0; 3] {
            return id;
        }
        // A shared shape reached with a move of its own (carried below a map) is moved as a
        // whole, not copied: each path to it may bring another move.
        if c != self.c && self.uses.get(&id).is_some_and(|&n| n > 1) {
            let span = self.scene.shape(id).span;
            return self.translated(id, c, span);
        }
        let key = (id, c.map(f64::to_bits));
        if let Some(s) = self.memo.get(&key) {
            return *s;
        }
        let node = self.scene.shape(id).clone();
        let span = node.span;
        let out = match node.kind {
            // A rigid map or scale whose child's move is still far out (the camera is near
            // this part of the scene along no axis, or not along all): s child((m (q + c) +
            // o) / s) = s child'((m q) / s), child' the child moved by w = (m c + o) / s,
            // which goes on down in f64 to a plane or repetition that can fold it. Not into
            // a shared child (it would be copied once per move), nor a move past MAX_MOVE.
            ShapeKind::Map {
                map: PointMap::Affine { m, o, s },
                child,
            } if self.uses.get(&child) == Some(&1) => match self.local_move(m, o, s, c) {
                Some(w) if w.iter().any(|x| x.abs() >= FROM as f64) => {
                    let child = self.moved(child, w);
                    self.push(
                        ShapeKind::Map {
                            map: PointMap::Affine { m, o: None, s },
                            child,
                        },
                        span,
                    )
                }
                _ => self.folded(m, o, s, c, child, span),
            },
            // Where the move becomes small it is folded into the map, once for all that is
            // below it: one small point that the children share, which they turn and offset
            // as at the origin (carrying a small move into each child turned points of size
            // 6 instead of 1, and normals at 1e5 were 30% further off).
            ShapeKind::Map {
                map: PointMap::Affine { m, o, s },
                child,
            } => self.folded(m, o, s, c, child, span),
            ShapeKind::Map {
                map: PointMap::Repeat { period },
                child,
            } => {
                // Along a repeated axis a move by whole periods changes nothing: what is
                // left of it, under half a period, goes above the repetition; along the
                // others the repetition leaves the point alone, so the move goes below it.
                let mut above = [0.0; 3];
                let mut below = c;
                for k in 0..3 {
                    if period[k] != 0.0 {
                        let p = period[k] as f64;
                        above[k] = c[k] - p * (c[k] / p).round();
                        below[k] = 0.0;
                    }
                }
                let child = self.moved(child, below);
                let repeated = self.push(
                    ShapeKind::Map {
                        map: PointMap::Repeat { period },
                        child,
                    },
                    span,
                );
                self.translated(repeated, above, span)
            }
            ShapeKind::Prim {
                prim: Prim::Plane,
                ref args,
            } => match (self.konst(args[0]), self.konst(args[1])) {
                // dot(q + c, n) - h = dot(q, n) - (h - dot(c, n)).
                (Some(Value::V3(n)), Some(Value::F(h))) => {
                    let h = h - (0..3).map(|k| c[k] * n[k]).sum::<f64>();
                    let h = self.scene.values.konst(Value::F(h as f32));
                    self.push(
                        ShapeKind::Prim {
                            prim: Prim::Plane,
                            args: vec![args[0], h],
                        },
                        span,
                    )
                }
                _ => self.translated(id, c, span),
            },
            ShapeKind::Combine {
                op,
                smooth,
                children,
            } => {
                let children = children.into_iter().map(|k| self.moved(k, c)).collect();
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
                let child = self.moved(child, c);
                self.push(ShapeKind::Material { material, child }, span)
            }
            ShapeKind::Modify { modifier, child } => {
                let child = self.moved(child, c);
                self.push(ShapeKind::Modify { modifier, child }, span)
            }
            _ => self.translated(id, c, span),
        };
        self.memo.insert(key, out);
        out
    }

    /// The map with the move folded into its offset: (m (q + c) + o) / s = (m q + (m c + o))
    /// / s, the sum rounded once where m and o are constants, else added at run time.
    fn folded(
        &mut self,
        m: Option<NodeId>,
        o: Option<NodeId>,
        s: Option<NodeId>,
        c: [f64; 3],
        child: ShapeId,
        span: sdfc_syntax::span::Span,
    ) -> ShapeId {
        let o = Some(match self.local_move(m, o, None, c) {
            Some(v) => self.vec3(v),
            None => self.runtime_offset(m, o, c, span),
        });
        self.push(
            ShapeKind::Map {
                map: PointMap::Affine { m, o, s },
                child,
            },
            span,
        )
    }

    /// `id` at q + `c`: an affine map with `c` (rounded once) as its offset; `id` itself
    /// where `c` is zero.
    fn translated(&mut self, id: ShapeId, c: [f64; 3], span: sdfc_syntax::span::Span) -> ShapeId {
        if c == [0.0; 3] {
            return id;
        }
        let o = Some(self.vec3(c));
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

    /// `(m c + o) / s` in f64, where m, o and s are constants (or absent).
    fn local_move(
        &mut self,
        m: Option<NodeId>,
        o: Option<NodeId>,
        s: Option<NodeId>,
        c: [f64; 3],
    ) -> Option<[f64; 3]> {
        let mut v = Value::V3(c);
        if let Some(m) = m {
            v = apply(Op::MatMul, Ty::Vec3, &[self.konst(m)?, v]);
        }
        if let Some(o) = o {
            v = apply(Op::Add, Ty::Vec3, &[v, self.konst(o)?]);
        }
        let Value::V3(mut w) = v else { return None };
        if let Some(s) = s {
            let Value::F(s) = self.konst(s)? else {
                return None;
            };
            w = w.map(|x| x / s);
        }
        w.iter().all(|x| x.abs() <= MAX_MOVE).then_some(w)
    }

    /// `m c + o` added at run time: m or o depend on params or time.
    fn runtime_offset(
        &mut self,
        m: Option<NodeId>,
        o: Option<NodeId>,
        c: [f64; 3],
        span: sdfc_syntax::span::Span,
    ) -> NodeId {
        let cn = self.vec3(c);
        let g = &mut self.scene.values;
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
