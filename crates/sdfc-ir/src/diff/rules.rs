//! The derivative rules of forward-mode differentiation, one per operation: the tangent of a
//! node along one axis from its arguments' tangents along that axis.

use super::{Differ, Tangent};
use crate::graph::NodeId;
use crate::ops::{Builtin, Helper, Op};
use crate::types::Ty;
use crate::value::Value;

/// A divisor floor where a derivative is infinite (the tip of `sqrt`, the centre of
/// `length`): there the gradient is taken as finite rather than NaN, which WGSL lets an
/// implementation assume never occurs.
const TINY: f32 = 1e-30;

impl Differ {
    pub(crate) fn zero(&mut self, ty: Ty) -> NodeId {
        self.konst_like(0.0, ty)
    }

    /// The constant `x` in every component of `ty` (a vector constant, not a splat).
    pub(crate) fn konst_like(&mut self, x: f32, ty: Ty) -> NodeId {
        let v = Value::from_comps(ty, &vec![x; ty.width().max(1)]);
        self.g.konst(v)
    }

    fn fill(&mut self, t: Option<NodeId>, ty: Ty) -> NodeId {
        match t {
            Some(t) => self.g.splat(t, ty),
            None => self.zero(ty),
        }
    }

    fn t_add(&mut self, a: Option<NodeId>, b: Option<NodeId>, ty: Ty) -> Option<NodeId> {
        match (a, b) {
            (None, None) => None,
            (Some(x), None) | (None, Some(x)) => Some(self.g.splat(x, ty)),
            (Some(x), Some(y)) => Some(self.op(Op::Add, &[x, y])),
        }
    }

    fn t_sub(&mut self, a: Option<NodeId>, b: Option<NodeId>, ty: Ty) -> Option<NodeId> {
        match (a, b) {
            (None, None) => None,
            (Some(x), None) => Some(self.g.splat(x, ty)),
            (None, Some(y)) => {
                let y = self.g.splat(y, ty);
                Some(self.op(Op::Neg, &[y]))
            }
            (Some(x), Some(y)) => Some(self.op(Op::Sub, &[x, y])),
        }
    }

    /// `t * f` (broadcasting).
    fn t_mul(&mut self, t: Option<NodeId>, f: NodeId) -> Option<NodeId> {
        t.map(|t| self.op(Op::Mul, &[t, f]))
    }

    fn max_tiny(&mut self, x: NodeId) -> NodeId {
        let ty = self.g.ty(x);
        let tiny = self.konst_like(TINY, ty);
        self.bop(Builtin::Max, &[x, tiny])
    }

