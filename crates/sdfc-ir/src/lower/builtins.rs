//! Built-in functions: dispatch by name to math, shapes and shape operations.

use super::scope::{Scope, Val};
use super::{Lowerer, Reported, R};
use crate::ops::{Builtin, Op};
use crate::types::Ty;
use crate::value::Value;
use sdfc_syntax::ast::{Arg, Ident};
use sdfc_syntax::diag::{nearest, Diagnostic};
use sdfc_syntax::span::Span;
use std::rc::Rc;

/// Shapes and operations this version implements.
pub const SHAPE_FUNCTIONS: &[&str] = &[
    "sphere",
    "box",
    "round_box",
    "plane",
    "torus",
    "cylinder",
    "capsule",
    "box_frame",
    "capped_torus",
    "infinite_cylinder",
    "cone",
    "capped_cone",
    "ellipsoid",
    "octahedron",
    "hex_prism",
    "tri_prism",
    "pyramid",
    "mandelbulb",
    "menger",
    "sierpinski",
    "sdf",
    "union",
    "intersect",
    "subtract",
    "xor",
    "translate",
    "rotate",
    "rotate_x",
    "rotate_y",
    "rotate_z",
    "scale",
    "mirror_x",
    "mirror_y",
    "mirror_z",
    "repeat",
    "elongate",
    "round",
    "onion",
    "material",
    "color",
    "displace",
    "stretch",
    "shear",
    "twist",
    "bend",
    "warp",
    "heightfield",
];

/// Part of the language (spec sections 3-5) but not built in this version yet.
pub const NOT_YET: &[&str] = &[];

/// The math built-ins users may call (`round` is the shape operation, not WGSL's).
fn user_math(name: &str) -> Option<Builtin> {
    Builtin::from_name(name).filter(|b| *b != Builtin::Round)
}

/// Built-ins beyond WGSL's: gradient noise and its fractal sum.
const NOISE_FUNCTIONS: &[&str] = &["noise", "fbm"];

pub fn is_builtin_function(name: &str) -> bool {
    user_math(name).is_some()
        || name == "select"
        || NOISE_FUNCTIONS.contains(&name)
        || SHAPE_FUNCTIONS.contains(&name)
        || NOT_YET.contains(&name)
}

fn all_function_names() -> Vec<&'static str> {
    let mut v: Vec<&'static str> = Builtin::ALL
        .iter()
        .filter(|b| **b != Builtin::Round)
        .map(|b| b.name())
        .collect();
    v.push("select");
    v.extend(NOISE_FUNCTIONS);
    v.extend(SHAPE_FUNCTIONS);
    v.extend(NOT_YET);
    v
}

impl<'a> Lowerer<'a> {
    pub fn builtin_call(
        &mut self,
        callee: &'a Ident,
        args: &'a [Arg],
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<Val<'a>> {
        let name = callee.name.as_str();
        if let Some(b) = user_math(name) {
            return self.math_call(b, callee, args, span, scope);
        }
        if name == "select" {
            return self.select_call(args, span, scope);
        }
        if NOISE_FUNCTIONS.contains(&name) {
            return self.noise_call(name, args, span, scope);
        }
        if SHAPE_FUNCTIONS.contains(&name) {
            return self.shape_call(callee, args, span, scope);
        }
        if NOT_YET.contains(&name) {
            return Err(self.error(
                Diagnostic::error(
                    callee.span,
                    format!("`{name}` is part of the scene language but this version of sdfc does not implement it yet"),
                )
                .with_label("not implemented yet")
                .with_hint("see the README's list of supported shapes and operations"),
            ));
        }
        if let Some(d) = self.defined_later(name, callee.span, "the function") {
            return Err(self.error(d));
        }
        let mut known = all_function_names();
        known.extend(self.visible_names(scope));
        let mut d = Diagnostic::error(callee.span, format!("unknown function `{name}`"))
            .with_label("no built-in or `fn` has this name");
        if let Some(s) = nearest(name, known.iter().copied()) {
            d = d.with_hint(format!("did you mean `{s}`?"));
        }
        Err(self.error(d))
    }

