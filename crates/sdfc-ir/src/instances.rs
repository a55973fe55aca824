//! Large unions as data: a scene whose root is a hard union of many instances (a primitive
//! with constant arguments under constant rigid moves and uniform scales, with a material)
//! can be marched from a table of the instances and a hierarchy of their boxes, walked by one
//! loop, instead of a block of code per shape (docs/performance.md, "Large unions as data").
//! This module finds such a union and builds the hierarchy; `sdfc-wgsl` lays it out and
//! emits the walk.

use crate::analysis::bounds::Aabb;
use crate::analysis::Analysis;
use crate::func::Func;
use crate::hash::FxHashMap;
use crate::passes::fold::const_value_in;
use crate::scene::Scene;
use crate::shape::{CombineOp, PointMap, Prim, ShapeId, ShapeKind};
use crate::types::Ty;
use crate::value::Value;

/// Unions of fewer children are left as code: the walk would not pay for itself.
pub const MIN_CHILDREN: usize = 16;

/// A node's box is padded by this share of its size (and as much again absolutely), so
/// that f32 rounding of the boxes cannot cut an instance's surface.
const PAD: f64 = 1e-3;

/// One instance: `template`'s distance with arguments `args` at `turn(q, p - centre) / scale`,
/// times `scale`.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// Index into [`Instances::templates`].
    pub template: u32,
    /// The primitive's arguments, as the language takes them.
    pub args: Vec<Value<f64>>,
    /// The scene's material index.
    pub material: u32,
    /// The turn, a unit quaternion (x, y, z, w).
    pub q: [f64; 4],
    pub centre: [f64; 3],
    pub scale: f64,
    /// The instance's box, in the coordinates the instances were found in.
    pub lo: [f64; 3],
    pub hi: [f64; 3],
}

/// A node of the hierarchy, in depth-first order: its subtree is the nodes from it up to
/// (not including) `skip`.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub centre: [f64; 3],
    pub half: [f64; 3],
    pub skip: u32,
    /// For a leaf, its instance (an index into [`Instances::items`]).
    pub leaf: Option<u32>,
}

/// A union found as instances, and their hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct Instances {
    /// The kinds of primitive, with their arguments' types.
    pub templates: Vec<(Prim, Vec<Ty>)>,
    pub items: Vec<Instance>,
    /// The hierarchy, one leaf per instance: the root first.
    pub nodes: Vec<Node>,
    /// The union's shape, and its children that are not instances (only from
    /// [`find_mixed`]): code, evaluated beside the walk.
    pub union: ShapeId,
    pub rest: Vec<ShapeId>,
}

impl Instances {
    /// The least factor by which an instance's distance outside its box is at least the
    /// distance to the box (`analysis::prim_outside`).
    /// Uniform scales and rigid moves keep it. Shadow rays pad their lists' boxes by it
    /// (`shadows.rs` in sdfc-wgsl).
    pub fn outside_factor(&self) -> f64 {
        self.items
            .iter()
            .map(|item| {
                let radii = match item.args.first() {
                    Some(Value::V3(r)) => Some(*r),
                    _ => None,
                };
                self.templates
                    .get(item.template as usize)
                    .map_or(0.0, |t| crate::analysis::prim_outside(t.0, radii))
            })
            .fold(1.0, f64::min)
    }

