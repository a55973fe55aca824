//! `sdfc render`: a scene to a PNG, or one of its float AOVs to EXR / NPY, on the wgpu device.

use crate::out::say;
use crate::{load_scene, Outcome};
use sdfc_ir::Program;
use sdfc_render::output::{self, FloatFormat};
use sdfc_render::{AovKind, RenderError, RenderOptions, Renderer};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
#[command(
    after_help = "The device: a GPU if there is one, else Mesa's software Vulkan \
    (lavapipe), else software GL; the one used is named on stderr. SDFC_BACKEND=vulkan or \
    SDFC_BACKEND=gl allows only that backend."
)]
pub struct Args {
    /// The scene file (.sdf)
    scene: PathBuf,
    /// The image to write: .png, or with --aov a float image, .exr or .npy
    #[arg(short, long, value_name = "OUT")]
    output: Option<PathBuf>,
    /// Image size, WIDTHxHEIGHT
    #[arg(long, value_name = "WxH", default_value = "512x512", value_parser = parse_size, allow_hyphen_values = true)]
    size: (u32, u32),
    /// Override a param: NAME=VALUE, or NAME=x,y,z for vectors (repeatable)
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Time in seconds (negative too: `--time -1`)
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    time: f32,
    /// Write a float image instead of the colour: depth (t along the ray, inf on a miss),
    /// normal (world space, 0 on a miss) or steps (march count)
    #[arg(long, value_name = "depth|normal|steps", value_parser = parse_aov)]
    aov: Option<AovKind>,
    /// Render with the generic interpreted marcher: one fixed shader that reads the scene as
    /// bytecode, instead of a shader specialised to the scene (the same picture, slower)
    #[arg(long)]
    interpreted: bool,
    /// Compile large unions with bounding-box early-outs, as `sdfc compile --cull`; with
    /// --interpreted, the bytecode jumps over the parts those early-outs skip
    #[arg(long)]
    cull: bool,
    /// Read the scene's root union from a buffer, as instances in a hierarchy of boxes walked
    /// by one loop, instead of compiling each shape: for a union of many constant shapes
    /// (moved, turned, scaled, with materials), whose pipeline then builds in about a second
    /// whatever its size. Done by default from 100 such shapes up (without --cull); this
    /// asks for it from 16. The union's other children (a floor, a fractal) stay code beside
    /// the walk. A scene without such a union is compiled as usual, with a note.
    /// With --interpreted, the interpreter walks the union read as data (its bytecode no
    /// longer grows with the shapes; by default too, at any size). With --live, the final
    /// frame's; the preview of such a union is interpreted from data in any case
    #[arg(long, conflicts_with = "cull")]
    instances: bool,
    /// Compile the scene's root union as code at any size (see --instances)
    #[arg(long, conflicts_with = "instances")]
    no_instances: bool,
    /// A first picture as soon as possible: if the scene's specialised pipeline is not built
    /// within the grace period, the interpreted marcher draws a preview into OUT while it
    /// builds (on a CPU device only once the interpreter is warm, as in --watch after its
    /// first frame, and with no grace before the build starts, so that the two do not share
    /// the cores), then the specialised frame replaces it; the times go to stderr
    #[arg(long, conflicts_with_all = ["interpreted", "compare"])]
    live: bool,
    /// With --live: milliseconds to wait for the specialised pipeline before drawing the
    /// preview
    #[arg(long, value_name = "MS", default_value_t = 0, requires = "live")]
    grace: u64,
    /// With --live: draw the preview at 1/N of the width and height, enlarged to the full size
    /// [default: 4 on a GPU, 8 on a CPU device]
    #[arg(long, value_name = "N", requires = "live",
          value_parser = clap::value_parser!(u32).range(1..=64))]
    preview_scale: Option<u32>,
    /// With --live: keep running, and render again each time the scene file changes (a
    /// mistake is reported and the last picture kept); stop with Ctrl-C
    #[arg(long, requires = "live")]
    watch: bool,
    /// Also render the f64 CPU reference and print the GPU frame's error against it (depth,
    /// hit/miss, normals, colour, NaN/Inf) on stdout; -o is optional then
    #[arg(long)]
    compare: bool,
    /// With --compare: print the table as Markdown (a header and one row named for the scene)
    #[arg(long, requires = "compare")]
    markdown: bool,
}

pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected WIDTHxHEIGHT (e.g. 640x480), found `{s}`");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    // Whole numbers of any length, so that a size too large says so rather than "malformed".
    let dim = |d: &str| -> Result<u32, String> {
        let d = d.trim();
        if d.is_empty() || !d.bytes().all(|b| b.is_ascii_digit()) {
            return Err(bad());
        }
        d.parse().map_err(|_| {
            format!(
                "`{d}` is too large for an image side (at most {})",
                u32::MAX
            )
        })
    };
    let (w, h) = (dim(w)?, dim(h)?);
    if w == 0 || h == 0 {
        return Err(format!("the image size must be at least 1x1, found `{s}`"));
    }
    Ok((w, h))
}

fn parse_aov(s: &str) -> Result<AovKind, String> {
    s.parse()
}

/// Parses `NAME=VALUE` param overrides against the scene's params. A malformed option is a
/// usage error; an unknown name or a wrong number of components is an input error.
pub fn param_overrides(
    program: &Program,
    specs: &[String],
) -> Result<Vec<(String, Vec<f64>)>, Outcome> {
    let mut out = Vec::new();
    for spec in specs {
        let Some((name, value)) = spec.split_once('=') else {
            say!("sdfc: --param takes NAME=VALUE, found `{spec}`");
            return Err(Outcome::EnvError);
        };
        let name = name.trim();
        let Some(decl) = program.scene.params.iter().find(|p| p.name == name) else {
            let known: Vec<&str> = program
                .scene
                .params
                .iter()
                .map(|p| p.name.as_str())
                .collect();
            if known.is_empty() {
                say!("sdfc: the scene has no param `{name}` (it declares none)");
            } else {
                say!(
                    "sdfc: the scene has no param `{name}` (its params: {})",
                    known.join(", ")
                );
            }
            return Err(Outcome::InputError);
        };
        let comps: Result<Vec<f64>, _> =
            value.split(',').map(|c| c.trim().parse::<f64>()).collect();
        match comps {
            Ok(c) if c.len() == decl.ty.width() && c.iter().all(|v| v.is_finite()) => {
                // Checked here too: `eval` without `--gpu` has no renderer to refuse it.
                if let Err(e) = sdfc_ir::scene::limits::check_param_magnitude(name, &c) {
                    say!("sdfc: {e}");
                    return Err(Outcome::InputError);
                }
                out.push((name.to_string(), c));
            }
            _ => {
                say!(
                    "sdfc: --param {name} needs {} finite number(s), found `{value}`",
                    decl.ty.width()
                );
                return Err(Outcome::InputError);
            }
        }
    }
    Ok(out)
}

/// Param overrides by name, in f64 as parsed.
pub type Overrides = Vec<(String, Vec<f64>)>;

/// What rendering a scene file needs: the compiled scene, its param overrides and the
/// device (named on stderr); on failure, the diagnostics are printed and the outcome comes
/// back.
pub fn prepare(
    scene: &PathBuf,
    params: &[String],
    opts: &sdfc_wgsl::Options,
) -> Result<(sdfc_wgsl::Compiled, Overrides, Renderer), Outcome> {
    let (compiled, renderer) = with_device(|| load_scene(scene, opts));
    let compiled = compiled?;
    let overrides = param_overrides(compiled.program(), params)?;
    Ok((compiled, overrides, renderer?))
}

/// Runs `work` (reading and compiling the scene) while the device opens on another thread:
/// opening it takes as long as compiling a small scene. The device is named on stderr only
/// once `work` has succeeded, after any diagnostics.
pub fn with_device<T>(
    work: impl FnOnce() -> Result<T, Outcome>,
) -> (Result<T, Outcome>, Result<Renderer, Outcome>) {
    let (done, device) = std::thread::scope(|s| {
        let device = s.spawn(Renderer::new);
        let done = work();
        (done, device.join())
    });
    if done.is_err() {
        return (done, Err(Outcome::InputError));
    }
    let device = match device {
        Ok(d) => named(d),
        Err(_) => named(Err(RenderError::Device(
            "opening the device panicked".into(),
        ))),
    };
    (done, device)
}

/// The f32 form the device takes.
pub fn to_f32(params: &[(String, Vec<f64>)]) -> Vec<(String, Vec<f32>)> {
    params
        .iter()
        .map(|(n, v)| (n.clone(), v.iter().map(|&c| c as f32).collect()))
        .collect()
}

/// Opens the device and says which on stderr.
pub fn open_renderer() -> Result<Renderer, Outcome> {
    named(Renderer::new())
}

