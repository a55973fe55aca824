//! Shape constructors and shape operations: checked arguments in, shape nodes out.

use super::scope::{LambdaVal, Scope, Val};
use super::{Lowerer, Reported, R};
use crate::graph::NodeId;
use crate::ops::{Builtin, Op};
use crate::scene::{limits, Material};
use crate::shape::{CombineOp, DistMod, PointMap, ShapeId, ShapeKind};
use crate::types::Ty;
use crate::value::Value;
use sdfc_syntax::ast::{Arg, Expr, ExprKind, Ident};
use sdfc_syntax::diag::{nearest, Diagnostic};
use sdfc_syntax::span::Span;
use std::rc::Rc;

impl<'a> Lowerer<'a> {
    pub fn shape_call(
        &mut self,
        callee: &'a Ident,
        args: &'a [Arg],
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<Val<'a>> {
        let name = callee.name.as_str();
        let s = match name {
            "union" | "intersect" => {
                let op = if name == "union" {
                    CombineOp::Union
                } else {
                    CombineOp::Intersect
                };
                let sig = format!("{name}(a, b, ..., smooth: k)");
                let (shapes, named) = self.bind_variadic(name, &sig, 1, &["smooth"], args, span)?;
                let mut children = Vec::new();
                for e in shapes {
                    children.push(self.arg_shape(e, scope, name)?);
                }
                let smooth = self.opt_nonneg(named[0], scope, super::WHAT_SMOOTH)?;
                ShapeKind::Combine {
                    op,
                    smooth,
                    children,
                }
            }
            "subtract" => {
                let b = self.bind_args(
                    name,
                    "subtract(a, b, smooth: k)",
                    &["a", "b", "smooth"],
                    2,
                    args,
                    span,
                )?;
                let children = vec![
                    self.arg_shape(b[0].ok_or(Reported)?, scope, name)?,
                    self.arg_shape(b[1].ok_or(Reported)?, scope, name)?,
                ];
                let smooth = self.opt_nonneg(b[2], scope, super::WHAT_SMOOTH)?;
                ShapeKind::Combine {
                    op: CombineOp::Subtract,
                    smooth,
                    children,
                }
            }
            "xor" => {
                let b = self.bind_args(name, "xor(a, b)", &["a", "b"], 2, args, span)?;
                let children = vec![
                    self.arg_shape(b[0].ok_or(Reported)?, scope, name)?,
                    self.arg_shape(b[1].ok_or(Reported)?, scope, name)?,
                ];
                ShapeKind::Combine {
                    op: CombineOp::Xor,
                    smooth: None,
                    children,
                }
            }
            "sdf" | "displace" => return self.lambda_shape_call(name, args, span, scope),
            "stretch" | "shear" | "twist" | "bend" | "warp" | "heightfield" => {
                self.warp_call(name, args, span, scope)?
            }
            "material" => return self.material_call(args, span, scope),
            "color" => {
                let b =
                    self.bind_args(name, "color(s, [r, g, b])", &["s", "rgb"], 2, args, span)?;
                let child = self.arg_shape(b[0].ok_or(Reported)?, scope, name)?;
                let rgb_e = b[1].ok_or(Reported)?;
                let rgb = match self.const_value(rgb_e, scope, "a colour")? {
                    Value::V3(c) => c,
                    v => {
                        return Err(self.error(
                            Diagnostic::error(
                                rgb_e.span,
                                format!(
                                    "a colour is a vec3 `[r, g, b]`, found {}",
                                    v.ty().user_name()
                                ),
                            )
                            .with_label("not a colour"),
                        ))
                    }
                };
                let material = self.anonymous_material(rgb);
                ShapeKind::Material { material, child }
            }
            _ => {
                if let Some(prim) = super::prims::prim_by_name(name) {
                    self.prim_call(prim, args, span, scope)?
                } else {
                    self.transform_call(name, args, span, scope)?
                }
            }
        };
        Ok(Val::Shape(self.shape(s, span)))
    }

