//! Conservative axis-aligned bounds of shapes (components may be infinite), for the
//! Lipschitz constants of twist and bend and for the regions the sampling check covers.

use crate::shape::Prim;
use crate::value::Value;

/// A box `lo..hi` per axis; an unbounded axis has infinite ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub lo: [f64; 3],
    pub hi: [f64; 3],
}

impl Aabb {
    pub const EVERYTHING: Aabb = Aabb {
        lo: [f64::NEG_INFINITY; 3],
        hi: [f64::INFINITY; 3],
    };

    pub fn symmetric(h: [f64; 3]) -> Aabb {
        Aabb {
            lo: h.map(|x| -x),
            hi: h,
        }
    }

    pub fn is_bounded(&self) -> bool {
        self.lo.iter().chain(&self.hi).all(|x| x.is_finite())
    }

    pub fn grow(&self, r: f64) -> Aabb {
        Aabb {
            lo: self.lo.map(|x| x - r),
            hi: self.hi.map(|x| x + r),
        }
    }

    /// Whether the box lies within the cell `[-half, half]` along `axis`.
    pub fn within_cell(&self, axis: usize, half: f64) -> bool {
        self.lo[axis] >= -half && self.hi[axis] <= half
    }

    pub fn hull(&self, o: &Aabb) -> Aabb {
        Aabb {
            lo: [0, 1, 2].map(|i| self.lo[i].min(o.lo[i])),
            hi: [0, 1, 2].map(|i| self.hi[i].max(o.hi[i])),
        }
    }

    pub fn intersect(&self, o: &Aabb) -> Aabb {
        Aabb {
            lo: [0, 1, 2].map(|i| self.lo[i].max(o.lo[i])),
            hi: [0, 1, 2].map(|i| self.hi[i].min(o.hi[i])),
        }
    }

