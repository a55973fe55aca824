//! `sdfc render --live`: the interpreted preview written while the specialised pipeline
//! builds, then the final frame over it, with the time of each on stderr.

use crate::out::say;
use crate::render::{param_overrides, render_failure, to_f32, with_device};
use crate::{load_lowered, Outcome};
use sdfc_render::output;
use sdfc_render::{AovKind, Drawn, Frame, LiveOptions, RenderError, RenderOptions, Renderer};
use sdfc_wgsl::Lowered;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// What `render --live` was asked for.
pub struct Request<'a> {
    pub scene: &'a PathBuf,
    pub output: Option<&'a Path>,
    pub aov: Option<AovKind>,
    pub params: &'a [String],
    pub size: (u32, u32),
    pub time: f32,
    pub cull: bool,
    /// When the final frame's union is data (`--instances`, `--no-instances`, or by size).
    pub instances: sdfc_wgsl::Instances,
    pub grace: Duration,
    pub preview_scale: Option<u32>,
    /// Render again each time the scene file changes, until interrupted.
    pub watch: bool,
}

impl Request<'_> {
    /// How the specialised shader is emitted.
    pub fn emit(&self) -> sdfc_wgsl::Options {
        sdfc_wgsl::Options {
            cull: self.cull,
            instances: self.instances,
            ..sdfc_wgsl::Options::default()
        }
    }
}

pub fn run(r: Request) -> Outcome {
    if r.watch {
        return crate::watch::run(&r);
    }
    // The clock starts before the scene file is read: "scene file to first pixel".
    let start = Instant::now();
    let (lowered, renderer) = with_device(|| load_lowered(r.scene, &r.emit()));
    let lowered = match lowered {
        Ok(l) => l,
        Err(o) => return o,
    };
    match renderer {
        Ok(renderer) => {
            // Never superseded here, so always an outcome.
            let outcome =
                draw(&r, &renderer, &lowered, start, &|| false).unwrap_or(Outcome::EnvError);
            // The interpreter may still be warming up (its preview lost the race): no
            // thread may be inside the driver when the process ends.
            renderer.wait_for_background_work();
            outcome
        }
        Err(o) => o,
    }
}

/// One live render of a lowered scene into the output, with its times on stderr; `start`
/// is when the scene file was read. `None` where `superseded` said to give up first.
pub fn draw(
    r: &Request,
    renderer: &Renderer,
    lowered: &Lowered,
    start: Instant,
    superseded: &dyn Fn() -> bool,
) -> Option<Outcome> {
    let program = &lowered.stages.program;
    let overrides = match param_overrides(program, r.params) {
        Ok(o) => o,
        Err(o) => return Some(o),
    };
    let opts = RenderOptions {
        width: r.size.0,
        height: r.size.1,
        time: r.time,
        params: to_f32(&overrides),
        aovs: r.aov.is_some(),
        ..RenderOptions::default()
    };
    let live = LiveOptions {
        start,
        grace: r.grace,
        preview_scale: r.preview_scale,
        emit: r.emit(),
        preview: lowered.preview.clone(),
    };
    let scale = live.preview_scale_on(renderer);
    let mut write_error = None;
    let rendered = renderer.render_live_until(program, &opts, &live, superseded, |drawn, frame| {
        if drawn == Drawn::Interpreted {
            say!(
                "sdfc: preview (interpreted, {}x{} enlarged) after {}; the specialised pipeline is still building",
                r.size.0.div_ceil(scale),
                r.size.1.div_ceil(scale),
                seconds(start.elapsed())
            );
        }
        if let (Some(out), None) = (r.output, &write_error) {
            write_error = replace(out, frame, r.aov).err();
        }
    });
    let (_, report) = match rendered {
        Ok(Some(done)) => done,
        // Superseded; but an output that could not be written still ends the loop.
        Ok(None) => return write_error.map(|e| render_failure(&e)),
        Err(e) => return Some(render_failure(&e)),
    };
    if let Some(why) = &report.preview_skipped {
        say!("sdfc: no preview: {why}");
    }
    if report.preview_cut > 0 {
        say!(
            "sdfc: the preview had {} pixels cut short by this device's loop budget (65 535 \
             trips per invocation on lavapipe and llvmpipe); the final frame has none",
            report.preview_cut
        );
    }
    let build = report.pipeline_ready.saturating_sub(report.build_started);
    let preview = match (report.interpreted, &report.preview_skipped) {
        (None, None) => format!(
            "; no preview needed, the pipeline was built within the {} grace",
            seconds(r.grace)
        ),
        _ => String::new(),
    };
    say!(
        "sdfc: final frame (specialised) after {} (its pipeline started after {}, built in \
         {}){preview}",
        seconds(report.specialised),
        seconds(report.build_started),
        seconds(build),
    );
    Some(match write_error {
        None => Outcome::Ok,
        Some(e) => render_failure(&e),
    })
}

/// Writes `frame` to `out` through a file beside it renamed over it, so that a viewer
/// watching `out` never reads half a file. Whatever fails, the file beside it is removed
/// and the error names `out`.
fn replace(out: &Path, frame: &Frame, aov: Option<AovKind>) -> Result<(), RenderError> {
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let partial = out.with_file_name(format!(".sdfc-live.{name}"));
    let written = match aov {
        None => output::write_png(&partial, frame),
        Some(kind) => output::write_aov(&partial, frame, kind),
    }
    .and_then(|()| {
        std::fs::rename(&partial, out).map_err(|e| RenderError::Output {
            path: out.to_path_buf(),
            message: e.to_string(),
        })
    });
    if let Err(e) = written {
        let _ = std::fs::remove_file(&partial);
        return Err(match e {
            RenderError::Output { message, .. } => RenderError::Output {
                path: out.to_path_buf(),
                message,
            },
            e => e,
        });
    }
    Ok(())
}

/// `412 ms` or `1.83 s`.
fn seconds(d: Duration) -> String {
    if d < Duration::from_secs(1) {
        format!("{} ms", d.as_millis())
    } else {
        format!("{:.2} s", d.as_secs_f64())
    }
}
