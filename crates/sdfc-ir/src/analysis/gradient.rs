//! A forward bound on values and gradients over the value DAG: for every component of every
//! node an interval of values and an upper bound on the norm of its gradient with respect
//! to the point, given intervals for the inputs. This is how the compiler derives a
//! Lipschitz bound for a point function (`displace`, `warp`, `heightfield`) nobody declared.

use crate::graph::{Graph, NodeId};
use crate::ops::{Builtin, Helper, Op};
use crate::value::Value;

/// Upper bound on `|grad noise(p)|`. Per axis: the trilinear blend of the corner terms moves
/// at most 1 (each corner's gradient vector has entries in {0, +-1} and the weights sum to
/// 1), and the fade weights (slope at most 15/8) move between corner terms that differ by at
/// most 4; so at most 1 + 7.5 per axis, and `sqrt(3) * 8.5` for the gradient's norm.
pub const NOISE_LIPSCHITZ: f64 = 14.73;

/// Upper bound on each partial derivative of `noise` (the per-axis bound above).
const NOISE_PARTIAL: f64 = 8.5;

/// One float component: its value interval and two bounds on its gradient, `g` on the
/// norm and `v` on each partial derivative (`INFINITY` where the component is not
/// Lipschitz in the point, or nothing bounds it). Each catches what the other loses:
/// `length(p)` has `g` 1 but partials (1, 1, 1); an identity map has Jacobian rows whose
/// norms give sqrt(3) but whose partials give the exact norm 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comp {
    pub lo: f64,
    pub hi: f64,
    pub g: f64,
    pub v: [f64; 3],
}

impl Comp {
    pub const UNKNOWN: Comp = Comp {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
        g: f64::INFINITY,
        v: [f64::INFINITY; 3],
    };

    /// Point coordinate `axis` ranging over `[lo, hi]`.
    pub fn coord(axis: usize, lo: f64, hi: f64) -> Comp {
        let mut v = [0.0; 3];
        v[axis] = 1.0;
        Comp { lo, hi, g: 1.0, v }
    }

    /// Something that does not depend on the point, with values in `[lo, hi]`.
    pub fn fixed(lo: f64, hi: f64) -> Comp {
        Comp {
            lo,
            hi,
            g: 0.0,
            v: [0.0; 3],
        }
    }

    fn constant(x: f64) -> Comp {
        Comp::fixed(x, x)
    }

    /// The better of the two gradient-norm bounds.
    pub fn slope(self) -> f64 {
        self.g.min(norm(&self.v))
    }

    /// Both gradient bounds times `m` (a zero gradient stays zero).
    fn scaled(self, m: f64) -> (f64, [f64; 3]) {
        (scale(m, self.g), self.v.map(|x| scale(m, x)))
    }

    /// Largest magnitude.
    pub fn mag(self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }

    /// Smallest magnitude.
    fn min_mag(self) -> f64 {
        if self.lo <= 0.0 && self.hi >= 0.0 {
            0.0
        } else {
            self.lo.abs().min(self.hi.abs())
        }
    }

    /// A function of this component that is not Lipschitz (a step, a floor).
    fn jumpy(self, lo: f64, hi: f64) -> Comp {
        Comp {
            lo,
            hi,
            g: inf_unless_zero(self.g),
            v: self.v.map(inf_unless_zero),
        }
    }
}