    /// The instances' usual spacing: the median distance between the box centres of two
    /// leaves that are one node's children (the hierarchy's splits make them neighbours).
    /// `None` where no node has two leaves. Ambient occlusion lists the instances near a
    /// point only where its samples reach no farther (`occlusion.rs` in sdfc-wgsl).
    pub fn spacing(&self) -> Option<f64> {
        let mut pairs: Vec<f64> = (0..self.nodes.len())
            .filter(|&i| self.nodes[i].leaf.is_none())
            .filter_map(|i| {
                let first = self.nodes.get(i + 1)?;
                let second = self.nodes.get(first.skip as usize)?;
                first.leaf?;
                second.leaf?;
                let d = [0, 1, 2].map(|a| first.centre[a] - second.centre[a]);
                Some((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt())
            })
            .collect();
        if pairs.is_empty() {
            return None;
        }
        let mid = pairs.len() / 2;
        Some(*pairs.select_nth_unstable_by(mid, f64::total_cmp).1)
    }
}

/// The root union of `scene` (whose `analysis` gives the boxes) as instances, in
/// coordinates centred on `origin` (the
/// camera-relative frame the renderer marches in, or the origin), or `None` where the root
/// (under constant moves, turns, scales and materials) is not a hard union of
/// [`MIN_CHILDREN`] or more instances: bounded primitives with constant arguments (the
/// fractals' are compile-time settings of their code, so they are left out).
pub fn find(scene: &Scene, analysis: &Analysis, origin: [f64; 3]) -> Option<Instances> {
    find_at_least(scene, analysis, origin, MIN_CHILDREN)
}

/// [`find`] for a union of at least `min` children (never fewer than [`MIN_CHILDREN`]); a
/// smaller union is refused before any instance is looked at.
pub fn find_at_least(
    scene: &Scene,
    analysis: &Analysis,
    origin: [f64; 3],
    min: usize,
) -> Option<Instances> {
    find_in(scene, analysis, origin, min, false)
}

/// [`find_at_least`], where the union may also hold other children (a floor plane, a
/// fractal, a smooth blend): `min` or more of its children must be instances, and the others
/// are [`Instances::rest`], to be evaluated as code beside the walk.
pub fn find_mixed(
    scene: &Scene,
    analysis: &Analysis,
    origin: [f64; 3],
    min: usize,
) -> Option<Instances> {
    find_in(scene, analysis, origin, min, true)
}

fn find_in(
    scene: &Scene,
    analysis: &Analysis,
    origin: [f64; 3],
    min: usize,
    mixed: bool,
) -> Option<Instances> {
    let min = min.max(MIN_CHILDREN);
    let mut memo = FxHashMap::default();
    let (root, outer) = peel(scene, scene.root, Frame::IDENTITY, &mut memo)?;
    let ShapeKind::Combine {
        op: CombineOp::Union,
        smooth: None,
        children,
    } = &scene.shape(root).kind
    else {
        return None;
    };
    if children.len() < min {
        return None;
    }
    let mut templates: Vec<(Prim, Vec<Ty>)> = Vec::new();
    let mut items = Vec::with_capacity(children.len());
    let mut rest = Vec::new();
    for &child in children {
        let found = instance(scene, analysis, root, child, &outer, &mut memo);
        let Some(found) = found else {
            if !mixed {
                return None;
            }
            rest.push(child);
            continue;
        };
        let key = (found.prim, found.args.iter().map(|v| v.ty()).collect());
        let template = match templates.iter().position(|k| *k == key) {
            Some(i) => i as u32,
            None => {
                templates.push(key);
                (templates.len() - 1) as u32
            }
        };
        let (b, c) = (&found.bounds, found.centre);
        items.push(Instance {
            template,
            material: found.material,
            q: found.q,
            centre: [0, 1, 2].map(|a| c[a] - origin[a]),
            scale: found.scale,
            lo: [0, 1, 2].map(|a| b.lo[a] - origin[a]),
            hi: [0, 1, 2].map(|a| b.hi[a] - origin[a]),
            args: found.args,
        });
    }
    if items.len() < min {
        return None;
    }
    let nodes = hierarchy(&items);
    Some(Instances {
        templates,
        items,
        nodes,
        union: root,
        rest,
    })
}

/// What [`instance`] finds, in world coordinates: an instance is its primitive with these
/// arguments at `turn(q, p - centre) / scale`, its distance times `scale`.
struct Found {
    prim: Prim,
    args: Vec<Value<f64>>,
    material: u32,
    scale: f64,
    q: [f64; 4],
    centre: [f64; 3],
    bounds: Aabb,
}

/// One child of the union as an instance; `None` where it is not one.
fn instance(
    scene: &Scene,
    analysis: &Analysis,
    root: ShapeId,
    child: ShapeId,
    outer: &Frame,
    memo: &mut FxHashMap<crate::graph::NodeId, Option<Value<f64>>>,
) -> Option<Found> {
    let (prim_shape, f) = peel(scene, child, outer.clone(), memo)?;
    let ShapeKind::Prim { prim, args } = &scene.shape(prim_shape).kind else {
        return None;
    };
    if matches!(
        prim,
        Prim::Plane | Prim::InfiniteCylinder | Prim::Mandelbulb | Prim::Menger | Prim::Sierpinski
    ) {
        return None;
    }
    let mut values = Vec::with_capacity(args.len());
    for a in args {
        // Scalars and vec3s: what the emitted kinds read from the data.
        match const_value_in(&scene.values, *a, memo)? {
            v @ (Value::F(_) | Value::V3(_)) => values.push(v),
            _ => return None,
        }
    }
    if !(f.s.is_finite() && f.s > 0.0) {
        return None;
    }
    // The child's box from the analysis where the union is the root; under the root's own
    // maps, the primitive's box seen through the instance's whole frame.
    let b = if root == scene.root {
        analysis.nodes[child.index()].bounds
    } else {
        transformed_box(&analysis.nodes[prim_shape.index()].bounds, &f)?
    };
    if !b.lo.iter().chain(&b.hi).all(|x| x.is_finite()) {
        return None;
    }
    // Turns only (a mirror or a shear has no quaternion): m p + o = m (p - c) with
    // c = -m^-1 o.
    Some(Found {
        prim: *prim,
        args: values,
        material: f.material.unwrap_or(0),
        scale: f.s,
        q: quaternion(&f.m)?,
        centre: mat_vec(&inverse(&f.m)?, &f.o).map(|x| -x),
        bounds: b,
    })
}

/// The frame a shape is evaluated in: `local = (m p + o) / s`, the distance times `s`; and
/// the innermost material set on the way.
#[derive(Clone)]
struct Frame {
    m: [[f64; 3]; 3],
    o: [f64; 3],
    s: f64,
    material: Option<u32>,
}

impl Frame {
    const IDENTITY: Frame = Frame {
        m: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        o: [0.0; 3],
        s: 1.0,
        material: None,
    };
}

/// Follows constant moves, turns, scales and materials down from `id`: the first other
/// shape, and the frame composed on the way; `None` where a map is not constant.
fn peel(
    scene: &Scene,
    mut id: ShapeId,
    mut f: Frame,
    memo: &mut FxHashMap<crate::graph::NodeId, Option<Value<f64>>>,
) -> Option<(ShapeId, Frame)> {
    loop {
        match &scene.shape(id).kind {
            ShapeKind::Map {
                map:
                    PointMap::Affine {
                        m: m2,
                        o: o2,
                        s: s2,
                    },
                child,
            } => {
                let m2 = match m2 {
                    Some(n) => match const_value_in(&scene.values, *n, memo)? {
                        Value::M3(c) => c,
                        _ => return None,
                    },
                    None => Frame::IDENTITY.m,
                };
                let o2 = match o2 {
                    Some(n) => match const_value_in(&scene.values, *n, memo)? {
                        Value::V3(v) => v,
                        _ => return None,
                    },
                    None => [0.0; 3],
                };
                let s2 = match s2 {
                    Some(n) => match const_value_in(&scene.values, *n, memo)? {
                        Value::F(v) => v,
                        _ => return None,
                    },
                    None => 1.0,
                };
                // (m2 ((m p + o) / s) + o2) / s2 = (m2 m p + m2 o + s o2) / (s s2).
                let mo = mat_vec(&m2, &f.o);
                f.o = [0, 1, 2].map(|i| mo[i] + f.s * o2[i]);
                f.m = mat_mul(&m2, &f.m);
                f.s *= s2;
                id = *child;
            }
            ShapeKind::Material { material, child } => {
                // The innermost material wins.
                f.material = Some(*material);
                id = *child;
            }
            _ => return Some((id, f)),
        }
    }
}

/// The world box of a shape whose local box is `b`, seen through frame `f`: the eight
/// corners of `b` mapped back, `p = m^-1 (s local - o)`.
fn transformed_box(b: &Aabb, f: &Frame) -> Option<Aabb> {
    if !b.lo.iter().chain(&b.hi).all(|x| x.is_finite()) {
        return None;
    }
    let inv = inverse(&f.m)?;
    let mut out = Aabb {
        lo: [f64::INFINITY; 3],
        hi: [f64::NEG_INFINITY; 3],
    };
    for k in 0..8 {
        let corner = [0, 1, 2].map(|a| if k >> a & 1 == 0 { b.lo[a] } else { b.hi[a] });
        let p = mat_vec(&inv, &[0, 1, 2].map(|a| f.s * corner[a] - f.o[a]));
        for (a, x) in p.into_iter().enumerate() {
            out.lo[a] = out.lo[a].min(x);
            out.hi[a] = out.hi[a].max(x);
        }
    }
    Some(out)
}

/// `a b` for column-major 3x3 matrices.
fn mat_mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|col| mat_vec(a, &b[col]))
}

