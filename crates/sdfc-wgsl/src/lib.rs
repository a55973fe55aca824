//! The WGSL back end of sdfc: emits a compute shader with the scene hard-coded (or, with
//! `lib`, just the scene functions) and validates it with naga before returning it.
//!
//! # Shader interface (full shader)
//!
//! The renderer relies on this interface as written.
//!
//! - Entry point `main`, `@compute @workgroup_size(8, 8, 1)`; dispatch
//!   `ceil(width / 8) x ceil(height / 8) x 1` (or fewer tiles: `flags` below). Invocation
//!   `(x, y)` shades pixel column `x`, row `y` (row 0 at the top); invocations outside the
//!   image return at once.
//! - `@group(0) @binding(0) var<storage, read> frame: Frame` with
//!   `struct Frame { resolution: vec2<u32>, time: f32, flags: u32, params: array<vec4<f32>, N> }`
//!   (16 + 16 N bytes; `params` is absent when the scene has no `param`). Param `i` (declaration
//!   order) sits in `params[i]`: a float in `.x`, a vec2 in `.xy`, a vec3 in `.xyz`.
//!   `flags` bit 0 asks for AOVs; bits 8 to 19 and 20 to 31 are the column and row, in 8x8
//!   tiles, of the dispatch's first workgroup (0 for the whole image): invocation `(x, y)`
//!   then shades pixel `(x + 8 column, y + 8 row)`. A host may so dispatch only the tiles that
//!   [`screen::screen_rect`] says rays can meet the scene in; every other pixel takes the
//!   background, with the AOVs of a miss (depth -1, steps 0), the same as any one of them.
//! - `@group(0) @binding(1) var<storage, read_write> color_out: array<u32>`: one `u32` per
//!   pixel, index `y * width + x`, packed by `pack4x8unorm` (RGBA8, gamma applied, alpha 1).
//! - `@group(0) @binding(2) var<storage, read_write> aov_out: array<vec4<f32>>`: two entries
//!   per pixel, written only when `flags & 1`: `aov_out[2 i] = (world normal, depth)` and
//!   `aov_out[2 i + 1] = (march steps, 0, 0, 0)`, for the ray through the pixel centre. Depth is
//!   the distance t along the ray (spec section 8), or `-1` on a miss (WGSL has no portable
//!   infinity; the renderer turns it into `inf`). When AOVs are off a 32-byte buffer will do.
//! - With [`Options::instances`], where the scene's root union was emitted as data:
//!   `@group(0) @binding(3) var<storage, read> scene_data: array<vec4<u32>>`, the bytes of
//!   [`Compiled::data`] (layout in `shaders/instances.wgsl`).
//!
//! # Library form (`lib`)
//!
//! `scene_distance(p: vec3<f32>) -> f32`, `scene_material(p: vec3<f32>) -> SceneMaterial`,
//! `struct SceneMaterial { albedo: vec4<f32>, phong: vec4<f32> }` (albedo = rgb colour and
//! reflectivity; phong = ambient, diffuse, specular, shininess) and the helpers they call;
//! module constants named `MATERIAL_*`; for a large union, `SceneSample` and its
//! `scene_group*` functions.
//! Where the scene uses them, `var<private> scene_time: f32` and
//! `var<private> scene_params: array<vec4<f32>, N>` (initialised to the defaults) are inputs the
//! caller may set. With an import path, a naga_oil `#define_import_path` line comes first.

pub mod consts;
mod dear;
pub mod eval_shader;
pub mod func;
pub mod instances;
pub mod interp;
pub mod literal;
pub mod marcher;
pub mod material_index;
pub mod module;
mod occlusion;
mod options;
pub mod parts;
pub mod screen;
mod shadows;
pub mod validate;

pub use options::{check_import_path, Instances, Options, AUTO_CROWD, AUTO_INSTANCES};
/// The IR a compiled scene carries ([`Compiled::program`]), which the renderer's interpreted
/// marcher and point evaluation take.
pub use sdfc_ir::{Program, Stages};
/// Diagnostics: [`Diagnostic`]'s `Display` is one line; `diag::render` adds the source line.
pub use sdfc_syntax::diag::{self, Diagnostic};

