//! Renders a scene with its own specialised shader and with another WGSL text for the same
//! scene, and prints both builds' and renders' times and how far the pictures differ: the
//! harness of experiments on the emitted shader's form (docs/performance.md, "Large unions
//! as tables"), run here and by `scripts/gpu-bench.sh` on a GPU.
//!
//! `cargo run --release -p sdfc-render --example compare_shader -- emit N DIR` writes
//! `DIR/gridN.sdf` (the generated grid of N shapes, seen from close by) and `DIR/gridN.wgsl`
//! (its shader); `... -- compare SCENE.sdf OTHER.wgsl WxH [BASE.wgsl]` renders both, OTHER
//! against the scene's own shader or, where given, against BASE. A shader written
//! `S.wgsl:D.bin` reads the bytes of `D.bin` as read-only storage at binding 3
//! (`scripts/bvh-experiment.py`); OTHER written `instances` is the scene compiled with
//! `Options::instances` (its union as data). `SDFC_COMPARE_REFERENCE=1` also prints each
//! frame's error against the f64 reference (with how many pixels both hit are off by more
//! than 1e-4 and 1e-3 relative), `SDFC_COMPARE_PIXELS=1` the pixels whose depths or
//! colours differ (and, with the reference, those whose depths differ from its by more than
//! `SDFC_COMPARE_OFF`, 1e-3 relative unless set);
//! `SDFC_COMPARE_AT="x,y x,y"` prints both frames' depth and steps at those pixels (a variant
//! can write a count of its own into the steps AOV); `SDFC_COMPARE_ALL_PIXELS=1` runs the own
//! (or base) shader on every pixel, the other on the tiles its rays can meet the scene in
//! only (the renderer's default).

use sdfc_reference::metrics::percentile;
use sdfc_render::{RenderOptions, Renderer};
use std::time::{Duration, Instant};

type Error = Box<dyn std::error::Error>;

#[path = "../tests/common/against_reference.rs"]
#[allow(dead_code)]
mod reference_metrics;

/// A shader's text and the data it reads at binding 3, if any.
type Shader = (String, Option<Vec<u8>>);

/// Whether the environment variable `name` is `1` (what the comparison also prints).
fn set(name: &str) -> bool {
    std::env::var(name).is_ok_and(|v| v == "1")
}

/// The scene's own shader, its union as code at any size (by default a union of
/// `AUTO_INSTANCES` or more instances would be data, the form compared against).
fn compile(source: &str) -> Result<sdfc_wgsl::Compiled, Error> {
    let code = sdfc_wgsl::Options {
        instances: sdfc_wgsl::Instances::Never,
        ..sdfc_wgsl::Options::default()
    };
    sdfc_wgsl::compile(source, &code).map_err(|_| "the scene does not compile".into())
}

fn emit(n: usize, dir: &str) -> Result<(), Error> {
    let source = sdfc_tests::grid_scene_close(n);
    let compiled = compile(&source)?;
    std::fs::write(format!("{dir}/grid{n}.sdf"), &source)?;
    std::fs::write(format!("{dir}/grid{n}.wgsl"), &compiled.wgsl)?;
    Ok(())
}

/// A shader's text and the data it reads at binding 3, if any, from `S.wgsl[:D.bin]`.
fn shader(arg: &str) -> Result<Shader, Error> {
    let (wgsl, data) = match arg.split_once(':') {
        Some((wgsl, data)) => (wgsl, Some(std::fs::read(data)?)),
        None => (arg, None),
    };
    Ok((std::fs::read_to_string(wgsl)?, data))
}