/// `a v` for a column-major 3x3 matrix.
fn mat_vec(a: &[[f64; 3]; 3], v: &[f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|row| (0..3).map(|k| a[k][row] * v[k]).sum())
}

/// `v` turned by the unit quaternion `q` (x, y, z, w), as `shaders/instances.wgsl` turns a
/// point into an instance's frame: `v + w t + q.xyz x t`, with `t = 2 q.xyz x v`.
pub fn turn(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let u = [q[0], q[1], q[2]];
    let t = cross(u, v).map(|x| 2.0 * x);
    let ut = cross(u, t);
    [0, 1, 2].map(|i| v[i] + q[3] * t[i] + ut[i])
}

/// The unit quaternion (x, y, z, w) of a rotation matrix (column-major), or `None` where the
/// matrix is not a rotation (to 1e-6).
fn quaternion(m: &[[f64; 3]; 3]) -> Option<[f64; 4]> {
    let e = |r: usize, c: usize| m[c][r];
    for i in 0..3 {
        for j in 0..3 {
            let dot: f64 = (0..3).map(|k| m[i][k] * m[j][k]).sum();
            if (dot - if i == j { 1.0 } else { 0.0 }).abs() > 1e-6 {
                return None;
            }
        }
    }
    let det = e(0, 0) * (e(1, 1) * e(2, 2) - e(1, 2) * e(2, 1))
        - e(0, 1) * (e(1, 0) * e(2, 2) - e(1, 2) * e(2, 0))
        + e(0, 2) * (e(1, 0) * e(2, 1) - e(1, 1) * e(2, 0));
    if det < 0.0 {
        return None;
    }
    // Shepperd's method: from the largest of w, x, y, z.
    let t = e(0, 0) + e(1, 1) + e(2, 2);
    let q = if t > 0.0 {
        let s = 0.5 / (t + 1.0).sqrt();
        [
            (e(2, 1) - e(1, 2)) * s,
            (e(0, 2) - e(2, 0)) * s,
            (e(1, 0) - e(0, 1)) * s,
            0.25 / s,
        ]
    } else if e(0, 0) > e(1, 1) && e(0, 0) > e(2, 2) {
        let s = 2.0 * (1.0 + e(0, 0) - e(1, 1) - e(2, 2)).sqrt();
        [
            0.25 * s,
            (e(0, 1) + e(1, 0)) / s,
            (e(0, 2) + e(2, 0)) / s,
            (e(2, 1) - e(1, 2)) / s,
        ]
    } else if e(1, 1) > e(2, 2) {
        let s = 2.0 * (1.0 + e(1, 1) - e(0, 0) - e(2, 2)).sqrt();
        [
            (e(0, 1) + e(1, 0)) / s,
            0.25 * s,
            (e(1, 2) + e(2, 1)) / s,
            (e(0, 2) - e(2, 0)) / s,
        ]
    } else {
        let s = 2.0 * (1.0 + e(2, 2) - e(0, 0) - e(1, 1)).sqrt();
        [
            (e(0, 2) + e(2, 0)) / s,
            (e(1, 2) + e(2, 1)) / s,
            0.25 * s,
            (e(1, 0) - e(0, 1)) / s,
        ]
    };
    Some(q)
}