/// A compiled scene: the validated WGSL, the IR stages, and any warnings.
#[derive(Clone, Debug)]
pub struct Compiled {
    /// The WGSL, validated by naga: a whole compute shader, or with [`Options::lib`] the
    /// library form (see the crate's documentation for both interfaces).
    pub wgsl: String,
    /// The scene as the compiler's stages left it: the IR before and after optimisation, and
    /// the [`Program`] (scene settings, params, functions) the WGSL was emitted from.
    pub stages: Stages,
    /// Warnings about the scene (placed: their `Display` says line and column).
    pub warnings: Vec<Diagnostic>,
    /// With [`Options::instances`], where the scene's union was emitted as data: the buffer
    /// the shader reads at binding 3 (see `shaders/instances.wgsl`); else empty.
    pub data: Vec<u8>,
    /// Whether `wgsl` is the library form, which has no entry point to render.
    library: bool,
}

impl Compiled {
    /// The optimised program the WGSL was emitted from.
    pub fn program(&self) -> &Program {
        &self.stages.program
    }

    /// Whether the WGSL is the library form ([`Options::lib`]): scene functions without an
    /// entry point, for the caller's own shaders; it cannot be rendered.
    pub fn is_library(&self) -> bool {
        self.library
    }
}

/// Why compilation failed.
#[derive(Debug)]
pub enum Failure {
    /// Mistakes in the scene (with any warnings), to show the user. Each is placed (line and
    /// column); [`Failure::render`] shows them with their source lines.
    Diagnostics(Vec<Diagnostic>),
    /// The emitted WGSL failed validation: a bug in sdfc, never the user's. `report` is
    /// naga's; `wgsl` the text it rejected (empty where none was emitted).
    Internal {
        /// naga's report (or what else went wrong inside the compiler).
        report: String,
        /// The rejected WGSL, for a bug report; empty where none was emitted.
        wgsl: String,
    },
    /// The [`Options`] do not make sense ([`Options::check`]): the caller's mistake, not
    /// the scene's.
    Usage(String),
}

impl Failure {
    /// The failure as a user should see it: each diagnostic with `file_name:line:column`,
    /// its source line and carets, and its hint (without colour); otherwise as `Display`.
    pub fn render(&self, file_name: &str, source: &str) -> String {
        match self {
            Failure::Diagnostics(d) => diag::render(file_name, source, d),
            _ => format!("error: {self}\n"),
        }
    }
}

/// The errors, one per line (`3:14: error: ...; hint: ...`), then the warnings.
impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::Diagnostics(d) => {
                let (errors, warnings): (Vec<_>, Vec<_>) = d.iter().partition(|d| d.is_error());
                let lines: Vec<String> = errors
                    .iter()
                    .chain(&warnings)
                    .map(|d| d.to_string())
                    .collect();
                f.write_str(&lines.join("\n"))
            }
            Failure::Internal { report, .. } => write!(
                f,
                "internal compiler error (a bug in sdfc, not in the scene): the emitted WGSL is invalid: {report}"
            ),
            Failure::Usage(message) => f.write_str(message),
        }
    }
}

impl std::error::Error for Failure {}

/// The stack the compiler runs on: deep but bounded inputs (limited by the parser) then
/// never come near the stack's end, whatever thread the caller uses.
const STACK_BYTES: usize = 256 << 20;

/// Parses, lowers, optimises, emits and validates a scene. Never panics on any input.
/// Blocks until done (the 5 000-shape test scene takes some 200 ms on a small machine).
pub fn compile(source: &str, opts: &Options) -> Result<Compiled, Failure> {
    on_compiler_stack(|| compile_here(source, opts))
}

