//! `sdfc render --compare`: the GPU frame's error against the f64 CPU reference
//! (sdfc-reference), as a plain or Markdown table on stdout.

use sdfc_reference::metrics::{self, GpuFrame, Metrics};
use sdfc_render::Frame;
use sdfc_wgsl::Compiled;
use std::fmt::Write;

/// Renders the reference of `compiled` at the frame's size, params (as the device got them,
/// rounded to f32) and time, and formats the metrics.
pub fn table(
    compiled: &Compiled,
    frame: &Frame,
    overrides: &[(String, Vec<f64>)],
    time: f64,
    name: &str,
    markdown: bool,
    device: &str,
) -> String {
    let program = compiled.program();
    let reference = reference(program, overrides, (frame.width, frame.height), time);
    if frame.aovs.is_none() {
        return String::from("no AOVs came back from the device\n");
    }
    let m = frame_metrics(frame, &reference);
    if markdown {
        markdown_table(name, &m)
    } else {
        plain_table(name, &m, device)
    }
}

/// The metrics of `frame` against `reference`; a frame without AOVs compares no pixel.
pub fn frame_metrics(frame: &Frame, reference: &sdfc_reference::Image) -> Metrics {
    let (depth, normal, steps): (&[f32], &[[f32; 3]], &[f32]) = match &frame.aovs {
        Some(a) => (&a.depth, &a.normal, &a.steps),
        None => (&[], &[], &[]),
    };
    metrics::compare(
        &GpuFrame {
            width: frame.width,
            height: frame.height,
            rgba: &frame.rgba,
            depth,
            normal,
            steps,
        },
        reference,
    )
}

/// The f64 reference render of `program` at `width` x `height`, with the param overrides and
/// the time rounded to f32 as the device gets them.
pub fn reference(
    program: &sdfc_ir::Program,
    overrides: &[(String, Vec<f64>)],
    (width, height): (u32, u32),
    time: f64,
) -> sdfc_reference::Image {
    let in_f32: Vec<(String, Vec<f64>)> = overrides
        .iter()
        .map(|(n, c)| (n.clone(), c.iter().map(|&v| v as f32 as f64).collect()))
        .collect();
    let opts = sdfc_reference::Options {
        width,
        height,
        time: time as f32 as f64,
        params: program.scene.param_values(&in_f32),
        threads: 0,
    };
    sdfc_reference::render(program, &opts)
}

fn markdown_table(name: &str, m: &Metrics) -> String {
    let mut s = format!("| scene | {} |\n", metrics::COLUMNS.join(" | "));
    let _ = writeln!(s, "|---{}|", "|---:".repeat(metrics::COLUMNS.len()));
    let _ = writeln!(s, "| {name} | {} |", metrics::row(m).join(" | "));
    s
}

fn plain_table(name: &str, m: &Metrics, device: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{name}: {device} against the f64 CPU reference");
    let mut line = |k: &str, v: String| {
        let _ = writeln!(s, "  {k:<34} {v}");
    };
    line("pixels", m.pixels.to_string());
    line(
        "hits (both / reference)",
        format!("{} / {}", m.both_hit, m.reference_hits),
    );
    line(
        "depth error, relative: median",
        format!("{:.3e}", m.depth_median),
    );
    line("  99.9th percentile", format!("{:.3e}", m.depth_p999));
    line("  max", format!("{:.3e}", m.depth_max));
    line(
        "hit/miss mismatches: interior",
        m.mismatch_interior.to_string(),
    );
    line("  at silhouettes", m.mismatch_silhouette.to_string());
    line(
        "normal error, degrees: median",
        format!("{:.4}", m.normal_median_deg),
    );
    line("  99th percentile", format!("{:.4}", m.normal_p99_deg));
    line("  max", format!("{:.4}", m.normal_max_deg));
    line(
        "colour error: mean absolute (/255)",
        format!("{:.3}", m.colour_mae),
    );
    line("  PSNR (dB)", format!("{:.2}", m.psnr_db));
    line("NaN/Inf pixels in the AOVs", m.nonfinite.to_string());
    line("negative or NaN depths", m.negative_depth.to_string());
    line(
        "mean steps: GPU / reference",
        format!("{:.1} / {:.1}", m.mean_steps_gpu, m.mean_steps_reference),
    );
    for (what, list) in [
        ("largest depth errors", &m.worst_depth),
        ("largest normal errors", &m.worst_normal),
        (
            "hit/miss mismatches away from silhouettes",
            &m.interior_mismatches,
        ),
    ] {
        if list.is_empty() {
            continue;
        }
        let _ = writeln!(
            s,
            "  {what} (x, y: GPU depth, reference depth, normal angle):"
        );
        for p in list {
            let _ = writeln!(
                s,
                "    {}, {}: {}, {}, {:.3}°",
                p.x, p.y, p.gpu_depth, p.reference_depth, p.normal_deg
            );
        }
    }
    s
}