/// The inverse of a column-major 3x3 matrix, where it is well conditioned.
fn inverse(a: &[[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let e = |r: usize, c: usize| a[c][r];
    let cof = |r: usize, c: usize| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        let (c1, c2) = ((c + 1) % 3, (c + 2) % 3);
        e(r1, c1) * e(r2, c2) - e(r1, c2) * e(r2, c1)
    };
    let det = e(0, 0) * cof(0, 0) + e(0, 1) * cof(0, 1) + e(0, 2) * cof(0, 2);
    // (A NaN determinant fails too.)
    if det.abs().partial_cmp(&1e-12) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    // inv[r][c] (row r, column c) = cof(c, r) / det; stored column-major.
    Some([0, 1, 2].map(|col| [0, 1, 2].map(|row| cof(col, row) / det)))
}

impl Instances {
    /// Whether more than `limit` instances' boxes hold one point (the middle of one of
    /// them): a crowd. A ray through more boxes at one place than its list holds (32 in the
    /// renderer) walks the whole hierarchy at every step there, and the union is then
    /// faster as code (`sdfc_wgsl::Instances::Auto` keeps it so). One query of the
    /// hierarchy a box, each stopped at `limit + 1` boxes, so a crowd is found at once.
    pub fn crowd_exceeds(&self, limit: usize) -> bool {
        self.items.iter().any(|it| {
            let p = it.middle();
            let mut count = 0;
            let mut i = 0;
            while i < self.nodes.len() && count <= limit {
                let n = &self.nodes[i];
                if (0..3).any(|a| (p[a] - n.centre[a]).abs() > n.half[a]) {
                    i = n.skip as usize;
                    continue;
                }
                if let Some(l) = n.leaf {
                    let b = &self.items[l as usize];
                    count += usize::from((0..3).all(|a| b.lo[a] <= p[a] && p[a] <= b.hi[a]));
                }
                i += 1;
            }
            count > limit
        })
    }
}

impl Instance {
    /// The middle of the instance's box.
    fn middle(&self) -> [f64; 3] {
        [0, 1, 2].map(|a| 0.5 * (self.lo[a] + self.hi[a]))
    }
}

/// A box as its lowest and highest corners.
type Bounds = ([f64; 3], [f64; 3]);

/// The box that holds nothing, which [`grow`] starts from.
const EMPTY: Bounds = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);

