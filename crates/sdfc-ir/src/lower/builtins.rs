//! Built-in functions: dispatch by name to math, shapes and shape operations.

use super::scope::{Scope, Val};
use super::{Lowerer, Reported, R};
use crate::ops::{Builtin, Op};
use crate::types::Ty;
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
];

/// Part of the language (spec sections 3-5) but not built in this version yet.
pub const NOT_YET: &[&str] = &[
    "capped_torus",
    "infinite_cylinder",
    "cone",
    "capped_cone",
    "ellipsoid",
    "octahedron",
    "hex_prism",
    "tri_prism",
    "pyramid",
    "heightfield",
    "mandelbulb",
    "menger",
    "sierpinski",
    "stretch",
    "shear",
    "twist",
    "bend",
    "warp",
    "noise",
    "fbm",
];

/// The math built-ins users may call (`round` is the shape operation, not WGSL's).
fn user_math(name: &str) -> Option<Builtin> {
    Builtin::from_name(name).filter(|b| *b != Builtin::Round)
}

pub fn is_builtin_function(name: &str) -> bool {
    user_math(name).is_some()
        || name == "select"
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

fn math_signature(b: Builtin) -> String {
    let names: &[&str] = match b {
        Builtin::Pow => &["x", "y"],
        Builtin::Atan2 => &["y", "x"],
        Builtin::Min | Builtin::Max => &["a", "b"],
        Builtin::Clamp => &["x", "lo", "hi"],
        Builtin::Mix => &["a", "b", "t"],
        Builtin::Step => &["edge", "x"],
        Builtin::Smoothstep => &["lo", "hi", "x"],
        Builtin::Distance | Builtin::Dot | Builtin::Cross => &["a", "b"],
        _ => &["x"],
    };
    format!("{}({})", b.name(), names.join(", "))
}