/// Names the device on stderr, or says why there is none.
fn named(opened: Result<Renderer, RenderError>) -> Result<Renderer, Outcome> {
    match opened {
        Ok(r) => {
            say!("sdfc: device: {}", r.adapter_description());
            Ok(r)
        }
        Err(e) => {
            say!("sdfc: cannot render: {e}");
            Err(Outcome::EnvError)
        }
    }
}

/// Why `--instances` changed nothing, then what was done instead. The specialised shader
/// (`normals`) reads a union with other children too (they stay code beside the walk), and
/// keeps the union as code where the scene uses analytic normals; the interpreter reads only
/// a union of such shapes alone, and has no analytic normals.
pub fn instances_note(normals: bool, instead: &str) -> String {
    let (which, analytic) = if normals {
        ("holding", ", or the scene uses analytic normals")
    } else {
        ("of nothing but", "")
    };
    format!(
        "sdfc: note: --instances: the scene's root is not a hard union {which} 16 or more \
         constant shapes (each a primitive, moved, turned or scaled by constants, with a \
         material){analytic}; {instead}"
    )
}

/// `--instances`, `--no-instances` or neither; `--cull` asks for code.
fn instances_mode(a: &Args) -> sdfc_wgsl::Instances {
    match (a.instances, a.no_instances || a.cull) {
        (true, _) => sdfc_wgsl::Instances::Always,
        (_, true) => sdfc_wgsl::Instances::Never,
        _ => sdfc_wgsl::Instances::Auto,
    }
}

/// A frame from the interpreted marcher: its root union read as data where it is a union of
/// instances (`encode_as_data`) unless `instances` is `Never` (by default at any size, as
/// the live preview does: the bytecode then no longer grows with the shapes), else as code,
/// with a note where data was asked for.
fn interpreted(
    renderer: &Renderer,
    program: &Program,
    instances: sdfc_wgsl::Instances,
    opts: &RenderOptions,
) -> Result<sdfc_render::Frame, RenderError> {
    if instances == sdfc_wgsl::Instances::Never {
        return renderer.render_interpreted(program, opts);
    }
    match sdfc_wgsl::interp::encode_instances::encode_as_data(program) {
        Some(code) => {
            let code = code.map_err(RenderError::Interpreter)?;
            renderer.render_bytecode(program, &code, opts)
        }
        None => {
            if instances == sdfc_wgsl::Instances::Always {
                say!(
                    "{}",
                    instances_note(false, "the interpreter runs it as code")
                );
            }
            renderer.render_interpreted(program, opts)
        }
    }
}

/// Prints a render error; returns the outcome it maps to.
pub fn render_failure(e: &RenderError) -> Outcome {
    say!("sdfc: {e}");
    if e.is_input_error() {
        Outcome::InputError
    } else {
        Outcome::EnvError
    }
}

fn check_output(out: &Path, aov: Option<AovKind>) -> Result<(), String> {
    check_place(out)?;
    let ext = out
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    match (aov, ext.as_deref()) {
        (None, Some("png")) => Ok(()),
        (None, _) => Err(format!(
            "the colour image is written as PNG: `{}` should end in .png (use --aov for .exr or .npy)",
            out.display()
        )),
        (Some(_), _) if FloatFormat::from_path(out).is_some() => Ok(()),
        (Some(_), _) => Err(format!(
            "AOVs are float images: `{}` should end in .exr or .npy",
            out.display()
        )),
    }
}

/// `--time` as the device takes it: an f32 that is finite (`1e39` is too, as an f64).
pub fn check_time(t: f32) -> Result<(), Outcome> {
    if t.is_finite() {
        Ok(())
    } else {
        say!("error: --time must be a finite f32, found {t}");
        Err(Outcome::EnvError)
    }
}

/// That a file can be written at `out` as far as can be told before the work: the path is not
/// a directory and its directory exists, so that a typo does not cost a whole render first.
pub fn check_place(out: &Path) -> Result<(), String> {
    if out.is_dir() {
        return Err(format!("cannot write {}: it is a directory", out.display()));
    }
    match out.parent() {
        Some(dir) if !dir.as_os_str().is_empty() && !dir.is_dir() => Err(format!(
            "cannot write {}: there is no directory {}",
            out.display(),
            dir.display()
        )),
        _ => Ok(()),
    }
}