fn compare(scene: &str, other: &str, size: &str, base: Option<&str>) -> Result<(), Error> {
    let source = std::fs::read_to_string(scene)?;
    let compiled = compile(&source)?;
    let other = if other == "instances" {
        let opts = sdfc_wgsl::Options {
            instances: sdfc_wgsl::Instances::Always,
            ..sdfc_wgsl::Options::default()
        };
        let c = sdfc_wgsl::compile(&source, &opts).map_err(|_| "the scene does not compile")?;
        if c.data.is_empty() {
            return Err("the scene's union is not emitted as data".into());
        }
        (c.wgsl, Some(c.data))
    } else {
        shader(other)?
    };
    let (own, base) = match base {
        Some(b) => ("base shader", shader(b)?),
        None => ("own shader", (compiled.wgsl.clone(), None)),
    };
    let (w, h) = size.split_once('x').ok_or("size is WxH")?;
    let mut opts = RenderOptions::sized(w.parse()?, h.parse()?);
    opts.aovs = true;
    let probes = probes(opts.width, opts.height)?;
    let r = Renderer::new()?;
    println!("adapter: {}", r.adapter_description());
    // The other shader first: where the own one is slow to build (a large union on a CPU
    // device), the other's figures are printed before a time limit cuts the run short.
    let shaders = [("other shader", &other), (own, &base)];
    // `SDFC_COMPARE_ALL_PIXELS=1`: the own (or base) shader runs on every pixel, the other
    // only on the tiles its rays can meet the scene in, as the renderer does by default.
    let all_pixels = RenderOptions {
        all_pixels: set("SDFC_COMPARE_ALL_PIXELS"),
        ..opts.clone()
    };
    let render = |i: usize, (wgsl, data): &Shader| {
        let opts = if i == 0 { &opts } else { &all_pixels };
        match data {
            Some(bytes) => r.render_wgsl_with_data(compiled.program(), wgsl, bytes, opts),
            None => r.render_wgsl(compiled.program(), wgsl, opts),
        }
    };
    let mut frames = Vec::new();
    for (i, (name, shader)) in shaders.into_iter().enumerate() {
        let start = Instant::now();
        let frame = render(i, shader)?;
        let steps = frame.aovs.as_ref().map_or(0.0, |a| a.mean_steps());
        println!(
            "{name}: {} bytes, build and first render {:.2?}, {steps:.2} steps per pixel",
            shader.0.len(),
            start.elapsed(),
        );
        frames.push(frame);
    }
    // Both shaders drawn in turn for a while first (`sdfc_tests::warm_up`), then timed
    // interleaved frame by frame, so that neither is measured at a clock the other did not have.
    sdfc_tests::warm_up(|| {
        for (i, (_, shader)) in shaders.iter().enumerate() {
            render(i, shader)?;
        }
        Ok::<_, sdfc_render::RenderError>(())
    })?;
    const FRAMES: usize = 21;
    let mut times = [(Vec::new(), Vec::new()), (Vec::new(), Vec::new())];
    for _ in 0..FRAMES {
        for (i, ((_, shader), (device, wall))) in shaders.iter().zip(&mut times).enumerate() {
            let f = render(i, shader)?;
            wall.push(f.wall_time);
            device.extend(f.device_time);
        }
    }
    let median = |v: &mut Vec<Duration>| {
        v.sort();
        (v.len() == FRAMES).then(|| v[FRAMES / 2])
    };
    let mut medians = Vec::new();
    for ((name, _), (device, wall)) in shaders.iter().zip(&mut times) {
        let (d, w) = (median(device), median(wall));
        let shown = d.map_or("none".into(), |d| format!("{d:.2?}"));
        println!(
            "{name}: median of {FRAMES} interleaved frames, device time {shown}, wall time {:.2?}",
            w.unwrap_or_default()
        );
        medians.push(d.or(w).unwrap_or_default());
    }
    println!(
        "{} time / other time: {:.2}x",
        own.trim_end_matches(" shader"),
        medians[1].as_secs_f64() / medians[0].as_secs_f64().max(1e-12)
    );
    let (a, b) = (&frames[1], &frames[0]);
    let off = a
        .rgba
        .iter()
        .zip(&b.rgba)
        .filter(|(x, y)| x.abs_diff(**y) > 2)
        .count();
    let (da, db) = (
        &a.aovs.as_ref().unwrap().depth,
        &b.aovs.as_ref().unwrap().depth,
    );
    let hit_miss = da
        .iter()
        .zip(db)
        .filter(|(x, y)| x.is_finite() != y.is_finite())
        .count();
    let mut rel: Vec<f64> = da
        .iter()
        .zip(db)
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .map(|(x, y)| ((x - y).abs() / x.abs().max(1e-6)) as f64)
        .collect();
    if set("SDFC_COMPARE_PIXELS") {
        // The pixels whose depths differ by more than 1e-3 relative, or hit and miss, or
        // whose colours differ by more than 2/255 (a secondary ray's march).
        let width = opts.width as usize;
        for (i, (x, y)) in da.iter().zip(db).enumerate() {
            let (ca, cb) = (&a.rgba[4 * i..4 * i + 3], &b.rgba[4 * i..4 * i + 3]);
            let coloured = ca.iter().zip(cb).any(|(p, q)| p.abs_diff(*q) > 2);
            if coloured || x.is_finite() != y.is_finite() || (x - y).abs() > 1e-3 * x.abs() {
                println!(
                    "pixel {} {}: depth {x} and {y}, colour {ca:?} and {cb:?}",
                    i % width,
                    i / width
                );
            }
        }
    }
    // Both frames' depth and steps at the pixels `SDFC_COMPARE_AT` names: a variant that
    // writes a count of its own into the steps AOV is read here.
    for &(x, y) in &probes {
        let i = y as usize * opts.width as usize + x as usize;
        for ((name, _), f) in shaders.iter().zip(&frames) {
            let aovs = f.aovs.as_ref().expect("AOVs");
            println!(
                "pixel {x} {y}, {name}: depth {}, steps {}",
                aovs.depth[i], aovs.steps[i]
            );
        }
    }
    rel.sort_by(f64::total_cmp);
    let p999 = percentile(&rel, 0.999);
    println!(
        "difference: {off} channels off by more than 2/255, {hit_miss} hit/miss, depth p99.9 {p999:.2e} relative"
    );
    if set("SDFC_COMPARE_REFERENCE") {
        against_reference(&compiled, &shaders, &frames, &opts);
    }
    Ok(())
}

