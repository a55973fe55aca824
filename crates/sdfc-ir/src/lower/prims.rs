//! Primitive constructors: argument binding and checks for every shape of spec section 4
//! (sizes, radii and angles; the fractals' compile-time iteration counts).

use super::scope::Scope;
use super::{Lowerer, Reported, R};
use crate::ops::Builtin;
use crate::shape::{Prim, ShapeKind};
use crate::value::Value;
use sdfc_syntax::ast::{Arg, Expr};
use sdfc_syntax::diag::Diagnostic;
use sdfc_syntax::span::Span;
use std::rc::Rc;

/// The iteration limits of the fractals (inclusive). Menger stops at 8: its level-8 holes
/// are 1/6561 wide, about the f32 resolution that `p * 3^8` leaves; beyond that the
/// repetition works on rounding noise. Sierpinski stops at 20 (tetrahedra a millionth wide).
pub const MANDELBULB_ITERATIONS: u32 = 32;
pub const MENGER_ITERATIONS: u32 = 8;
pub const SIERPINSKI_ITERATIONS: u32 = 20;
/// The mandelbulb's power: a constant in this range (inclusive).
pub const MANDELBULB_POWER: (f32, f32) = (2.0, 16.0);

impl<'a> Lowerer<'a> {
    pub(super) fn prim_call(
        &mut self,
        prim: Prim,
        args: &'a [Arg],
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<ShapeKind> {
        let name = prim.name();
        let (names, sig): (&[&str], &str) = match prim {
            Prim::Sphere => (&["r"], "sphere(r)"),
            Prim::Box => (&["size"], "box(size)"),
            Prim::RoundBox => (&["size", "r"], "round_box(size, r)"),
            Prim::Plane => (&["normal", "h"], "plane(normal, h)"),
            Prim::Torus => (&["R", "r"], "torus(R, r)"),
            Prim::Cylinder => (&["r", "h"], "cylinder(r, h)"),
            Prim::Capsule => (&["a", "b", "r"], "capsule(a, b, r)"),
            Prim::BoxFrame => (&["size", "e"], "box_frame(size, e)"),
            Prim::CappedTorus => (&["R", "r", "angle"], "capped_torus(R, r, angle)"),
            Prim::InfiniteCylinder => (&["r"], "infinite_cylinder(r)"),
            Prim::Cone => (&["r", "h"], "cone(r, h)"),
            Prim::CappedCone => (&["h", "r1", "r2"], "capped_cone(h, r1, r2)"),
            Prim::Ellipsoid => (&["radii"], "ellipsoid(radii)"),
            Prim::Octahedron => (&["s"], "octahedron(s)"),
            Prim::HexPrism => (&["r", "h"], "hex_prism(r, h)"),
            Prim::TriPrism => (&["r", "h"], "tri_prism(r, h)"),
            Prim::Pyramid => (&["h"], "pyramid(h)"),
            Prim::Mandelbulb | Prim::Menger | Prim::Sierpinski => {
                return self.fractal_call(prim, args, span, scope)
            }
        };
        let b = self.bind_args(name, sig, names, names.len(), args, span)?;
        let e = |i: usize| b[i].ok_or(Reported);
        let args = match prim {
            Prim::Sphere => vec![self.arg_nonneg(e(0)?, scope, "the radius")?],
            Prim::Box => vec![self.arg_size(e(0)?, scope, "the size of a box")?],
            Prim::RoundBox => {
                let size = self.arg_size(e(0)?, scope, "the size of a box")?;
                let r = self.arg_nonneg(e(1)?, scope, "the rounding radius")?;
                if let (Some(Value::V3(s)), Some(Value::F(r))) =
                    (self.const_of(size), self.const_of(r))
                {
                    let half = s[0].min(s[1]).min(s[2]) * 0.5;
                    if r > half {
                        return Err(self.error(
                            Diagnostic::error(e(1)?.span, format!("rounding radius {r} is more than half the box's smallest side ({half})"))
                                .with_label("too large")
                                .with_hint("the outer size stays `size`, so r can be at most half of its smallest component"),
                        ));
                    }
                }
                vec![size, r]
            }
            Prim::Plane => {
                let ne = e(0)?;
                let n = self.arg_vec3(ne, scope, "the plane's normal")?;
                let n = match self.const_of(n) {
                    Some(Value::V3(v)) => {
                        let l = v.iter().map(|x| (*x as f64).powi(2)).sum::<f64>().sqrt();
                        if l == 0.0 {
                            return Err(self.error(
                                Diagnostic::error(ne.span, "the plane's normal is the zero vector")
                                    .with_label("has no direction")
                                    .with_hint("use for example `[0, 1, 0]` for a floor"),
                            ));
                        }
                        self.g.vec3(v.map(|x| (x as f64 / l) as f32))
                    }
                    _ => self.g.builtin(Builtin::Normalize, &[n]),
                };
                vec![n, self.arg_num(e(1)?, scope, "the plane's offset `h`")?]
            }
            Prim::Torus => vec![
                self.arg_nonneg(e(0)?, scope, "the major radius")?,
                self.arg_nonneg(e(1)?, scope, "the tube radius")?,
            ],
            Prim::Cylinder => vec![
                self.arg_nonneg(e(0)?, scope, "the radius")?,
                self.arg_nonneg(e(1)?, scope, "the height")?,
            ],
            Prim::Capsule => vec![
                self.arg_vec3(e(0)?, scope, "the capsule's end `a`")?,
                self.arg_vec3(e(1)?, scope, "the capsule's end `b`")?,
                self.arg_nonneg(e(2)?, scope, "the radius")?,
            ],
            Prim::BoxFrame => {
                let size = self.arg_size(e(0)?, scope, "the size of a box frame")?;
                let w = self.arg_nonneg(e(1)?, scope, "the bar thickness")?;
                if let (Some(Value::V3(s)), Some(Value::F(w))) =
                    (self.const_of(size), self.const_of(w))
                {
                    let half = s[0].min(s[1]).min(s[2]) * 0.5;
                    if w > half {
                        return Err(self.error(
                            Diagnostic::error(
                                e(1)?.span,
                                format!("bar thickness {w} is more than half the frame's smallest side ({half})"),
                            )
                            .with_label("too thick")
                            .with_hint("the bars lie inside `size`, so e can be at most half of its smallest component"),
                        ));
                    }
                }
                vec![size, w]
            }
            Prim::CappedTorus => {
                let major = self.arg_nonneg(e(0)?, scope, "the major radius")?;
                let minor = self.arg_nonneg(e(1)?, scope, "the tube radius")?;
                let ae = e(2)?;
                let angle = self.arg_num(ae, scope, "the half-angle")?;
                if let Some(Value::F(a)) = self.const_of(angle) {
                    if !(0.0..=std::f32::consts::PI).contains(&a) {
                        return Err(self.error(
                            Diagnostic::error(
                                ae.span,
                                format!("the half-angle of a capped torus must be from 0 to pi, found {a}"),
                            )
                            .with_label("out of range")
                            .with_hint("the arc covers the angles within `angle` of +y: `180deg` is the whole ring"),
                        ));
                    }
                }
                vec![major, minor, angle]
            }
            Prim::InfiniteCylinder => vec![self.arg_nonneg(e(0)?, scope, "the radius")?],
            Prim::Cone => vec![
                self.arg_nonneg(e(0)?, scope, "the base radius")?,
                self.arg_nonneg(e(1)?, scope, "the height")?,
            ],
            Prim::CappedCone => vec![
                self.arg_nonneg(e(0)?, scope, "the height")?,
                self.arg_nonneg(e(1)?, scope, "the bottom radius `r1`")?,
                self.arg_nonneg(e(2)?, scope, "the top radius `r2`")?,
            ],
            Prim::Ellipsoid => {
                let re = e(0)?;
                let radii = self.arg_size(re, scope, "the radii of an ellipsoid")?;
                if let Some(Value::V3(r)) = self.const_of(radii) {
                    if r.contains(&0.0) {
                        return Err(self.error(
                            Diagnostic::error(
                                re.span,
                                "the radii of an ellipsoid must be positive, found a zero",
                            )
                            .with_label("zero radius")
                            .with_hint(
                                "a flat ellipsoid has no inside; use a small positive radius",
                            ),
                        ));
                    }
                }
                vec![radii]
            }
            Prim::Octahedron => vec![self.arg_nonneg(e(0)?, scope, "the size")?],
            Prim::HexPrism | Prim::TriPrism => vec![
                self.arg_nonneg(e(0)?, scope, "the radius")?,
                self.arg_nonneg(e(1)?, scope, "the length")?,
            ],
            Prim::Pyramid => vec![self.arg_nonneg(e(0)?, scope, "the height")?],
            // Bound by `fractal_call` above; this arm is never reached.
            Prim::Mandelbulb | Prim::Menger | Prim::Sierpinski => return Err(Reported),
        };
        Ok(ShapeKind::Prim { prim, args })
    }

    /// `mandelbulb(power: 8, iterations: 8)`, `menger(iterations: 4)`,
    /// `sierpinski(iterations: 8)`: every argument a compile-time constant, checked.
    fn fractal_call(
        &mut self,
        prim: Prim,
        args: &'a [Arg],
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<ShapeKind> {
        let name = prim.name();
        let (names, sig, default_iter, max_iter): (&[&str], &str, u32, u32) = match prim {
            Prim::Mandelbulb => (
                &["power", "iterations"],
                "mandelbulb(power: 8, iterations: 8)",
                8,
                MANDELBULB_ITERATIONS,
            ),
            Prim::Menger => (
                &["iterations"],
                "menger(iterations: 4)",
                4,
                MENGER_ITERATIONS,
            ),
            _ => (
                &["iterations"],
                "sierpinski(iterations: 8)",
                8,
                SIERPINSKI_ITERATIONS,
            ),
        };
        let b = self.bind_args(name, sig, names, 0, args, span)?;
        let iter_e = *b.last().ok_or(Reported)?;
        let iterations = match iter_e {
            None => default_iter,
            Some(e) => {
                let x = self.fractal_constant(e, scope, "`iterations`")?;
                if x.fract() != 0.0 || !(1.0..=max_iter as f32).contains(&x) {
                    return Err(self.error(
                        Diagnostic::error(
                            e.span,
                            format!("`iterations` of `{name}` must be a whole number from 1 to {max_iter}, found {x}"),
                        )
                        .with_label("invalid iteration count")
                        .with_hint(format!("the default is `iterations: {default_iter}`")),
                    ));
                }
                x as u32
            }
        };
        let mut out = Vec::new();
        if prim == Prim::Mandelbulb {
            let power = match b[0] {
                None => 8.0,
                Some(e) => {
                    let x = self.fractal_constant(e, scope, "`power`")?;
                    let (lo, hi) = MANDELBULB_POWER;
                    if !(lo..=hi).contains(&x) {
                        return Err(self.error(
                            Diagnostic::error(
                                e.span,
                                format!(
                                    "the mandelbulb's `power` must be from {lo} to {hi}, found {x}"
                                ),
                            )
                            .with_label("out of range")
                            .with_hint("the classic mandelbulb is `power: 8`"),
                        ));
                    }
                    x
                }
            };
            out.push(self.g.f32(power));
            out.push(self.g.f32(iterations as f32));
            out.push(self.g.f32(mandelbulb_bound(power)));
        } else {
            out.push(self.g.f32(iterations as f32));
        }
        Ok(ShapeKind::Prim { prim, args: out })
    }

    /// A fractal argument: a finite constant number.
    fn fractal_constant(&mut self, e: &'a Expr, scope: &Rc<Scope<'a>>, what: &str) -> R<f32> {
        match self.const_value(e, scope, what)? {
            Value::F(x) if x.is_finite() => Ok(x),
            v => Err(self.error(
                Diagnostic::error(
                    e.span,
                    format!("{what} must be a number, found {}", v.ty().user_name()),
                )
                .with_label("expected a number"),
            )),
        }
    }
}

/// The radius outside which the mandelbulb of this power has no points: the spec's 1.2,
/// widened to the escape radius `2^(1 / (power - 1))` for powers below 5 (any `c` farther
/// out escapes, so it is not in the set).
pub fn mandelbulb_bound(power: f32) -> f32 {
    let escape = 2f64.powf(1.0 / (power as f64 - 1.0));
    escape.max(1.2) as f32
}

pub fn prim_by_name(name: &str) -> Option<Prim> {
    Some(match name {
        "sphere" => Prim::Sphere,
        "box" => Prim::Box,
        "round_box" => Prim::RoundBox,
        "plane" => Prim::Plane,
        "torus" => Prim::Torus,
        "cylinder" => Prim::Cylinder,
        "capsule" => Prim::Capsule,
        "box_frame" => Prim::BoxFrame,
        "capped_torus" => Prim::CappedTorus,
        "infinite_cylinder" => Prim::InfiniteCylinder,
        "cone" => Prim::Cone,
        "capped_cone" => Prim::CappedCone,
        "ellipsoid" => Prim::Ellipsoid,
        "octahedron" => Prim::Octahedron,
        "hex_prism" => Prim::HexPrism,
        "tri_prism" => Prim::TriPrism,
        "pyramid" => Prim::Pyramid,
        "mandelbulb" => Prim::Mandelbulb,
        "menger" => Prim::Menger,
        "sierpinski" => Prim::Sierpinski,
        _ => return None,
    })
}
