//! The WGSL back end of sdfc: emits a compute shader with the scene hard-coded (or, with
//! `lib`, just the scene functions) and validates it with naga before returning it.
//!
//! # Shader interface (full shader)
//!
//! The renderer relies on this interface as written.
//!
//! - Entry point `main`, `@compute @workgroup_size(8, 8, 1)`; dispatch
//!   `ceil(width / 8) x ceil(height / 8) x 1`. Invocation `(x, y)` shades pixel column `x`,
//!   row `y` (row 0 at the top); invocations outside the image return at once.
//! - `@group(0) @binding(0) var<uniform> frame: Frame` with
//!   `struct Frame { resolution: vec2<u32>, time: f32, flags: u32, params: array<vec4<f32>, N> }`
//!   (16 + 16 N bytes; `params` is absent when the scene has no `param`). Param `i` (declaration
//!   order) sits in `params[i]`: a float in `.x`, a vec2 in `.xy`, a vec3 in `.xyz`.
//!   `flags` bit 0 asks for AOVs.
//! - `@group(0) @binding(1) var<storage, read_write> color_out: array<u32>`: one `u32` per
//!   pixel, index `y * width + x`, packed by `pack4x8unorm` (RGBA8, gamma applied, alpha 1).
//! - `@group(0) @binding(2) var<storage, read_write> aov_out: array<vec4<f32>>`: two entries
//!   per pixel, written only when `flags & 1`: `aov_out[2 i] = (world normal, depth)` and
//!   `aov_out[2 i + 1] = (march steps, 0, 0, 0)`, for the ray through the pixel centre. Depth is
//!   the distance t along the ray (spec section 8), or `-1` on a miss (WGSL has no portable
//!   infinity; the renderer turns it into `inf`). When AOVs are off a 32-byte buffer will do.
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
pub mod eval_shader;
pub mod func;
pub mod interp;
pub mod literal;
pub mod marcher;
pub mod material_index;
pub mod module;
pub mod parts;
pub mod validate;

use sdfc_ir::{Program, Stages};
use sdfc_syntax::diag::Diagnostic;

/// What to emit.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Only the scene functions, no entry point (`sdfc compile --lib`).
    pub lib: bool,
    /// A naga_oil `#define_import_path` for the library form.
    pub import_path: Option<String>,
    /// Bounding-box early-outs in large unions (`sdfc compile --cull`); the distances are the
    /// same near the surface, and a lower bound far from every part of the union. Off by
    /// default until it is measured to win on a device (docs/performance.md).
    pub cull: bool,
}

/// A compiled scene: the validated WGSL, the IR stages, and any warnings.
pub struct Compiled {
    pub wgsl: String,
    pub stages: Stages,
    pub warnings: Vec<Diagnostic>,
}

impl Compiled {
    pub fn program(&self) -> &Program {
        &self.stages.program
    }
}

/// Why compilation failed.
#[derive(Debug)]
pub enum Failure {
    /// Mistakes in the scene (with any warnings), to show the user.
    Diagnostics(Vec<Diagnostic>),
    /// The emitted WGSL failed validation: a bug in sdfc, never the user's.
    Internal { report: String, wgsl: String },
}

/// The stack the compiler runs on: deep but bounded inputs (limited by the parser) then
/// never come near the stack's end, whatever thread the caller uses.
const STACK_BYTES: usize = 256 << 20;

/// Parses, lowers, optimises, emits and validates a scene. Never panics on any input.
pub fn compile(source: &str, opts: &Options) -> Result<Compiled, Failure> {
    on_compiler_stack(|| compile_here(source, opts))
}

/// As [`compile`], on the calling thread's stack.
pub fn compile_here(source: &str, opts: &Options) -> Result<Compiled, Failure> {
    let Lowered {
        stages, warnings, ..
    } = lower_here(source, opts)?;
    let wgsl = emit_validated(&stages.program, opts)?;
    Ok(Compiled {
        wgsl,
        stages,
        warnings,
    })
}

/// A scene parsed, lowered and optimised, not yet emitted: what the interpreted marcher
/// needs (`interp::encode`), and what [`emit_validated`] turns into WGSL.
pub struct Lowered {
    pub stages: Stages,
    pub warnings: Vec<Diagnostic>,
    /// From [`lower_live`]: the scene lowered with culling for the interpreted preview, where
    /// that differs from `stages.program` (a union large enough to cull, and `cull` not
    /// asked for). The interpreter's skips pay wherever neighbouring pixels take them alike,
    /// on lavapipe too, whose `if`s do not branch (docs/performance.md).
    pub preview: Option<std::sync::Arc<Program>>,
}

/// The front half of [`compile`]: parses, lowers and optimises. Never panics on any input.
/// The live path uses it to start the interpreted marcher before the WGSL exists.
pub fn lower(source: &str, opts: &Options) -> Result<Lowered, Failure> {
    on_compiler_stack(|| lower_here(source, opts))
}

/// [`lower`] for the live path: also the culled program the interpreted preview draws
/// ([`Lowered::preview`]). Both are lowered from one parse, at once on two threads (the
/// preview waits for both; the 5 000-shape union's two take about as long as one).
pub fn lower_live(source: &str, opts: &Options) -> Result<Lowered, Failure> {
    on_compiler_stack(|| {
        let file = sdfc_syntax::parse(source).map_err(Failure::Diagnostics)?;
        if opts.cull {
            return lower_parsed(&file, source.len(), opts);
        }
        let culling = Options {
            cull: true,
            ..opts.clone()
        };
        let (culled, plain) = std::thread::scope(|s| {
            let plain = compiler_thread(s, || lower_parsed(&file, source.len(), opts));
            let culled = lower_parsed(&file, source.len(), &culling);
            let plain = match plain {
                Ok(handle) => joined(handle),
                // No second thread: one after the other.
                Err(_) => lower_parsed(&file, source.len(), opts),
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
    let file = sdfc_syntax::parse(source).map_err(Failure::Diagnostics)?;
    lower_parsed(&file, source.len(), opts)
}

fn lower_parsed(
    file: &sdfc_syntax::ast::File,
    source_len: usize,
    opts: &Options,
) -> Result<Lowered, Failure> {
    let ir = sdfc_ir::IrOptions { cull: opts.cull };
    let (stages, warnings) = sdfc_ir::compile_with(file, source_len, &ir);
    match stages {
        Some(stages) => Ok(Lowered {
            stages,
            warnings,
            preview: None,
        }),
        None => Err(Failure::Diagnostics(warnings)),
    }
}

/// Runs `f` on a thread with the compiler's stack ([`STACK_BYTES`]); a panic in it (a bug)
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

/// Starts `f` on a scoped thread with the compiler's stack.
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

/// Emits and validates; the import-path line (not WGSL) is added after validation.
pub fn emit_validated(program: &Program, opts: &Options) -> Result<String, Failure> {
    let wgsl = module::emit(program, opts.lib);
    if let Err(report) = validate::validate("scene.wgsl", &wgsl) {
        return Err(Failure::Internal { report, wgsl });
    }
    Ok(match (&opts.import_path, opts.lib) {
        (Some(path), true) => format!("#define_import_path {path}\n\n{wgsl}"),
        _ => wgsl,
    })
}