/// `b` grown to hold the box from `lo` to `hi`.
fn grow(b: &mut Bounds, lo: &[f64; 3], hi: &[f64; 3]) {
    for a in 0..3 {
        b.0[a] = b.0[a].min(lo[a]);
        b.1[a] = b.1[a].max(hi[a]);
    }
}

/// The box around the instances `idx`.
fn bounds_of(items: &[Instance], idx: &[u32]) -> Bounds {
    let mut b = EMPTY;
    for &i in idx {
        grow(&mut b, &items[i as usize].lo, &items[i as usize].hi);
    }
    b
}

/// The lowest and highest middle of the instances `idx` along axis `a`.
fn middles(items: &[Instance], idx: &[u32], a: usize) -> (f64, f64) {
    idx.iter()
        .map(|&i| items[i as usize].middle()[a])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(mn, mx), m| {
            (mn.min(m), mx.max(m))
        })
}

/// The hierarchy over the instances' boxes, one instance per leaf: each node split where the
/// surface area heuristic says a ray meets fewest boxes (`sah_split`), or at the median of
/// the longest axis of the centres where it finds no split; the child nearer the frame's
/// origin (the camera, where the renderer marches in its frame) first.
fn hierarchy(items: &[Instance]) -> Vec<Node> {
    let mut nodes = Vec::with_capacity(2 * items.len());
    let mut idx: Vec<u32> = (0..items.len() as u32).collect();
    let bounds = bounds_of(items, &idx);
    build(items, &mut idx, bounds, &mut nodes);
    nodes
}