    /// The tangents of node `id`, whose arguments already have theirs.
    pub(super) fn rule(&mut self, id: NodeId) -> Tangent {
        let node = *self.g.node(id);
        let a: Vec<NodeId> = node.args().to_vec();
        let ty = node.ty;
        let ta: Vec<Tangent> = a.iter().map(|x| self.tangent(*x)).collect();
        let mut out: Tangent = [None; 3];
        // Rules built from other nodes whose tangents follow by the same rules: the
        // expansion's tangent is the node's.
        if let Some(e) = self.expansion(node.op, &a, ty) {
            return self.tangent(e);
        }
        if let Op::Helper(h) = node.op {
            if let Some(e) = self.helper_expansion(h, &a) {
                return self.tangent(e);
            }
        }
        for k in 0..3 {
            let t = |i: usize| ta[i][k];
            out[k] = match node.op {
                Op::Point => {
                    let mut e = [0.0; 3];
                    e[k] = 1.0;
                    Some(self.g.vec3(e))
                }
                Op::Const(_)
                | Op::Ray
                | Op::Param(_)
                | Op::Time
                | Op::Best
                | Op::LambdaArg { .. }
                | Op::Call { .. }
                | Op::Lt
                | Op::Le
                | Op::Gt
                | Op::Ge
                | Op::Eq
                | Op::Ne => None,
                Op::Neg => t(0).map(|x| self.op(Op::Neg, &[x])),
                Op::Add => self.t_add(t(0), t(1), ty),
                Op::Sub => self.t_sub(t(0), t(1), ty),
                Op::Mul => {
                    let x = self.t_mul(t(0), a[1]);
                    let y = t(1).map(|tb| self.op(Op::Mul, &[a[0], tb]));
                    self.t_add(x, y, ty)
                }
                Op::MatMul => {
                    let x = t(0).map(|tm| self.op(Op::MatMul, &[tm, a[1]]));
                    let y = t(1).map(|tx| self.op(Op::MatMul, &[a[0], tx]));
                    self.t_add(x, y, ty)
                }
                // (ta - (a / b) tb) / b
                Op::Div => {
                    let y = t(1).map(|tb| self.op(Op::Mul, &[id, tb]));
                    self.t_sub(t(0), y, ty)
                        .map(|n| self.op(Op::Div, &[n, a[1]]))
                }
                // a - b floor(a / b)
                Op::Mod => {
                    let q = self.op(Op::Div, &[a[0], a[1]]);
                    let f = self.bop(Builtin::Floor, &[q]);
                    let y = self.t_mul(t(1), f);
                    self.t_sub(t(0), y, ty)
                }
                Op::Select => {
                    if t(0).is_none() && t(1).is_none() {
                        None
                    } else {
                        let (x, y) = (self.fill(t(0), ty), self.fill(t(1), ty));
                        Some(self.op(Op::Select, &[x, y, a[2]]))
                    }
                }
                Op::MakeVec => {
                    if (0..a.len()).all(|i| t(i).is_none()) {
                        None
                    } else {
                        let c: Vec<NodeId> =
                            (0..a.len()).map(|i| self.fill(t(i), Ty::F32)).collect();
                        Some(self.op(Op::MakeVec, &c))
                    }
                }
                Op::MakeMat3 => {
                    if (0..3).all(|i| t(i).is_none()) {
                        None
                    } else {
                        let c: Vec<NodeId> = (0..3).map(|i| self.fill(t(i), Ty::Vec3)).collect();
                        Some(self.op(Op::MakeMat3, &c))
                    }
                }
                Op::Swizzle(_) | Op::Transpose => t(0).map(|x| self.op(node.op, &[x])),
                Op::Builtin(b) => self.builtin_rule(b, id, &a, &|i| t(i), ty),
                Op::Helper(h) => self.helper_rule(h, &a, &ta, k),
            };
            if out[k].is_some_and(|t| self.is_zero(t)) {
                out[k] = None;
            }
        }
        out
    }

