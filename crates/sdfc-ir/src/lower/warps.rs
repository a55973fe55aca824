//! The bound-only shape operations: `stretch`, `shear`, `twist`, `bend`, `warp` and
//! `heightfield`, and the `lipschitz: L` argument they (and `sdf`, `displace`) share.

use super::scope::{Scope, Val};
use super::{Lowerer, Reported, R};
use crate::graph::NodeId;
use crate::shape::{ShapeKind, WarpMap};
use crate::types::Ty;
use crate::value::Value;
use sdfc_syntax::ast::{Arg, Expr};
use sdfc_syntax::diag::Diagnostic;
use sdfc_syntax::span::Span;
use std::rc::Rc;

impl<'a> Lowerer<'a> {
    pub(super) fn warp_call(
        &mut self,
        name: &str,
        args: &'a [Arg],
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<ShapeKind> {
        let (sig, names, required): (&str, &[&str], usize) = match name {
            "stretch" => ("stretch(s, [sx, sy, sz])", &["s", "factors"], 2),
            "shear" => ("shear(s, [kxy, kxz, kyz])", &["s", "k"], 2),
            "twist" => ("twist(s, k, lipschitz: L)", &["s", "k", "lipschitz"], 2),
            "bend" => ("bend(s, k, lipschitz: L)", &["s", "k", "lipschitz"], 2),
            "warp" => ("warp(s, |p| v, lipschitz: L)", &["s", "f", "lipschitz"], 2),
            _ => (
                "heightfield(|x, z| h, lipschitz: L)",
                &["f", "lipschitz"],
                1,
            ),
        };
        let b = self.bind_args(name, sig, names, required, args, span)?;
        let declared = match names.iter().position(|n| *n == "lipschitz") {
            Some(i) => b[i]
                .map(|le| self.declared_lipschitz(le, scope))
                .transpose()?,
            None => None,
        };
        if name == "heightfield" {
            let fe = b[0].ok_or(Reported)?;
            let (lambda, body) = self.lambda_arg(fe, scope, name, &[Ty::F32, Ty::F32], Ty::F32)?;
            return Ok(ShapeKind::Heightfield {
                body,
                lambda,
                lipschitz: declared,
            });
        }
        let child = self.arg_shape(b[0].ok_or(Reported)?, scope, name)?;
        let e1 = b[1].ok_or(Reported)?;
        let map = match name {
            "stretch" => {
                let s = self.arg_vec3(e1, scope, "the stretch factors")?;
                if let Some(Value::V3(v)) = self.const_of(s) {
                    if v.iter().any(|x| *x <= 0.0) {
                        return Err(self.error(
                            Diagnostic::error(
                                e1.span,
                                format!(
                                    "stretch factors must be positive, found [{}]",
                                    v.map(|x| x.to_string()).join(", ")
                                ),
                            )
                            .with_label("not positive")
                            .with_hint(
                                "to mirror a shape use `mirror_x`, `mirror_y` or `mirror_z`",
                            ),
                        ));
                    }
                }
                WarpMap::Stretch(s)
            }
            "shear" => WarpMap::Shear(self.arg_vec3(e1, scope, "the shear factors")?),
            "twist" => WarpMap::Twist(self.arg_num(e1, scope, "the twist rate")?),
            "bend" => WarpMap::Bend(self.arg_num(e1, scope, "the bend rate")?),
            _ => {
                let (lambda, body) = self.lambda_arg(e1, scope, name, &[Ty::Vec3], Ty::Vec3)?;
                WarpMap::Lambda { body, lambda }
            }
        };
        Ok(ShapeKind::Warp {
            map,
            child,
            lipschitz: declared,
        })
    }

    /// A lambda argument applied to fresh parameters of types `tys`, giving `result`.
    fn lambda_arg(
        &mut self,
        fe: &'a Expr,
        scope: &Rc<Scope<'a>>,
        name: &str,
        tys: &[Ty],
        result: Ty,
    ) -> R<(u32, NodeId)> {
        let lam = match self.expr(fe, scope)? {
            Val::Lambda(l) => l,
            Val::Poison => return Err(Reported),
            other => {
                let d = self.describe(&other);
                return Err(self.error(
                    Diagnostic::error(fe.span, format!("`{name}` takes a lambda, found {d}"))
                        .with_label("expected a lambda")
                        .with_hint(if name == "warp" {
                            "for example `warp(s, |p| p + [0, sin(p.x), 0], lipschitz: 1.5)`"
                        } else {
                            "for example `heightfield(|x, z| sin(x) * cos(z), lipschitz: 1.5)`"
                        }),
                ));
            }
        };
        self.apply_lambda(&lam, tys, name, result)
    }

    /// A `lipschitz: L` argument: a positive constant.
    pub(super) fn declared_lipschitz(
        &mut self,
        le: &'a Expr,
        scope: &Rc<Scope<'a>>,
    ) -> R<(NodeId, Span)> {
        let l = self.arg_num(le, scope, "the Lipschitz bound")?;
        match self.const_of(l) {
            Some(Value::F(x)) if x > 0.0 => Ok((l, le.span)),
            Some(Value::F(x)) => Err(self.error(
                Diagnostic::error(
                    le.span,
                    format!("the Lipschitz bound must be positive, found {x}"),
                )
                .with_label("not positive"),
            )),
            _ => Err(self.error(
                Diagnostic::error(le.span, "the Lipschitz bound must be a constant")
                    .with_label("depends on a param or time"),
            )),
        }
    }
}