    fn transform_call(
        &mut self,
        name: &str,
        args: &'a [Arg],
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<ShapeKind> {
        let two = |n: &'static str| -> [&'static str; 2] { ["s", n] };
        match name {
            "translate" => {
                let b = self.bind_args(name, "translate(s, v)", &two("v"), 2, args, span)?;
                let child = self.arg_shape(b[0].ok_or(Reported)?, scope, name)?;
                let v = self.arg_vec3(b[1].ok_or(Reported)?, scope, "the offset")?;
                let o = self.g.add(Op::Neg, &[v], b[1].map_or(span, |e| e.span));
                Ok(ShapeKind::Map {
                    map: PointMap::Affine {
                        m: None,
                        o: Some(o),
                        s: None,
                    },
                    child,
                })
            }
            "rotate" | "rotate_x" | "rotate_y" | "rotate_z" => {
                let (child, axis, angle) = if name == "rotate" {
                    let b = self.bind_args(
                        name,
                        "rotate(s, axis, angle)",
                        &["s", "axis", "angle"],
                        3,
                        args,
                        span,
                    )?;
                    let child = self.arg_shape(b[0].ok_or(Reported)?, scope, name)?;
                    let ae = b[1].ok_or(Reported)?;
                    let axis = self.arg_vec3(ae, scope, "the rotation axis")?;
                    if let Some(Value::V3([0.0, 0.0, 0.0])) = self.const_of(axis) {
                        return Err(self.error(
                            Diagnostic::error(ae.span, "the rotation axis is the zero vector")
                                .with_label("has no direction")
                                .with_hint("use for example `[0, 1, 0]` to turn about y"),
                        ));
                    }
                    (
                        child,
                        axis,
                        self.arg_num(b[2].ok_or(Reported)?, scope, "the angle")?,
                    )
                } else {
                    let sig = format!("{name}(s, angle)");
                    let b = self.bind_args(name, &sig, &two("angle"), 2, args, span)?;
                    let child = self.arg_shape(b[0].ok_or(Reported)?, scope, name)?;
                    let mut a = [0.0f32; 3];
                    a[(name.as_bytes()[7] - b'x') as usize] = 1.0;
                    let axis = self.g.vec3(a);
                    (
                        child,
                        axis,
                        self.arg_num(b[1].ok_or(Reported)?, scope, "the angle")?,
                    )
                };
                let m = self.rotation_inverse(axis, angle);
                Ok(ShapeKind::Map {
                    map: PointMap::Affine {
                        m: Some(m),
                        o: None,
                        s: None,
                    },
                    child,
                })
            }
            "scale" => {
                let b = self.bind_args(name, "scale(s, f)", &two("f"), 2, args, span)?;
                let child = self.arg_shape(b[0].ok_or(Reported)?, scope, name)?;
                let fe = b[1].ok_or(Reported)?;
                let f = self.arg_num(fe, scope, "the scale factor")?;
                if let Some(Value::F(x)) = self.const_of(f) {
                    if x <= 0.0 {
                        return Err(self.error(
                            Diagnostic::error(
                                fe.span,
                                format!("the scale factor must be positive, found {x}"),
                            )
                            .with_label("not positive")
                            .with_hint(
                                "to mirror a shape use `mirror_x`, `mirror_y` or `mirror_z`",
                            ),
                        ));
                    }
                }
                Ok(ShapeKind::Map {
                    map: PointMap::Affine {
                        m: None,
                        o: None,
                        s: Some(f),
                    },
                    child,
                })
            }
            "mirror_x" | "mirror_y" | "mirror_z" => {
                let sig = format!("{name}(s)");
                let b = self.bind_args(name, &sig, &["s"], 1, args, span)?;
                let child = self.arg_shape(b[0].ok_or(Reported)?, scope, name)?;
                Ok(ShapeKind::Map {
                    map: PointMap::Mirror(name.as_bytes()[7] - b'x'),
                    child,
                })
            }
            "repeat" => self.repeat_call(args, span, scope),
            "elongate" => {
                let b = self.bind_args(name, "elongate(s, h)", &two("h"), 2, args, span)?;
                let child = self.arg_shape(b[0].ok_or(Reported)?, scope, name)?;
                let h = self.arg_size(b[1].ok_or(Reported)?, scope, "the elongation")?;
                Ok(ShapeKind::Map {
                    map: PointMap::Elongate(h),
                    child,
                })
            }
            "round" | "onion" => {
                let (sig, what) = if name == "round" {
                    ("round(s, r)", "the rounding radius")
                } else {
                    ("onion(s, t)", "the shell thickness")
                };
                let pname = if name == "round" { "r" } else { "t" };
                let b = self.bind_args(name, sig, &two(pname), 2, args, span)?;
                let child = self.arg_shape(b[0].ok_or(Reported)?, scope, name)?;
                let r = self.arg_nonneg(b[1].ok_or(Reported)?, scope, what)?;
                let modifier = if name == "round" {
                    DistMod::Round(r)
                } else {
                    DistMod::Onion(r)
                };
                Ok(ShapeKind::Modify { modifier, child })
            }
            _ => Err(self.error(Diagnostic::error(
                span,
                format!("internal: no shape function `{name}`"),
            ))),
        }
    }