    fn builtin_rule(
        &mut self,
        b: Builtin,
        id: NodeId,
        a: &[NodeId],
        t: &dyn Fn(usize) -> Option<NodeId>,
        ty: Ty,
    ) -> Option<NodeId> {
        use Builtin::*;
        let bi = |d: &mut Differ, f: Builtin, args: &[NodeId]| d.bop(f, args);
        match b {
            Sign | Floor | Ceil | Round | Step => None,
            Fract => t(0),
            Abs => {
                let s = bi(self, Sign, &[a[0]]);
                self.t_mul(t(0), s)
            }
            Sqrt => {
                let ta = t(0)?;
                let s = self.max_tiny(id);
                let half = self.konst_like(0.5, ty);
                let f = self.op(Op::Div, &[half, s]);
                Some(self.op(Op::Mul, &[ta, f]))
            }
            Exp => self.t_mul(t(0), id),
            Log => t(0).map(|x| self.op(Op::Div, &[x, a[0]])),
            Sin => {
                let c = bi(self, Cos, &[a[0]]);
                self.t_mul(t(0), c)
            }
            Cos => {
                let s = bi(self, Sin, &[a[0]]);
                let s = self.op(Op::Neg, &[s]);
                self.t_mul(t(0), s)
            }
            // 1 + tan^2
            Tan => {
                let ta = t(0)?;
                let sq = self.op(Op::Mul, &[id, id]);
                let one = self.konst_like(1.0, ty);
                let f = self.op(Op::Add, &[one, sq]);
                Some(self.op(Op::Mul, &[ta, f]))
            }
            Asin | Acos => {
                let ta = t(0)?;
                let sq = self.op(Op::Mul, &[a[0], a[0]]);
                let one = self.konst_like(1.0, ty);
                let r = self.op(Op::Sub, &[one, sq]);
                let r = self.max_tiny(r);
                let r = bi(self, Sqrt, &[r]);
                let x = self.op(Op::Div, &[ta, r]);
                Some(if b == Acos { self.op(Op::Neg, &[x]) } else { x })
            }
            Atan => {
                let ta = t(0)?;
                let sq = self.op(Op::Mul, &[a[0], a[0]]);
                let one = self.konst_like(1.0, ty);
                let r = self.op(Op::Add, &[one, sq]);
                Some(self.op(Op::Div, &[ta, r]))
            }
            // atan2(y, x): (x ty - y tx) / (x^2 + y^2)
            Atan2 => {
                let x = t(1).map(|tx| self.op(Op::Mul, &[a[0], tx]));
                let y = t(0).map(|ty_| self.op(Op::Mul, &[a[1], ty_]));
                let n = self.t_sub(y, x, ty)?;
                let xx = self.op(Op::Mul, &[a[1], a[1]]);
                let yy = self.op(Op::Mul, &[a[0], a[0]]);
                let r = self.op(Op::Add, &[xx, yy]);
                let r = self.max_tiny(r);
                Some(self.op(Op::Div, &[n, r]))
            }
            // The argument the result took: a where a <= b (min), a where a >= b (max).
            Min | Max => {
                if t(0).is_none() && t(1).is_none() {
                    return None;
                }
                let w = if b == Min {
                    bi(self, Step, &[a[0], a[1]])
                } else {
                    bi(self, Step, &[a[1], a[0]])
                };
                let (x, y) = (self.fill(t(0), ty), self.fill(t(1), ty));
                let diff = self.op(Op::Sub, &[x, y]);
                let m = self.op(Op::Mul, &[diff, w]);
                Some(self.op(Op::Add, &[y, m]))
            }
            Dot => {
                let x = t(0).map(|x| bi(self, Dot, &[x, a[1]]));
                let y = t(1).map(|y| bi(self, Dot, &[a[0], y]));
                self.t_add(x, y, Ty::F32)
            }
            Cross => {
                let x = t(0).map(|x| bi(self, Cross, &[x, a[1]]));
                let y = t(1).map(|y| bi(self, Cross, &[a[0], y]));
                self.t_add(x, y, Ty::Vec3)
            }
            Length => {
                let ta = t(0)?;
                if self.g.ty(a[0]) == Ty::F32 {
                    let s = bi(self, Sign, &[a[0]]);
                    return Some(self.op(Op::Mul, &[ta, s]));
                }
                let n = bi(self, Dot, &[a[0], ta]);
                let l = self.max_tiny(id);
                Some(self.op(Op::Div, &[n, l]))
            }
            // (ta - n (n . ta)) / |a|
            Normalize => {
                let ta = t(0)?;
                let l = bi(self, Length, &[a[0]]);
                let l = self.max_tiny(l);
                let nd = bi(self, Dot, &[id, ta]);
                let along = self.op(Op::Mul, &[id, nd]);
                let perp = self.op(Op::Sub, &[ta, along]);
                Some(self.op(Op::Div, &[perp, l]))
            }
            Radians | Degrees => {
                let f = if b == Radians {
                    std::f32::consts::PI / 180.0
                } else {
                    180.0 / std::f32::consts::PI
                };
                let f = self.g.f32(f);
                self.t_mul(t(0), f)
            }
            // Expanded in `expansion` (clamp, mix, smoothstep, distance, pow); unreachable.
            Clamp | Mix | Smoothstep | Distance | Pow => None,
        }
    }