/// The subtree of the instances `idx`, whose box is `(lo, hi)`.
fn build(items: &[Instance], idx: &mut [u32], (lo, hi): Bounds, nodes: &mut Vec<Node>) {
    let me = nodes.len();
    let centre = [0, 1, 2].map(|a| 0.5 * (lo[a] + hi[a]));
    let half = [0, 1, 2].map(|a| 0.5 * (hi[a] - lo[a]) * (1.0 + PAD) + PAD);
    nodes.push(Node {
        centre,
        half,
        skip: 0,
        leaf: (idx.len() == 1).then_some(idx[0]),
    });
    if idx.len() > 1 {
        let k = sah_split(items, idx).unwrap_or_else(|| median_split(items, idx));
        let (left, right) = idx.split_at_mut(k);
        let (bl, br) = (bounds_of(items, left), bounds_of(items, right));
        // Nearer the origin first: from the camera a ray's walk then meets the instances
        // roughly in the order it lists them, so its insertion sort seldom shifts.
        if box_distance(&br) < box_distance(&bl) {
            build(items, right, br, nodes);
            build(items, left, bl, nodes);
        } else {
            build(items, left, bl, nodes);
            build(items, right, br, nodes);
        }
    }
    nodes[me].skip = nodes.len() as u32;
}