/// As [`compile`], on the calling thread's stack.
pub fn compile_here(source: &str, opts: &Options) -> Result<Compiled, Failure> {
    // `lower_here` checks the options.
    let Lowered {
        stages, warnings, ..
    } = lower_here(source, opts)?;
    let (wgsl, data) = emit_with_data(&stages.program, opts)?;
    Ok(Compiled {
        wgsl,
        data,
        stages,
        warnings,
        library: opts.lib,
    })
}

/// A scene parsed, lowered and optimised, not yet emitted: what the interpreted marcher
/// needs (`interp::encode`), and what [`emit_validated`] turns into WGSL.
pub struct Lowered {
    /// The IR stages, as in [`Compiled::stages`].
    pub stages: Stages,
    /// Warnings about the scene, placed.
    pub warnings: Vec<Diagnostic>,
    /// From [`lower_live`]: the scene lowered with culling for the interpreted preview, where
    /// that differs from `stages.program` (a union large enough to cull, `cull` not asked
    /// for, and the root not a union of instances, which is previewed from data). The
    /// interpreter's skips pay wherever neighbouring pixels take them alike, on lavapipe too,
    /// whose `if`s do not branch (docs/performance.md).
    pub preview: Option<std::sync::Arc<Program>>,
}

/// The front half of [`compile`]: parses, lowers and optimises. Never panics on any input.
/// The live path uses it to start the interpreted marcher before the WGSL exists.
pub fn lower(source: &str, opts: &Options) -> Result<Lowered, Failure> {
    on_compiler_stack(|| lower_here(source, opts))
}

/// [`lower`] for the live path: also the culled program the interpreted preview draws
/// ([`Lowered::preview`]). Both are built from one parse, lowering and analysis
/// (`sdfc_ir::front`), their functions at once on two threads. A root union of instances
/// (`sdfc_ir::instances`) is previewed from data instead (`interp::encode_instances`), so
/// its scene is not built culled.
pub fn lower_live(source: &str, opts: &Options) -> Result<Lowered, Failure> {
    on_compiler_stack(|| {
        opts.check().map_err(Failure::Usage)?;
        let file = parse(source)?;
        if opts.cull {
            return lower_parsed(&file, source, opts);
        }
        let front = sdfc_ir::front(&file, source.len())
            .map_err(|d| Failure::Diagnostics(placed(d, source)))?;
        let as_is = sdfc_ir::IrOptions { cull: false };
        if sdfc_ir::instances::find(front.scene(), front.analysis(), [0.0; 3]).is_some() {
            return backed(sdfc_ir::back(front, &as_is), source);
        }
        let culling = sdfc_ir::IrOptions { cull: true };
        let (culled, plain) = std::thread::scope(|s| {
            let copy = front.clone();
            let plain = compiler_thread(s, || backed(sdfc_ir::back(copy, &as_is), source));
            let culled = backed(sdfc_ir::back(front.clone(), &culling), source);
            let plain = match plain {
                Ok(handle) => joined(handle),
                // No second thread: one after the other.
                Err(_) => backed(sdfc_ir::back(front, &as_is), source),
            };
            (culled, plain)
        });
        let (culled, plain) = (culled?, plain?);
        Ok(Lowered {
            preview: culled
                .stages
                .program
                .culls()
                .then(|| std::sync::Arc::new(culled.stages.program)),
            ..plain
        })
    })
}

fn lower_here(source: &str, opts: &Options) -> Result<Lowered, Failure> {
    opts.check().map_err(Failure::Usage)?;
    lower_parsed(&parse(source)?, source, opts)
}

/// Parses; syntax errors come back placed.
fn parse(source: &str) -> Result<sdfc_syntax::ast::File, Failure> {
    sdfc_syntax::parse(source).map_err(|d| Failure::Diagnostics(placed(d, source)))
}

/// The diagnostics with their line and column in `source` filled in.
fn placed(diagnostics: Vec<Diagnostic>, source: &str) -> Vec<Diagnostic> {
    diagnostics.into_iter().map(|d| d.placed(source)).collect()
}