    /// Rotations about an axis are linear in the point (and in their cosine and sine:
    /// `R(c, s) p = c A p + s B p + C p`, so the tangent is `R(c, s) tp + R(tc, ts) p - C p`);
    /// noise's tangent is its gradient (`noise_gradient`) dotted with its point's.
    fn helper_rule(&mut self, h: Helper, a: &[NodeId], ta: &[Tangent], k: usize) -> Option<NodeId> {
        if matches!(h, Helper::RotateX | Helper::RotateY | Helper::RotateZ) {
            let x = ta[0][k].map(|tp| self.op(Op::Helper(h), &[tp, a[1], a[2]]));
            if ta[1][k].is_none() && ta[2][k].is_none() {
                return x;
            }
            let tc = self.fill(ta[1][k], Ty::F32);
            let ts = self.fill(ta[2][k], Ty::F32);
            let y = self.op(Op::Helper(h), &[a[0], tc, ts]);
            let z = self.g.f32(0.0);
            let axis = self.op(Op::Helper(h), &[a[0], z, z]);
            let y = self.op(Op::Sub, &[y, axis]);
            return self.t_add(x, Some(y), Ty::Vec3);
        }
        let tp = ta[0][k]?;
        // The helpers' other arguments (sizes, iteration counts) never depend on the point;
        // every distance helper but noise has an expansion (`helpers.rs`).
        match h {
            Helper::Noise => {
                let grad = self.op(Op::Helper(Helper::NoiseGradient), &[a[0]]);
                Some(self.bop(Builtin::Dot, &[grad, tp]))
            }
            _ => None,
        }
    }

    /// Operations whose tangent is that of an equivalent expression in simpler ones.
    fn expansion(&mut self, op: Op, a: &[NodeId], ty: Ty) -> Option<NodeId> {
        let Op::Builtin(b) = op else {
            return None;
        };
        use Builtin::*;
        Some(match b {
            // min(max(x, lo), hi)
            Clamp => {
                let m = self.node(Op::Builtin(Max), &[a[0], a[1]]);
                self.node(Op::Builtin(Min), &[m, a[2]])
            }
            // a + (b - a) t
            Mix => {
                let d = self.node(Op::Sub, &[a[1], a[0]]);
                let m = self.node(Op::Mul, &[d, a[2]]);
                self.node(Op::Add, &[a[0], m])
            }
            // u^2 (3 - 2u), u = clamp((x - e0) / (e1 - e0), 0, 1)
            Smoothstep => {
                let n = self.node(Op::Sub, &[a[2], a[0]]);
                let w = self.node(Op::Sub, &[a[1], a[0]]);
                let u = self.node(Op::Div, &[n, w]);
                let (z, one) = (self.zero(ty), self.konst_like(1.0, ty));
                let u = self.node(Op::Builtin(Clamp), &[u, z, one]);
                let (two, three) = (self.konst_like(2.0, ty), self.konst_like(3.0, ty));
                let tu = self.node(Op::Mul, &[two, u]);
                let r = self.node(Op::Sub, &[three, tu]);
                let uu = self.node(Op::Mul, &[u, u]);
                self.node(Op::Mul, &[uu, r])
            }
            Distance => {
                let d = self.node(Op::Sub, &[a[0], a[1]]);
                self.node(Op::Builtin(Length), &[d])
            }
            // exp(b log a) where the exponent varies; b a^(b - 1) ta otherwise (below).
            Pow => {
                if self.tangent(a[1]) == [None; 3] {
                    // pow(a, b) with a constant exponent: a tangent-free stand-in whose
                    // tangent rule is b a^(b-1) ta, built directly.
                    return self.pow_const_exponent(a, ty);
                }
                let l = self.node(Op::Builtin(Log), &[a[0]]);
                let m = self.node(Op::Mul, &[a[1], l]);
                self.node(Op::Builtin(Exp), &[m])
            }
            _ => return None,
        })
    }

    /// `pow(a, b)` for an exponent that does not depend on the point: the node itself, with
    /// the tangents `b pow(a, b - 1) ta` recorded for it.
    fn pow_const_exponent(&mut self, a: &[NodeId], ty: Ty) -> Option<NodeId> {
        let id = self.bop(Builtin::Pow, a);
        let ta = self.tangent(a[0]);
        let one = self.konst_like(1.0, self.g.ty(a[1]));
        let bm1 = self.op(Op::Sub, &[a[1], one]);
        let pw = self.bop(Builtin::Pow, &[a[0], bm1]);
        let f = self.op(Op::Mul, &[a[1], pw]);
        let t = ta.map(|t| t.map(|t| self.op(Op::Mul, &[t, f])));
        let _ = ty;
        self.set_tangent(id, t);
        Some(id)
    }

    /// A constant value's node (for the helpers' expansions).
    pub(crate) fn value(&mut self, v: Value<f32>) -> NodeId {
        self.g.konst(v)
    }
}