    fn repeat_call(&mut self, args: &'a [Arg], span: Span, scope: &Rc<Scope<'a>>) -> R<ShapeKind> {
        let b = self.bind_args(
            "repeat",
            "repeat(s, period, count: [nx, ny, nz])",
            &["s", "period", "count"],
            2,
            args,
            span,
        )?;
        let child = self.arg_shape(b[0].ok_or(Reported)?, scope, "repeat")?;
        let pe = b[1].ok_or(Reported)?;
        let period = self.const_vec3(pe, scope, "the repeat period")?;
        if period.iter().any(|x| *x < 0.0) || period.iter().all(|x| *x == 0.0) {
            return Err(self.error(
                Diagnostic::error(
                    pe.span,
                    format!(
                        "the repeat period [{}] must be non-negative and not all zero",
                        period.map(|x| x.to_string()).join(", ")
                    ),
                )
                .with_label("invalid period")
                .with_hint("a 0 component means no repetition on that axis, e.g. `[3, 0, 3]`"),
            ));
        }
        let Some(ce) = b[2] else {
            return Ok(ShapeKind::Map {
                map: PointMap::Repeat { period },
                child,
            });
        };
        let c = self.const_vec3(ce, scope, "the repeat count")?;
        let mut count = [1u32; 3];
        for i in 0..3 {
            if c[i] < 1.0 || c[i].fract() != 0.0 || c[i] > limits::MAX_REPEAT_COUNT as f32 {
                return Err(self.error(
                    Diagnostic::error(
                        ce.span,
                        format!(
                            "repeat counts must be whole numbers from 1 to {}, found {}",
                            limits::MAX_REPEAT_COUNT,
                            c[i]
                        ),
                    )
                    .with_label("invalid count"),
                ));
            }
            count[i] = if period[i] == 0.0 { 1 } else { c[i] as u32 };
        }
        Ok(ShapeKind::Map {
            map: PointMap::RepeatLimited { period, count },
            child,
        })
    }

    /// `sdf(|p| expr, lipschitz: L)` and `displace(s, |p| expr, lipschitz: L)`.
    fn lambda_shape_call(
        &mut self,
        name: &str,
        args: &'a [Arg],
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<Val<'a>> {
        let (b, child) = if name == "sdf" {
            (
                self.bind_args(
                    name,
                    "sdf(|p| expr, lipschitz: L)",
                    &["f", "lipschitz"],
                    1,
                    args,
                    span,
                )?,
                None,
            )
        } else {
            let mut b = self.bind_args(
                name,
                "displace(s, |p| expr, lipschitz: L)",
                &["s", "f", "lipschitz"],
                2,
                args,
                span,
            )?;
            let child = self.arg_shape(b.remove(0).ok_or(Reported)?, scope, name)?;
            (b, Some(child))
        };
        let fe = b[0].ok_or(Reported)?;
        let lam = match self.expr(fe, scope)? {
            Val::Lambda(l) => l,
            Val::Poison => return Err(Reported),
            other => {
                let d = self.describe(&other);
                return Err(self.error(
                    Diagnostic::error(
                        fe.span,
                        format!("`{name}` takes a lambda `|p| expr`, found {d}"),
                    )
                    .with_label("expected a lambda")
                    .with_hint(if name == "sdf" {
                        "for example `sdf(|p| length(p) - 1)`"
                    } else {
                        "for example `displace(s, |p| sin(30 * p.y) / 16, lipschitz: 2.875)`"
                    }),
                ));
            }
        };
        let (lambda, body) = self.apply_lambda(&lam, &[Ty::Vec3], name, Ty::F32)?;
        let declared = b[1]
            .map(|le| self.declared_lipschitz(le, scope))
            .transpose()?;
        let kind = match child {
            None => ShapeKind::Sdf {
                body,
                lambda,
                lipschitz: declared.map_or_else(|| self.g.f32(1.0), |d| d.0),
                declared: declared.map(|d| d.1),
            },
            Some(child) => ShapeKind::Displace {
                child,
                body,
                lambda,
                lipschitz: declared,
            },
        };
        Ok(Val::Shape(self.shape(kind, span)))
    }