/// The pixels `SDFC_COMPARE_AT="x,y x,y"` names, each within the image.
fn probes(width: u32, height: u32) -> Result<Vec<(u32, u32)>, Error> {
    let Ok(at) = std::env::var("SDFC_COMPARE_AT") else {
        return Ok(Vec::new());
    };
    at.split_whitespace()
        .map(|xy| {
            let bad = || format!("SDFC_COMPARE_AT: `{xy}` is not x,y within {width}x{height}");
            let (x, y) = xy.split_once(',').ok_or_else(bad)?;
            let (x, y) = (
                x.parse::<u32>().map_err(|_| bad())?,
                y.parse::<u32>().map_err(|_| bad())?,
            );
            if x < width && y < height {
                Ok((x, y))
            } else {
                Err(bad().into())
            }
        })
        .collect()
}

/// Each frame's error against the f64 reference (`SDFC_COMPARE_REFERENCE=1`; slow: the CPU
/// renders the scene), so that a shader that differs from another can be told closer or
/// farther.
fn against_reference(
    compiled: &sdfc_wgsl::Compiled,
    shaders: &[(&str, &Shader); 2],
    frames: &[sdfc_render::Frame],
    opts: &RenderOptions,
) {
    let (width, height) = (opts.width, opts.height);
    let reference = sdfc_reference::render(
        compiled.program(),
        &sdfc_reference::Options::sized(width, height),
    );
    for ((name, _), f) in shaders.iter().zip(frames) {
        let m = reference_metrics::frame_metrics(f, &reference);
        println!(
            "{name} against the f64 reference: hits {}/{}, mismatches {} interior + {} at \
             silhouettes, depth median {:.2e} p99.9 {:.2e}, normal median {:.3} deg, PSNR {:.1} dB",
            m.both_hit,
            m.reference_hits,
            m.mismatch_interior,
            m.mismatch_silhouette,
            m.depth_median,
            m.depth_p999,
            m.normal_median_deg,
            m.psnr_db
        );
        // The depth bar (docs/accuracy.md) is 1e-4 relative on 99.9% of the hit pixels: how
        // many pixels are above it, and above 1e-3, of those both hit.
        let a = f.aovs.as_ref().expect("AOVs");
        // Whether a depth both hit is off the reference's by more than `tol` relative.
        let off_by = |r: &sdfc_reference::Pixel, d: f32, tol: f64| {
            (f64::from(d) - r.depth).abs() > tol * r.depth.abs()
        };
        let above = |tol: f64| {
            (reference.pixels.iter().zip(&a.depth))
                .filter(|&(r, &d)| r.hit && d.is_finite() && off_by(r, d, tol))
                .count()
        };
        let bar = above(1e-4);
        println!(
            "{name} depths off by more than 1e-4 relative: {bar} ({:.3}% of both hit), 1e-3: {}",
            100.0 * bar as f64 / m.both_hit.max(1) as f64,
            above(1e-3)
        );
        if set("SDFC_COMPARE_PIXELS") {
            // The pixels whose depth differs from the reference's by more than the tolerance,
            // or that hit where it misses or the other way, with both colours.
            let tol = std::env::var("SDFC_COMPARE_OFF")
                .ok()
                .and_then(|v| v.parse::<f64>().ok())
                .unwrap_or(1e-3);
            for (i, (r, &d)) in reference.pixels.iter().zip(&a.depth).enumerate() {
                let off = if r.hit && d.is_finite() {
                    off_by(r, d, tol)
                } else {
                    r.hit != d.is_finite()
                };
                if off {
                    let rgb = &f.rgba[4 * i..4 * i + 3];
                    println!(
                        "  pixel {} {}: depth {d} (reference {:.6}), colour {rgb:?} (reference {:?})",
                        i % width as usize,
                        i / width as usize,
                        if r.hit { r.depth } else { f64::INFINITY },
                        &r.rgba[..3]
                    );
                }
            }
        }
    }
}

fn main() -> Result<(), Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["emit", n, dir] => emit(n.parse()?, dir),
        ["compare", scene, other, size] => compare(scene, other, size, None),
        ["compare", scene, other, size, base] => compare(scene, other, size, Some(base)),
        _ => Err(
            "usage: compare_shader emit N DIR | compare SCENE.sdf OTHER.wgsl[:DATA.bin] WxH [BASE.wgsl[:DATA.bin]]"
                .into(),
        ),
    }
}