    /// Evaluates every argument of a call to a number or vector node.
    fn num_args(
        &mut self,
        fname: &str,
        args: &'a [Arg],
        scope: &Rc<Scope<'a>>,
    ) -> R<Vec<(crate::graph::NodeId, Span)>> {
        let mut out = Vec::new();
        let mut failed = false;
        for a in args {
            if let Some(n) = &a.name {
                self.error(
                    Diagnostic::error(n.span, format!("`{fname}` takes no named arguments"))
                        .with_label("named argument"),
                );
                failed = true;
                continue;
            }
            match self.expr(&a.value, scope) {
                Ok(Val::Num(n)) if self.g.ty(n) != Ty::Bool => out.push((n, a.value.span)),
                Ok(Val::Poison) | Err(_) => failed = true,
                Ok(other) => {
                    let d = self.describe(&other);
                    self.error(
                        Diagnostic::error(
                            a.value.span,
                            format!("`{fname}` takes numbers or vectors, found {d}"),
                        )
                        .with_label("this argument"),
                    );
                    failed = true;
                }
            }
        }
        if failed {
            Err(Reported)
        } else {
            Ok(out)
        }
    }

    fn math_call(
        &mut self,
        b: Builtin,
        callee: &Ident,
        args: &'a [Arg],
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<Val<'a>> {
        let name = b.name();
        let vals = self.num_args(name, args, scope)?;
        if vals.len() != b.arity() {
            return Err(self.error(
                Diagnostic::error(
                    span,
                    format!(
                        "`{name}` takes {} argument{}, found {}",
                        b.arity(),
                        if b.arity() == 1 { "" } else { "s" },
                        vals.len()
                    ),
                )
                .with_label("wrong number of arguments")
                .with_hint(format!("the signature is `{}`", math_signature(b))),
            ));
        }
        let mut ids: Vec<_> = vals.iter().map(|(n, _)| *n).collect();
        // Component-wise built-ins accept a number where a vector is expected (broadcast).
        if !matches!(
            b,
            Builtin::Dot
                | Builtin::Distance
                | Builtin::Cross
                | Builtin::Length
                | Builtin::Normalize
        ) {
            if let Some(vt) = ids.iter().map(|n| self.g.ty(*n)).find(|t| *t != Ty::F32) {
                for n in ids.iter_mut() {
                    *n = self.g.splat(*n, vt);
                }
            }
        }
        let tys: Vec<Ty> = ids.iter().map(|n| self.g.ty(*n)).collect();
        if crate::graph::infer(Op::Builtin(b), &tys).is_none() {
            let found = tys
                .iter()
                .map(|t| t.user_name())
                .collect::<Vec<_>>()
                .join(", ");
            return Err(self.error(
                Diagnostic::error(callee.span, format!("`{name}` cannot take ({found})"))
                    .with_label("argument types do not fit")
                    .with_hint(format!("the signature is `{}`", math_signature(b))),
            ));
        }
        Ok(Val::Num(self.g.add(Op::Builtin(b), &ids, span)))
    }

    fn select_call(&mut self, args: &'a [Arg], span: Span, scope: &Rc<Scope<'a>>) -> R<Val<'a>> {
        let sig = "select(a, b, cond)";
        let bound = self.bind_args("select", sig, &["a", "b", "cond"], 3, args, span)?;
        let mut v = Vec::new();
        for e in bound.into_iter().flatten() {
            match self.expr(e, scope)? {
                Val::Num(n) => v.push((n, e.span)),
                Val::Poison => return Err(Reported),
                other => {
                    let d = self.describe(&other);
                    return Err(self.error(
                        Diagnostic::error(e.span, format!("`select` takes values, found {d}"))
                            .with_hint("to choose between shapes, use `union` or `intersect`"),
                    ));
                }
            }
        }
        let (mut a, mut b, c) = (v[0].0, v[1].0, v[2]);
        if self.g.ty(c.0) != Ty::Bool {
            return Err(self.error(
                Diagnostic::error(
                    c.1,
                    format!(
                        "the condition of `select` must be a comparison, found {}",
                        self.g.ty(c.0).user_name()
                    ),
                )
                .with_label("not a boolean")
                .with_hint("write a comparison such as `p.y > 0`"),
            ));
        }
        let (ta, tb) = (self.g.ty(a), self.g.ty(b));
        if ta != tb {
            if ta == Ty::F32 {
                a = self.g.splat(a, tb);
            } else if tb == Ty::F32 {
                b = self.g.splat(b, ta);
            }
        }
        if self.g.ty(a) != self.g.ty(b) || self.g.ty(a) == Ty::Bool {
            return Err(self.error(
                Diagnostic::error(
                    span,
                    format!(
                        "`select` needs two values of one type, found {} and {}",
                        ta.user_name(),
                        tb.user_name()
                    ),
                )
                .with_label("mismatched types"),
            ));
        }
        Ok(Val::Num(self.g.add(Op::Select, &[a, b, c.0], span)))
    }
}