    /// Lowers a lambda's body with its parameters bound to fresh placeholders.
    pub fn apply_lambda(
        &mut self,
        lam: &Rc<LambdaVal<'a>>,
        tys: &[Ty],
        fname: &str,
        result: Ty,
    ) -> R<(u32, NodeId)> {
        if lam.params.len() != tys.len() {
            let want = if tys.len() == 1 {
                "one parameter, `|p| ...`"
            } else {
                "two parameters, `|x, z| ...`"
            };
            return Err(self.error(
                Diagnostic::error(
                    lam.span,
                    format!(
                        "the lambda of `{fname}` takes {want}, this one has {}",
                        lam.params.len()
                    ),
                )
                .with_label("wrong number of parameters")
                .with_hint(if tys.len() == 1 {
                    "the one parameter is the point, a vec3: `|p| length(p) - 1`"
                } else {
                    "the two parameters are the ground point's x and z; the lambda gives the height there: `|x, z| sin(x) * cos(z)`"
                }),
            ));
        }
        let id = self.fresh_lambda();
        let mut locals = Vec::new();
        for (i, (p, ty)) in lam.params.iter().zip(tys).enumerate() {
            let n = self.g.input(
                Op::LambdaArg {
                    lambda: id,
                    index: i as u8,
                },
                *ty,
                p.span,
            );
            locals.push((p.name.as_str(), Val::Num(n)));
        }
        let scope = Rc::new(Scope {
            locals,
            parent: Some(lam.scope.clone()),
            visible: lam.scope.visible,
        });
        let v = self.expr(lam.body, &scope)?;
        match v {
            Val::Num(n) if self.g.ty(n) == result => Ok((id, n)),
            Val::Poison => Err(Reported),
            other => {
                let d = self.describe(&other);
                Err(self.error(
                    Diagnostic::error(
                        lam.body.span,
                        format!(
                            "the lambda of `{fname}` must give {}, this one gives {d}",
                            result.user_name()
                        ),
                    )
                    .with_label("lambda body"),
                ))
            }
        }
    }

