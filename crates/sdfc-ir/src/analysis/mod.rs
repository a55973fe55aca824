//! Exactness and Lipschitz analysis of the shape DAG. For every shape node: whether its
//! distance is exact (outside the shape, where the marcher walks), a bound, or neither;
//! conservative bounds; and, for the bound-only nodes (stretch, shear, twist, bend, warp,
//! displace, heightfield, sdf), the Lipschitz constant `L` of the field they compute before
//! they normalise it. Safe stepping is done at those nodes: each divides its field by its
//! `L` (see `to_ssa`), so every node's distance is 1-Lipschitz and exact subtrees elsewhere
//! in the scene keep full steps. Declared `lipschitz:` bounds are checked by sampling.

pub mod bounds;
mod declared;
mod explain;
pub mod gradient;
mod lipschitz;
mod maps;
pub mod sample;
pub mod symmetry;

use crate::graph::NodeId;
use crate::hash::FxHashMap;
use crate::passes::fold::const_value;
use crate::scene::Scene;
use crate::shape::{CombineOp, DistMod, PointMap, Prim, ShapeKind};
use crate::value::Value;
use bounds::Aabb;
pub use explain::explain;
pub use lipschitz::{bend_lipschitz, shear_inverse, spectral_norm, twist_lipschitz};
use sdfc_syntax::diag::Diagnostic;

/// What a node's distance is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Exactness {
    /// The Euclidean distance, at least outside the shape.
    Exact,
    /// Never more than the distance (1-Lipschitz and zero on the surface).
    Bound,
    /// Not even a bound (a repeated shape that does not fit its cell, say).
    Neither,
}

impl Exactness {
    pub fn name(self) -> &'static str {
        match self {
            Exactness::Exact => "exact",
            Exactness::Bound => "bound",
            Exactness::Neither => "neither",
        }
    }
}

/// Where a node's Lipschitz constant comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// A `lipschitz:` argument.
    Declared,
    /// Derived by the compiler (matrix norms, bounds, gradient bounds of the expression).
    Derived,
    /// The language's default (`sdf` without `lipschitz:` has L = 1).
    Default,
    /// Computed per point at run time (twist and bend outside their child's bounds, a
    /// shear by params): only the value inside the bounds is known here.
    Symbolic,
}

/// The analysis of one shape node.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeInfo {
    pub exactness: Exactness,
    /// Conservative bounds of the shape (infinite where unbounded).
    pub bounds: Aabb,
    /// For bound-only nodes: the Lipschitz constant of the field the node divides by it
    /// (`None` where it depends on a param); `None` for the other nodes too.
    pub lipschitz: Option<f64>,
    pub source: Option<Source>,
    /// Whether the node normalises its field (bound-only nodes).
    pub normalises: bool,
    /// `displace`: the largest magnitude of the displacement; `heightfield`: the greatest
    /// height. `None` where the analysis finds no finite bound (or for other nodes). The
    /// emitted field uses it for a second, cheaper bound that takes full steps far from the
    /// surface, where the divided field would crawl.
    pub reach: Option<f64>,
    /// `displace` and `heightfield`: bounds on the absolute partial derivatives of the point
    /// function (the displacement; the height, by x and z with 0 for y), where all are finite.
    /// `scene_distance_ray` divides by the slope along the ray that they bound.
    pub partials: Option<[f64; 3]>,
    /// Outside its bounds the node's field is at least this factor times the distance to
    /// them (0: nothing is known). 1 for an exact distance (every surface lies in the box);
    /// `1 / L` for a heightfield, `c / L` for a displacement of a child with factor c divided
    /// by L; the least of the children's for unions and `xor`; the first child's for a
    /// subtraction and, for an intersection, that of a child whose box is the node's (or the
    /// least over sqrt(n)), smooth or not; kept by moves, turns, scales, mirrors,
    /// repetitions, elongation, materials, `round` and `onion` (whose box grows by their
    /// reach over it); a smooth union's box grows by what the blend takes off, over the
    /// factor. Shadow rays stop once their cone has left the scene's box for good by it
    /// (`bounds_outside` in the emitted shader).
    pub outside: f64,
}

