//! `sdfc bench`: run time against error. The scene is rendered under a sweep of the settings
//! that trade one for the other, each timed over warm runs and compared with one f64 reference
//! render; the table marks the settings on the Pareto front.

use crate::out::say;
use crate::render::{parse_size, prepare, render_failure, to_f32};
use crate::Outcome;
use indicatif::{ProgressBar, ProgressStyle};
use sdfc_ir::scene::{Epsilon, Normals, RenderSettings, Shadows};
use sdfc_ir::Program;
use sdfc_reference::metrics::Metrics;
use sdfc_render::{Frame, RenderOptions};
use std::fmt::Write;
use std::path::PathBuf;
use std::time::Duration;

/// Frames of every setting drawn in turn before the timed ones.
const WARM_UP: Duration = Duration::from_millis(500);

#[derive(clap::Args)]
#[command(
    after_help = "Each setting changes one thing from the scene's own settings, except the \
    plain marcher of the tutorials (absolute epsilon 1e-3, no relaxation, central normals), \
    the baseline. Time is the device's (timestamp queries) where the adapter has them, else \
    wall time from submit to readback; the median of the warm runs. Every setting's pipeline \
    is built first; then the settings are drawn in turn for half a second, untimed, and then \
    in turn for the timed runs, so that all are timed at the same device clocks. A setting \
    marked * is on the Pareto front: no other is both faster and more accurate (fewer \
    hit/miss mismatches away from silhouettes, then a smaller depth error). The f64 reference \
    is drawn on the CPU: minutes at the default 512x512 on two cores, so pass a smaller \
    --size for a quick look."
)]
pub struct Args {
    /// The scene file (.sdf)
    scene: PathBuf,
    /// Image size, WIDTHxHEIGHT
    // 512x512 as every `--size` of the command line's contract (shared/spec/cli.md).
    #[arg(long, value_name = "WxH", default_value = "512x512", value_parser = parse_size, allow_hyphen_values = true)]
    size: (u32, u32),
    /// Timed warm runs per setting (the median is reported)
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    runs: u32,
    /// Override a param: NAME=VALUE, or NAME=x,y,z for vectors (repeatable)
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Print the table as Markdown
    #[arg(long)]
    markdown: bool,
    /// Also write the steps per pixel of the scene's own settings as a heat map (PNG: black
    /// for one step, through blue, red and yellow, to white at max_steps)
    #[arg(long, value_name = "OUT.png")]
    heatmap: Option<PathBuf>,
    /// Also write a plot of time against error (PNG): one point per setting, the depth
    /// error's 99.9th percentile on a log scale, the Pareto front joined, settings with
    /// hit/miss mismatches in red
    #[arg(long, value_name = "OUT.png")]
    plot: Option<PathBuf>,
}

/// One setting of the sweep: its name and the settings it renders with.
struct Setting {
    name: String,
    render: RenderSettings,
}

/// One row of the table.
struct Row {
    name: String,
    time: Duration,
    steps_mean: f64,
    steps_p99: f64,
    /// Share of pixels that took `max_steps` samples or more: every ray out of steps, and
    /// those that needed a refinement's budget beside the march's to stay in (the shader's
    /// `march_spent`: a pass by's refinements have a budget of their own, and the steps
    /// AOV counts every sample).
    at_max: f64,
    metrics: Metrics,
    pareto: bool,
}