fn lower_parsed(
    file: &sdfc_syntax::ast::File,
    source: &str,
    opts: &Options,
) -> Result<Lowered, Failure> {
    let ir = sdfc_ir::IrOptions { cull: opts.cull };
    backed(sdfc_ir::compile_with(file, source.len(), &ir), source)
}

/// The stages of `source` (or its diagnostics, placed) as [`Lowered`], without a preview.
fn backed(
    (stages, warnings): (Option<Stages>, Vec<Diagnostic>),
    source: &str,
) -> Result<Lowered, Failure> {
    let warnings = placed(warnings, source);
    match stages {
        Some(stages) => Ok(Lowered {
            stages,
            warnings,
            preview: None,
        }),
        None => Err(Failure::Diagnostics(warnings)),
    }
}

/// Runs `f` on a thread with the compiler's stack (256 MiB); a panic in it (a bug)
/// comes back as an internal error.
pub fn on_compiler_stack<T: Send>(
    f: impl FnOnce() -> Result<T, Failure> + Send,
) -> Result<T, Failure> {
    std::thread::scope(|s| {
        let handle = compiler_thread(s, f).map_err(|e| Failure::Internal {
            report: format!("could not start the compiler thread: {e}"),
            wgsl: String::new(),
        })?;
        joined(handle)
    })
}

/// Starts `f` on a scoped thread with the compiler's stack ([`STACK_BYTES`]).
fn compiler_thread<'s, T: Send + 's>(
    s: &'s std::thread::Scope<'s, '_>,
    f: impl FnOnce() -> Result<T, Failure> + Send + 's,
) -> std::io::Result<std::thread::ScopedJoinHandle<'s, Result<T, Failure>>> {
    std::thread::Builder::new()
        .name("sdfc-compile".into())
        .stack_size(STACK_BYTES)
        .spawn_scoped(s, f)
}

/// A compiler thread's result; its panic (a bug) as an internal error.
fn joined<T>(handle: std::thread::ScopedJoinHandle<'_, Result<T, Failure>>) -> Result<T, Failure> {
    handle.join().unwrap_or_else(|_| {
        Err(Failure::Internal {
            report: "the compiler panicked".into(),
            wgsl: String::new(),
        })
    })
}

/// Emits and validates; the import-path line (not WGSL) is added after validation. The
/// union is emitted as code whatever [`Options::instances`] says: the data would have
/// nowhere to go ([`compile`] returns it).
pub fn emit_validated(program: &Program, opts: &Options) -> Result<String, Failure> {
    opts.check().map_err(Failure::Usage)?;
    emit_checked(program, opts, None)
}

/// [`emit_validated`] with [`Options::instances`] honoured: the WGSL and the data it reads at
/// binding 3 (empty where the union stays code), as [`compile`] gives them.
pub fn emit_validated_with_data(
    program: &Program,
    opts: &Options,
) -> Result<(String, Vec<u8>), Failure> {
    opts.check().map_err(Failure::Usage)?;
    emit_with_data(program, opts)
}

/// [`emit_validated_with_data`] with options already checked.
fn emit_with_data(program: &Program, opts: &Options) -> Result<(String, Vec<u8>), Failure> {
    let plan = opts
        .data_from()
        .and_then(|min| instances::plan_at_least(program, min, opts.crowd_limit()));
    let wgsl = emit_checked(program, opts, plan.as_ref())?;
    Ok((wgsl, plan.map_or_else(Vec::new, |p| p.data())))
}

/// [`emit_validated`] with options already checked, the union as data where `plan` says.
fn emit_checked(
    program: &Program,
    opts: &Options,
    plan: Option<&instances::Plan>,
) -> Result<String, Failure> {
    let wgsl = module::emit(program, opts.lib, plan);
    if let Err(report) = validate::validate("scene.wgsl", &wgsl) {
        return Err(Failure::Internal { report, wgsl });
    }
    Ok(match (&opts.import_path, opts.lib) {
        (Some(path), true) => format!("#define_import_path {path}\n\n{wgsl}"),
        _ => wgsl,
    })
}