/// The analysis of a scene, node by node (indexed like `Scene::shapes`).
#[derive(Clone, Debug, Default)]
pub struct Analysis {
    pub nodes: Vec<NodeInfo>,
    /// The axes each shape is mirror-symmetric about (`symmetry::mirror_axes`).
    pub mirror: Vec<[bool; 3]>,
    /// The size of the smallest shape, in the scene's units: the least, over the shapes the
    /// root reaches, of their box's largest half-extent (at most `THIN_RATIO` times its
    /// smallest) times the scales above it (the least over the paths to it); 0 where a leaf
    /// other than a plane has no finite box, or below a warp or a displacement, which may
    /// make a shape smaller than its box. The distance function's numbers near a surface are
    /// about that large or larger, so the difference normals' step need not go below 2e-5 of
    /// it (`normal_step` in `shaders/main.wgsl`, `FEATURE_SIZE`). A point near the frame's
    /// origin (the camera, in camera-relative coordinates) is no measure of that: seen from
    /// 0.05 away, a unit sphere's distance rounds to 6e-8 while 2e-5 of the point's size is
    /// 1e-6, and its normals were off by 0.4 degree (docs/accuracy.md, "Normals near the
    /// camera"). The smallest shape keeps its small step (a step near a shape's size tilts
    /// its normal: moving the point by half a step did on a sphere of radius 1e-3; a slab
    /// thinner than the step would be stepped across).
    pub feature: f64,
    /// Errors (a twist of an unbounded shape with no declared bound, a displacement whose
    /// slope nothing bounds) and warnings (declared bounds contradicted by sampling).
    pub diagnostics: Vec<Diagnostic>,
}

impl Analysis {
    /// Whether the scene's distance is trusted never to exceed the true distance: exact, or
    /// a bound that the language's operators make or the compiler derives or checks. Not
    /// where any node is neither, nor with an estimated primitive (`Prim::estimate`: the
    /// mandelbulb's) or an `sdf` without a declared `lipschitz:` (L = 1 by default, a claim
    /// nobody made). A rise of a trusted distance along a ray after its minimum proves that
    /// the ray passed its surface by.
    pub fn distance_trusted(&self, scene: &Scene) -> bool {
        let estimated = scene.shapes.iter().zip(&self.nodes).any(|(s, n)| match &s.kind {
            ShapeKind::Prim { prim, .. } => prim.estimate(),
            ShapeKind::Sdf { .. } => n.source == Some(Source::Default),
            _ => false,
        } || n.exactness == Exactness::Neither);
        !self.nodes.is_empty() && !estimated
    }
}

impl Analysis {
    /// Outside the scene's bounds its distance is at least this factor times the distance
    /// to them ([`NodeInfo::outside`] of the root; 0 where nothing is known).
    pub fn outside_factor(&self, scene: &Scene) -> f64 {
        self.nodes
            .get(scene.root.index())
            .map_or(0.0, |n| n.outside)
    }
}

/// The factor by which a primitive's distance outside its box is at least the distance to
/// it (`NodeInfo::outside`): 1 for an exact one; for the bounds, `Analyser::bound_prim_outside`
/// says why; an ellipsoid's from its radii (`None`: not constant, 0).
pub fn prim_outside(prim: Prim, radii: Option<[f64; 3]>) -> f64 {
    match (prim, radii) {
        (p, _) if p.exact() => 1.0,
        (Prim::Menger, _) => 1.0,
        (Prim::Mandelbulb, _) => 1.0,
        (Prim::Sierpinski, _) => 1.0 / 3.0,
        (Prim::Ellipsoid, Some(r)) => {
            let lo = r.iter().fold(f64::INFINITY, |a, &x| a.min(x));
            let hi = r.iter().fold(0.0f64, |a, &x| a.max(x));
            if lo > 0.0 && hi.is_finite() {
                lo / hi
            } else {
                0.0
            }
        }
        _ => 0.0,
    }
}

/// A shape's size for [`Analysis::feature`] is at most this many times its box's smallest
/// half-extent: moving a point by half the normal's step (2e-5 of the size) then tilts the
/// normal of its thinnest part by at most 2e-5 * 16 / 2 radians (0.01 degree).
const THIN_RATIO: f64 = 16.0;

/// How far the sampling check reaches on unbounded axes.
pub const DEFAULT_REGION: f64 = 4.0;

/// At most this many declared bounds are checked per scene (the first in the shape DAG's
/// order), so that compile time stays bounded for scenes with thousands of displacements.
pub const MAX_CHECKED: usize = 64;