/// The sweep: the scene's settings, the tutorials' plain marcher, then one change at a time.
fn settings(base: &RenderSettings) -> Vec<Setting> {
    let mut out = vec![Setting {
        name: "scene's settings".into(),
        render: base.clone(),
    }];
    let mut add = |name: String, render: RenderSettings| {
        if render != *base && out.iter().all(|s| s.render != render) {
            out.push(Setting { name, render });
        }
    };
    add(
        "plain marcher (epsilon 1e-3, central normals)".into(),
        RenderSettings {
            epsilon: Epsilon::Absolute(1e-3),
            relaxation: 1.0,
            normals: Normals::Central,
            ..base.clone()
        },
    );
    for steps in [64, 128, 256, 512, 1024] {
        add(
            format!("max_steps: {steps}"),
            RenderSettings {
                max_steps: steps,
                ..base.clone()
            },
        );
    }
    add(
        "epsilon: pixel".into(),
        RenderSettings {
            epsilon: Epsilon::Pixel,
            ..base.clone()
        },
    );
    for e in [1e-2, 1e-3, 1e-4] {
        add(
            format!("epsilon: {e:e}"),
            RenderSettings {
                epsilon: Epsilon::Absolute(e),
                ..base.clone()
            },
        );
    }
    for k in [1.0, 1.2, 1.6] {
        add(
            format!("relaxation: {k}"),
            RenderSettings {
                relaxation: k,
                ..base.clone()
            },
        );
    }
    for (name, n) in [
        ("central", Normals::Central),
        ("forward", Normals::Forward),
        ("tetrahedron", Normals::Tetrahedron),
        ("analytic", Normals::Analytic),
    ] {
        add(
            format!("normals: {name}"),
            RenderSettings {
                normals: n,
                ..base.clone()
            },
        );
    }
    if let Shadows::Soft(_) = base.shadows {
        add(
            "shadows: hard".into(),
            RenderSettings {
                shadows: Shadows::Hard,
                ..base.clone()
            },
        );
    }
    if let Some(ao) = base.ao {
        for samples in [ao.samples / 2, ao.samples * 2] {
            let mut ao = ao;
            ao.samples = samples.clamp(1, sdfc_ir::scene::limits::MAX_AO_SAMPLES);
            add(
                format!("ao samples: {}", ao.samples),
                RenderSettings {
                    ao: Some(ao),
                    ..base.clone()
                },
            );
        }
    }
    out
}

pub fn run(a: Args) -> Outcome {
    for (flag, out) in [("--plot", &a.plot), ("--heatmap", &a.heatmap)] {
        if let Some(Err(msg)) = out.as_deref().map(|o| crate::render::check_png(flag, o)) {
            say!("error: {msg}");
            return Outcome::EnvError;
        }
    }
    let (compiled, overrides, renderer) =
        match prepare(&a.scene, &a.params, &sdfc_wgsl::Options::default()) {
            Ok(p) => p,
            Err(o) => return o,
        };
    let opts = RenderOptions {
        width: a.size.0,
        height: a.size.1,
        time: 0.0,
        params: to_f32(&overrides),
        aovs: true,
        ..RenderOptions::default()
    };
    let program = compiled.program();
    let sweep = settings(&program.scene.render);
    let progress = ProgressBar::new(sweep.len() as u64 + 1).with_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    progress.set_message("f64 reference");
    let reference = crate::compare::reference(program, &overrides, a.size, 0.0);
    progress.inc(1);

    // Every setting's pipeline is built, and its first frame drawn and measured against the
    // reference (its row, but for the time), before any is timed; the frames are not kept.
    let (mut built, mut rows) = (Vec::new(), Vec::new());
    for setting in &sweep {
        progress.set_message(setting.name.clone());
        let mut variant = program.clone();
        variant.scene.render = setting.render.clone();
        // As `sdfc render` draws it: a large union read as data (`Instances::Auto`).
        let emitted = sdfc_wgsl::emit_validated_with_data(&variant, &sdfc_wgsl::Options::default());
        let (wgsl, data) = match emitted {
            Ok(w) => w,
            Err(f) => {
                progress.finish_and_clear();
                let name = a.scene.display().to_string();
                return crate::report::failure(&name, "", &f);
            }
        };
        let frame = match renderer.render_wgsl_with_data(&variant, &wgsl, &data, &opts) {
            Ok(f) => f,
            Err(e) => {
                progress.finish_and_clear();
                return render_failure(&e);
            }
        };
        if setting.render == program.scene.render {
            if let Some(path) = &a.heatmap {
                if let Err(e) = sdfc_render::output::write_png(path, &heatmap(&frame, &variant)) {
                    progress.finish_and_clear();
                    return render_failure(&e);
                }
            }
        }
        rows.push(row(setting, Duration::ZERO, &frame, &reference));
        built.push((variant, wgsl, data));
        progress.inc(1);
    }
    // Then timed frame by frame in turn, after WARM_UP of the same: a GPU idles at a fraction
    // of its clock while pipelines build and takes a while to raise it, so settings timed one
    // after another were measured at different clocks (on an NVIDIA H200 the ribbed sphere
    // took 0.08 ms a frame under its own settings early in a sweep, and 0.36 ms under
    // `max_steps: 512` later in it, with the same steps).
    progress.set_message("timing");
    let medians = match timed_in_turn(&renderer, &built, &opts, a.runs as usize) {
        Ok(m) => m,
        Err(e) => {
            progress.finish_and_clear();
            return render_failure(&e);
        }
    };
    for (row, time) in rows.iter_mut().zip(medians) {
        row.time = time;
    }
    progress.finish_and_clear();
    mark_pareto(&mut rows);
    let timing = if renderer.has_timestamps() {
        "device time (timestamp queries)"
    } else {
        "wall time, submit to readback (the adapter has no timestamp queries)"
    };
    let title = format!(
        "{} at {}x{} on {}: median {timing} of {} warm runs",
        a.scene.display(),
        a.size.0,
        a.size.1,
        renderer.adapter_description(),
        a.runs
    );
    if let Err(o) = crate::out::print(&table(&title, &rows, a.markdown)) {
        return o;
    }
    if let Some(path) = &a.plot {
        // Named on the plot: the front, the scene's settings and the plain marcher (rows 0, 1).
        let points: Vec<crate::plot::Point> = rows
            .iter()
            .enumerate()
            .map(|(i, r)| crate::plot::Point {
                name: &r.name,
                time_ms: r.time.as_secs_f64() * 1e3,
                error: r.metrics.depth_p999,
                misses: r.metrics.mismatch_interior,
                pareto: r.pareto,
                labelled: r.pareto || i < 2,
            })
            .collect();
        let caption = format!(
            "{} at {}x{} on {}",
            a.scene.display(),
            a.size.0,
            a.size.1,
            renderer.adapter_description()
        );
        if let Err(e) = crate::plot::write(path, &caption, &points) {
            say!("error: {e}");
            return Outcome::EnvError;
        }
    }
    Outcome::Ok
}