impl<'a> Lowerer<'a> {
    /// `noise(p)` and `fbm(p, octaves: 5, lacunarity: 2, gain: 0.5)`: the octaves are
    /// unrolled, each `gain` times the amplitude and `lacunarity` times the frequency of the
    /// one before, and the sum is divided by the total amplitude so it stays in [-1, 1].
    fn noise_call(
        &mut self,
        name: &str,
        args: &'a [Arg],
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<Val<'a>> {
        let (sig, names, required): (&str, &[&str], usize) = if name == "noise" {
            ("noise(p)", &["p"], 1)
        } else {
            (
                "fbm(p, octaves: 5, lacunarity: 2, gain: 0.5)",
                &["p", "octaves", "lacunarity", "gain"],
                1,
            )
        };
        let b = self.bind_args(name, sig, names, required, args, span)?;
        let what = format!("the point of `{name}`");
        let p = self.arg_vec3(b[0].ok_or(Reported)?, scope, &what)?;
        let noise = |g: &mut crate::graph::Graph, q| {
            g.add(Op::Helper(crate::ops::Helper::Noise), &[q], span)
        };
        if name == "noise" {
            return Ok(Val::Num(noise(&mut self.g, p)));
        }
        let octaves = match b[1] {
            None => 5,
            Some(e) => match self.const_value(e, scope, "`octaves`")? {
                Value::F(x) if x.fract() == 0.0 && (1.0..=16.0).contains(&x) => x as u32,
                v => {
                    return Err(self.error(
                        Diagnostic::error(
                            e.span,
                            format!(
                                "`octaves` must be a whole number from 1 to 16, found {}",
                                crate::dump::const_text(&v)
                            ),
                        )
                        .with_label("invalid octave count"),
                    ))
                }
            },
        };
        let number = |this: &mut Self,
                      e: Option<&'a sdfc_syntax::ast::Expr>,
                      default: f32,
                      what: &str|
         -> R<crate::graph::NodeId> {
            match e {
                None => Ok(this.g.f32(default)),
                Some(e) => match this.expr(e, scope)? {
                    Val::Num(n) if this.g.ty(n) == Ty::F32 => Ok(n),
                    Val::Poison => Err(Reported),
                    other => {
                        let d = this.describe(&other);
                        Err(this.error(
                            Diagnostic::error(
                                e.span,
                                format!("{what} must be a number, found {d}"),
                            )
                            .with_label("expected a number"),
                        ))
                    }
                },
            }
        };
        let lacunarity = number(self, b[2], 2.0, "`lacunarity`")?;
        let gain = number(self, b[3], 0.5, "`gain`")?;
        let mut freq = self.g.f32(1.0);
        let mut amp = self.g.f32(1.0);
        let mut sum = self.g.f32(0.0);
        let mut total = self.g.f32(0.0);
        for _ in 0..octaves {
            let q = self.g.add(Op::Mul, &[p, freq], span);
            let n = noise(&mut self.g, q);
            let term = self.g.add(Op::Mul, &[n, amp], span);
            sum = self.g.add(Op::Add, &[sum, term], span);
            total = self.g.add(Op::Add, &[total, amp], span);
            freq = self.g.add(Op::Mul, &[freq, lacunarity], span);
            amp = self.g.add(Op::Mul, &[amp, gain], span);
        }
        Ok(Val::Num(self.g.add(Op::Div, &[sum, total], span)))
    }
}

fn math_signature(b: Builtin) -> String {
    let names: &[&str] = match b {
        Builtin::Pow => &["x", "y"],
        Builtin::Atan2 => &["y", "x"],
        Builtin::Min | Builtin::Max => &["a", "b"],
        Builtin::Clamp => &["x", "lo", "hi"],
        Builtin::Mix => &["a", "b", "t"],
        Builtin::Step => &["edge", "x"],
        Builtin::Smoothstep => &["lo", "hi", "x"],
        Builtin::Distance => &["a", "b"],
        Builtin::Dot => &["a: vector", "b: vector of the same size"],
        Builtin::Cross => &["a: vec3", "b: vec3"],
        Builtin::Normalize => &["v: vector"],
        _ => &["x"],
    };
    format!("{}({})", b.name(), names.join(", "))
}
