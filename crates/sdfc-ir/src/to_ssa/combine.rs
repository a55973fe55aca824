//! Combinations: hard and smooth unions, intersections, differences and xor, and the
//! material each picks or blends.

use super::{Builder, Mat, FREE_OF_GROUPS, GROUP_SIZE};
use crate::graph::NodeId;
use crate::ops::{Builtin, Op};
use crate::shape::{CombineOp, ShapeId};
use crate::types::Ty;

impl Builder<'_> {
    pub(super) fn combine(
        &mut self,
        op: CombineOp,
        smooth: Option<NodeId>,
        children: &[ShapeId],
        p: NodeId,
        mat: u32,
    ) -> (NodeId, Option<Mat>) {
        if op == CombineOp::Union && smooth.is_none() && self.cull {
            if let Some(out) = self.culled_union(children, p, mat) {
                return out;
            }
        }
        let parts: Vec<(NodeId, Option<Mat>)> =
            if op == CombineOp::Union && smooth.is_none() && children.len() > GROUP_SIZE {
                // A few unbounded children (a floor) stay out of the groups, first: a group
                // function never sees the ray's direction, and a floor's distance along the
                // ray (`plane_along_ray`) is what its grazing rays need, as the culled
                // union's and a union read as data's other children have it.
                let (free, bounded): (Vec<ShapeId>, Vec<ShapeId>) =
                    children.iter().partition(|c| self.bounded(**c).is_none());
                let (free, grouped) = if free.len() <= FREE_OF_GROUPS && !bounded.is_empty() {
                    (free, bounded)
                } else {
                    (Vec::new(), children.to_vec())
                };
                // Balanced groups of at most GROUP_SIZE children each, and at most
                // GROUP_SIZE groups: a larger union becomes a tree of groups (each group
                // splits its own children again), so no function grows with the scene.
                let n = grouped.len().div_ceil(GROUP_SIZE).min(GROUP_SIZE);
                let per = grouped.len().div_ceil(n);
                let mut parts: Vec<(NodeId, Option<Mat>)> =
                    free.iter().map(|c| self.shape(*c, p, mat)).collect();
                for c in grouped.chunks(per) {
                    let part = self.group(c, p, mat);
                    parts.push(part);
                }
                parts
            } else {
                children.iter().map(|c| self.shape(*c, p, mat)).collect()
            };
        let Some(&(mut d, mut m)) = parts.first() else {
            let far = self.f(1e30);
            return (far, self.materials.then(|| self.material_const(mat)));
        };
        let k = smooth.map(|k| {
            let k = self.import(k, None);
            if self.g.as_const(k).is_some() {
                k
            } else {
                // A param may be 0 at run time: keep the division finite.
                let tiny = self.f(1e-20);
                self.g.builtin(Builtin::Max, &[k, tiny])
            }
        });
        for &(e, me) in &parts[1..] {
            let (nd, h) = match (op, k) {
                (CombineOp::Union, None) => (self.g.builtin(Builtin::Min, &[d, e]), None),
                (CombineOp::Intersect, None) => (self.g.builtin(Builtin::Max, &[d, e]), None),
                (CombineOp::Subtract, None) => {
                    let ne = self.op(Op::Neg, &[e]);
                    (self.g.builtin(Builtin::Max, &[d, ne]), None)
                }
                (CombineOp::Xor, _) => {
                    let lo = self.g.builtin(Builtin::Min, &[d, e]);
                    let hi = self.g.builtin(Builtin::Max, &[d, e]);
                    let nhi = self.op(Op::Neg, &[hi]);
                    (self.g.builtin(Builtin::Max, &[lo, nhi]), None)
                }
                (_, Some(k)) => {
                    let (nd, h) = self.smooth(op, d, e, k);
                    (nd, Some(h))
                }
            };
            if let (Some(ma), Some(mb)) = (m, me) {
                m = Some(self.blend(op, d, e, ma, mb, h));
            }
            d = self.hinted(nd, "d");
        }
        (d, m)
    }

    /// iq's polynomial smooth min/max: returns the distance and the weight `h` of the first
    /// operand, which materials blend with.
    fn smooth(&mut self, op: CombineOp, a: NodeId, b: NodeId, k: NodeId) -> (NodeId, NodeId) {
        let half = self.f(0.5);
        let zero = self.f(0.0);
        let one = self.f(1.0);
        // Union: h = clamp(0.5 + 0.5 (b - a) / k, 0, 1), d = mix(b, a, h) - k h (1 - h).
        // Intersect: h = clamp(0.5 - 0.5 (b - a) / k, 0, 1), d = mix(b, a, h) + k h (1 - h).
        // Subtract (a minus b): h = clamp(0.5 - 0.5 (a + b) / k, 0, 1) weighs a against -b.
        let (num, other, plus) = match op {
            CombineOp::Union => (self.op(Op::Sub, &[b, a]), b, false),
            CombineOp::Intersect => (self.op(Op::Sub, &[a, b]), b, true),
            _ => {
                let s = self.op(Op::Add, &[a, b]);
                let nb = self.op(Op::Neg, &[b]);
                (s, nb, true)
            }
        };
        let t = self.op(Op::Div, &[num, k]);
        let t = self.op(Op::Mul, &[half, t]);
        let t = self.op(Op::Add, &[half, t]);
        let h = self.g.builtin(Builtin::Clamp, &[t, zero, one]);
        let h = self.hinted(h, "h");
        let mixed = self.g.builtin(Builtin::Mix, &[other, a, h]);
        let omh = self.op(Op::Sub, &[one, h]);
        let kh = self.op(Op::Mul, &[k, h]);
        let corr = self.op(Op::Mul, &[kh, omh]);
        let d = self.op(if plus { Op::Add } else { Op::Sub }, &[mixed, corr]);
        (d, h)
    }

    /// The material after combining `a` (distance `da`) with `b` (distance `db`): the operand
    /// that decides the distance gives its material; smooth operators blend by `h`.
    pub(super) fn blend(
        &mut self,
        op: CombineOp,
        da: NodeId,
        db: NodeId,
        ma: Mat,
        mb: Mat,
        h: Option<NodeId>,
    ) -> Mat {
        // One material on both sides needs no choice (and mix(m, m, h) would round).
        if ma == mb {
            return ma;
        }
        if let Some(h) = h {
            let h4 = self.g.splat(h, Ty::Vec4);
            return [0, 1].map(|i| {
                if ma[i] == mb[i] {
                    return ma[i];
                }
                let n = self.g.builtin(Builtin::Mix, &[mb[i], ma[i], h4]);
                self.hinted(n, "m")
            });
        }
        let take_b = match op {
            CombineOp::Union => self.op(Op::Lt, &[db, da]),
            CombineOp::Intersect => self.op(Op::Gt, &[db, da]),
            CombineOp::Subtract => {
                let nb = self.op(Op::Neg, &[db]);
                self.op(Op::Gt, &[nb, da])
            }
            CombineOp::Xor => {
                let aa = self.g.builtin(Builtin::Abs, &[da]);
                let ab = self.g.builtin(Builtin::Abs, &[db]);
                self.op(Op::Lt, &[ab, aa])
            }
        };
        [0, 1].map(|i| {
            if ma[i] == mb[i] {
                return ma[i];
            }
            let n = self.op(Op::Select, &[ma[i], mb[i], take_b]);
            self.hinted(n, "m")
        })
    }
}
