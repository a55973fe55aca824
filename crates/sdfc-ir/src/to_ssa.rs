//! Lowers the shape tree to the scalar SSA functions `scene_distance(p)` and
//! `scene_material(p)`: point maps become arithmetic on `p`, primitives become helper calls,
//! combinations become `min`/`max` (and, for materials, selects and blends).

use crate::func::{Func, FuncKind};
use crate::graph::{Graph, NodeId};
use crate::hash::FxHashMap;
use crate::ops::{Builtin, Op, Swizzle};
use crate::scene::{Material, Scene};
use crate::shape::{CombineOp, DistMod, Prim, ShapeId, ShapeKind};
use crate::types::Ty;
use crate::value::Value;

mod along_ray;
mod combine;
mod cull;
mod maps;
mod prims;
mod warp;

pub use cull::CULL_MIN;

use crate::rounding::f32_up;

/// The material of a point: `albedo` (rgb, reflectivity) and `phong` (ambient, diffuse,
/// specular, shininess), both vec4.
type Mat = [NodeId; 2];

/// Unions of more children than this are split into group functions of at most this many
/// children each: WGSL front ends (naga's among them) slow down with the size of a single
/// function, and the groups are where bounding-volume early-outs will go.
pub const GROUP_SIZE: usize = 32;

/// A large union's unbounded children (floors) stay out of its group functions where there
/// are at most this many of them: each is built in the union's own function, where it can
/// take its distance along the ray.
const FREE_OF_GROUPS: usize = 4;

/// A shape whose unfolded tree has at least this many nodes gets a function of its own (a
/// group function of one child), called wherever the shape is used. A `let` shape used at many
/// places is then emitted once instead of once per use, and no function grows with the scene:
/// naga's front end takes time quadratic in the size of one function (a 2 kB file whose
/// `let`s double the scene on each line took 27 s to validate as one function).
pub const OUTLINE_SHAPES: u64 = 64;

/// The scalar functions of a scene.
pub struct Functions {
    /// `scene_distance(p) -> f32`.
    pub distance: Func,
    /// `scene_material(p) -> SceneMaterial`: results albedo and phong.
    pub material: Func,
    /// Group functions that the two call (`Op::Call`), by index.
    pub groups: Vec<Func>,
    /// `scene_distance_ray(p, rd) -> f32` for the marcher, where some node of the scene can
    /// step further along a known direction than its isotropic bound allows (`along_ray`).
    pub distance_ray: Option<Func>,
    /// Whether a displacement or heightfield divides by its slope along the ray in
    /// `distance_ray` (not only planes: see [`crate::Program::distance_ray_slopes`]).
    pub distance_ray_slopes: bool,
}

/// `instance_shape{k}(p) -> f32` for each primitive of `templates` (the kinds of a union
/// emitted as data, `crate::instances`): its distance in its own frame, its arguments read
/// from `Op::Param(i)` (of the types given), which the emitter binds to the instance's
/// arguments rather than the scene's params. Unoptimised.
pub fn template_functions(
    scene: &Scene,
    analysis: &crate::analysis::Analysis,
    templates: &[(Prim, Vec<Ty>)],
) -> Vec<Func> {
    let counts = crate::lower::expansion::instance_counts(&scene.shapes);
    templates
        .iter()
        .enumerate()
        .map(|(k, (prim, tys))| {
            let mut b = Builder::new(scene, &counts, analysis, false, Groups::default());
            b.cull = false;
            let p = b.point();
            let args: Vec<NodeId> = tys
                .iter()
                .enumerate()
                .map(|(i, ty)| {
                    b.g.add_typed(Op::Param(i as u16), &[], *ty, Default::default())
                })
                .collect();
            let d = b.prim_of(*prim, &args, p);
            Func {
                name: format!("instance_shape{k}"),
                kind: FuncKind::Distance,
                graph: b.g,
                results: vec![d],
            }
        })
        .collect()
}