/// A PNG output of `sdfc bench` (`--plot`, `--heatmap`): checked as [`check_place`], and
/// by its extension, as `render` checks its colour image.
pub fn check_png(flag: &str, out: &Path) -> Result<(), String> {
    check_place(out)?;
    let png = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if png {
        Ok(())
    } else {
        Err(format!(
            "{flag} writes a PNG: `{}` should end in .png",
            out.display()
        ))
    }
}

pub fn run(a: Args) -> Outcome {
    if a.output.is_none() && !a.compare {
        say!("error: `sdfc render` needs an output file: -o OUT.png (or -o OUT.exr|OUT.npy with --aov)");
        say!("\nUsage: sdfc render SCENE.sdf -o OUT.png [--size WxH] [--param NAME=VALUE]... [--time T] [--aov depth|normal|steps]");
        return Outcome::EnvError;
    }
    if let Some(out) = &a.output {
        if let Err(msg) = check_output(out, a.aov) {
            say!("error: {msg}");
            return Outcome::EnvError;
        }
    }
    if let Err(o) = check_time(a.time) {
        return o;
    }
    let instances = instances_mode(&a);
    if a.live {
        return crate::live::run(crate::live::Request {
            scene: &a.scene,
            output: a.output.as_deref(),
            aov: a.aov,
            params: &a.params,
            size: a.size,
            time: a.time,
            cull: a.cull,
            instances,
            grace: std::time::Duration::from_millis(a.grace),
            preview_scale: a.preview_scale,
            watch: a.watch,
        });
    }
    let opts = sdfc_wgsl::Options {
        cull: a.cull,
        instances,
        ..sdfc_wgsl::Options::default()
    };
    let (compiled, overrides, renderer) = match prepare(&a.scene, &a.params, &opts) {
        Ok(p) => p,
        Err(o) => return o,
    };
    if a.instances && !a.interpreted && compiled.data.is_empty() {
        say!("{}", instances_note(true, "it is compiled as code"));
    }
    if instances == sdfc_wgsl::Instances::Auto
        && compiled.data.is_empty()
        && sdfc_wgsl::instances::crowded(compiled.program())
    {
        say!(
            "sdfc: note: the scene's root union holds {} or more constant shapes, but more \
             than {} of their boxes hold one point, where every ray would walk them all at \
             each step, so they stay code (--instances reads them as data)",
            sdfc_wgsl::AUTO_INSTANCES,
            sdfc_wgsl::AUTO_CROWD
        );
    }
    if instances == sdfc_wgsl::Instances::Auto && !compiled.data.is_empty() {
        // Said, because the picture's time and the flags that apply (`--cull`) change with it.
        say!(
            "sdfc: note: the scene's root union holds {} or more constant shapes, so they \
             are read as data, walked by one loop (--no-instances compiles them as code)",
            sdfc_wgsl::AUTO_INSTANCES
        );
    }
    let params = to_f32(&overrides);
    let opts = RenderOptions {
        width: a.size.0,
        height: a.size.1,
        time: a.time,
        params,
        aovs: a.aov.is_some() || a.compare,
        ..RenderOptions::default()
    };
    let frame = if a.interpreted {
        if compiled.program().scene.render.normals == sdfc_ir::scene::Normals::Analytic {
            say!(
                "sdfc: note: the interpreted marcher has no gradient code; `normals: analytic` renders with `tetrahedron` there"
            );
        }
        interpreted(&renderer, compiled.program(), instances, &opts)
    } else {
        crate::slow_note::unless_quick(|| renderer.render(&compiled, &opts))
    };
    let frame = match frame {
        Ok(f) => f,
        Err(e) => return render_failure(&e),
    };
    if a.compare {
        let name = a.scene.file_stem().map_or_else(
            || a.scene.display().to_string(),
            |s| s.to_string_lossy().into_owned(),
        );
        let table = crate::compare::table(
            &compiled,
            &frame,
            &overrides,
            a.time as f64,
            &name,
            a.markdown,
            &renderer.adapter_description().to_string(),
        );
        if let Err(o) = crate::out::print(&table) {
            return o;
        }
    }
    let Some(out) = &a.output else {
        return Outcome::Ok;
    };
    let written = match a.aov {
        None => output::write_png(out, &frame),
        Some(kind) => output::write_aov(out, &frame, kind),
    };
    match written {
        Ok(()) => Outcome::Ok,
        Err(e) => render_failure(&e),
    }
}
