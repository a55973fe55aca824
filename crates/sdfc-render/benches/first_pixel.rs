//! Time from scene source to first pixel, in a process whose interpreter is already built (a
//! live editor after start-up): the specialised path alone (compile, build the pipeline,
//! render) against the live path (`render_live`: lower, then the interpreted preview while
//! the specialised pipeline builds), with no grace (the default) and with 250 ms of grace.
//! As `sdfc render --live`, the preview draws the scene lowered with culling
//! (`sdfc_wgsl::lower_live`); the specialised shader culls only with `SDFC_BENCH_CULL=1`.
//! The specialised path and each of the two live settings have a renderer of their own, so
//! a scene's pipeline is never in the in-process cache when it is measured; the live ones
//! warm the interpreter once, before the first scene.
//!
//! `cargo bench -p sdfc-render --bench first_pixel`. The image is 160x120, or
//! `SDFC_BENCH_SIZE=WxH`; the preview at the device's default scale (an eighth of it on a CPU
//! device, a quarter on a GPU). `SDFC_BENCH_5000=1` adds the
//! 5 000-shape union (minutes on a CPU device). `SDFC_BENCH_SCENES=a,b` measures those suite
//! scenes instead. `SDFC_BENCH_LIVE_ONLY=1` measures the live path without grace alone, and
//! prints the preview's time as soon as it is drawn: NVIDIA's driver had not built the
//! 5 000-shape union's pipeline after 236 s (docs/performance.md), so a run limited in time
//! still learns the first pixel. `SDFC_BENCH_INSTANCES=1`: the specialised shader reads a
//! union of 16 or more instances as data (`--instances`); `=0`: never (`--no-instances`);
//! unset: from `AUTO_INSTANCES` (100) up, the default. Mesa keeps built shaders in a disk cache:
//! `MESA_SHADER_CACHE_DISABLE=true` measures cold builds.

use sdfc_render::{LiveOptions, RenderOptions, Renderer};
use std::time::{Duration, Instant};

/// A fresh renderer with the interpreter's pipeline built.
fn warm_renderer() -> Renderer {
    let r = Renderer::new().unwrap_or_else(|e| panic!("cannot render: {e}"));
    r.warm_interpreter().expect("the interpreter builds");
    r
}

fn ms(d: Duration) -> String {
    format!("{:.0} ms", d.as_secs_f64() * 1e3)
}

fn main() {
    let (w, h) = sdfc_tests::bench_size();
    let opts = RenderOptions::sized(w, h);
    let mut scenes = vec![
        "sphere",
        "spec_section10",
        "grid_300",
        "terrain",
        "fractals",
    ];
    if std::env::var("SDFC_BENCH_5000").is_ok_and(|v| v == "1") {
        scenes.push("grid_5000");
    }
    let chosen = std::env::var("SDFC_BENCH_SCENES").unwrap_or_default();
    if !chosen.is_empty() {
        scenes = chosen.split(',').collect();
    }
    let live_only = std::env::var("SDFC_BENCH_LIVE_ONLY").is_ok_and(|v| v == "1");
    // `SDFC_BENCH_CULL=1`: both paths with bounding-box early-outs (`--cull`).
    let emit = sdfc_wgsl::Options {
        cull: std::env::var("SDFC_BENCH_CULL").is_ok_and(|v| v == "1"),
        instances: match std::env::var("SDFC_BENCH_INSTANCES").as_deref() {
            Ok("1") => sdfc_wgsl::Instances::Always,
            Ok("0") => sdfc_wgsl::Instances::Never,
            _ => sdfc_wgsl::Instances::Auto,
        },
        ..Default::default()
    };
    let start = Instant::now();
    let probe = warm_renderer();
    println!("adapter: {}", probe.adapter_description());
    println!(
        "image: {w}x{h}; the interpreter built in {:.2?} first",
        start.elapsed()
    );
    drop(probe);
    println!(
        "{:<16} {:>13} | {:>13} {:>13} {:>13} | {:>13} {:>13}",
        "scene", "specialised", "live: lowered", "first pixel", "final", "grace 250 ms", "final"
    );
    let now_renderer = warm_renderer();
    // Not warmed where it is not used: the interpreter's build took NVIDIA's driver 4 s.
    let graced_renderer = (!live_only).then(warm_renderer);
    for name in scenes {
        let src = sdfc_tests::suite_scene(name);

        let specialised = if live_only {
            None
        } else {
            let r = Renderer::new().unwrap_or_else(|e| panic!("cannot render: {e}"));
            let t = Instant::now();
            let c = sdfc_wgsl::compile(&src, &emit)
                .unwrap_or_else(|_| panic!("{name} does not compile"));
            r.render(&c, &opts).expect("render");
            Some(t.elapsed())
        };

        let live = |r: &Renderer, grace: Duration| {
            let t = Instant::now();
            let lowered = sdfc_wgsl::lower_live(&src, &emit)
                .unwrap_or_else(|_| panic!("{name} does not lower"));
            let lowered_at = t.elapsed();
            let options = LiveOptions {
                start: t,
                grace,
                emit: emit.clone(),
                preview: lowered.preview.clone(),
                ..LiveOptions::default()
            };
            let (_, report) = r
                .render_live(&lowered.stages.program, &opts, &options, |drawn, _| {
                    if live_only && matches!(drawn, sdfc_render::Drawn::Interpreted) {
                        println!(
                            "{name}: lowered at {}, preview drawn at {}",
                            ms(lowered_at),
                            ms(t.elapsed())
                        );
                    }
                })
                .expect("live render");
            (lowered_at, report)
        };
        let (lowered, now) = live(&now_renderer, Duration::ZERO);
        let first = |r: &sdfc_render::LiveReport| {
            let mark = if r.interpreted.is_some() { "" } else { " *" };
            format!("{}{mark}", ms(r.first_pixel()))
        };
        let Some(specialised) = specialised else {
            println!(
                "{name:<16} {:>13} | {:>13} {:>13} {:>13} | (live only: pipeline ready at {})",
                "-",
                ms(lowered),
                first(&now),
                ms(now.specialised),
                ms(now.pipeline_ready),
            );
            continue;
        };
        let graced_renderer = graced_renderer.as_ref().expect("warmed unless live only");
        let (_, graced) = live(graced_renderer, Duration::from_millis(250));
        println!(
            "{name:<16} {:>13} | {:>13} {:>13} {:>13} | {:>13} {:>13}",
            ms(specialised),
            ms(lowered),
            first(&now),
            ms(now.specialised),
            first(&graced),
            ms(graced.specialised),
        );
    }
    println!("(* no preview: the specialised frame came first)");
}