/// Builds `scene_distance` and `scene_material` (and their group functions).
pub fn functions(scene: &Scene, cull: bool) -> Functions {
    let counts = crate::lower::expansion::instance_counts(&scene.shapes);
    let analysis = crate::analysis::analyse(scene, false);
    let info = &analysis.nodes[..];
    let mut groups = Groups::default();
    let mut b = Builder::new(scene, &counts, &analysis, false, groups);
    b.cull = cull;
    let p = b.point();
    let (d, _) = b.shape(scene.root, p, 0);
    let distance = Func {
        name: "scene_distance".into(),
        kind: FuncKind::Distance,
        graph: b.g,
        results: vec![d],
    };
    groups = b.groups;
    let mut b = Builder::new(scene, &counts, &analysis, true, groups);
    b.cull = cull;
    let p = b.point();
    let (_, m) = b.shape(scene.root, p, 0);
    let m = m.unwrap_or_else(|| b.material_const(0));
    let material = Func {
        name: "scene_material".into(),
        kind: FuncKind::Material,
        graph: b.g,
        results: m.to_vec(),
    };
    groups = b.groups;
    // Nodes whose slope along a ray can be below their bound: displacements and heightfields
    // (their partial derivatives) and planes (`plane_along_ray`).
    let along = info.iter().any(|i| i.partials.is_some())
        || scene.shapes.iter().any(|n| {
            matches!(
                n.kind,
                ShapeKind::Prim {
                    prim: Prim::Plane,
                    ..
                }
            )
        });
    let mut distance_ray = None;
    let mut distance_ray_slopes = false;
    if along {
        let mut b = Builder::new(scene, &counts, &analysis, false, groups);
        b.cull = cull;
        let p = b.point();
        let rd = b.g.op(Op::Ray, &[]);
        b.g.set_hint(rd, "rd");
        b.dir = Some(rd);
        let (d, _) = b.shape(scene.root, p, 0);
        if b.used_dir {
            distance_ray = Some(Func {
                name: "scene_distance_ray".into(),
                kind: FuncKind::DistanceRay,
                graph: b.g,
                results: vec![d],
            });
            distance_ray_slopes = b.used_slopes;
        }
        groups = b.groups;
    }
    Functions {
        distance,
        material,
        groups: groups.funcs,
        distance_ray,
        distance_ray_slopes,
    }
}

/// Group functions built so far, shared by the distance and the material function: one
/// function per group serves both (its material part is emitted behind a flag).
#[derive(Default)]
struct Groups {
    funcs: Vec<Func>,
    /// By children, material and whether the group is a culled part (which reads the
    /// caller's best distance).
    index: FxHashMap<(Vec<ShapeId>, u32, bool), u32>,
}

/// A shape built at a point, by shape, point, material, direction (`dir`, with `dir_signs`
/// in the top bit; all ones for none) and `values_matter`.
type MemoKey = (ShapeId, NodeId, u32, u32, bool);

struct Builder<'s> {
    scene: &'s Scene,
    /// Unfolded size of each shape (`expansion::instance_counts`), to decide what to outline.
    counts: &'s [u64],
    /// The shape whose group function this builder is building: inlined, not outlined again.
    body_of: Option<ShapeId>,
    /// The exactness/Lipschitz analysis, for the divisors of bound-only nodes, the bounds
    /// that culled unions test and the shapes' symmetries, for repetitions.
    analysis: &'s crate::analysis::Analysis,
    /// Whether large unions get bounding-box early-outs (`cull.rs`).
    cull: bool,
    /// Whether the union about to be built is a culled part's body, called only where its
    /// box is nearer than the caller's best distance (`Op::Best`); `cull.rs` takes it.
    culled_body: bool,
    g: Graph,
    materials: bool,
    imported: FxHashMap<NodeId, NodeId>,
    memo: FxHashMap<MemoKey, (NodeId, Option<Mat>)>,
    /// In `scene_distance_ray`: the ray's direction in the current shape's coordinates
    /// (`None` where no map keeps it known: everywhere else, and under warps).
    dir: Option<NodeId>,
    /// Whether `dir` is known only up to the signs of its components, some of which may
    /// also have stopped (below a mirror or an elongation): a rotation further down then
    /// loses it, since the bound needs `|u|` per component in the node's own frame.
    dir_signs: bool,
    /// Whether the current node's values shape the surface (below a smooth blend, `round`,
    /// `onion`, a displaced child, a warp, and in group functions, which any context may
    /// call), or only their signs do. Only where they do not may a node replace its value by
    /// a larger bound: the far bound of `displace` and `heightfield`, the ray's slope.
    values_matter: bool,
    /// Whether some node divided by its slope along `dir` (else the ray function is not
    /// worth emitting).
    used_dir: bool,
    /// Whether a displacement or heightfield divided by its slope along `dir` (`along_ray`),
    /// as well as or instead of planes (`plane_along_ray`).
    used_slopes: bool,
    consts: FxHashMap<NodeId, Option<Value<f32>>>,
    groups: Groups,
}