/// Analyses every shape of `scene`; `check` runs the sampling check of declared bounds.
pub fn analyse(scene: &Scene, check: bool) -> Analysis {
    let mut a = Analyser {
        scene,
        memo: FxHashMap::default(),
        out: Analysis::default(),
        check,
        checked: 0,
    };
    for i in 0..scene.shapes.len() {
        let info = a.node(i);
        a.out.nodes.push(info);
    }
    a.out.mirror = symmetry::mirror_axes(scene);
    a.out.feature = a.feature();
    a.out
}

struct Analyser<'s> {
    scene: &'s Scene,
    memo: FxHashMap<NodeId, Option<Value<f32>>>,
    out: Analysis,
    check: bool,
    /// Declared bounds checked so far.
    checked: usize,
}

impl Analyser<'_> {
    /// [`Analysis::feature`], from the boxes found: the scales are carried down from the
    /// root (children come before their parents in `scene.shapes`).
    fn feature(&mut self) -> f64 {
        let n = self.scene.shapes.len();
        let mut scale = vec![f64::INFINITY; n];
        if let Some(s) = scale.get_mut(self.scene.root.index()) {
            *s = 1.0;
        }
        for i in (0..n).rev() {
            if !scale[i].is_finite() {
                continue;
            }
            let kind = &self.scene.shapes[i].kind;
            let own = match kind {
                ShapeKind::Map {
                    map: PointMap::Affine { s: Some(s), .. },
                    ..
                } => self.scalar(*s).map_or(0.0, f64::abs),
                // A warp (a stretch by 0.01) or a displacement (by nearly the radius) may
                // make what is below it smaller than its box says: no floor below them.
                ShapeKind::Warp { .. } | ShapeKind::Displace { .. } => 0.0,
                _ => 1.0,
            };
            let below = scale[i] * own;
            for c in crate::lower::expansion::children(kind) {
                let c = c.index();
                scale[c] = scale[c].min(below);
            }
        }
        let mut least = f64::INFINITY;
        for ((node, info), s) in self.scene.shapes.iter().zip(&self.out.nodes).zip(&scale) {
            if !s.is_finite() {
                continue; // not reached from the root
            }
            // A shape's numbers are as large as its largest half-extent (a torus's ring), but
            // a step of 2e-5 of that must stay far below its thinnest side: at most
            // `THIN_RATIO` times the smallest.
            let b = &info.bounds;
            let halves = [0, 1, 2].map(|k| 0.5 * (b.hi[k] - b.lo[k]));
            let small = halves.into_iter().fold(f64::INFINITY, f64::min);
            let large = halves.into_iter().fold(0.0, f64::max);
            let half = large.min(THIN_RATIO * small);
            let leaf = crate::lower::expansion::children(&node.kind).is_empty();
            let plane = matches!(
                node.kind,
                ShapeKind::Prim {
                    prim: Prim::Plane,
                    ..
                }
            );
            if half.is_finite() {
                least = least.min(s * half);
            } else if leaf && !plane {
                // A leaf whose size is not known (a lambda's `sdf`, a param's radius, an
                // infinite cylinder) may be the smallest of all. A plane has no size.
                return 0.0;
            }
        }
        if least.is_finite() {
            least.clamp(0.0, 1e30)
        } else {
            0.0
        }
    }

    fn konst(&mut self, n: NodeId) -> Option<Value<f32>> {
        const_value(&self.scene.values, n, &mut self.memo)
    }

    fn scalar(&mut self, n: NodeId) -> Option<f64> {
        self.konst(n).and_then(|v| v.scalar()).map(|x| x as f64)
    }

    fn vec3(&mut self, n: NodeId) -> Option<[f64; 3]> {
        match self.konst(n) {
            Some(Value::V3(v)) => Some(v.map(|x| x as f64)),
            Some(Value::F(x)) => Some([x as f64; 3]),
            _ => None,
        }
    }

    fn info(&self, s: crate::shape::ShapeId) -> &NodeInfo {
        &self.out.nodes[s.index()]
    }

    fn node(&mut self, i: usize) -> NodeInfo {
        let node = &self.scene.shapes[i];
        let span = node.span;
        let plain = |exactness, bounds, outside| NodeInfo {
            exactness,
            bounds,
            lipschitz: None,
            source: None,
            normalises: false,
            reach: None,
            partials: None,
            outside,
        };
        match &node.kind {
            ShapeKind::Prim { prim, args } => {
                let vals: Vec<Option<Value<f32>>> = args.iter().map(|a| self.konst(*a)).collect();
                let (e, outside) = if prim.exact() {
                    (Exactness::Exact, 1.0)
                } else {
                    (Exactness::Bound, Self::bound_prim_outside(*prim, &vals))
                };
                plain(e, bounds::prim(*prim, &vals), outside)
            }
            ShapeKind::Sdf {
                body,
                lambda,
                lipschitz,
                declared,
            } => {
                let l = self.scalar(*lipschitz);
                if let (Some(l), Some(at)) = (l, declared) {
                    self.check_declared(*body, *lambda, 1, l, None, *at, &Aabb::EVERYTHING, "sdf");
                }
                NodeInfo {
                    exactness: Exactness::Bound,
                    bounds: Aabb::EVERYTHING,
                    lipschitz: l,
                    source: Some(if declared.is_some() {
                        Source::Declared
                    } else {
                        Source::Default
                    }),
                    normalises: true,
                    reach: None,
                    partials: None,
                    outside: 0.0,
                }
            }
            ShapeKind::Displace {
                child,
                body,
                lambda,
                lipschitz,
            } => {
                let c = self.info(*child).clone();
                let slope = self.body_bound(*body, *lambda, 1);
                let grow = slope.iter().map(|x| x.mag()).fold(0.0, f64::max);
                let (l, source) = match lipschitz {
                    Some((n, at)) => {
                        let l = self.scalar(*n);
                        if let Some(l) = l {
                            self.check_declared(
                                *body,
                                *lambda,
                                1,
                                l,
                                Some(*child),
                                *at,
                                &c.bounds.grow(grow),
                                "displace",
                            );
                        }
                        (l, Source::Declared)
                    }
                    None => {
                        let g = slope.first().map_or(f64::INFINITY, |c| c.slope());
                        if !g.is_finite() {
                            self.out.diagnostics.push(
                                Diagnostic::error(span, "the compiler cannot bound how fast this displacement changes")
                                    .with_label("no Lipschitz bound")
                                    .with_hint("declare one: `lipschitz: L` with L at least 1 plus the largest slope of the expression"),
                            );
                        }
                        (Some(1.0 + g), Source::Derived)
                    }
                };
                NodeInfo {
                    exactness: c.exactness.max(Exactness::Bound),
                    // The surface lies where the child's field is at most the displacement's
                    // largest magnitude.
                    bounds: grow_below(&c, grow),
                    lipschitz: l,
                    source: Some(source),
                    normalises: true,
                    reach: grow.is_finite().then_some(grow),
                    partials: slope
                        .first()
                        .map(|c| c.v)
                        .filter(|v| v.iter().all(|x| x.is_finite())),
                    // Outside the box (the child's grown by g / c, g the largest
                    // |displacement|, c the child's factor), base + disp >= c dist(child's
                    // box) - g >= c dist(box): a box grown by r is at least r nearer.
                    outside: match l {
                        Some(l) if c.outside > 0.0 && grow.is_finite() && l >= 1.0 => c.outside / l,
                        _ => 0.0,
                    },
                }
            }
            ShapeKind::Heightfield {
                body,
                lambda,
                lipschitz,
            } => {
                let height = self.body_bound(*body, *lambda, 2).first().copied();
                let top = height.map(|c| c.hi).filter(|h| h.is_finite());
                let (l, source) = match lipschitz {
                    Some((n, at)) => {
                        let l = self.scalar(*n);
                        if let Some(l) = l {
                            self.check_declared(
                                *body,
                                *lambda,
                                2,
                                l,
                                None,
                                *at,
                                &Aabb::EVERYTHING,
                                "heightfield",
                            );
                        }
                        (l, Source::Declared)
                    }
                    None => {
                        let g = height.map_or(f64::INFINITY, |c| c.slope());
                        if !g.is_finite() {
                            self.out.diagnostics.push(
                                Diagnostic::error(span, "the compiler cannot bound the slope of this heightfield")
                                    .with_label("no Lipschitz bound")
                                    .with_hint("declare one: `lipschitz: L` with L at least the terrain's steepest slope"),
                            );
                        }
                        (Some(g), Source::Derived)
                    }
                };
                let mut bounds = Aabb::EVERYTHING;
                if let Some(top) = top {
                    bounds.hi[1] = top;
                }
                NodeInfo {
                    exactness: Exactness::Bound,
                    bounds,
                    // The field p.y - h is (1 + L^2)^(1/2)-Lipschitz.
                    lipschitz: l.map(|l| (1.0 + l * l).sqrt()),
                    source: Some(source),
                    normalises: true,
                    reach: top,
                    partials: height
                        .map(|c| c.v)
                        .filter(|v| v.iter().all(|x| x.is_finite())),
                    // Above the top, p.y - h >= p.y - top, the distance to the box.
                    outside: l.map_or(0.0, |l| 1.0 / (1.0 + l * l).sqrt()),
                }
            }
            ShapeKind::Warp {
                map,
                child,
                lipschitz,
            } => {
                let c = self.info(*child).clone();
                let declared = lipschitz.and_then(|(n, at)| self.scalar(n).map(|l| (l, at)));
                let (bounds, l, source) = self.warp(*map, &c.bounds, declared, *lipschitz, span);
                NodeInfo {
                    exactness: c.exactness.max(Exactness::Bound),
                    bounds,
                    lipschitz: l,
                    source: Some(source),
                    normalises: true,
                    reach: None,
                    partials: None,
                    outside: 0.0,
                }
            }
            ShapeKind::Combine {
                op,
                smooth,
                children,
            } => {
                let kids: Vec<NodeInfo> = children.iter().map(|c| self.info(*c).clone()).collect();
                let worst = kids
                    .iter()
                    .map(|k| k.exactness)
                    .max()
                    .unwrap_or(Exactness::Exact);
                let exactness = if *op == CombineOp::Union && smooth.is_none() {
                    // A min of distances is the distance outside.
                    worst
                } else {
                    worst.max(Exactness::Bound)
                };
                let mut b = match op {
                    CombineOp::Union | CombineOp::Xor => {
                        kids.iter().map(|k| k.bounds).reduce(|a, b| a.hull(&b))
                    }
                    CombineOp::Intersect => {
                        kids.iter().map(|k| k.bounds).reduce(|a, b| a.intersect(&b))
                    }
                    CombineOp::Subtract => kids.first().map(|k| k.bounds),
                }
                .unwrap_or(Aabb::EVERYTHING);
                let least = kids.iter().map(|k| k.outside).fold(1.0, f64::min);
                // A smooth max with k >= 0 is never below the plain max, so smooth
                // intersections and subtractions keep the plain ones' factors.
                let at_least_max = match smooth {
                    None => true,
                    Some(k) => self.scalar(*k).is_some_and(|k| k >= 0.0),
                };
                let mut outside = match (op, at_least_max) {
                    (CombineOp::Union, _) => least,
                    // Outside the hull both children are positive, and xor is their min.
                    (CombineOp::Xor, _) => least,
                    // The max is at least the first child's, whose box is the node's.
                    (CombineOp::Subtract, true) => kids.first().map_or(0.0, |k| k.outside),
                    // At least each child's: by any child whose box is the node's, and by
                    // all n together, since per axis the distance to the boxes' intersection
                    // is the largest of the distances to each, so its square is at most the
                    // sum of theirs, n times the largest (an empty intersection: nothing).
                    (CombineOp::Intersect, true) => {
                        let n = kids.len().max(1) as f64;
                        let all = if b.lo.iter().zip(&b.hi).all(|(l, h)| l <= h) {
                            least / n.sqrt()
                        } else {
                            0.0
                        };
                        kids.iter()
                            .filter(|k| k.bounds == b)
                            .map(|k| k.outside)
                            .fold(all, f64::max)
                    }
                    _ => 0.0,
                };
                if let (CombineOp::Union, Some(k)) = (op, smooth) {
                    // The polynomial smooth min of two is at most k/4 below their min; the
                    // children fold pairwise, each fold at most (k - e)^2 / 4k below the
                    // lesser of its two when the running value is e below it already, so n
                    // children drop by at most D = k min(1, (n - 1) / 4) (three by 0.39 k
                    // at most, growing towards k). Outside the hull H of the children's boxes
                    // the value is at least c dist(H) - D (c their least factor), positive
                    // beyond D / c: the surface lies within D / c of H, and the box grows by
                    // that (D for exact children). There c dist(H) - D >= c dist(box), so
                    // the factor stays c. Children of unknown factor (a warp's bound, a
                    // fractal, an `sdf`) may blend below zero anywhere near the hull: no
                    // box. (It grew by k/4 whatever the count and the children: three unit
                    // spheres blended with k = 1 reached 1.39 where the box ended at 1.25,
                    // and two displaced spheres, c = 1 / 2.875, reached 0.3 beyond theirs.)
                    let drop = 0.25 * (kids.len().max(2) - 1) as f64;
                    b = match self.scalar(*k) {
                        Some(k) if least > 0.0 => b.grow(k.abs() * drop.min(1.0) / least),
                        _ => Aabb::EVERYTHING,
                    };
                    if !self.scalar(*k).is_some_and(|k| k >= 0.0) {
                        outside = 0.0;
                    }
                }
                plain(exactness, b, outside)
            }
            ShapeKind::Map { map, child } => {
                let c = self.info(*child).clone();
                let (e, b) = self.point_map(map, &c);
                // Each map moves the point to one at least as far from the child's box as
                // it is from the node's (turns and scales by the same factor as the value).
                plain(e, b, c.outside)
            }
            ShapeKind::Modify { modifier, child } => {
                let c = self.info(*child).clone();
                let r = match modifier {
                    DistMod::Round(r) | DistMod::Onion(r) => self.scalar(*r),
                };
                // The surface lies where the child's field is r (an onion's also at -r,
                // inside the child's box).
                let b = match r {
                    Some(r) => grow_below(&c, r),
                    None => Aabb::EVERYTHING,
                };
                // d - r >= c dist(child's box) - r >= c dist(box grown by r / c) for a
                // child with factor c (outside, an onion's |d| is d).
                let outside = match r {
                    Some(r) if r >= 0.0 => c.outside,
                    _ => 0.0,
                };
                plain(c.exactness, b, outside)
            }
            ShapeKind::Material { child, .. } => {
                let c = self.info(*child).clone();
                plain(c.exactness, c.bounds, c.outside)
            }
        }
    }

    /// [`NodeInfo::outside`] of a primitive whose distance is a bound. The ellipsoid's first
    /// term, (|u| - 1) min(r) with u = p / r, is at least min(r) / max(r) times the distance
    /// to its box [-r, r]: with w_k = max(|u_k| - 1, 0), that distance is at most max(r) |w|,
    /// and |u| >= |w| + 1 (|u|^2 >= |w|^2 + 2 |w|_1 + 1 outside the box). The Menger sponge
    /// is the max of its box's exact distance and the holes': 1. The mandelbulb is the
    /// distance to the sphere of its bound beyond 1.25 times it, where its box ends: 1. The
    /// Sierpinski tetrahedron's estimate is the largest of its face planes' distances to the
    /// nearest copy at the last level, whose faces are the whole's moved inwards, so at least
    /// the whole's: in the doubled frame z = 2p, max(n.z) - 1 over the four normals n = (+-1,
    /// +-1, +-1) with an odd count of minus signs is at least |z|_inf - 1 (two of them match
    /// the largest component's sign, and one of those the sign of the other two's
    /// difference), twice the distance to the box in the max norm: the estimate, that over
    /// 2 sqrt(3), is at least a third of the Euclidean distance.
    fn bound_prim_outside(prim: Prim, vals: &[Option<Value<f32>>]) -> f64 {
        let radii = match vals.first() {
            Some(Some(Value::V3(r))) => Some(r.map(|x| x as f64)),
            _ => None,
        };
        prim_outside(prim, radii)
    }
}

/// The box of the points where a child's field is at most `g`: for g > 0 its own box grown
/// by g over its outside factor c (beyond that the field is at least c times the distance,
/// above g), and no box where c is 0 (a fractal's or a warp's field may stay below g
/// anywhere); for g <= 0 its box shrunk by |g| (within |g| of its faces every point is within
/// |g| of the surface, so above g). Growing by g alone, as `round`, `onion` and `displace`
/// did, held for exact children only: a rounded Sierpinski tetrahedron (c = 1/3) reached 0.02
/// outside its box.
fn grow_below(c: &NodeInfo, g: f64) -> Aabb {
    if g <= 0.0 {
        c.bounds.grow(g)
    } else if c.outside > 0.0 && g.is_finite() {
        c.bounds.grow(g / c.outside)
    } else {
        Aabb::EVERYTHING
    }
}
