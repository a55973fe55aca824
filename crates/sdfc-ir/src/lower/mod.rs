//! Lowering: names resolved, `fn`s and lambdas inlined, types and arities checked, the AST
//! turned into a [`Scene`] (shapes over a hash-consed value graph).

mod args;
mod builtins;
pub mod expansion;
mod expr;
mod prims;
mod scope;
mod settings;
mod shapes;
mod warps;

/// The hint of every "not finite" constant error.
pub(crate) const NOT_FINITE_HINT: &str =
    "check for a division by zero, a root, log or `pow` of a negative number, or an overflow past 3.4e38";
/// What some arguments are called in messages, where a message adds a hint for them.
pub(crate) const WHAT_SMOOTH: &str = "`smooth`";
pub(crate) const WHAT_PARAM_DEFAULT: &str = "a param's default";

use crate::graph::{Graph, NodeId};
use crate::hash::{FxHashMap, FxHashSet};
use crate::ops::Op;
use crate::scene::{limits, Camera, Material, ParamDecl, RenderSettings, Scene};
use crate::shape::{ShapeId, ShapeKind, ShapeNode};
use crate::types::Ty;
use crate::value::Value;
use scope::{FnDef, Scope, Val};
use sdfc_syntax::ast::{File, Ident, ItemKind};
use sdfc_syntax::diag::Diagnostic;
use sdfc_syntax::span::Span;
use sdfc_syntax::MAX_DIAGNOSTICS;
use std::rc::Rc;

/// Marks that a diagnostic was already recorded; the caller just stops.
#[derive(Debug, Clone, Copy)]
pub struct Reported;

pub type R<T> = Result<T, Reported>;

/// The result of lowering: the scene, or every error found; warnings either way.
pub struct Lowered {
    pub scene: Option<Scene>,
    pub diagnostics: Vec<Diagnostic>,
}

/// Lowers a parsed file. Never panics; all problems come back as diagnostics.
pub fn lower(file: &File, source_len: usize) -> Lowered {
    let mut l = Lowerer::new();
    l.items(file, source_len);
    let mut diagnostics = std::mem::take(&mut l.diags);
    // In the order of the text: unused `fn`s are checked last, and `check` prints the first.
    diagnostics.sort_by_key(|d| d.span.start);
    let errors = diagnostics.iter().any(|d| d.is_error());
    // As the parser does: a chain of ten thousand numbers joined by `|` is ten thousand
    // errors, and rendering each with its snippet would take seconds.
    if errors && diagnostics.len() > MAX_DIAGNOSTICS {
        let at = diagnostics[MAX_DIAGNOSTICS].span.start as usize;
        diagnostics.truncate(MAX_DIAGNOSTICS);
        diagnostics.push(Diagnostic::error(
            Span::new(at, at),
            format!("too many errors; stopping after {MAX_DIAGNOSTICS}"),
        ));
    }
    let scene_span = l.scene.map(|(_, span)| span);
    let mut scene = if errors { None } else { l.finish() };
    if let (Some(s), Some(span)) = (&scene, scene_span) {
        if let Some(d) = expansion::check(&s.shapes, s.root, span) {
            diagnostics.push(d);
            scene = None;
        }
    }
    Lowered { scene, diagnostics }
}

pub(crate) struct Lowerer<'a> {
    pub g: Graph,
    pub shapes: Vec<ShapeNode>,
    pub diags: Vec<Diagnostic>,
    globals: Vec<(&'a str, Val<'a>, Span)>,
    global_index: FxHashMap<&'a str, usize>,
    pub materials: Vec<Material>,
    material_spans: Vec<Span>,
    pub params: Vec<ParamDecl>,
    lights: Vec<crate::scene::Light>,
    camera: Option<(Camera, Span)>,
    render: Option<(RenderSettings, Span)>,
    scene: Option<(ShapeId, Span)>,
    /// fns being inlined right now, to report recursion.
    call_stack: Vec<usize>,
    next_lambda: u32,
    const_memo: FxHashMap<NodeId, Option<Value<f32>>>,
    too_big: bool,
    /// `fn` calls inlined so far (bounded by `limits::MAX_INLINED_CALLS`).
    inlined_calls: u64,
    /// The `fn`s (by global index) lowered at least once, called or checked.
    called: FxHashSet<usize>,
    /// Each error's place and message, so that a mistake in a `fn` lowered more than once is
    /// reported once (a set: a file of many mistakes must not make this quadratic).
    reported: FxHashSet<(Span, String)>,
    /// Where each `let`, `fn`, `param` and `material` of the file is defined, to explain a
    /// use above its definition.
    pub definitions: FxHashMap<&'a str, Span>,
}