    /// The largest distance from the axis through the origin along `axis` (`0` x, `1` y,
    /// `2` z) to a point of the box.
    pub fn radius_about(&self, axis: usize) -> f64 {
        (0..3)
            .filter(|i| *i != axis)
            .map(|i| self.lo[i].abs().max(self.hi[i].abs()).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    /// The box of `s l - o` for `l` in this box: exact axis by axis, so a box unbounded on
    /// some sides stays bounded on the others, where [`Aabb::map_corners`] gives up. `s` is
    /// non-zero and finite.
    pub fn moved(&self, s: f64, o: [f64; 3]) -> Aabb {
        let a = [0, 1, 2].map(|k| s * self.lo[k] - o[k]);
        let b = [0, 1, 2].map(|k| s * self.hi[k] - o[k]);
        Aabb {
            lo: [0, 1, 2].map(|k| a[k].min(b[k])),
            hi: [0, 1, 2].map(|k| a[k].max(b[k])),
        }
    }

    /// The box of the images of this box's corners under `f` (exact for linear maps).
    pub fn map_corners(&self, f: impl Fn([f64; 3]) -> [f64; 3]) -> Aabb {
        if !self.is_bounded() {
            return Aabb::EVERYTHING;
        }
        let mut out = Aabb {
            lo: [f64::INFINITY; 3],
            hi: [f64::NEG_INFINITY; 3],
        };
        for k in 0..8 {
            let c = [0, 1, 2].map(|i| {
                if k >> i & 1 == 0 {
                    self.lo[i]
                } else {
                    self.hi[i]
                }
            });
            let q = f(c);
            for (i, x) in q.into_iter().enumerate() {
                out.lo[i] = out.lo[i].min(x);
                out.hi[i] = out.hi[i].max(x);
            }
        }
        out
    }
}

/// The box of the half-space `dot(p, n) <= h` where `n` has one non-zero component: one end
/// of that axis finite, everything else infinite. `None` for any other normal.
fn axis_half_space(n: [f64; 3], h: f64) -> Option<Aabb> {
    let mut axes = (0..3).filter(|&k| n[k] != 0.0);
    let k = axes.next()?;
    if axes.next().is_some() {
        return None;
    }
    let end = h / n[k];
    let mut b = Aabb::EVERYTHING;
    if n[k] > 0.0 {
        b.hi[k] = end;
    } else {
        b.lo[k] = end;
    }
    end.is_finite().then_some(b)
}

/// Bounds of a primitive from its constant arguments (`None` where one is not constant).
pub fn prim(prim: Prim, args: &[Option<Value<f32>>]) -> Aabb {
    let f = |i: usize| match args.get(i) {
        Some(Some(Value::F(x))) => Some(*x as f64),
        _ => None,
    };
    let v = |i: usize| match args.get(i) {
        Some(Some(Value::V3(x))) => Some(x.map(|c| c as f64)),
        _ => None,
    };
    let b = match prim {
        Prim::Sphere => f(0).map(|r| Aabb::symmetric([r; 3])),
        Prim::Box | Prim::RoundBox => v(0).map(|s| Aabb::symmetric(s.map(|x| x * 0.5))),
        // An axis-aligned normal bounds the half-space on one side: dot(p, n) <= h.
        Prim::Plane => match (v(0), f(1)) {
            (Some(n), Some(h)) => axis_half_space(n, h),
            _ => None,
        },
        Prim::Torus => match (f(0), f(1)) {
            (Some(big), Some(r)) => Some(Aabb::symmetric([big + r, r, big + r])),
            _ => None,
        },
        Prim::Cylinder => match (f(0), f(1)) {
            (Some(r), Some(h)) => Some(Aabb::symmetric([r, h * 0.5, r])),
            _ => None,
        },
        Prim::Capsule => match (v(0), v(1), f(2)) {
            (Some(a), Some(b), Some(r)) => Some(
                Aabb {
                    lo: [0, 1, 2].map(|i| a[i].min(b[i])),
                    hi: [0, 1, 2].map(|i| a[i].max(b[i])),
                }
                .grow(r),
            ),
            _ => None,
        },
        Prim::BoxFrame => v(0).map(|s| Aabb::symmetric(s.map(|x| x * 0.5))),
        Prim::InfiniteCylinder => None,
        // The arc lies in the xy plane; the whole ring's box is enough.
        Prim::CappedTorus => match (f(0), f(1)) {
            (Some(big), Some(r)) => Some(Aabb::symmetric([big + r, big + r, r])),
            _ => None,
        },
        Prim::Cone => match (f(0), f(1)) {
            (Some(r), Some(h)) => Some(Aabb {
                lo: [-r, h.min(0.0), -r],
                hi: [r, h.max(0.0), r],
            }),
            _ => None,
        },
        Prim::CappedCone => match (f(0), f(1), f(2)) {
            (Some(h), Some(r1), Some(r2)) => {
                let r = r1.max(r2);
                Some(Aabb::symmetric([r, h * 0.5, r]))
            }
            _ => None,
        },
        Prim::Ellipsoid => v(0).map(|r| Aabb::symmetric(r.map(f64::abs))),
        Prim::Octahedron => f(0).map(|s| Aabb::symmetric([s * 0.5; 3])),
        // Inradius r: the hexagon's corners lie at 2r / sqrt(3), the triangle's at 2r.
        Prim::HexPrism => match (f(0), f(1)) {
            (Some(r), Some(h)) => {
                let c = r * 2.0 / 3f64.sqrt();
                Some(Aabb::symmetric([c, c, h * 0.5]))
            }
            _ => None,
        },
        Prim::TriPrism => match (f(0), f(1)) {
            (Some(r), Some(h)) => Some(Aabb::symmetric([2.0 * r, 2.0 * r, h * 0.5])),
            _ => None,
        },
        Prim::Pyramid => f(0).map(|h| Aabb {
            lo: [-0.5, h.min(0.0), -0.5],
            hi: [0.5, h.max(0.0), 0.5],
        }),
        // The estimator is evaluated within 1.25 times its bounding radius (argument 2).
        Prim::Mandelbulb => f(2).map(|r| Aabb::symmetric([1.25 * r; 3])),
        Prim::Menger | Prim::Sierpinski => Some(Aabb::symmetric([0.5; 3])),
    };
    b.unwrap_or(Aabb::EVERYTHING)
}
