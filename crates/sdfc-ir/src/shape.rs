//! The shape level of the IR: primitives, combinations, point maps and materials, with
//! their numeric arguments as nodes of the scene's value graph.

use crate::graph::NodeId;
use sdfc_syntax::span::Span;

/// Index of a shape node in [`crate::scene::Scene::shapes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ShapeId(pub u32);

impl ShapeId {
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// The primitives, with their arguments as the language takes them (full sizes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Prim {
    /// `[r]`
    Sphere,
    /// `[size: vec3]`
    Box,
    /// `[size: vec3, r]`
    RoundBox,
    /// `[unit normal: vec3, h]`
    Plane,
    /// `[R, r]`
    Torus,
    /// `[r, h]`
    Cylinder,
    /// `[a: vec3, b: vec3, r]`
    Capsule,
    /// `[size: vec3, e]`: the twelve edges of a box of full size `size`, as square bars of
    /// side `e` flush with its faces.
    BoxFrame,
    /// `[R, r, angle]`: a torus arc in the xy plane, the angles within `angle` of +y.
    CappedTorus,
    /// `[r]`: along y.
    InfiniteCylinder,
    /// `[r, h]`: base radius r at y = 0, apex at y = h.
    Cone,
    /// `[h, r1, r2]`: frustum along y from -h/2 (radius r1) to h/2 (radius r2).
    CappedCone,
    /// `[radii: vec3]`: semi-axes.
    Ellipsoid,
    /// `[s]`: full size, vertices at distance s/2 on the axes.
    Octahedron,
    /// `[r, h]`: along z, inradius r, length h.
    HexPrism,
    /// `[r, h]`: along z, equilateral triangle of inradius r pointing to +y, length h.
    TriPrism,
    /// `[h]`: square base [-0.5, 0.5]^2 on y = 0, apex at y = h.
    Pyramid,
    /// `[power, iterations, bound radius]`, all compile-time constants.
    Mandelbulb,
    /// `[iterations]`: in the cube of side 1.
    Menger,
    /// `[iterations]`: on alternate corners of the cube of side 1.
    Sierpinski,
}

impl Prim {
    pub fn name(self) -> &'static str {
        match self {
            Prim::Sphere => "sphere",
            Prim::Box => "box",
            Prim::RoundBox => "round_box",
            Prim::Plane => "plane",
            Prim::Torus => "torus",
            Prim::Cylinder => "cylinder",
            Prim::Capsule => "capsule",
            Prim::BoxFrame => "box_frame",
            Prim::CappedTorus => "capped_torus",
            Prim::InfiniteCylinder => "infinite_cylinder",
            Prim::Cone => "cone",
            Prim::CappedCone => "capped_cone",
            Prim::Ellipsoid => "ellipsoid",
            Prim::Octahedron => "octahedron",
            Prim::HexPrism => "hex_prism",
            Prim::TriPrism => "tri_prism",
            Prim::Pyramid => "pyramid",
            Prim::Mandelbulb => "mandelbulb",
            Prim::Menger => "menger",
            Prim::Sierpinski => "sierpinski",
        }
    }

    /// True when the primitive's formula is the exact Euclidean signed distance everywhere
    /// (inside and outside); false when it is only a bound: the sign is right and
    /// `|d| <= true distance`, with Lipschitz constant at most 1.
    ///
    /// - exact: sphere, box, round_box, plane, torus, cylinder, capsule, box_frame (the
    ///   interior at the corner cubes is computed exactly too), capped_torus,
    ///   infinite_cylinder, cone, capped_cone, octahedron, hex_prism, tri_prism and pyramid
    ///   (both exact inside as well as outside: 2D polygon distances, not the max-of-planes
    ///   bounds).
    /// - bound: ellipsoid (`max((|p / radii| - 1) * min(radii), |p| - max(radii))`, each term a
    ///   1-Lipschitz function that vanishes on the surface only where the ellipsoid does),
    ///   menger and sierpinski (exact sign; the max of exact distances for menger, the distance
    ///   to the nearest level-n tetrahedron bounded by its face planes for sierpinski),
    ///   mandelbulb (the usual `0.5 r ln r / dr` estimate: an estimate believed to
    ///   underestimate, not a proven bound; beyond 1.25 times its bounding radius, the distance to the bounding
    ///   sphere).
    pub fn exact(self) -> bool {
        !matches!(
            self,
            Prim::Ellipsoid | Prim::Mandelbulb | Prim::Menger | Prim::Sierpinski
        )
    }

    /// True when the primitive's distance is an estimate, not a proven bound: the
    /// mandelbulb's (see [`Prim::exact`]). Such a distance may rise along a ray while its
    /// surface is still ahead.
    pub fn estimate(self) -> bool {
        self == Prim::Mandelbulb
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CombineOp {
    Union,
    Intersect,
    /// First child minus the rest.
    Subtract,
    Xor,
}

impl CombineOp {
    pub fn name(self) -> &'static str {
        match self {
            CombineOp::Union => "union",
            CombineOp::Intersect => "intersect",
            CombineOp::Subtract => "subtract",
            CombineOp::Xor => "xor",
        }
    }
}