impl<'a> Lowerer<'a> {
    fn new() -> Lowerer<'a> {
        Lowerer {
            g: Graph::new(),
            shapes: Vec::new(),
            diags: Vec::new(),
            globals: Vec::new(),
            global_index: FxHashMap::default(),
            materials: vec![Material::default()],
            material_spans: vec![Span::default()],
            params: Vec::new(),
            lights: Vec::new(),
            camera: None,
            render: None,
            scene: None,
            call_stack: Vec::new(),
            next_lambda: 0,
            const_memo: FxHashMap::default(),
            too_big: false,
            inlined_calls: 0,
            called: FxHashSet::default(),
            reported: FxHashSet::default(),
            definitions: FxHashMap::default(),
        }
    }

    /// Records a diagnostic, once: a `fn` lowered at two calls (or at a call and by the
    /// unused-`fn` check) would otherwise report the same mistake at the same place twice.
    pub fn error(&mut self, d: Diagnostic) -> Reported {
        if self.reported.insert((d.span, d.message.clone())) {
            self.diags.push(d);
        }
        Reported
    }

    pub fn shape(&mut self, kind: ShapeKind, span: Span) -> ShapeId {
        let id = ShapeId(self.shapes.len() as u32);
        self.shapes.push(ShapeNode { kind, span });
        id
    }

    /// The global scope as seen from the item being lowered now.
    fn global_scope(&self) -> Rc<Scope<'a>> {
        Rc::new(Scope {
            locals: Vec::new(),
            parent: None,
            visible: self.globals.len(),
        })
    }

    pub fn lookup(&self, name: &str, scope: &Scope<'a>) -> Option<Val<'a>> {
        if let Some(v) = scope.lookup_local(name) {
            return Some(v.clone());
        }
        let mut s = Some(scope);
        let mut visible = scope.visible;
        while let Some(sc) = s {
            visible = visible.max(sc.visible);
            s = sc.parent.as_deref();
        }
        match self.global_index.get(name) {
            Some(&i) if i < visible => Some(self.globals[i].1.clone()),
            _ => None,
        }
    }

    /// Every name visible from `scope`, for suggestions.
    pub fn visible_names(&self, scope: &Scope<'a>) -> Vec<&'a str> {
        let mut out = Vec::new();
        scope.local_names(&mut out);
        let mut s = Some(scope);
        let mut visible = scope.visible;
        while let Some(sc) = s {
            visible = visible.max(sc.visible);
            s = sc.parent.as_deref();
        }
        out.extend(self.globals.iter().take(visible).map(|(n, _, _)| *n));
        out
    }

    fn define(&mut self, name: &'a Ident, val: Val<'a>) {
        if let Some(&i) = self.global_index.get(name.name.as_str()) {
            let prev = self.globals[i].2;
            self.error(
                Diagnostic::error(name.span, format!("`{}` is already defined", name.name))
                    .with_label("defined again here")
                    .with_secondary(prev, "first defined here")
                    .with_hint("give the second definition another name"),
            );
            return;
        }
        if builtins::is_builtin_function(&name.name) && matches!(val, Val::Func(_)) {
            self.error(
                Diagnostic::error(
                    name.span,
                    format!(
                        "`{}` is a built-in function and cannot be redefined",
                        name.name
                    ),
                )
                .with_label("built-in name")
                .with_hint(format!("call it `my_{}` or another unused name", name.name)),
            );
            return;
        }
        self.global_index
            .insert(name.name.as_str(), self.globals.len());
        self.globals.push((name.name.as_str(), val, name.span));
    }

    /// A diagnostic for a name used before (above) its definition, if that is the mistake.
    pub fn defined_later(&self, name: &str, used: Span, what: &str) -> Option<Diagnostic> {
        let def = *self.definitions.get(name)?;
        (def.start > used.start).then(|| {
            Diagnostic::error(
                used,
                format!("{what} `{name}` is used before it is defined"),
            )
            .with_label("used here")
            .with_secondary(def, "defined later here")
            .with_hint("names must be defined above their first use: move the definition up")
        })
    }

    fn items(&mut self, file: &'a File, source_len: usize) {
        for item in &file.items {
            match &item.kind {
                ItemKind::Let { name, .. }
                | ItemKind::Fn { name, .. }
                | ItemKind::Param { name, .. }
                | ItemKind::Material { name, .. } => {
                    self.definitions
                        .entry(name.name.as_str())
                        .or_insert(name.span);
                }
                _ => {}
            }
        }
        for item in &file.items {
            if self.too_big {
                return;
            }
            match &item.kind {
                ItemKind::Let { name, value } => {
                    let scope = self.global_scope();
                    let v = self.expr(value, &scope).unwrap_or(Val::Poison);
                    // `let big = 1e30 * 1e30;` is wrong where it is written, not where used.
                    let v = self.finite_or_reported(v, value.span);
                    self.define(name, v);
                }
                ItemKind::Fn { name, params, body } => {
                    self.check_fn_params(params);
                    let def = FnDef {
                        name,
                        params,
                        body,
                        index: self.globals.len(),
                        span: item.span,
                    };
                    self.define(name, Val::Func(Rc::new(def)));
                }
                ItemKind::Param { name, default } => {
                    let v = self.param(name, default);
                    self.define(name, v);
                }
                ItemKind::Material { name, fields } => self.material_item(name, fields),
                ItemKind::Light { kind, fields } => self.light_item(kind, fields),
                ItemKind::Camera { fields } => {
                    if let Some((_, prev)) = &self.camera {
                        let prev = *prev;
                        self.error(
                            Diagnostic::error(item.span, "a second `camera` item")
                                .with_label("second camera")
                                .with_secondary(prev, "first camera here")
                                .with_hint("a scene has one camera; remove one of them"),
                        );
                    } else if let Ok(c) = self.camera_item(fields, item.span) {
                        self.camera = Some((c, item.span));
                    }
                }
                ItemKind::Render { fields } => {
                    if let Some((_, prev)) = &self.render {
                        let prev = *prev;
                        self.error(
                            Diagnostic::error(item.span, "a second `render` item")
                                .with_label("second render block")
                                .with_secondary(prev, "first render block here")
                                .with_hint("merge the fields into one `render { ... }`"),
                        );
                    } else if let Ok(r) = self.render_item(fields) {
                        self.render = Some((r, item.span));
                    }
                }
                ItemKind::Scene { value } => {
                    let scope = self.global_scope();
                    let v = self.expr(value, &scope);
                    let shape = match v {
                        Ok(v) => self.expect_shape(v, value.span, "the scene"),
                        Err(r) => Err(r),
                    };
                    if let Some((_, prev)) = &self.scene {
                        let prev = *prev;
                        self.error(
                            Diagnostic::error(item.span, "a second `scene` item")
                                .with_label("second scene")
                                .with_secondary(prev, "first scene here")
                                .with_hint("a file has exactly one `scene = ...;`; combine shapes with `|`"),
                        );
                    } else if let Ok(s) = shape {
                        self.scene = Some((s, item.span));
                    } else {
                        // Remember that there was a scene, so we do not also say it is missing.
                        self.scene = Some((ShapeId(u32::MAX), item.span));
                    }
                }
            }
        }
        if !self.too_big {
            self.check_uncalled_fns();
        }
        if self.scene.is_none() {
            let end = source_len;
            self.error(
                Diagnostic::error(Span::new(end, end), "the file has no `scene` item")
                    .with_label("expected `scene = ...;` somewhere in the file")
                    .with_hint("add a line such as `scene = sphere(1);`"),
            );
        }
    }

    /// A `fn` is lowered where it is called, so the mistakes in one that is never called
    /// would go unreported (`fn f(x) = 1 / 0;`, which the contract makes an error). Each such
    /// body is lowered once with its parameters unknown (`Val::Poison`, which is silent:
    /// whatever depends on a parameter is not checked) and the result dropped; the graph's
    /// dead nodes go with dead code elimination.
    fn check_uncalled_fns(&mut self) {
        let uncalled: Vec<Rc<FnDef<'a>>> = self
            .globals
            .iter()
            .filter_map(|(_, v, _)| match v {
                Val::Func(d) if !self.called.contains(&d.index) => Some(d.clone()),
                _ => None,
            })
            .collect();
        for def in uncalled {
            if self.called.contains(&def.index) {
                continue; // the same fn under another name (`let g = f;`), checked already
            }
            self.called.insert(def.index);
            let scope = Scope {
                locals: def
                    .params
                    .iter()
                    .map(|p| (p.name.name.as_str(), Val::Poison))
                    .collect(),
                parent: None,
                visible: def.index + 1,
            };
            self.call_stack.push(def.index);
            if let Ok(v) = self.expr(def.body, &Rc::new(scope)) {
                self.finite_or_reported(v, def.body.span);
            }
            self.call_stack.pop();
        }
        // A `.color(...)` in such a body leaves its anonymous material in the table (shown
        // by `--emit opt-ir`, never emitted: no live shape names it). Truncating the table
        // would leave the dead shapes naming materials that are not there.
    }

    /// `v`, or `Val::Poison` with an error at `span` where it is a constant that is not
    /// finite (a `let`'s value, an unused `fn`'s body that depends on no parameter).
    fn finite_or_reported(&mut self, v: Val<'a>, span: Span) -> Val<'a> {
        let Val::Num(n) = v else { return v };
        if self.const_of(n).is_none_or(|c| c.all_finite()) {
            return v;
        }
        self.error(
            Diagnostic::error(span, "a constant expression is not finite")
                .with_label("evaluates to infinity or NaN")
                .with_hint(NOT_FINITE_HINT),
        );
        Val::Poison
    }

    fn check_fn_params(&mut self, params: &'a [sdfc_syntax::ast::FnParam]) {
        let mut seen_default = false;
        for (i, p) in params.iter().enumerate() {
            if let Some(prev) = params[..i].iter().find(|q| q.name.name == p.name.name) {
                let prev = prev.name.span;
                self.error(
                    Diagnostic::error(
                        p.name.span,
                        format!("parameter `{}` appears twice", p.name.name),
                    )
                    .with_secondary(prev, "first here"),
                );
            }
            if p.default.is_some() {
                seen_default = true;
            } else if seen_default {
                self.error(
                    Diagnostic::error(
                        p.name.span,
                        format!(
                            "parameter `{}` has no default but follows one that has",
                            p.name.name
                        ),
                    )
                    .with_hint("put parameters with defaults last"),
                );
            }
        }
    }

    fn param(&mut self, name: &'a Ident, default: &'a sdfc_syntax::ast::Expr) -> Val<'a> {
        let scope = self.global_scope();
        let Ok(v) = self.const_value(default, &scope, WHAT_PARAM_DEFAULT) else {
            return Val::Poison;
        };
        if !matches!(v.ty(), Ty::F32 | Ty::Vec2 | Ty::Vec3) {
            self.error(
                Diagnostic::error(
                    default.span,
                    format!(
                        "a param must be a number, vec2 or vec3, found {}",
                        v.ty().user_name()
                    ),
                )
                .with_label("this default"),
            );
            return Val::Poison;
        }
        if v.comps().iter().any(|c| c.abs() > limits::MAX_MAGNITUDE) {
            self.error(
                Diagnostic::error(
                    default.span,
                    format!(
                        "a param's value must be at most {:e} in magnitude",
                        limits::MAX_MAGNITUDE
                    ),
                )
                .with_label("this default")
                .with_hint(limits::PARAM_MAGNITUDE_WHY),
            );
            return Val::Poison;
        }
        if self.params.len() >= limits::MAX_PARAMS {
            self.error(Diagnostic::error(
                name.span,
                format!("more than {} params", limits::MAX_PARAMS),
            ));
            return Val::Poison;
        }
        let index = self.params.len() as u16;
        self.params.push(ParamDecl {
            name: name.name.clone(),
            ty: v.ty(),
            default: v,
        });
        Val::Num(self.g.input(Op::Param(index), v.ty(), name.span))
    }

    /// Checks the node budget after inlining; reports once.
    pub fn check_size(&mut self, span: Span) -> R<()> {
        if self.g.len() <= limits::MAX_NODES && self.shapes.len() <= limits::MAX_NODES {
            return Ok(());
        }
        self.too_big_once(|| {
            Diagnostic::error(
                span,
                format!("the scene grows past {} nodes once every `fn` is inlined", limits::MAX_NODES),
            )
            .with_label("while expanding this")
            .with_hint("a `fn` or `let` that doubles its input on every level grows exponentially; share values with `let` instead")
        })
    }

    /// Counts one more `fn` call inlined; past the budget, reports once.
    pub fn count_inlined_call(&mut self, span: Span) -> R<()> {
        self.inlined_calls += 1;
        if self.inlined_calls <= limits::MAX_INLINED_CALLS {
            return Ok(());
        }
        self.too_big_once(|| {
            Diagnostic::error(
                span,
                format!("more than {} `fn` calls once every `fn` is inlined", limits::MAX_INLINED_CALLS),
            )
            .with_label("while expanding this call")
            .with_hint("a `fn` that calls another twice doubles the work on every level; compute the value once with `let` and use the name twice")
        })
    }

    /// A growth limit passed: the first such diagnostic is reported and lowering stops.
    fn too_big_once(&mut self, diagnostic: impl FnOnce() -> Diagnostic) -> R<()> {
        if !self.too_big {
            self.too_big = true;
            self.error(diagnostic());
        }
        Err(Reported)
    }

    pub fn fresh_lambda(&mut self) -> u32 {
        self.next_lambda += 1;
        self.next_lambda - 1
    }

    fn finish(self) -> Option<Scene> {
        let (root, _) = self.scene?;
        if root.0 == u32::MAX {
            return None;
        }
        let lights = if self.lights.is_empty() {
            vec![crate::scene::Light::default_light()]
        } else {
            self.lights
        };
        Some(Scene {
            values: self.g,
            shapes: self.shapes,
            root,
            materials: self.materials,
            params: self.params,
            lights,
            camera: self.camera.map(|c| c.0).unwrap_or_default(),
            render: self.render.map(|r| r.0).unwrap_or_default(),
        })
    }
}
