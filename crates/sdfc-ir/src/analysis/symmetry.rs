//! The axes each shape is mirror-symmetric about (x -> -x and so on, through its origin),
//! which decide how a repetition is lowered: a copy symmetric about a repeated axis is never
//! farther than its neighbours along it from a point of its own cell, so its cell alone
//! gives the distance there; along any other axis the neighbour on the point's side is
//! evaluated too (`to_ssa`). Conservative: an axis not proven symmetric costs one more
//! evaluation, never a wrong distance.

use crate::graph::NodeId;
use crate::hash::FxHashMap;
use crate::passes::fold::const_value;
use crate::scene::Scene;
use crate::shape::{PointMap, Prim, ShapeKind};
use crate::value::Value;

/// For every shape of `scene` (indexed like `Scene::shapes`), whether it is symmetric about
/// each axis.
pub fn mirror_axes(scene: &Scene) -> Vec<[bool; 3]> {
    let mut consts = FxHashMap::default();
    let mut out: Vec<[bool; 3]> = Vec::with_capacity(scene.shapes.len());
    for node in &scene.shapes {
        let of = |c: crate::shape::ShapeId, out: &Vec<[bool; 3]>| out[c.index()];
        let axes = match &node.kind {
            ShapeKind::Prim { prim, .. } => prim_axes(*prim),
            ShapeKind::Combine { children, .. } => children
                .iter()
                .map(|c| of(*c, &out))
                .fold([true; 3], |a, b| [a[0] && b[0], a[1] && b[1], a[2] && b[2]]),
            ShapeKind::Map { map, child } => {
                let c = of(*child, &out);
                match map {
                    PointMap::Affine { m, o, .. } => affine_axes(scene, *m, *o, c, &mut consts),
                    PointMap::Mirror(axis) => {
                        let mut a = c;
                        a[*axis as usize] = true;
                        a
                    }
                    // Copies centred on the origin, and an odd clamp: the child's.
                    PointMap::Repeat { .. }
                    | PointMap::RepeatLimited { .. }
                    | PointMap::Elongate(_) => c,
                }
            }
            ShapeKind::Modify { child, .. } | ShapeKind::Material { child, .. } => of(*child, &out),
            // A displacement, a warp, a heightfield or an `sdf` may be anything.
            ShapeKind::Sdf { .. }
            | ShapeKind::Displace { .. }
            | ShapeKind::Warp { .. }
            | ShapeKind::Heightfield { .. } => [false; 3],
        };
        out.push(axes);
    }
    out
}

/// The primitives' symmetries, from their definitions in `shaders/prims`.
fn prim_axes(prim: Prim) -> [bool; 3] {
    match prim {
        Prim::Sphere
        | Prim::Box
        | Prim::RoundBox
        | Prim::Torus
        | Prim::Cylinder
        | Prim::BoxFrame
        | Prim::InfiniteCylinder
        | Prim::Ellipsoid
        | Prim::Octahedron
        | Prim::HexPrism
        | Prim::Menger => [true; 3],
        // About the y axis, or pointing along +y.
        Prim::CappedTorus | Prim::Cone | Prim::CappedCone | Prim::TriPrism | Prim::Pyramid => {
            [true, false, true]
        }
        Prim::Plane | Prim::Capsule | Prim::Mandelbulb | Prim::Sierpinski => [false; 3],
    }
}

/// `local = (m p + o) / s`: with m a signed permutation on axis k's row and column (a turn
/// about k, or by a multiple of 90 degrees), mirroring p about k mirrors local about the
/// axis j that m sends k to, if o leaves j alone; so the node is symmetric about k where the
/// child is about j. A scale changes nothing.
fn affine_axes(
    scene: &Scene,
    m: Option<NodeId>,
    o: Option<NodeId>,
    child: [bool; 3],
    consts: &mut FxHashMap<NodeId, Option<Value<f32>>>,
) -> [bool; 3] {
    let offset = match o {
        None => Some([0.0f32; 3]),
        Some(o) => match const_value(&scene.values, o, consts) {
            Some(Value::V3(v)) => Some(v),
            _ => None,
        },
    };
    let Some(offset) = offset else {
        return [false; 3];
    };
    // Columns of m; the identity where there is none.
    let cols = match m {
        None => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        Some(m) => match const_value(&scene.values, m, consts) {
            Some(Value::M3(c)) => c,
            _ => return [false; 3],
        },
    };
    [0, 1, 2].map(|k| {
        // Column k has one entry, in row j, and row j none but in column k.
        let mut rows = (0..3).filter(|&r| !zero(cols[k][r]));
        let (Some(j), None) = (rows.next(), rows.next()) else {
            return false;
        };
        let row_alone = (0..3).all(|c| c == k || zero(cols[c][j]));
        row_alone && offset[j] == 0.0 && child[j]
    })
}

/// A matrix entry meant as 0: a turn by 90 degrees leaves f32 rounding there (cos =
/// -4.4e-8), and that little asymmetry moves the distance by as little.
fn zero(x: f32) -> bool {
    x.abs() <= 1e-6
}
