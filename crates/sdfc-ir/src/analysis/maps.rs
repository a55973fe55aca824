//! What point maps do to a child's exactness and bounds: moves, turns, scales, mirrors,
//! repetitions and elongation, and the bound-only warps with their Lipschitz constants.

use super::bounds::Aabb;
use super::gradient;
use super::lipschitz::{bend_lipschitz, shear_inverse, spectral_norm, twist_lipschitz};
use super::{Analyser, Exactness, NodeInfo, Source};
use crate::shape::{Declared, PointMap, WarpMap};
use crate::value::Value;
use sdfc_syntax::diag::Diagnostic;
use sdfc_syntax::span::Span;

impl Analyser<'_> {
    pub(super) fn point_map(&mut self, map: &PointMap, c: &NodeInfo) -> (Exactness, Aabb) {
        match map {
            PointMap::Affine { m, o, s } => {
                // local = (m p + o) / s, so p = m^T (s local - o) (m is orthonormal).
                let m = match m {
                    Some(m) => match self.konst(*m) {
                        Some(Value::M3(cols)) => Some(cols.map(|c| c.map(|x| x as f64))),
                        _ => return (c.exactness, Aabb::EVERYTHING),
                    },
                    None => None,
                };
                let o = match o {
                    Some(o) => match self.vec3(*o) {
                        Some(v) => v,
                        None => return (c.exactness, Aabb::EVERYTHING),
                    },
                    None => [0.0; 3],
                };
                let s = match s {
                    Some(s) => match self.scalar(*s) {
                        Some(v) => v,
                        None => return (c.exactness, Aabb::EVERYTHING),
                    },
                    None => 1.0,
                };
                // Without a turn, axis by axis: a box open on some sides (a floor's
                // half-space) keeps its closed ones, where the corners' box gives up. (Turns
                // are not exact in f32: a quarter turn's matrix has entries of 1e-8, which
                // mix an infinite side into every axis.)
                if m.is_none() && s != 0.0 && s.is_finite() {
                    return (c.exactness, c.bounds.moved(s, o));
                }
                let b = c.bounds.map_corners(|l| {
                    let v = [0, 1, 2].map(|i| s * l[i] - o[i]);
                    match m {
                        // m^T v: row r of m^T is column r of m.
                        Some(cols) => [0, 1, 2].map(|r| (0..3).map(|k| cols[r][k] * v[k]).sum()),
                        None => v,
                    }
                });
                (c.exactness, b)
            }
            PointMap::Mirror(axis) => {
                let a = *axis as usize;
                let mut b = c.bounds;
                let h = b.hi[a].max(0.0);
                b.lo[a] = -h;
                b.hi[a] = h;
                (c.exactness.max(Exactness::Bound), b)
            }
            PointMap::Repeat { period } | PointMap::RepeatLimited { period, .. } => {
                let count = match map {
                    PointMap::RepeatLimited { count, .. } => Some(*count),
                    _ => None,
                };
                let mut b = c.bounds;
                let mut fits = true;
                let halves = map.half_periods();
                for i in 0..3 {
                    // One copy along an axis has no neighbour there.
                    if halves[i] == 0.0 {
                        continue;
                    }
                    // A copy that stays in its cell: the nearest copy to a point is its own
                    // cell's or, along an axis the copy is not symmetric about, the
                    // neighbour on the point's side, which `to_ssa` evaluates too.
                    fits &= c.bounds.within_cell(i, halves[i]);
                    let p = period[i] as f64;
                    match count {
                        Some(n) => {
                            let e = p * (n[i] as f64 - 1.0) / 2.0;
                            b.lo[i] -= e;
                            b.hi[i] += e;
                        }
                        None => {
                            b.lo[i] = f64::NEG_INFINITY;
                            b.hi[i] = f64::INFINITY;
                        }
                    }
                }
                let e = if fits {
                    c.exactness.max(Exactness::Bound)
                } else {
                    Exactness::Neither
                };
                (e, b)
            }
            PointMap::Elongate(h) => match self.vec3(*h) {
                Some(h) => (
                    c.exactness,
                    Aabb {
                        lo: [0, 1, 2].map(|i| c.bounds.lo[i] - h[i]),
                        hi: [0, 1, 2].map(|i| c.bounds.hi[i] + h[i]),
                    },
                ),
                None => (c.exactness, Aabb::EVERYTHING),
            },
        }
    }

    /// Bounds, Lipschitz constant and its source of a bound-only point map.
    pub(super) fn warp(
        &mut self,
        map: WarpMap,
        child: &Aabb,
        declared: Option<(f64, Span)>,
        raw: Declared,
        span: Span,
    ) -> (Aabb, Option<f64>, Source) {
        match map {
            WarpMap::Stretch(s) => match self.vec3(s) {
                Some(s) => {
                    let b = child.map_corners(|p| [0, 1, 2].map(|i| p[i] * s[i]));
                    (b, Some(1.0 / s[0].min(s[1]).min(s[2])), Source::Derived)
                }
                None => (Aabb::EVERYTHING, None, Source::Symbolic),
            },
            WarpMap::Shear(k) => match self.vec3(k) {
                Some(k) => {
                    let [kxy, kxz, kyz] = k;
                    let b = child
                        .map_corners(|p| [p[0] + kxy * p[1] + kxz * p[2], p[1] + kyz * p[2], p[2]]);
                    (b, Some(spectral_norm(shear_inverse(k))), Source::Derived)
                }
                None => (Aabb::EVERYTHING, None, Source::Symbolic),
            },
            WarpMap::Twist(k) | WarpMap::Bend(k) => {
                let twist = matches!(map, WarpMap::Twist(_));
                // Twist keeps the distance from the y axis, bend that from the z axis.
                let axis = if twist { 1 } else { 2 };
                let r = child.radius_about(axis);
                let mut b = Aabb::EVERYTHING;
                if r.is_finite() {
                    for i in (0..3).filter(|i| *i != axis) {
                        b.lo[i] = -r;
                        b.hi[i] = r;
                    }
                }
                b.lo[axis] = child.lo[axis];
                b.hi[axis] = child.hi[axis];
                if let Some((l, _)) = declared {
                    return (b, Some(l), Source::Declared);
                }
                if !r.is_finite() && raw.is_none() {
                    let name = if twist { "twist" } else { "bend" };
                    self.out.diagnostics.push(
                        Diagnostic::error(span, format!("`{name}` of a shape whose bounds are not known at compile time needs a declared Lipschitz bound"))
                            .with_label("unbounded, repeated, or sized by a param")
                            .with_hint(format!("bound the shape (intersect it with a box), or give `lipschitz: L` with L at least 1 + |k| times the largest distance from the {} axis your scene reaches", if twist { "y" } else { "z" })),
                    );
                    return (b, None, Source::Symbolic);
                }
                let l = self.scalar(k).map(|k| {
                    if twist {
                        twist_lipschitz(k * r)
                    } else {
                        bend_lipschitz(k * r)
                    }
                });
                (b, l, Source::Symbolic)
            }
            WarpMap::Lambda { body, lambda } => {
                if let Some((l, at)) = declared {
                    self.check_declared(body, lambda, 1, l, None, at, &Aabb::EVERYTHING, "warp");
                    return (Aabb::EVERYTHING, Some(l), Source::Declared);
                }
                let j = gradient::jacobian_norm(&self.body_bound(body, lambda, 1));
                if !j.is_finite() {
                    self.out.diagnostics.push(
                        Diagnostic::error(span, "the compiler cannot bound how much this warp stretches space")
                            .with_label("no Lipschitz bound")
                            .with_hint("declare one: `lipschitz: L` with L at least the largest stretch factor of the map"),
                    );
                }
                (Aabb::EVERYTHING, Some(j), Source::Derived)
            }
        }
    }
}