/// The median time of `runs` frames of each shader, drawn in turn after [`WARM_UP`] of the
/// same (each drawn at least once).
fn timed_in_turn(
    renderer: &sdfc_render::Renderer,
    shaders: &[(Program, String, Vec<u8>)],
    opts: &RenderOptions,
    runs: usize,
) -> Result<Vec<Duration>, sdfc_render::RenderError> {
    let draw = |(program, wgsl, data): &(Program, String, Vec<u8>)| {
        renderer
            .render_wgsl_with_data(program, wgsl, data, opts)
            .map(|f| f.device_time.unwrap_or(f.wall_time))
    };
    let start = std::time::Instant::now();
    loop {
        for s in shaders {
            draw(s)?;
        }
        if start.elapsed() >= WARM_UP {
            break;
        }
    }
    let mut times = vec![Vec::with_capacity(runs); shaders.len()];
    for _ in 0..runs {
        for (s, t) in shaders.iter().zip(&mut times) {
            t.push(draw(s)?);
        }
    }
    Ok(times
        .into_iter()
        .map(|mut t| {
            t.sort();
            t[t.len() / 2]
        })
        .collect())
}

fn row(setting: &Setting, time: Duration, frame: &Frame, reference: &sdfc_reference::Image) -> Row {
    let steps: &[f32] = frame.aovs.as_ref().map_or(&[], |a| &a.steps);
    let metrics = crate::compare::frame_metrics(frame, reference);
    let mut sorted = steps.to_vec();
    sorted.sort_by(f32::total_cmp);
    let n = sorted.len().max(1) as f64;
    let max = setting.render.max_steps as f32;
    Row {
        name: setting.name.clone(),
        time,
        steps_mean: sorted.iter().map(|&s| s as f64).sum::<f64>() / n,
        steps_p99: sorted
            .get(((sorted.len() as f64 * 0.99) as usize).min(sorted.len().saturating_sub(1)))
            .map_or(0.0, |&s| s as f64),
        at_max: sorted.iter().filter(|&&s| s >= max).count() as f64 / n,
        metrics,
        pareto: false,
    }
}

/// The error a row is ranked by: hit/miss mismatches away from silhouettes first (a missing
/// or extra surface is worse than any depth error), then the depth error's 99.9th percentile.
fn error_key(r: &Row) -> (usize, f64) {
    (r.metrics.mismatch_interior, r.metrics.depth_p999)
}

fn mark_pareto(rows: &mut [Row]) {
    let keys: Vec<(Duration, (usize, f64))> = rows.iter().map(|r| (r.time, error_key(r))).collect();
    for (r, front) in rows.iter_mut().zip(pareto_front(&keys)) {
        r.pareto = front;
    }
}

/// For each (time, error), whether no other is at least as good in both and better in one.
fn pareto_front<E: PartialOrd + Copy>(keys: &[(Duration, E)]) -> Vec<bool> {
    keys.iter()
        .enumerate()
        .map(|(i, &(t, e))| {
            !keys
                .iter()
                .enumerate()
                .any(|(j, &(tj, ej))| j != i && tj <= t && ej <= e && (tj < t || ej < e))
        })
        .collect()
}