impl<'s> Builder<'s> {
    fn new(
        scene: &'s Scene,
        counts: &'s [u64],
        analysis: &'s crate::analysis::Analysis,
        materials: bool,
        groups: Groups,
    ) -> Builder<'s> {
        Builder {
            scene,
            counts,
            body_of: None,
            analysis,
            cull: true,
            culled_body: false,
            g: Graph::new(),
            materials,
            imported: FxHashMap::default(),
            memo: FxHashMap::default(),
            dir: None,
            dir_signs: false,
            values_matter: false,
            used_dir: false,
            used_slopes: false,
            consts: FxHashMap::default(),
            groups,
        }
    }

    fn point(&mut self) -> NodeId {
        let p = self.g.op(Op::Point, &[]);
        self.g.set_hint(p, "p");
        p
    }

    /// The group function for a union of `children` (built once, with its material part),
    /// and its call's results at `p`.
    fn group(&mut self, children: &[ShapeId], p: NodeId, mat: u32) -> (NodeId, Option<Mat>) {
        self.group_call(children, p, mat, None)
    }

    /// [`Self::group`], with an optional guard `(bound, best)`: the call is made only where
    /// `bound < best`, and otherwise its distance is `bound` (see `cull.rs`).
    fn group_call(
        &mut self,
        children: &[ShapeId],
        p: NodeId,
        mat: u32,
        guard: Option<(NodeId, NodeId)>,
    ) -> (NodeId, Option<Mat>) {
        let key = (children.to_vec(), mat, guard.is_some());
        let index = match self.groups.index.get(&key) {
            Some(i) => *i,
            None => {
                let mut sub = Builder::new(
                    self.scene,
                    self.counts,
                    self.analysis,
                    true,
                    std::mem::take(&mut self.groups),
                );
                sub.cull = self.cull;
                sub.culled_body = guard.is_some();
                sub.values_matter = true;
                if let [only] = children {
                    sub.body_of = Some(*only);
                }
                let sp = sub.point();
                let (d, m) = sub.combine(CombineOp::Union, None, children, sp, mat);
                let m = m.unwrap_or_else(|| sub.material_const(mat));
                let index = sub.groups.funcs.len() as u32;
                sub.groups.funcs.push(Func {
                    name: format!("scene_group{index}"),
                    kind: FuncKind::Group,
                    graph: sub.g,
                    results: vec![d, m[0], m[1]],
                });
                sub.groups.index.insert(key, index);
                self.groups = sub.groups;
                index
            }
        };
        let args: Vec<NodeId> = match guard {
            Some((bound, best)) => vec![p, bound, best],
            None => vec![p],
        };
        let call = |g: &mut Graph, result: u8, ty: Ty| {
            g.add_typed(
                Op::Call {
                    func: index,
                    result,
                },
                &args,
                ty,
                Default::default(),
            )
        };
        let d = call(&mut self.g, 0, Ty::F32);
        let d = self.hinted(d, "d");
        let m = self.materials.then(|| {
            [
                call(&mut self.g, 1, Ty::Vec4),
                call(&mut self.g, 2, Ty::Vec4),
            ]
        });
        (d, m)
    }

    /// Copies a value-graph node (and what it uses) into the function; lambda parameter
    /// `(lambda, i)` becomes `args[i]` when `subst` is `Some((lambda, args))`.
    fn import(&mut self, id: NodeId, subst: Option<(u32, &[NodeId])>) -> NodeId {
        let vals = &self.scene.values;
        let mut local: FxHashMap<NodeId, NodeId> = FxHashMap::default();
        let mut stack = vec![id];
        let mut order = Vec::new();
        let mut seen: FxHashMap<NodeId, ()> = FxHashMap::default();
        while let Some(n) = stack.pop() {
            if seen.contains_key(&n) || (subst.is_none() && self.imported.contains_key(&n)) {
                continue;
            }
            seen.insert(n, ());
            order.push(n);
            stack.extend(vals.node(n).args().iter().copied());
        }
        order.sort();
        for n in order {
            let node = *vals.node(n);
            let lookup = |m: NodeId,
                          local: &FxHashMap<NodeId, NodeId>,
                          imported: &FxHashMap<NodeId, NodeId>| {
                local
                    .get(&m)
                    .or_else(|| imported.get(&m))
                    .copied()
                    .unwrap_or(NodeId(0))
            };
            let args: Vec<NodeId> = node
                .args()
                .iter()
                .map(|a| lookup(*a, &local, &self.imported))
                .collect();
            let new = match (node.op, subst) {
                (Op::LambdaArg { lambda, index }, Some((l, ps)))
                    if lambda == l && (index as usize) < ps.len() =>
                {
                    ps[index as usize]
                }
                (Op::Param(_) | Op::LambdaArg { .. }, _) => {
                    self.g.input(node.op, node.ty, vals.span(n))
                }
                (op, _) => self.g.add(op, &args, vals.span(n)),
            };
            if subst.is_some() {
                local.insert(n, new);
            } else {
                self.imported.insert(n, new);
            }
        }
        if subst.is_some() {
            local.get(&id).copied().unwrap_or(NodeId(0))
        } else {
            self.imported.get(&id).copied().unwrap_or(NodeId(0))
        }
    }

    fn material_const(&mut self, index: u32) -> Mat {
        let m: &Material = &self.scene.materials[index as usize];
        let (albedo, phong) = (Value::V4(m.albedo()), Value::V4(m.phong()));
        [self.g.konst(albedo), self.g.konst(phong)]
    }

    fn hinted(&mut self, n: NodeId, hint: &'static str) -> NodeId {
        self.g.set_hint(n, hint);
        n
    }

    fn op(&mut self, op: Op, args: &[NodeId]) -> NodeId {
        self.g.op(op, args)
    }

    fn f(&mut self, x: f32) -> NodeId {
        self.g.f32(x)
    }

    /// The distance (and material) of shape `s` at point `p`, with `mat` the material of
    /// parts that name none.
    fn shape(&mut self, s: ShapeId, p: NodeId, mat: u32) -> (NodeId, Option<Mat>) {
        let key = (
            s,
            p,
            if self.materials { mat } else { 0 },
            self.dir
                .map_or(u32::MAX, |d| d.0 | (u32::from(self.dir_signs) << 31)),
            self.values_matter,
        );
        if let Some(r) = self.memo.get(&key) {
            return *r;
        }
        if s != self.scene.root
            && self.body_of != Some(s)
            && self
                .counts
                .get(s.index())
                .is_some_and(|&n| n >= OUTLINE_SHAPES)
        {
            let out = self.group(&[s], p, mat);
            self.memo.insert(key, out);
            return out;
        }
        let node = self.scene.shape(s).clone();
        let out = match &node.kind {
            ShapeKind::Prim { prim, args } => {
                let d = self.prim(*prim, args, p);
                let d = self.hinted(d, "d");
                (d, self.materials.then(|| self.material_const(mat)))
            }
            ShapeKind::Sdf {
                body,
                lambda,
                lipschitz,
                ..
            } => {
                let d = self.import(*body, Some((*lambda, &[p])));
                let l = self.import(*lipschitz, None);
                let d = self.op(Op::Div, &[d, l]);
                let d = self.hinted(d, "d");
                (d, self.materials.then(|| self.material_const(mat)))
            }
            ShapeKind::Displace {
                child,
                body,
                lambda,
                lipschitz,
            } => {
                let (base, m) = self.isotropic(|b| b.shape(*child, p, mat));
                let f = self.import(*body, Some((*lambda, &[p])));
                let l = self.divisor(s, *lipschitz);
                let l = self.along_ray(s, l, false);
                let d = self.op(Op::Add, &[base, f]);
                let d = self.op(Op::Div, &[d, l]);
                let d = self.hinted(d, "d");
                // The surface lies where base = -f, so within {base <= M} for M the largest
                // |f|; base is 1-Lipschitz, so base - M is a lower bound on the distance to
                // it that needs no divisor. Far from the shape it takes the full steps the
                // divided field would not.
                let reach = self.analysis.nodes[s.index()]
                    .reach
                    .filter(|_| !self.values_matter && self.divides(l));
                let d = match reach {
                    Some(reach) => {
                        let reach = self.f(f32_up(reach));
                        let far = self.op(Op::Sub, &[base, reach]);
                        self.g.builtin(Builtin::Max, &[d, far])
                    }
                    _ => d,
                };
                (self.hinted(d, "d"), m)
            }
            ShapeKind::Combine {
                op,
                smooth,
                children,
            } => {
                if smooth.is_some() {
                    self.isotropic(|b| b.combine(*op, *smooth, children, p, mat))
                } else {
                    self.combine(*op, *smooth, children, p, mat)
                }
            }
            ShapeKind::Map { map, child } => self.map(s, map, *child, p, mat),
            ShapeKind::Modify { modifier, child } => {
                let (d, m) = self.isotropic(|b| b.shape(*child, p, mat));
                let d = match *modifier {
                    DistMod::Round(r) => {
                        let r = self.import(r, None);
                        self.op(Op::Sub, &[d, r])
                    }
                    DistMod::Onion(t) => {
                        let t = self.import(t, None);
                        let a = self.g.builtin(Builtin::Abs, &[d]);
                        self.op(Op::Sub, &[a, t])
                    }
                };
                (self.hinted(d, "d"), m)
            }
            ShapeKind::Material { material, child } => self.shape(*child, p, *material),
            ShapeKind::Warp {
                map,
                child,
                lipschitz,
            } => {
                // The warp's own divisor is isotropic; below it the direction is not tracked.
                self.isotropic(|b| b.warp(s, *map, *child, *lipschitz, p, mat))
            }
            ShapeKind::Heightfield { body, lambda, .. } => {
                // (p.y - h(p.x, p.z)) / sqrt(1 + L^2)
                let x = self.op(Op::Swizzle(Swizzle::new(&[0])), &[p]);
                let y = self.op(Op::Swizzle(Swizzle::new(&[1])), &[p]);
                let z = self.op(Op::Swizzle(Swizzle::new(&[2])), &[p]);
                let h = self.import(*body, Some((*lambda, &[x, z])));
                let d = self.op(Op::Sub, &[y, h]);
                let l = self.divisor(s, None);
                let l = self.along_ray(s, l, true);
                let d = self.op(Op::Div, &[d, l]);
                // Above the highest point of the terrain, the height over it is a lower bound
                // on the distance that needs no divisor.
                let top = self.analysis.nodes[s.index()]
                    .reach
                    .filter(|_| !self.values_matter && self.divides(l));
                let d = match top {
                    Some(top) => {
                        let d = self.hinted(d, "d");
                        let top = self.f(f32_up(top));
                        let far = self.op(Op::Sub, &[y, top]);
                        self.g.builtin(Builtin::Max, &[d, far])
                    }
                    _ => d,
                };
                (
                    self.hinted(d, "d"),
                    self.materials.then(|| self.material_const(mat)),
                )
            }
        };
        self.memo.insert(key, out);
        out
    }
}