    fn material_call(&mut self, args: &'a [Arg], span: Span, scope: &Rc<Scope<'a>>) -> R<Val<'a>> {
        let b = self.bind_args(
            "material",
            "material(s, NAME)",
            &["s", "name"],
            2,
            args,
            span,
        )?;
        // The name first: in an unused `fn` whose shape is a parameter (unknown, so silent),
        // a material defined below is still reported.
        let ne = b[1].ok_or(Reported)?;
        let ExprKind::Name(id) = &ne.kind else {
            return Err(self.error(
                Diagnostic::error(ne.span, "`material` takes the name of a `material` item")
                    .with_label("expected a material name")
                    .with_hint("declare `material red { color: [1, 0, 0] }` above, then write `.material(red)`"),
            ));
        };
        let Some(material) = self
            .materials
            .iter()
            .position(|m| m.name == id.name && !m.name.contains('#'))
        else {
            if let Some(d) = self.defined_later(&id.name, id.span, "the material") {
                return Err(self.error(d));
            }
            let names: Vec<&str> = self
                .materials
                .iter()
                .skip(1)
                .filter(|m| !m.name.contains('#'))
                .map(|m| m.name.as_str())
                .collect();
            let mut d = Diagnostic::error(id.span, format!("unknown material `{}`", id.name))
                .with_label("no material item has this name above");
            d = match nearest(&id.name, names.iter().copied()) {
                Some(s) => d.with_hint(format!("did you mean `{s}`?")),
                None => d.with_hint(format!(
                    "declare it first: `material {} {{ color: [r, g, b] }}`",
                    id.name
                )),
            };
            return Err(self.error(d));
        };
        // A `fn` body is lowered where the fn is called, when every material above the call
        // is known; the contract still asks for the material above its use in the text.
        if let Some(d) = self.defined_later(&id.name, id.span, "the material") {
            return Err(self.error(d));
        }
        let child = self.arg_shape(b[0].ok_or(Reported)?, scope, "material")?;
        let kind = ShapeKind::Material {
            material: material as u32,
            child,
        };
        Ok(Val::Shape(self.shape(kind, span)))
    }

    fn anonymous_material(&mut self, rgb: [f32; 3]) -> u32 {
        if let Some(i) = self
            .materials
            .iter()
            .position(|m| m.name.starts_with("color#") && m.color == rgb)
        {
            return i as u32;
        }
        let n = self
            .materials
            .iter()
            .filter(|m| m.name.starts_with("color#"))
            .count();
        self.materials.push(Material {
            name: format!("color#{n}"),
            color: rgb,
            ..Material::default()
        });
        // Kept in step with `materials`, which a duplicate `material` item indexes.
        self.material_spans.push(Span::default());
        self.materials.len() as u32 - 1
    }

    /// The matrix that maps a world point into the frame of a shape rotated by `angle` about
    /// `axis` (the transpose of the rotation). Constant inputs are computed in f64.
    fn rotation_inverse(&mut self, axis: NodeId, angle: NodeId) -> NodeId {
        if let (Some(Value::V3(a)), Some(Value::F(t))) = (self.const_of(axis), self.const_of(angle))
        {
            let l = a.iter().map(|x| (*x as f64).powi(2)).sum::<f64>().sqrt();
            let a = a.map(|x| x as f64 / l);
            let (s, c) = (t as f64).sin_cos();
            // Rodrigues: R = c I + s [a]x + (1 - c) a a^T; we store R^T, column by column.
            let r = |i: usize, j: usize| {
                let cross = [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]];
                let id = if i == j { 1.0 } else { 0.0 };
                c * id + s * cross[i][j] + (1.0 - c) * a[i] * a[j]
            };
            let cols = [0, 1, 2].map(|col| [0, 1, 2].map(|row| r(col, row) as f32));
            return self.g.konst(Value::M3(cols));
        }
        // Symbolic (an animated angle): the same formula as nodes.
        let a = self.g.builtin(Builtin::Normalize, &[axis]);
        let s = self.g.builtin(Builtin::Sin, &[angle]);
        let c = self.g.builtin(Builtin::Cos, &[angle]);
        let one = self.g.f32(1.0);
        let omc = self.g.op(Op::Sub, &[one, c]);
        let comp: Vec<NodeId> = (0..3u8)
            .map(|i| self.g.op(Op::Swizzle(crate::ops::Swizzle::new(&[i])), &[a]))
            .collect();
        let mut cols = Vec::new();
        for col in 0..3 {
            let mut entries = Vec::new();
            for row in 0..3 {
                // R^T[row][col] = R[col][row]
                let (i, j) = (col, row);
                let aa = self.g.op(Op::Mul, &[comp[i], comp[j]]);
                let mut e = self.g.op(Op::Mul, &[omc, aa]);
                if i == j {
                    e = self.g.op(Op::Add, &[e, c]);
                } else {
                    // [a]x[i][j] = -eps_ijk a_k
                    let k = 3 - i - j;
                    let sign_pos = (i + 1) % 3 != j;
                    let sa = self.g.op(Op::Mul, &[s, comp[k]]);
                    e = if sign_pos {
                        self.g.op(Op::Add, &[e, sa])
                    } else {
                        self.g.op(Op::Sub, &[e, sa])
                    };
                }
                entries.push(e);
            }
            cols.push(self.g.op(Op::MakeVec, &entries));
        }
        self.g.op(Op::MakeMat3, &cols)
    }

    // ---- argument helpers ----

    pub fn arg_shape(&mut self, e: &'a Expr, scope: &Rc<Scope<'a>>, fname: &str) -> R<ShapeId> {
        let v = self.expr(e, scope)?;
        self.expect_shape(v, e.span, &format!("this argument of `{fname}`"))
    }

    pub(super) fn arg_num(&mut self, e: &'a Expr, scope: &Rc<Scope<'a>>, what: &str) -> R<NodeId> {
        let v = self.expr(e, scope)?;
        let n = self.expect_num(v, e.span, what)?;
        self.check_finite(n, e.span, what)
    }

    /// A constant argument must be finite (`1 / 0` is an error where it is written) and
    /// within `limits::MAX_MAGNITUDE`: the compiled formulas multiply sizes together (a
    /// capsule's `dot(b - a, b - a)`, a cone's slopes, a scene's bounds), and a product past
    /// f32's 3.4e38 would make the shader invalid, since WGSL makes an overflow in a
    /// constant expression an error.
    pub(super) fn check_finite(&mut self, n: NodeId, span: Span, what: &str) -> R<NodeId> {
        let max = crate::scene::limits::MAX_MAGNITUDE;
        match self.const_of(n) {
            Some(v) if !v.all_finite() => Err(self.error(
                Diagnostic::error(span, format!("{what} is not finite"))
                    .with_label("evaluates to infinity or NaN")
                    .with_hint(super::NOT_FINITE_HINT),
            )),
            Some(v) if v.comps().iter().any(|x| x.abs() > max) => Err(self.error(
                Diagnostic::error(span, format!("{what} must be at most {max:e} in magnitude"))
                    .with_label("too large")
                    .with_hint("the shader computes in f32, about 7 significant digits: at 1e12 neighbouring values are 65 536 apart, and products of such values overflow"),
            )),
            _ => Ok(n),
        }
    }

    pub(super) fn arg_nonneg(
        &mut self,
        e: &'a Expr,
        scope: &Rc<Scope<'a>>,
        what: &str,
    ) -> R<NodeId> {
        let n = self.arg_num(e, scope, what)?;
        self.check_nonneg(n, e.span, what)?;
        Ok(n)
    }

    pub(super) fn opt_nonneg(
        &mut self,
        e: Option<&'a Expr>,
        scope: &Rc<Scope<'a>>,
        what: &str,
    ) -> R<Option<NodeId>> {
        e.map(|e| self.arg_nonneg(e, scope, what)).transpose()
    }

    pub(super) fn check_nonneg(&mut self, n: NodeId, span: Span, what: &str) -> R<()> {
        if let Some(v) = self.const_of(n) {
            if v.comps().iter().any(|x| *x < 0.0) {
                let shown = match v {
                    Value::F(x) => format!("{x}"),
                    Value::V3(x) => format!("[{}]", x.map(|c| c.to_string()).join(", ")),
                    _ => "a negative value".into(),
                };
                return Err(self.error(
                    Diagnostic::error(span, format!("{what} must not be negative, found {shown}"))
                        .with_label("negative")
                        .with_hint(
                            "sizes and radii are zero or more; to move a shape use `.translate(v)`",
                        ),
                ));
            }
        }
        Ok(())
    }

    pub(super) fn arg_vec3(&mut self, e: &'a Expr, scope: &Rc<Scope<'a>>, what: &str) -> R<NodeId> {
        match self.expr(e, scope)? {
            Val::Num(n) if self.g.ty(n) == Ty::Vec3 => self.check_finite(n, e.span, what),
            Val::Poison => Err(Reported),
            other => {
                let d = self.describe(&other);
                let mut diag =
                    Diagnostic::error(e.span, format!("{what} must be a vec3, found {d}"))
                        .with_label("expected `[x, y, z]`");
                if matches!(other, Val::Num(n) if self.g.ty(n) == Ty::F32) {
                    diag = diag.with_hint("a vec3 has three components, `[x, y, z]`: `[2, 0, 0]`, or `[2, 2, 2]` for the same on every axis");
                }
                Err(self.error(diag))
            }
        }
    }

    /// A size: a vec3, or a number meaning the same on every axis; never negative.
    pub(super) fn arg_size(&mut self, e: &'a Expr, scope: &Rc<Scope<'a>>, what: &str) -> R<NodeId> {
        let n = match self.expr(e, scope)? {
            Val::Num(n) if self.g.ty(n) == Ty::Vec3 => n,
            Val::Num(n) if self.g.ty(n) == Ty::F32 => self.g.splat(n, Ty::Vec3),
            Val::Poison => return Err(Reported),
            other => {
                let d = self.describe(&other);
                return Err(self.error(
                    Diagnostic::error(
                        e.span,
                        format!("{what} must be a number or a vec3, found {d}"),
                    )
                    .with_label("expected a size"),
                ));
            }
        };
        self.check_nonneg(n, e.span, what)?;
        self.check_finite(n, e.span, what)
    }

    fn const_vec3(&mut self, e: &'a Expr, scope: &Rc<Scope<'a>>, what: &str) -> R<[f32; 3]> {
        match self.const_value(e, scope, what)? {
            Value::V3(v) => Ok(v),
            Value::F(x) => Ok([x; 3]),
            v => Err(self.error(
                Diagnostic::error(
                    e.span,
                    format!(
                        "{what} must be a number or a vec3, found {}",
                        v.ty().user_name()
                    ),
                )
                .with_label("expected `[x, y, z]`"),
            )),
        }
    }
}