/// How far the box `(lo, hi)` is from the frame's origin.
fn box_distance((lo, hi): &Bounds) -> f64 {
    let d = [0, 1, 2].map(|a| lo[a].max(0.0) + (-hi[a]).max(0.0));
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// A box's surface area over 2, from its extent: the share of random rays that meet it.
fn area((lo, hi): &Bounds) -> f64 {
    let e = [0, 1, 2].map(|a| (hi[a] - lo[a]).max(0.0));
    e[0] * e[1] + e[1] * e[2] + e[2] * e[0]
}

/// Bins of the surface area heuristic on each axis.
const BINS: usize = 32;

/// The bin of `x` where bins `1 / scale` wide start at `mn`.
fn bin(x: f64, mn: f64, scale: f64) -> usize {
    (((x - mn) * scale) as usize).min(BINS - 1)
}

/// Splits `idx` (reordering it) where the surface area heuristic is lowest over BINS bins of
/// the centres on each axis: the children's areas times their counts, the expected number
/// of boxes a ray through the node meets below it. Returns the left child's length, or
/// `None` where every centre falls in one bin on every axis. Binning is linear in the
/// instances, so the 5 000-shape union builds as fast as with the median (a sort a level).
fn sah_split(items: &[Instance], idx: &mut [u32]) -> Option<usize> {
    let mut best: Option<(f64, usize, usize, f64, f64)> = None;
    for a in 0..3 {
        let (mn, mx) = middles(items, idx, a);
        if mx <= mn {
            continue;
        }
        let scale = BINS as f64 / (mx - mn);
        let mut count = [0usize; BINS];
        let mut boxes = [EMPTY; BINS];
        for &i in idx.iter() {
            let it = &items[i as usize];
            let b = bin(it.middle()[a], mn, scale);
            count[b] += 1;
            grow(&mut boxes[b], &it.lo, &it.hi);
        }
        // Suffix areas and counts, then a sweep from the left.
        let mut right_area = [0.0; BINS];
        let mut right_count = [0usize; BINS];
        let (mut right, mut n) = (EMPTY, 0);
        for b in (1..BINS).rev() {
            grow(&mut right, &boxes[b].0, &boxes[b].1);
            n += count[b];
            right_area[b] = area(&right);
            right_count[b] = n;
        }
        let (mut left, mut n) = (EMPTY, 0);
        for b in 0..BINS - 1 {
            grow(&mut left, &boxes[b].0, &boxes[b].1);
            n += count[b];
            let rn = right_count[b + 1];
            if n == 0 || rn == 0 {
                continue;
            }
            let cost = area(&left) * n as f64 + right_area[b + 1] * rn as f64;
            if best.is_none_or(|(c, ..)| cost < c) {
                best = Some((cost, a, b, mn, scale));
            }
        }
    }
    let (_, a, split, mn, scale) = best?;
    let left = |i: &u32| bin(items[*i as usize].middle()[a], mn, scale) <= split;
    // Stable, so that the union's order holds within each side.
    idx.sort_by_key(|i| !left(i));
    Some(idx.iter().take_while(|i| left(i)).count())
}

/// Splits `idx` (reordering it) at the median of the longest axis of the centres; returns the
/// left child's length.
fn median_split(items: &[Instance], idx: &mut [u32]) -> usize {
    let extent = [0, 1, 2].map(|a| {
        let (mn, mx) = middles(items, idx, a);
        mx - mn
    });
    let axis = (0..3).fold(0, |best, a| if extent[a] > extent[best] { a } else { best });
    let mid = |i: &u32| items[*i as usize].middle()[axis];
    // Stable, so that equal centres keep the union's order.
    idx.sort_by(|x, y| mid(x).total_cmp(&mid(y)));
    idx.len() / 2
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quaternion_turns_as_its_matrix_does() {
        // Turns about each axis and a mixed one, through each branch of Shepperd's method.
        let (c, s) = (0.6f64, 0.8f64);
        let rx = [[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]];
        let ry = [[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]];
        let rz = [[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]];
        let flip_x = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]];
        let flip_y = [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]];
        for m in [rx, ry, rz, flip_x, flip_y, mat_mul(&rx, &mat_mul(&ry, &rz))] {
            let q = quaternion(&m).expect("a rotation");
            for v in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.3, -0.5, 2.0]] {
                let (a, b) = (turn(q, v), mat_vec(&m, &v));
                for i in 0..3 {
                    assert!(
                        (a[i] - b[i]).abs() < 1e-12,
                        "{m:?} {v:?}: {a:?} against {b:?}"
                    );
                }
            }
        }
        // A mirror and a stretch are not turns.
        assert!(quaternion(&[[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]).is_none());
        assert!(quaternion(&[[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]).is_none());
    }

    #[test]
    fn inverse_undoes_a_turn_and_scale() {
        let (c, s) = (0.6f64, 0.8f64);
        let m = [
            [2.0 * c, 0.0, -2.0 * s],
            [0.0, 2.0, 0.0],
            [2.0 * s, 0.0, 2.0 * c],
        ];
        let inv = inverse(&m).unwrap();
        let id = mat_mul(&inv, &m);
        for (i, col) in id.iter().enumerate() {
            for (j, x) in col.iter().enumerate() {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((x - want).abs() < 1e-12, "{id:?}");
            }
        }
        assert!(inverse(&[[1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]).is_none());
    }
}

/// The code of a mixed union's other children ([`Instances::rest`]): `rest_distance`,
/// `rest_material` and the groups they call, and `rest_distance_ray` where a plane among
/// them divides by its slope along the ray (`march_rest` steps with it).
#[derive(Clone, Debug)]
pub struct Rest {
    pub distance: Func,
    pub distance_ray: Option<Func>,
    pub material: Func,
    pub groups: Vec<Func>,
}

/// The functions of `found`'s other children, or `None` where it has none: `scene` with the
/// union cut down to them, built and optimised as a program's own functions are, and moved
/// to be seen from `relative` where the program marches in coordinates relative to it (the
/// instances' records are, too). The union's analysis is left as it was: its box holds the
/// cut union's, which is all the marcher asks of it.
pub fn rest_functions(
    scene: &Scene,
    found: &Instances,
    relative: Option<[f32; 3]>,
) -> Option<Rest> {
    if found.rest.is_empty() {
        return None;
    }
    let mut cut = scene.clone();
    cut.shapes[found.union.index()].kind = ShapeKind::Combine {
        op: CombineOp::Union,
        smooth: None,
        children: found.rest.clone(),
    };
    if let Some(origin) = relative {
        cut = crate::passes::relative::shift(&cut, origin);
    }
    let cut = crate::passes::merge::run(&cut);
    let funcs = crate::to_ssa::functions(&cut, false);
    let opt = |f: &Func, name: &str| Func {
        name: name.into(),
        ..crate::passes::optimise(f).0
    };
    Some(Rest {
        distance: opt(&funcs.distance, "rest_distance"),
        distance_ray: funcs
            .distance_ray
            .as_ref()
            .map(|f| opt(f, "rest_distance_ray")),
        material: opt(&funcs.material, "rest_material"),
        groups: funcs.groups.iter().map(|g| opt(g, &g.name)).collect(),
    })
}
