//! Primitives as helper calls at a point, with the large sphere near the camera in a form
//! that keeps its precision there.

use super::Builder;
use crate::graph::NodeId;
use crate::ops::{Builtin, Helper, Op, Swizzle};
use crate::shape::Prim;
use crate::value::Value;

impl Builder<'_> {
    /// A large sphere whose surface passes near the frame's origin (the camera, in
    /// camera-relative coordinates), as `|x - c| - r` with `x - c` rounded in f32 is only good
    /// to ulp(|c|), which swamps the depth of a surface a short way in front of the camera
    /// (the stress suite's 1e-3 sphere before a radius-300 one). The same distance reads
    /// `(|x|^2 - 2 x.c + (|c|^2 - r^2)) / (|x - c| + r)`, whose terms are all small near the
    /// origin and whose constant is computed in f64 and rounded once: its error is relative
    /// to |x| there instead of to |c|. Used only for |c| >= 16 (below, ulp(|c|) is under 2e-6
    /// and the plain form's three fewer operations win) where the origin lies within a
    /// quarter of |c| of the surface (elsewhere the plain form is as good), for constant c
    /// and r > 0.
    fn sphere_near_origin(&mut self, p: NodeId, r: NodeId) -> Option<NodeId> {
        let n = *self.g.node(p);
        let (Op::Sub, [x, c]) = (n.op, n.args()) else {
            return None;
        };
        let (x, cn) = (*x, *c);
        let (Some(Value::V3(c)), Some(Value::F(r_f))) = (self.g.as_const(cn), self.g.as_const(r))
        else {
            return None;
        };
        let c64 = c.map(|v| v as f64);
        let len = (c64[0] * c64[0] + c64[1] * c64[1] + c64[2] * c64[2]).sqrt();
        let r64 = r_f as f64;
        if !(r_f > 0.0 && len >= 16.0 && (len - r64).abs() <= 0.25 * len) {
            return None;
        }
        let k = ((len - r64) * (len + r64)) as f32;
        let k = self.f(k);
        let two_c = self.g.vec3(c.map(|v| 2.0 * v));
        let xx = self.g.builtin(Builtin::Dot, &[x, x]);
        let xc = self.g.builtin(Builtin::Dot, &[x, two_c]);
        let num = self.op(Op::Sub, &[xx, xc]);
        let num = self.op(Op::Add, &[num, k]);
        let len_q = self.g.builtin(Builtin::Length, &[p]);
        let den = self.op(Op::Add, &[len_q, r]);
        let d = self.op(Op::Div, &[num, den]);
        Some(self.hinted(d, "d"))
    }

    pub(super) fn prim(&mut self, prim: Prim, args: &[NodeId], p: NodeId) -> NodeId {
        let a: Vec<NodeId> = args.iter().map(|x| self.import(*x, None)).collect();
        self.prim_of(prim, &a, p)
    }

    /// [`Builder::prim`] with its arguments already nodes of the function.
    pub(super) fn prim_of(&mut self, prim: Prim, a: &[NodeId], p: NodeId) -> NodeId {
        let half = self.f(0.5);
        match prim {
            Prim::Sphere => self
                .sphere_near_origin(p, a[0])
                .unwrap_or_else(|| self.op(Op::Helper(Helper::SdSphere), &[p, a[0]])),
            Prim::Box => {
                let b = self.op(Op::Mul, &[a[0], half]);
                self.op(Op::Helper(Helper::SdBox), &[p, b])
            }
            Prim::RoundBox => {
                let b = self.op(Op::Mul, &[a[0], half]);
                let b = self.op(Op::Sub, &[b, a[1]]);
                self.op(Op::Helper(Helper::SdRoundBox), &[p, b, a[1]])
            }
            Prim::Plane => {
                let d = self.g.builtin(Builtin::Dot, &[p, a[0]]);
                let d = self.op(Op::Sub, &[d, a[1]]);
                self.plane_along_ray(d, a[0])
            }
            Prim::Torus => self.op(Op::Helper(Helper::SdTorus), &[p, a[0], a[1]]),
            Prim::Cylinder => {
                let h = self.op(Op::Mul, &[a[1], half]);
                self.op(Op::Helper(Helper::SdCylinder), &[p, a[0], h])
            }
            Prim::Capsule => self.op(Op::Helper(Helper::SdCapsule), &[p, a[0], a[1], a[2]]),
            Prim::BoxFrame => {
                let b = self.op(Op::Mul, &[a[0], half]);
                self.op(Op::Helper(Helper::SdBoxFrame), &[p, b, a[1]])
            }
            Prim::CappedTorus => {
                // The angle is clamped to [0, pi], where the arc test is valid; the upper end
                // is the f32 just below pi, whose sine is positive (f32 pi's is negative,
                // which would cut a sliver along +y out of the full ring).
                let below_pi = f32::from_bits(std::f32::consts::PI.to_bits() - 1);
                let (lo, hi) = (self.f(0.0), self.f(below_pi));
                let angle = self.g.builtin(Builtin::Clamp, &[a[2], lo, hi]);
                let s = self.g.builtin(Builtin::Sin, &[angle]);
                let c = self.g.builtin(Builtin::Cos, &[angle]);
                let sc = self.op(Op::MakeVec, &[s, c]);
                self.op(Op::Helper(Helper::SdCappedTorus), &[p, sc, a[0], a[1]])
            }
            Prim::InfiniteCylinder => {
                let xz = self.op(Op::Swizzle(Swizzle::new(&[0, 2])), &[p]);
                let l = self.g.builtin(Builtin::Length, &[xz]);
                self.op(Op::Sub, &[l, a[0]])
            }
            Prim::Cone => {
                // The frustum from y = 0 (radius r) to y = h (radius 0), centred first.
                let hh = self.op(Op::Mul, &[a[1], half]);
                let zero = self.f(0.0);
                let centre = self.op(Op::MakeVec, &[zero, hh, zero]);
                let q = self.op(Op::Sub, &[p, centre]);
                self.op(Op::Helper(Helper::SdCappedCone), &[q, hh, a[0], zero])
            }
            Prim::CappedCone => {
                let hh = self.op(Op::Mul, &[a[0], half]);
                self.op(Op::Helper(Helper::SdCappedCone), &[p, hh, a[1], a[2]])
            }
            Prim::Ellipsoid => self.op(Op::Helper(Helper::SdEllipsoid), &[p, a[0]]),
            Prim::Octahedron => {
                let s = self.op(Op::Mul, &[a[0], half]);
                self.op(Op::Helper(Helper::SdOctahedron), &[p, s])
            }
            Prim::HexPrism | Prim::TriPrism => {
                let h = self.op(Op::Mul, &[a[1], half]);
                let helper = if prim == Prim::HexPrism {
                    Helper::SdHexPrism
                } else {
                    Helper::SdTriPrism
                };
                self.op(Op::Helper(helper), &[p, a[0], h])
            }
            Prim::Pyramid => self.op(Op::Helper(Helper::SdPyramid), &[p, a[0]]),
            Prim::Mandelbulb => {
                // The power is a constant (the lowering checks it); a whole one gets the
                // trigonometry-free helper.
                let whole = self
                    .g
                    .as_scalar_const(a[0])
                    .is_some_and(|n| n.fract() == 0.0);
                let helper = if whole {
                    Helper::SdMandelbulbInt
                } else {
                    Helper::SdMandelbulb
                };
                self.op(Op::Helper(helper), &[p, a[0], a[1], a[2]])
            }
            Prim::Menger => self.op(Op::Helper(Helper::SdMenger), &[p, a[0]]),
            Prim::Sierpinski => self.op(Op::Helper(Helper::SdSierpinski), &[p, a[0]]),
        }
    }
}