/// How a node maps the point before its child sees it.
#[derive(Clone, Debug, PartialEq)]
pub enum PointMap {
    /// `local = (m * p + o) / s`, and the child's distance is multiplied by `s`
    /// (rigid motions and uniform scale; `None` is the identity part).
    Affine {
        m: Option<NodeId>,
        o: Option<NodeId>,
        s: Option<NodeId>,
    },
    /// `p[axis] = abs(p[axis])`.
    Mirror(u8),
    /// Infinite repetition; a zero period component leaves that axis alone.
    Repeat { period: [f32; 3] },
    /// `count[i]` copies along each axis, centred on the origin.
    RepeatLimited { period: [f32; 3], count: [u32; 3] },
    /// iq's elongation by `h` (vec3): `p - clamp(p, -h, h)`.
    Elongate(NodeId),
}

impl PointMap {
    /// Half a repetition's period along each axis where its copies have neighbours: 0 where
    /// the axis is not repeated or holds one copy (and for the other maps).
    pub fn half_periods(&self) -> [f64; 3] {
        let (period, count) = match self {
            PointMap::Repeat { period } => (period, None),
            PointMap::RepeatLimited { period, count } => (period, Some(count)),
            _ => return [0.0; 3],
        };
        [0, 1, 2].map(|i| {
            if count.is_some_and(|n| n[i] <= 1) {
                0.0
            } else {
                period[i] as f64 / 2.0
            }
        })
    }
}

/// A declared `lipschitz: L` argument: its value node and where it was written.
pub type Declared = Option<(NodeId, Span)>;

/// Point maps that are not isometries: the child's distance at the mapped point is only a
/// bound, so the node normalises it by the map's Lipschitz constant (see `crate::lipschitz`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WarpMap {
    /// `stretch(s, [sx, sy, sz])`: the child at `p / s`, distance times `min(s)`.
    Stretch(NodeId),
    /// `shear(s, [kxy, kxz, kyz])`: the child at the inverse-sheared point.
    Shear(NodeId),
    /// `twist(s, k)`: about y, `k` radians per unit of y.
    Twist(NodeId),
    /// `bend(s, k)`: in the xy plane, `k` radians per unit of x.
    Bend(NodeId),
    /// `warp(s, |p| v)`: the child at `v(p)` (a vec3 body of lambda `lambda`).
    Lambda { body: NodeId, lambda: u32 },
}

impl WarpMap {
    pub fn name(self) -> &'static str {
        match self {
            WarpMap::Stretch(_) => "stretch",
            WarpMap::Shear(_) => "shear",
            WarpMap::Twist(_) => "twist",
            WarpMap::Bend(_) => "bend",
            WarpMap::Lambda { .. } => "warp",
        }
    }
}

/// How a node changes its child's distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DistMod {
    /// `d - r`
    Round(NodeId),
    /// `abs(d) - t`
    Onion(NodeId),
}

#[derive(Clone, Debug, PartialEq)]
pub enum ShapeKind {
    Prim {
        prim: Prim,
        args: Vec<NodeId>,
    },
    /// `sdf(|p| body, lipschitz: L)`: the body uses `LambdaArg { lambda, 0 }` as its point;
    /// `declared` is where `lipschitz:` was written (absent: the default 1).
    Sdf {
        body: NodeId,
        lambda: u32,
        lipschitz: NodeId,
        declared: Option<Span>,
    },
    /// `displace(child, |p| body, lipschitz: L)`: `(d + body(p)) / L`, with `L` the declared
    /// bound of the displaced distance, or the one `crate::lipschitz` derives when none is.
    Displace {
        child: ShapeId,
        body: NodeId,
        lambda: u32,
        lipschitz: Declared,
    },
    /// A non-isometric point map (stretch, shear, twist, bend, warp), normalised at the node.
    Warp {
        map: WarpMap,
        child: ShapeId,
        lipschitz: Declared,
    },
    /// `heightfield(|x, z| h, lipschitz: L)`: `(p.y - h(p.x, p.z)) / sqrt(1 + L^2)`; the
    /// body uses `LambdaArg { lambda, 0 }` for x and `{ lambda, 1 }` for z.
    Heightfield {
        body: NodeId,
        lambda: u32,
        lipschitz: Declared,
    },
    Combine {
        op: CombineOp,
        smooth: Option<NodeId>,
        children: Vec<ShapeId>,
    },
    Map {
        map: PointMap,
        child: ShapeId,
    },
    Modify {
        modifier: DistMod,
        child: ShapeId,
    },
    /// The child's parts that have no material of their own get material `material`.
    Material {
        material: u32,
        child: ShapeId,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct ShapeNode {
    pub kind: ShapeKind,
    pub span: Span,
}
