//! The block items: `material`, `light`, `camera` and `render`, with the spec's defaults.

use super::scope::Scope;
use super::{Lowerer, Reported, R};
use crate::scene::{
    limits, Ao, Camera, Epsilon, Fog, Light, LightKind, Material, Normals, RenderSettings, Shadows,
};
use crate::value::Value;
use sdfc_syntax::ast::{Expr, ExprKind, Field, Ident};
use sdfc_syntax::diag::{nearest, Diagnostic};
use sdfc_syntax::span::Span;
use std::rc::Rc;

impl<'a> Lowerer<'a> {
    /// Checks field names against `known` (unknown and repeated fields are errors).
    fn check_fields(&mut self, block: &str, fields: &'a [Field], known: &[&str]) -> R<()> {
        let mut ok = true;
        for (i, f) in fields.iter().enumerate() {
            if !known.contains(&f.name.name.as_str()) {
                let mut d = Diagnostic::error(
                    f.name.span,
                    format!("`{block}` has no field `{}`", f.name.name),
                )
                .with_label("unknown field");
                d = match nearest(&f.name.name, known.iter().copied()) {
                    Some(s) => d.with_hint(format!("did you mean `{s}`?")),
                    None => d.with_hint(format!(
                        "the fields are {}",
                        known
                            .iter()
                            .map(|k| format!("`{k}`"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    )),
                };
                self.error(d);
                ok = false;
            } else if let Some(prev) = fields[..i].iter().find(|g| g.name.name == f.name.name) {
                let prev = prev.name.span;
                self.error(
                    Diagnostic::error(
                        f.name.span,
                        format!("field `{}` is given twice", f.name.name),
                    )
                    .with_secondary(prev, "first here"),
                );
                ok = false;
            }
        }
        if ok {
            Ok(())
        } else {
            Err(Reported)
        }
    }

    fn field_f32(&mut self, f: &'a Field, scope: &Rc<Scope<'a>>) -> R<f32> {
        let what = format!("`{}`", f.name.name);
        match self.const_value(&f.value, scope, &what)? {
            Value::F(x) => Ok(x),
            v => Err(self.error(
                Diagnostic::error(
                    f.value.span,
                    format!("{what} must be a number, found {}", v.ty().user_name()),
                )
                .with_label("expected a number"),
            )),
        }
    }

    fn field_vec3(&mut self, f: &'a Field, scope: &Rc<Scope<'a>>) -> R<[f32; 3]> {
        let what = format!("`{}`", f.name.name);
        match self.const_value(&f.value, scope, &what)? {
            Value::V3(x) => Ok(x),
            v => Err(self.error(
                Diagnostic::error(
                    f.value.span,
                    format!(
                        "{what} must be a vec3 `[x, y, z]`, found {}",
                        v.ty().user_name()
                    ),
                )
                .with_label("expected a vec3"),
            )),
        }
    }

    fn field_range(
        &mut self,
        f: &'a Field,
        scope: &Rc<Scope<'a>>,
        lo: f32,
        hi: f32,
        hint: &str,
    ) -> R<f32> {
        let x = self.field_f32(f, scope)?;
        if x < lo || x > hi {
            let mut d = Diagnostic::error(
                f.value.span,
                format!(
                    "`{}` must be between {} and {}, found {}",
                    f.name.name,
                    readable(lo),
                    readable(hi),
                    readable(x)
                ),
            )
            .with_label("out of range");
            if !hint.is_empty() {
                d = d.with_hint(hint.to_string());
            }
            return Err(self.error(d));
        }
        Ok(x)
    }

    fn field_count(&mut self, f: &'a Field, scope: &Rc<Scope<'a>>, lo: u32, hi: u32) -> R<u32> {
        let x = self.field_f32(f, scope)?;
        if x.fract() != 0.0 || x < lo as f32 || x > hi as f32 {
            return Err(self.error(
                Diagnostic::error(
                    f.value.span,
                    format!(
                        "`{}` must be a whole number from {lo} to {hi}, found {x}",
                        f.name.name
                    ),
                )
                .with_label(if x > hi as f32 {
                    "above the documented limit"
                } else {
                    "invalid count"
                }),
            ));
        }
        Ok(x as u32)
    }

    pub(super) fn material_item(&mut self, name: &'a Ident, fields: &'a [Field]) {
        let known = [
            "color",
            "ambient",
            "diffuse",
            "specular",
            "shininess",
            "reflectivity",
        ];
        if let Some(i) = self.materials.iter().position(|m| m.name == name.name) {
            let prev = self.material_spans[i];
            self.error(
                Diagnostic::error(
                    name.span,
                    format!("material `{}` is already defined", name.name),
                )
                .with_secondary(prev, "first defined here"),
            );
            return;
        }
        let _ = self.check_fields("material", fields, &known);
        let scope = Rc::new(Scope {
            visible: self.globals_len(),
            ..Scope::default()
        });
        let mut m = Material {
            name: name.name.clone(),
            ..Material::default()
        };
        for f in fields {
            let r = match f.name.name.as_str() {
                "color" => self.field_vec3(f, &scope).map(|c| m.color = c),
                "ambient" => self
                    .field_range(f, &scope, 0.0, 1e6, "")
                    .map(|x| m.ambient = x),
                "diffuse" => self
                    .field_range(f, &scope, 0.0, 1e6, "")
                    .map(|x| m.diffuse = x),
                "specular" => self
                    .field_range(f, &scope, 0.0, 1e6, "")
                    .map(|x| m.specular = x),
                "shininess" => self
                    .field_range(f, &scope, 0.0, 1e6, "")
                    .map(|x| m.shininess = x),
                "reflectivity" => self
                    .field_range(f, &scope, 0.0, 1.0, "")
                    .map(|x| m.reflectivity = x),
                _ => Ok(()),
            };
            let _ = r;
        }
        self.materials.push(m);
        self.material_spans.push(name.span);
    }

    pub(super) fn light_item(&mut self, kind: &'a Ident, fields: &'a [Field]) {
        let scope = Rc::new(Scope {
            visible: self.globals_len(),
            ..Scope::default()
        });
        let place = match kind.name.as_str() {
            "point" => "position",
            "directional" => "direction",
            other => {
                let mut d =
                    Diagnostic::error(kind.span, format!("unknown kind of light `{other}`"))
                        .with_label("light kind");
                d = match nearest(other, ["point", "directional"]) {
                    Some(s) => d.with_hint(format!("did you mean `{s}`?")),
                    None => d.with_hint("lights are `point` or `directional`"),
                };
                self.error(d);
                return;
            }
        };
        if self
            .check_fields(
                &format!("light {}", kind.name),
                fields,
                &[place, "color", "intensity"],
            )
            .is_err()
        {
            return;
        }
        let mut light = Light {
            kind: LightKind::Point { position: [0.0; 3] },
            color: [1.0; 3],
            intensity: 1.0,
        };
        let mut vector = None;
        for f in fields {
            match f.name.name.as_str() {
                "color" => {
                    if let Ok(c) = self.field_vec3(f, &scope) {
                        light.color = c;
                    }
                }
                "intensity" => {
                    if let Ok(x) = self.field_range(f, &scope, 0.0, 1e9, "") {
                        light.intensity = x;
                    }
                }
                _ => vector = self.field_vec3(f, &scope).ok().map(|v| (v, f.value.span)),
            }
        }
        let Some((v, vspan)) = vector else {
            if !fields.iter().any(|f| f.name.name == place) {
                self.error(
                    Diagnostic::error(
                        kind.span,
                        format!("a {} light needs a `{place}`", kind.name),
                    )
                    .with_label("missing field")
                    .with_hint(format!("add `{place}: [x, y, z]`")),
                );
            }
            return;
        };
        light.kind = if place == "position" {
            LightKind::Point { position: v }
        } else {
            let l = v.iter().map(|x| (*x as f64).powi(2)).sum::<f64>().sqrt();
            if l == 0.0 {
                self.error(
                    Diagnostic::error(vspan, "the light's direction is the zero vector")
                        .with_label("has no direction"),
                );
                return;
            }
            LightKind::Directional {
                direction: v.map(|x| (x as f64 / l) as f32),
            }
        };
        self.lights.push(light);
    }

    pub(super) fn camera_item(&mut self, fields: &'a [Field], span: Span) -> R<Camera> {
        self.check_fields(
            "camera",
            fields,
            &["position", "target", "up", "fov", "focal_length"],
        )?;
        let scope = Rc::new(Scope {
            visible: self.globals_len(),
            ..Scope::default()
        });
        let mut c = Camera::default();
        let mut fov_field: Option<Span> = None;
        let mut ok = true;
        for f in fields {
            let r = match f.name.name.as_str() {
                "position" => self.field_vec3(f, &scope).map(|v| c.position = v),
                "target" => self.field_vec3(f, &scope).map(|v| c.target = v),
                "up" => self.field_vec3(f, &scope).map(|v| c.up = v),
                "fov" | "focal_length" => {
                    if let Some(prev) = fov_field {
                        Err(self.error(
                            Diagnostic::error(
                                f.name.span,
                                "the camera has both `fov` and `focal_length`",
                            )
                            .with_secondary(prev, "the other one")
                            .with_hint("give one of them"),
                        ))
                    } else {
                        fov_field = Some(f.name.span);
                        if f.name.name == "fov" {
                            let hint = match self.const_of_expr(&f.value) {
                                Some(x) if x >= std::f32::consts::PI => {
                                    format!("angles are radians: write `{x}deg` for {x} degrees")
                                }
                                _ => {
                                    "the vertical field of view is between 0 and 180deg".to_string()
                                }
                            };
                            match self.field_f32(f, &scope) {
                                Ok(x) if x > 0.0 && x < std::f32::consts::PI => {
                                    c.fov = x;
                                    Ok(())
                                }
                                Ok(x) => Err(self.error(
                                    Diagnostic::error(f.value.span, format!("`fov` must be between 0 and 180deg (3.14159 radians), found {x}"))
                                        .with_label("out of range")
                                        .with_hint(hint),
                                )),
                                Err(e) => Err(e),
                            }
                        } else {
                            self.field_range(f, &scope, 1e-6, 1e6, "")
                                .map(|fl| c.fov = (2.0 * (1.0 / fl as f64).atan()) as f32)
                        }
                    }
                }
                _ => Ok(()),
            };
            ok &= r.is_ok();
        }
        if !ok {
            return Err(Reported);
        }
        let sub = |a: [f32; 3], b: [f32; 3]| [0, 1, 2].map(|i| a[i] as f64 - b[i] as f64);
        let fwd = sub(c.target, c.position);
        let up = c.up.map(|x| x as f64);
        let cross = [
            fwd[1] * up[2] - fwd[2] * up[1],
            fwd[2] * up[0] - fwd[0] * up[2],
            fwd[0] * up[1] - fwd[1] * up[0],
        ];
        let n2 = |v: [f64; 3]| v.iter().map(|x| x * x).sum::<f64>();
        if n2(fwd) == 0.0 {
            return Err(self.error(
                Diagnostic::error(span, "the camera's target is its position")
                    .with_label("no viewing direction")
                    .with_hint("move `target` away from `position`"),
            ));
        }
        if n2(cross) <= 1e-12 * n2(fwd) * n2(up) {
            let at = fields
                .iter()
                .find(|f| f.name.name == "up")
                .map_or(span, |f| f.value.span);
            return Err(self.error(
                Diagnostic::error(at, "the camera's `up` is parallel to its viewing direction")
                    .with_label("no way to tell right from left")
                    .with_hint("choose an `up` that is not along `target - position`, e.g. `[0, 0, 1]` when looking straight down"),
            ));
        }
        Ok(c)
    }

    pub(super) fn render_item(&mut self, fields: &'a [Field]) -> R<RenderSettings> {
        let known = [
            "max_steps",
            "max_distance",
            "epsilon",
            "relaxation",
            "normals",
            "shadows",
            "ao",
            "reflections",
            "background",
            "fog",
            "antialias",
            "gamma",
        ];
        self.check_fields("render", fields, &known)?;
        let scope = Rc::new(Scope {
            visible: self.globals_len(),
            ..Scope::default()
        });
        let mut r = RenderSettings::default();
        let mut ok = true;
        for f in fields {
            let res = match f.name.name.as_str() {
                "max_steps" => self
                    .field_count(f, &scope, 1, limits::MAX_STEPS)
                    .map(|x| r.max_steps = x),
                "max_distance" => self
                    .field_range(f, &scope, 1e-6, 1e30, "")
                    .map(|x| r.max_distance = x),
                "epsilon" => match word(&f.value) {
                    Some("pixel") => {
                        r.epsilon = Epsilon::Pixel;
                        Ok(())
                    }
                    _ => self
                        .field_range(f, &scope, 1e-30, 1e6, "write a positive number, or `pixel`")
                        .map(|x| r.epsilon = Epsilon::Absolute(x)),
                },
                "relaxation" => {
                    let x = self.field_f32(f, &scope);
                    match x {
                        Ok(x) if (1.0..2.0).contains(&x) => {
                            r.relaxation = x;
                            Ok(())
                        }
                        Ok(x) => Err(self.error(
                            Diagnostic::error(
                                f.value.span,
                                format!("`relaxation` must be at least 1 and below 2, found {x}"),
                            )
                            .with_label("out of range")
                            .with_hint("1 is plain sphere tracing; 1.2 to 1.6 is typical"),
                        )),
                        Err(e) => Err(e),
                    }
                }
                "normals" => {
                    let choices = ["central", "tetrahedron", "forward", "analytic"];
                    match word(&f.value) {
                        Some("central") => {
                            r.normals = Normals::Central;
                            Ok(())
                        }
                        Some("tetrahedron") => {
                            r.normals = Normals::Tetrahedron;
                            Ok(())
                        }
                        Some("forward") => {
                            r.normals = Normals::Forward;
                            Ok(())
                        }
                        Some("analytic") => {
                            r.normals = Normals::Analytic;
                            Ok(())
                        }
                        other => Err(self.bad_choice(f, other, &choices)),
                    }
                }
                "shadows" => match (&f.value.kind, word(&f.value)) {
                    (_, Some("none")) => {
                        r.shadows = Shadows::None;
                        Ok(())
                    }
                    (_, Some("hard")) => {
                        r.shadows = Shadows::Hard;
                        Ok(())
                    }
                    (ExprKind::Call { callee, args, .. }, _) if callee.name == "soft" => {
                        let b = self.bind_args("soft", "soft(k)", &["k"], 1, args, f.value.span)?;
                        let k = self.const_positive(
                            b[0].ok_or(Reported)?,
                            &scope,
                            "the penumbra sharpness `k`",
                        )?;
                        {
                            r.shadows = Shadows::Soft(k);
                            Ok(())
                        }
                    }
                    (_, other) => Err(self.bad_choice(f, other, &["none", "hard", "soft(k)"])),
                },
                "ao" => match (&f.value.kind, word(&f.value)) {
                    (_, Some("none")) => {
                        r.ao = None;
                        Ok(())
                    }
                    (ExprKind::Call { callee, args, .. }, _) if callee.name == "ao" => {
                        let names = ["samples", "step", "strength", "falloff"];
                        let b = self.bind_args(
                            "ao",
                            "ao(samples: 5, step: 0.05, strength: 1, falloff: 0.75)",
                            &names,
                            0,
                            args,
                            f.value.span,
                        )?;
                        let mut ao = Ao {
                            samples: 5,
                            step: 0.05,
                            strength: 1.0,
                            falloff: 0.75,
                        };
                        if let Some(e) = b[0] {
                            let x = self.const_positive(e, &scope, "`samples`")?;
                            if x.fract() != 0.0 || x > limits::MAX_AO_SAMPLES as f32 {
                                return Err(self.error(Diagnostic::error(
                                    e.span,
                                    format!(
                                        "`samples` must be a whole number from 1 to {}",
                                        limits::MAX_AO_SAMPLES
                                    ),
                                )));
                            }
                            ao.samples = x as u32;
                        }
                        if let Some(e) = b[1] {
                            ao.step = self.const_positive(e, &scope, "`step`")?;
                        }
                        if let Some(e) = b[2] {
                            ao.strength = self.const_positive(e, &scope, "`strength`")?;
                        }
                        if let Some(e) = b[3] {
                            ao.falloff = self.const_positive(e, &scope, "`falloff`")?;
                        }
                        {
                            r.ao = Some(ao);
                            Ok(())
                        }
                    }
                    (_, other) => Err(self.bad_choice(f, other, &["none", "ao(...)"])),
                },
                "reflections" => self
                    .field_count(f, &scope, 0, limits::MAX_REFLECTIONS)
                    .map(|x| r.reflections = x),
                "background" => self.field_vec3(f, &scope).map(|v| r.background = v),
                "fog" => match (&f.value.kind, word(&f.value)) {
                    (_, Some("none")) => {
                        r.fog = None;
                        Ok(())
                    }
                    (ExprKind::Call { callee, args, .. }, _) if callee.name == "fog" => {
                        let b = self.bind_args(
                            "fog",
                            "fog(density, [r, g, b])",
                            &["density", "color"],
                            2,
                            args,
                            f.value.span,
                        )?;
                        let density =
                            self.const_positive(b[0].ok_or(Reported)?, &scope, "the fog density")?;
                        let ce = b[1].ok_or(Reported)?;
                        let color = match self.const_value(ce, &scope, "the fog colour")? {
                            Value::V3(c) => c,
                            v => {
                                return Err(self.error(Diagnostic::error(
                                    ce.span,
                                    format!(
                                        "the fog colour must be a vec3, found {}",
                                        v.ty().user_name()
                                    ),
                                )))
                            }
                        };
                        {
                            r.fog = Some(Fog { density, color });
                            Ok(())
                        }
                    }
                    (_, other) => {
                        Err(self.bad_choice(f, other, &["none", "fog(density, [r, g, b])"]))
                    }
                },
                "antialias" => self
                    .field_count(f, &scope, 1, limits::MAX_ANTIALIAS)
                    .map(|x| r.antialias = x),
                "gamma" => self
                    .field_range(f, &scope, 0.1, 10.0, "")
                    .map(|x| r.gamma = x),
                _ => Ok(()),
            };
            ok &= res.is_ok();
        }
        if ok {
            Ok(r)
        } else {
            Err(Reported)
        }
    }

    fn const_positive(&mut self, e: &'a Expr, scope: &Rc<Scope<'a>>, what: &str) -> R<f32> {
        match self.const_value(e, scope, what)? {
            Value::F(x) if x > 0.0 => Ok(x),
            Value::F(x) => Err(self.error(
                Diagnostic::error(e.span, format!("{what} must be positive, found {x}"))
                    .with_label("not positive"),
            )),
            v => Err(self.error(Diagnostic::error(
                e.span,
                format!("{what} must be a number, found {}", v.ty().user_name()),
            ))),
        }
    }

    fn bad_choice(&mut self, f: &'a Field, found: Option<&str>, choices: &[&str]) -> Reported {
        let list = choices
            .iter()
            .map(|c| format!("`{c}`"))
            .collect::<Vec<_>>()
            .join(", ");
        let mut d = Diagnostic::error(
            f.value.span,
            format!("`{}` must be one of {list}", f.name.name),
        )
        .with_label("not a valid setting");
        if let Some(s) = found.and_then(|w| nearest(w, choices.iter().copied())) {
            d = d.with_hint(format!("did you mean `{s}`?"));
        }
        self.error(d)
    }

    fn globals_len(&self) -> usize {
        self.global_scope().visible
    }
}

impl<'a> Lowerer<'a> {
    /// The value of a plain number literal, for hints (no diagnostics).
    fn const_of_expr(&self, e: &Expr) -> Option<f32> {
        match &e.kind {
            ExprKind::Number(x) => Some(*x),
            _ => None,
        }
    }
}

/// The bare word of a setting such as `pixel` or `none`.
fn word(e: &Expr) -> Option<&str> {
    match &e.kind {
        ExprKind::Name(id) => Some(id.name.as_str()),
        _ => None,
    }
}

/// A number as a message shows it: `1e30` and `1e-6` in exponent form rather than thirty
/// digits, others as written (`0.5`, `1000`).
fn readable(x: f32) -> String {
    let a = x.abs();
    if a != 0.0 && a.is_finite() && !(1e-4..1e6).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}
