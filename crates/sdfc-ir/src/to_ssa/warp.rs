//! The bound-only point maps as arithmetic on `p`: stretch, shear, twist, bend and `warp`,
//! each normalising its child's distance by the map's Lipschitz constant, so that the node's
//! distance stays 1-Lipschitz (see `crate::analysis`).

use super::{Builder, Mat};
use crate::graph::NodeId;
use crate::ops::{Builtin, Helper, Op, Swizzle};
use crate::passes::fold::const_value;
use crate::rounding::f32_up;
use crate::shape::{Declared, ShapeId, WarpMap};
use crate::value::Value;

impl Builder<'_> {
    fn swz(&mut self, v: NodeId, idx: &[u8]) -> NodeId {
        self.op(Op::Swizzle(Swizzle::new(idx)), &[v])
    }

    /// What node `s` divides its field by: the declared bound, or the analysis's constant.
    pub(super) fn divisor(&mut self, s: ShapeId, declared: Declared) -> NodeId {
        if let Some((n, _)) = declared {
            return self.import(n, None);
        }
        let l = self.analysis.nodes[s.index()].lipschitz.unwrap_or(1.0);
        // Heightfields divide p.y - h by sqrt(1 + L^2), which the analysis already reports.
        self.f(f32_up(l.max(1.0)))
    }

    pub(super) fn warp(
        &mut self,
        s: ShapeId,
        map: WarpMap,
        child: ShapeId,
        declared: Declared,
        p: NodeId,
        mat: u32,
    ) -> (NodeId, Option<Mat>) {
        match map {
            WarpMap::Stretch(f) => {
                // min(f) d(p / f): the map p -> p / f is 1/min(f)-Lipschitz.
                let fv = self.import(f, None);
                let q = self.op(Op::Div, &[p, fv]);
                let q = self.hinted(q, "q");
                let (d, m) = self.shape(child, q, mat);
                let k = match const_value(&self.scene.values, f, &mut self.consts) {
                    Some(Value::V3(v)) => self.f(v[0].min(v[1]).min(v[2])),
                    _ => {
                        let (x, y, z) =
                            (self.swz(fv, &[0]), self.swz(fv, &[1]), self.swz(fv, &[2]));
                        let yz = self.g.builtin(Builtin::Min, &[y, z]);
                        self.g.builtin(Builtin::Min, &[x, yz])
                    }
                };
                let d = self.op(Op::Mul, &[d, k]);
                (self.hinted(d, "d"), m)
            }
            WarpMap::Shear(k) => {
                // The inverse of x += kxy y + kxz z, y += kyz z:
                // (x - kxy y + (kxy kyz - kxz) z, y - kyz z, z).
                let kv = self.import(k, None);
                let (kxy, kxz, kyz) = (self.swz(kv, &[0]), self.swz(kv, &[1]), self.swz(kv, &[2]));
                let (x, y, z) = (self.swz(p, &[0]), self.swz(p, &[1]), self.swz(p, &[2]));
                let a = self.op(Op::Mul, &[kxy, kyz]);
                let c = self.op(Op::Sub, &[a, kxz]);
                let t1 = self.op(Op::Mul, &[kxy, y]);
                let t2 = self.op(Op::Mul, &[c, z]);
                let qx = self.op(Op::Sub, &[x, t1]);
                let qx = self.op(Op::Add, &[qx, t2]);
                let t3 = self.op(Op::Mul, &[kyz, z]);
                let qy = self.op(Op::Sub, &[y, t3]);
                let q = self.op(Op::MakeVec, &[qx, qy, z]);
                let q = self.hinted(q, "q");
                let (d, m) = self.shape(child, q, mat);
                let l = match (declared, self.analysis.nodes[s.index()].lipschitz) {
                    (None, Some(l)) => self.f(f32_up(l)),
                    (Some(_), _) => self.divisor(s, declared),
                    (None, None) => {
                        // A shear by params: |I + N| <= 1 + |N|_F, N the off-diagonal part.
                        let n = self.op(Op::MakeVec, &[kxy, kyz, c]);
                        let n = self.g.builtin(Builtin::Length, &[n]);
                        let one = self.f(1.0);
                        self.op(Op::Add, &[one, n])
                    }
                };
                let d = self.op(Op::Div, &[d, l]);
                (self.hinted(d, "d"), m)
            }
            WarpMap::Twist(k) | WarpMap::Bend(k) => {
                let twist = matches!(map, WarpMap::Twist(_));
                let kv = self.import(k, None);
                // Twist turns the slice at height y by k y about y; bend turns the slice at
                // x by k x about z. The rotation helpers apply the inverse turn to the point.
                let (along, plane, helper): (u8, &[u8], Helper) = if twist {
                    (1, &[0, 2], Helper::RotateY)
                } else {
                    (0, &[0, 1], Helper::RotateZ)
                };
                let t = self.swz(p, &[along]);
                let angle = self.op(Op::Mul, &[kv, t]);
                let c = self.g.builtin(Builtin::Cos, &[angle]);
                let sn = self.g.builtin(Builtin::Sin, &[angle]);
                let q = self.op(Op::Helper(helper), &[p, c, sn]);
                let q = self.hinted(q, "q");
                let (d, m) = self.shape(child, q, mat);
                if declared.is_some() {
                    let l = self.divisor(s, declared);
                    let d = self.op(Op::Div, &[d, l]);
                    return (self.hinted(d, "d"), m);
                }
                // The map's Lipschitz constant grows with the distance r from the axis; along
                // the segment from p to the nearest surface point r stays below max(r(p), R),
                // R bounding the child, so dividing by L(max(r(p), R)) is safe everywhere and
                // constant (L(R)) inside the bounds.
                let bounds = &self.analysis.nodes[child.index()].bounds;
                let radius = bounds.radius_about(if twist { 1 } else { 2 });
                let radius = if radius.is_finite() { radius } else { 0.0 };
                let pr = self.swz(p, plane);
                let r = self.g.builtin(Builtin::Length, &[pr]);
                let big_r = self.f(f32_up(radius));
                let r = self.g.builtin(Builtin::Max, &[r, big_r]);
                let ka = self.g.builtin(Builtin::Abs, &[kv]);
                let kr = self.op(Op::Mul, &[ka, r]);
                let one = self.f(1.0);
                let l = if twist {
                    // t + sqrt(1 + t^2), t = |k| r / 2
                    let half = self.f(0.5);
                    let t = self.op(Op::Mul, &[kr, half]);
                    let tt = self.op(Op::Mul, &[t, t]);
                    let u = self.op(Op::Add, &[one, tt]);
                    let u = self.g.builtin(Builtin::Sqrt, &[u]);
                    self.op(Op::Add, &[t, u])
                } else {
                    self.op(Op::Add, &[one, kr])
                };
                let d = self.op(Op::Div, &[d, l]);
                (self.hinted(d, "d"), m)
            }
            WarpMap::Lambda { body, lambda } => {
                let q = self.import(body, Some((lambda, &[p])));
                let q = self.hinted(q, "q");
                let (d, m) = self.shape(child, q, mat);
                let l = self.divisor(s, declared);
                let d = self.op(Op::Div, &[d, l]);
                (self.hinted(d, "d"), m)
            }
        }
    }
}