const HEADER: [&str; 10] = [
    "setting",
    "time ms",
    "steps mean",
    "steps p99",
    "at max",
    "depth p99.9",
    "miss int",
    "miss sil",
    "normal med°",
    "PSNR dB",
];

fn cells(r: &Row) -> [String; 10] {
    let m = &r.metrics;
    [
        format!("{}{}", if r.pareto { "* " } else { "  " }, r.name),
        format!("{:.3}", r.time.as_secs_f64() * 1e3),
        format!("{:.1}", r.steps_mean),
        format!("{:.0}", r.steps_p99),
        format!("{:.2}%", 100.0 * r.at_max),
        format!("{:.2e}", m.depth_p999),
        m.mismatch_interior.to_string(),
        m.mismatch_silhouette.to_string(),
        format!("{:.4}", m.normal_median_deg),
        format!("{:.1}", m.psnr_db),
    ]
}

fn table(title: &str, rows: &[Row], markdown: bool) -> String {
    let body: Vec<[String; 10]> = rows.iter().map(cells).collect();
    let mut s = String::new();
    if markdown {
        let _ = writeln!(s, "{title}\n");
        let _ = writeln!(s, "| {} |", HEADER.join(" | "));
        let _ = writeln!(s, "|---{}|", "|---:".repeat(HEADER.len() - 1));
        for c in &body {
            let _ = writeln!(s, "| {} |", c.join(" | "));
        }
        return s;
    }
    let widths: Vec<usize> = (0..HEADER.len())
        .map(|i| {
            body.iter()
                .map(|c| c[i].chars().count())
                .chain([HEADER[i].chars().count()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let _ = writeln!(s, "{title}");
    let line = |cells: &[String]| {
        let mut l = String::new();
        for (i, c) in cells.iter().enumerate() {
            let pad = widths[i].saturating_sub(c.chars().count());
            if i == 0 {
                let _ = write!(l, "{c}{}", " ".repeat(pad));
            } else {
                let _ = write!(l, "  {}{c}", " ".repeat(pad));
            }
        }
        l
    };
    let header: Vec<String> = HEADER.iter().map(|h| h.to_string()).collect();
    let _ = writeln!(s, "{}", line(&header));
    for c in &body {
        let _ = writeln!(s, "{}", line(c));
    }
    s
}

/// The steps AOV as colours: black at one step, then blue, red, yellow, white at max_steps.
fn heatmap(frame: &Frame, program: &Program) -> Frame {
    let max = program.scene.render.max_steps.max(2) as f32;
    let stops: [[f32; 3]; 5] = [
        [0.0, 0.0, 0.0],
        [0.1, 0.2, 0.9],
        [0.9, 0.1, 0.1],
        [1.0, 0.9, 0.1],
        [1.0, 1.0, 1.0],
    ];
    let steps = frame.aovs.as_ref().map_or(&[][..], |a| &a.steps[..]);
    let mut rgba = Vec::with_capacity(steps.len() * 4);
    for &s in steps {
        let x = ((s - 1.0) / (max - 1.0)).clamp(0.0, 1.0) * (stops.len() - 1) as f32;
        let i = (x as usize).min(stops.len() - 2);
        let f = x - i as f32;
        for (a, b) in stops[i].iter().zip(&stops[i + 1]) {
            rgba.push(((a + (b - a) * f) * 255.0).round() as u8);
        }
        rgba.push(255);
    }
    Frame {
        width: frame.width,
        height: frame.height,
        rgba,
        aovs: None,
        device_time: None,
        wall_time: Duration::ZERO,
    }
}

#[cfg(test)]
mod tests {
    use super::pareto_front;
    use std::time::Duration;

    #[test]
    fn the_pareto_front_keeps_what_nothing_beats() {
        let ms = Duration::from_millis;
        let keys = [
            (ms(10), (0, 1e-3)), // front: fastest of the exact ones
            (ms(20), (0, 1e-6)), // front: most accurate
            (ms(30), (0, 1e-5)), // beaten by the one above in both
            (ms(5), (3, 1e-7)),  // front: fastest, though it has mismatches
            (ms(10), (0, 1e-3)), // ties with the first: neither beats the other
            (ms(15), (1, 1e-6)), // beaten by the first (fewer mismatches, faster)
        ];
        assert_eq!(pareto_front(&keys), [true, true, false, true, true, false]);
    }
}