fn inf_unless_zero(x: f64) -> f64 {
    if x == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

fn norm(v: &[f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn vadd(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn vmax(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0].max(b[0]), a[1].max(b[1]), a[2].max(b[2])]
}

/// A component from an interval and gradient bounds, the norm bound tightened by the
/// partials' norm.
fn comp(lo: f64, hi: f64, g: f64, v: [f64; 3]) -> Comp {
    Comp {
        lo,
        hi,
        g: g.min(norm(&v)),
        v,
    }
}

/// `m * g` where a zero gradient times an unbounded magnitude stays zero.
fn scale(m: f64, g: f64) -> f64 {
    if g == 0.0 || m == 0.0 {
        0.0
    } else {
        m * g
    }
}

fn add(a: Comp, b: Comp) -> Comp {
    comp(a.lo + b.lo, a.hi + b.hi, a.g + b.g, vadd(a.v, b.v))
}

fn neg(a: Comp) -> Comp {
    Comp {
        lo: -a.hi,
        hi: -a.lo,
        ..a
    }
}

/// `a * ga + b * gb` for both gradient bounds.
fn combine(a: Comp, ma: f64, b: Comp, mb: f64) -> (f64, [f64; 3]) {
    let (g1, v1) = a.scaled(ma);
    let (g2, v2) = b.scaled(mb);
    (g1 + g2, vadd(v1, v2))
}

fn mul(a: Comp, b: Comp) -> Comp {
    let p = [a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi];
    let (lo, hi) = hull(&p);
    let (g, v) = combine(a, b.mag(), b, a.mag());
    comp(lo, hi, g, v)
}

fn div(a: Comp, b: Comp) -> Comp {
    let m = b.min_mag();
    if m == 0.0 {
        return Comp::UNKNOWN.jumpy_from(&[a, b]);
    }
    let p = [a.lo / b.lo, a.lo / b.hi, a.hi / b.lo, a.hi / b.hi];
    let (lo, hi) = hull(&p);
    let (g, v) = combine(a, 1.0 / m, b, a.mag() / (m * m));
    comp(lo, hi, g, v)
}

impl Comp {
    /// These values, with gradients zero where all of `from`'s are and unbounded elsewhere.
    fn jumpy_from(self, from: &[Comp]) -> Comp {
        let g = from.iter().map(|c| c.g).sum::<f64>();
        let v = from.iter().map(|c| c.v).fold([0.0; 3], vadd);
        Comp {
            g: inf_unless_zero(g),
            v: v.map(inf_unless_zero),
            ..self
        }
    }
}

/// The interval spanned by some values (NaN, from `0 * inf`, widens to everything).
fn hull(v: &[f64]) -> (f64, f64) {
    if v.iter().any(|x| x.is_nan()) {
        return (f64::NEG_INFINITY, f64::INFINITY);
    }
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (lo, hi)
}

/// A smooth scalar function with derivative bounded by `slope` on the argument's interval.
fn smooth(a: Comp, lo: f64, hi: f64, slope: f64) -> Comp {
    let (g, v) = a.scaled(slope);
    comp(lo, hi, g, v)
}

/// Bounds of every component of `root`, with `input` giving the components of input nodes
/// (lambda parameters, params, time) given the node's width; `None` from it means unknown.
pub fn bound(g: &Graph, root: NodeId, input: &dyn Fn(Op, usize) -> Option<Vec<Comp>>) -> Vec<Comp> {
    let mut need = vec![false; root.index() + 1];
    need[root.index()] = true;
    for i in (0..=root.index()).rev() {
        if need[i] {
            for a in g.node(NodeId(i as u32)).args() {
                need[a.index()] = true;
            }
        }
    }
    let mut vals: Vec<Vec<Comp>> = vec![Vec::new(); root.index() + 1];
    for i in 0..=root.index() {
        if !need[i] {
            continue;
        }
        let node = g.node(NodeId(i as u32));
        let args: Vec<&[Comp]> = node.args().iter().map(|a| &vals[a.index()][..]).collect();
        let width = node.ty.width().max(1);
        let out = match node.op {
            Op::Const(c) => match c.to_value() {
                Value::B(_) => vec![Comp::constant(0.0)],
                v => v
                    .comps()
                    .iter()
                    .map(|x| Comp::constant(*x as f64))
                    .collect(),
            },
            op if op.is_input() => input(op, width).unwrap_or_else(|| vec![Comp::UNKNOWN; width]),
            op => apply(op, &args, width),
        };
        vals[i] = if out.len() == width {
            out
        } else {
            vec![Comp::UNKNOWN; width]
        };
    }
    std::mem::take(&mut vals[root.index()])
}

/// Component `i` of an argument, a scalar broadcasting over vectors.
fn at(a: &[Comp], i: usize) -> Comp {
    if a.len() == 1 {
        a[0]
    } else {
        a.get(i).copied().unwrap_or(Comp::UNKNOWN)
    }
}

/// A bound on the spectral norm of a vector's Jacobian: the rows' norms give the
/// Frobenius norm, the partials a matrix whose spectral norm bounds the Jacobian's.
pub fn jacobian_norm(v: &[Comp]) -> f64 {
    let frob = v.iter().map(|c| c.g * c.g).sum::<f64>().sqrt();
    let partials = if v.len() <= 3 {
        let mut rows = [[0.0; 3]; 3];
        for (r, c) in rows.iter_mut().zip(v) {
            *r = c.v;
        }
        if rows.iter().flatten().all(|x| x.is_finite()) {
            super::spectral_norm(rows)
        } else {
            f64::INFINITY
        }
    } else {
        f64::INFINITY
    };
    frob.min(partials)
}

/// Bounds on the partial derivatives of a function of a vector whose own gradient norm is at
/// most 1: column norms of the vector's partials.
fn column_norms(v: &[Comp]) -> [f64; 3] {
    [0, 1, 2].map(|j| v.iter().map(|c| c.v[j] * c.v[j]).sum::<f64>().sqrt())
}

fn apply(op: Op, a: &[&[Comp]], width: usize) -> Vec<Comp> {
    let each = |f: &dyn Fn(usize) -> Comp| (0..width).map(f).collect::<Vec<Comp>>();
    let unknown = || vec![Comp::UNKNOWN; width];
    match op {
        Op::Neg => each(&|i| neg(at(a[0], i))),
        Op::Add => each(&|i| add(at(a[0], i), at(a[1], i))),
        Op::Sub => each(&|i| add(at(a[0], i), neg(at(a[1], i)))),
        Op::Mul if a[0].len() == 9 && a[1].len() == 3 => mat_vec(a[0], a[1]),
        Op::Mul => each(&|i| mul(at(a[0], i), at(a[1], i))),
        Op::Div => each(&|i| div(at(a[0], i), at(a[1], i))),
        Op::Mod => each(&|i| {
            let (x, m) = (at(a[0], i), at(a[1], i));
            Comp::fixed(-m.mag(), m.mag()).jumpy_from(&[x, m])
        }),
        Op::Lt | Op::Le | Op::Gt | Op::Ge | Op::Eq | Op::Ne => {
            vec![Comp::constant(0.0).jumpy_from(&[a[0][0], a[1][0]])]
        }
        Op::Select => each(&|i| {
            let (f, t, c) = (at(a[0], i), at(a[1], i), a[2][0]);
            let (lo, hi) = (f.lo.min(t.lo), f.hi.max(t.hi));
            if c.g == 0.0 {
                comp(lo, hi, f.g.max(t.g), vmax(f.v, t.v))
            } else {
                Comp::fixed(lo, hi).jumpy_from(&[c])
            }
        }),
        Op::MakeVec | Op::MakeMat3 => a.iter().flat_map(|x| x.iter().copied()).collect(),
        Op::Swizzle(s) => s.indices().iter().map(|&k| at(a[0], k as usize)).collect(),
        Op::MatMul if a[1].len() == 3 => mat_vec(a[0], a[1]),
        Op::Transpose => (0..9).map(|k| at(a[0], (k % 3) * 3 + k / 3)).collect(),
        Op::Builtin(b) => builtin(b, a, width),
        Op::Helper(Helper::Noise) => {
            // d noise(v) / dx_j = sum_i dnoise/dv_i dv_i/dx_j, each |dnoise/dv_i| <= 8.5.
            let cols = column_norms(a[0]);
            let sums = [0, 1, 2].map(|j| a[0].iter().map(|c| c.v[j]).sum::<f64>());
            let v = [0, 1, 2]
                .map(|j| scale(NOISE_LIPSCHITZ, cols[j]).min(scale(NOISE_PARTIAL, sums[j])));
            vec![comp(
                -1.0,
                1.0,
                scale(NOISE_LIPSCHITZ, jacobian_norm(a[0])),
                v,
            )]
        }
        _ => unknown(),
    }
}

/// `m * v` for a column-major matrix of 9 components.
fn mat_vec(m: &[Comp], v: &[Comp]) -> Vec<Comp> {
    (0..3)
        .map(|r| {
            (0..3)
                .map(|c| mul(at(m, c * 3 + r), at(v, c)))
                .reduce(add)
                .unwrap_or(Comp::UNKNOWN)
        })
        .collect()
}

fn builtin(b: Builtin, a: &[&[Comp]], width: usize) -> Vec<Comp> {
    use std::f64::consts::{FRAC_PI_2, PI};
    use Builtin::*;
    let each = |f: &dyn Fn(usize) -> Comp| (0..width).map(f).collect::<Vec<Comp>>();
    let x = |i: usize| at(a[0], i);
    match b {
        Abs => each(&|i| {
            let c = x(i);
            Comp {
                lo: c.min_mag(),
                hi: c.mag(),
                ..c
            }
        }),
        Sign | Step => each(&|i| {
            let from: Vec<Comp> = a.iter().map(|v| at(v, i)).collect();
            Comp::fixed(-1.0, 1.0).jumpy_from(&from)
        }),
        Floor | Ceil | Round => each(&|i| {
            let c = x(i);
            c.jumpy(c.lo.floor(), c.hi.ceil())
        }),
        Fract => each(&|i| x(i).jumpy(0.0, 1.0)),
        Sqrt => each(&|i| {
            let c = x(i);
            let lo = c.lo.max(0.0).sqrt();
            let slope = if lo > 0.0 { 0.5 / lo } else { f64::INFINITY };
            smooth(c, lo, c.hi.max(0.0).sqrt(), slope)
        }),
        Pow => each(&|i| {
            let (c, e) = (x(i), at(a[1], i));
            if e.g != 0.0 || e.lo != e.hi {
                return Comp::UNKNOWN;
            }
            let y = e.lo;
            if c.lo > 0.0 {
                let (l, h) = hull(&[c.lo.powf(y), c.hi.powf(y)]);
                let s = y.abs() * c.lo.powf(y - 1.0).max(c.hi.powf(y - 1.0));
                smooth(c, l, h, s)
            } else if c.lo >= 0.0 && y >= 1.0 {
                // A base that may be negative is NaN there (`pow` is `exp2(y * log2(x))`, as
                // on the device), so only a base that cannot be has a range.
                let h = c.hi.powf(y);
                smooth(c, 0.0, h, y * c.hi.powf(y - 1.0))
            } else {
                Comp::UNKNOWN
            }
        }),
        Exp => each(&|i| {
            let c = x(i);
            smooth(c, c.lo.exp(), c.hi.exp(), c.hi.exp())
        }),
        Log => each(&|i| {
            let c = x(i);
            if c.lo > 0.0 {
                smooth(c, c.lo.ln(), c.hi.ln(), 1.0 / c.lo)
            } else {
                Comp::UNKNOWN
            }
        }),
        Sin | Cos => each(&|i| smooth(x(i), -1.0, 1.0, 1.0)),
        Tan => each(&|i| x(i).jumpy(f64::NEG_INFINITY, f64::INFINITY)),
        Asin | Acos => each(&|i| {
            let c = x(i);
            let m = c.mag();
            let slope = if m < 1.0 {
                1.0 / (1.0 - m * m).sqrt()
            } else {
                f64::INFINITY
            };
            let (lo, hi) = if b == Asin {
                (-FRAC_PI_2, FRAC_PI_2)
            } else {
                (0.0, PI)
            };
            smooth(c, lo, hi, slope)
        }),
        Atan => each(&|i| {
            let c = x(i);
            smooth(c, c.lo.atan(), c.hi.atan(), 1.0)
        }),
        Atan2 => each(&|i| {
            // |grad atan2(y, x)| <= (|x| |grad y| + |y| |grad x|) / (x^2 + y^2).
            let (y, xx) = (x(i), at(a[1], i));
            let r2 = y.min_mag().powi(2) + xx.min_mag().powi(2);
            let (num, nv) = combine(y, xx.mag(), xx, y.mag());
            let over = |n: f64| {
                if n == 0.0 {
                    0.0
                } else if r2 > 0.0 {
                    n / r2
                } else {
                    f64::INFINITY
                }
            };
            comp(-PI, PI, over(num), nv.map(over))
        }),
        Min | Max => each(&|i| {
            let (p, q) = (x(i), at(a[1], i));
            let (lo, hi) = if b == Min {
                (p.lo.min(q.lo), p.hi.min(q.hi))
            } else {
                (p.lo.max(q.lo), p.hi.max(q.hi))
            };
            comp(lo, hi, p.g.max(q.g), vmax(p.v, q.v))
        }),
        Clamp => each(&|i| {
            let (c, l, h) = (x(i), at(a[1], i), at(a[2], i));
            comp(
                c.lo.max(l.lo).min(h.lo),
                c.hi.max(l.hi).min(h.hi),
                c.g.max(l.g).max(h.g),
                vmax(c.v, vmax(l.v, h.v)),
            )
        }),
        Mix => each(&|i| {
            // x (1 - t) + y t
            let (p, q, t) = (x(i), at(a[1], i), at(a[2], i));
            let omt = add(Comp::constant(1.0), neg(t));
            add(mul(p, omt), mul(q, t))
        }),
        Smoothstep => each(&|i| {
            let (e0, e1, c) = (x(i), at(a[1], i), at(a[2], i));
            if e0.g == 0.0 && e1.g == 0.0 && e0.lo == e0.hi && e1.lo == e1.hi && e0.lo != e1.lo {
                smooth(c, 0.0, 1.0, 1.5 / (e1.lo - e0.lo).abs())
            } else {
                Comp::UNKNOWN
            }
        }),
        Length => vec![length(a[0])],
        Distance => {
            let d: Vec<Comp> = (0..a[0].len().max(a[1].len()))
                .map(|i| add(at(a[0], i), neg(at(a[1], i))))
                .collect();
            vec![length(&d)]
        }
        Dot => vec![(0..a[0].len())
            .map(|i| mul(at(a[0], i), at(a[1], i)))
            .reduce(add)
            .unwrap_or(Comp::UNKNOWN)],
        Cross => {
            let (u, v) = (a[0], a[1]);
            let c = |i: usize, j: usize| add(mul(at(u, i), at(v, j)), neg(mul(at(u, j), at(v, i))));
            vec![c(1, 2), c(2, 0), c(0, 1)]
        }
        Normalize => {
            // |d(v/|v|)| <= |dv| / |v|.
            let l = length(a[0]);
            let k = if l.lo > 0.0 {
                1.0 / l.lo
            } else {
                f64::INFINITY
            };
            let g = scale(k, jacobian_norm(a[0]));
            let v = column_norms(a[0]).map(|c| scale(k, c));
            each(&|_| comp(-1.0, 1.0, g, v))
        }
        Radians | Degrees => {
            let k = if b == Radians { PI / 180.0 } else { 180.0 / PI };
            each(&|i| mul(x(i), Comp::constant(k)))
        }
    }
}

/// `length(v)`: 1-Lipschitz in `v`, so its gradient is bounded by the Jacobian's norm and
/// its partials by the Jacobian's column norms.
fn length(v: &[Comp]) -> Comp {
    let lo = v.iter().map(|c| c.min_mag().powi(2)).sum::<f64>().sqrt();
    let hi = v.iter().map(|c| c.mag().powi(2)).sum::<f64>().sqrt();
    comp(lo, hi, jacobian_norm(v), column_norms(v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ops::Swizzle;

    #[test]
    fn ribbed_sphere_slope() {
        // sin(30 * p.y) / 16: |grad| <= 30 / 16.
        let mut g = Graph::new();
        let p = g.input(
            Op::LambdaArg {
                lambda: 0,
                index: 0,
            },
            crate::types::Ty::Vec3,
            Default::default(),
        );
        let y = g.op(Op::Swizzle(Swizzle::new(&[1])), &[p]);
        let k = g.f32(30.0);
        let ky = g.op(Op::Mul, &[k, y]);
        let s = g.builtin(Builtin::Sin, &[ky]);
        let d = g.f32(16.0);
        let r = g.op(Op::Div, &[s, d]);
        let everywhere = |op: Op, _: usize| {
            matches!(op, Op::LambdaArg { .. }).then(|| {
                (0..3)
                    .map(|i| Comp::coord(i, f64::NEG_INFINITY, f64::INFINITY))
                    .collect()
            })
        };
        let b = bound(&g, r, &everywhere);
        assert_eq!(b.len(), 1);
        assert_eq!(b[0].slope(), 30.0 / 16.0);
        // The identity map's Jacobian norm is 1, and |grad length(p)| is 1.
        assert_eq!(jacobian_norm(&bound(&g, p, &everywhere)), 1.0);
        let l = g.builtin(Builtin::Length, &[p]);
        assert_eq!(bound(&g, l, &everywhere)[0].slope(), 1.0);
        assert_eq!((b[0].lo, b[0].hi), (-1.0 / 16.0, 1.0 / 16.0));
        // floor(p.y) is not Lipschitz.
        let f = g.builtin(Builtin::Floor, &[y]);
        assert_eq!(bound(&g, f, &everywhere)[0].slope(), f64::INFINITY);
    }
}
