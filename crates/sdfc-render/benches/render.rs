//! Render benchmark: the scene suite but its 5 000-shape union (one sphere, the spec's section
//! 10 scene, a 300-shape flat union, the terrain, the fractals) at 160x120, or at the size in
//! `SDFC_BENCH_SIZE` (`WxH`). Before divan's wall-clock table it prints, per scene,
//! the adapter, the device time of the compute pass (timestamp queries, mean of several
//! frames) and the mean march steps per pixel, over all pixels and over the pixels whose ray
//! hits (from the steps AOV); then the same frames from the interpreted marcher
//! (`render_interpreted`, bytecode encoded once outside the timing, as a live editor would
//! after an edit) and its time as a ratio to the specialised shader's, measured in this run.
//!
//! `cargo bench -p sdfc-render --bench render`; `-- none` skips divan's table after it.
//! The 5 000-shape union is not here: lavapipe's build of its specialised pipeline alone takes
//! longer than the rest of the run (docs/performance.md).

use sdfc_render::{RenderOptions, Renderer};
use std::sync::OnceLock;
use std::time::Duration;

const SCENES: [&str; 5] = [
    "sphere",
    "spec_section10",
    "grid_300",
    "terrain",
    "fractals",
];

fn renderer() -> &'static Renderer {
    static R: OnceLock<Renderer> = OnceLock::new();
    R.get_or_init(|| Renderer::new().unwrap_or_else(|e| panic!("cannot render: {e}")))
}

fn compiled(name: &str) -> sdfc_wgsl::Compiled {
    sdfc_wgsl::compile(&sdfc_tests::suite_scene(name), &Default::default())
        .unwrap_or_else(|_| panic!("{name} does not compile"))
}

fn options() -> RenderOptions {
    let (w, h) = sdfc_tests::bench_size();
    RenderOptions::sized(w, h)
}

fn main() {
    let r = renderer();
    println!("adapter: {}", r.adapter_description());
    let (w, h) = sdfc_tests::bench_size();
    println!("image: {w}x{h}");
    println!(
        "{:<16} {:>14} {:>14} {:>12} {:>16} {:>10} {:>22}",
        "scene",
        "device time",
        "wall time",
        "steps/pixel",
        "steps/hit pixel",
        "hit pixels",
        "first frame (pipeline)"
    );
    for name in SCENES {
        let c = compiled(name);
        // The first render builds the pipeline: reported on its own, left out of the frames.
        let start = std::time::Instant::now();
        r.render(&c, &options()).expect("render");
        let first = start.elapsed();
        sdfc_tests::warm_up(|| r.render(&c, &options()).map(drop)).expect("render");
        let frames = 5;
        let mut device = Duration::ZERO;
        let mut wall = Duration::ZERO;
        let mut timed = true;
        for _ in 0..frames {
            let f = r.render(&c, &options()).expect("render");
            wall += f.wall_time;
            match f.device_time {
                Some(t) => device += t,
                None => timed = false,
            }
        }
        let with_aovs = r
            .render(
                &c,
                &RenderOptions {
                    aovs: true,
                    ..options()
                },
            )
            .expect("render");
        let aovs = with_aovs.aovs.as_ref().expect("aovs");
        let steps = aovs.mean_steps();
        let hit_steps: Vec<f64> = aovs
            .depth
            .iter()
            .zip(&aovs.steps)
            .filter(|(d, _)| d.is_finite())
            .map(|(_, &s)| s as f64)
            .collect();
        let hit_mean = hit_steps.iter().sum::<f64>() / hit_steps.len().max(1) as f64;
        let hit_share = 100.0 * hit_steps.len() as f64 / aovs.depth.len() as f64;
        let device = if timed {
            format!("{:.3?}", device / frames)
        } else {
            "n/a".into()
        };
        println!(
            "{name:<16} {device:>14} {:>14} {steps:>12.1} {hit_mean:>16.1} {:>9.1}% {:>22}",
            format!("{:.3?}", wall / frames),
            hit_share,
            format!("{first:.3?}")
        );
    }
    println!();
    println!("interpreted marcher against the specialised shader (same frames, same run):");
    println!(
        "{:<16} {:>14} {:>14} {:>14} {:>14} {:>8}",
        "scene", "specialised", "interpreted", "spec. wall", "interp. wall", "ratio"
    );
    for name in SCENES {
        let c = compiled(name);
        let code = match sdfc_wgsl::interp::encode::encode(c.program()) {
            Ok(code) => code,
            Err(e) => {
                println!("{name:<16} not interpreted: {e}");
                continue;
            }
        };
        r.render(&c, &options()).expect("render");
        let start = std::time::Instant::now();
        r.render_bytecode(c.program(), &code, &options())
            .expect("render");
        println!(
            "{name:<16} first interpreted frame (the interpreter's pipeline is built once): {:.3?}",
            start.elapsed()
        );
        sdfc_tests::warm_up(|| {
            r.render(&c, &options())?;
            r.render_bytecode(c.program(), &code, &options()).map(drop)
        })
        .expect("render");
        let frames = 3;
        let (mut spec, mut interp) = (Timing::default(), Timing::default());
        // Interleaved, so a change in the machine's load hits both alike.
        for _ in 0..frames {
            spec.add(&r.render(&c, &options()).expect("render"));
            interp.add(
                &r.render_bytecode(c.program(), &code, &options())
                    .expect("render"),
            );
        }
        let (s, i) = (spec.best(), interp.best());
        println!(
            "{name:<16} {:>14} {:>14} {:>14} {:>14} {:>7.2}x",
            spec.device_text(frames),
            interp.device_text(frames),
            format!("{:.3?}", spec.wall / frames),
            format!("{:.3?}", interp.wall / frames),
            i.as_secs_f64() / s.as_secs_f64()
        );
    }
    println!("(ratio: interpreted / specialised, device time where the device has timestamps, else wall time)");
    println!();
    divan::main();
}

/// Summed times of several frames.
#[derive(Default)]
struct Timing {
    device: Duration,
    wall: Duration,
    timed: bool,
    frames: u32,
}

impl Timing {
    fn add(&mut self, f: &sdfc_render::Frame) {
        self.timed = (self.frames == 0 || self.timed) && f.device_time.is_some();
        self.device += f.device_time.unwrap_or_default();
        self.wall += f.wall_time;
        self.frames += 1;
    }

    /// The total the ratio uses: device time if every frame had it, else wall time.
    fn best(&self) -> Duration {
        if self.timed {
            self.device
        } else {
            self.wall
        }
    }

    fn device_text(&self, frames: u32) -> String {
        if self.timed {
            format!("{:.3?}", self.device / frames)
        } else {
            "n/a".into()
        }
    }
}

/// Wall time of a whole frame: upload, dispatch, readback (the pipeline is cached).
#[divan::bench(args = SCENES, sample_count = 10, sample_size = 1)]
fn render(bencher: divan::Bencher, name: &str) {
    let r = renderer();
    let c = compiled(name);
    r.render(&c, &options()).expect("render");
    bencher.bench_local(|| r.render(&c, &options()).expect("render"));
}

/// Wall time of a whole interpreted frame (the bytecode encoded once, outside the loop).
/// Fewer samples: on lavapipe an interpreted frame of the larger scenes takes seconds.
#[divan::bench(args = SCENES, sample_count = 3, sample_size = 1)]
fn render_interpreted(bencher: divan::Bencher, name: &str) {
    let r = renderer();
    let c = compiled(name);
    let Ok(code) = sdfc_wgsl::interp::encode::encode(c.program()) else {
        return; // beyond the interpreter's limits (the table above says so)
    };
    r.render_bytecode(c.program(), &code, &options())
        .expect("render");
    bencher.bench_local(|| {
        r.render_bytecode(c.program(), &code, &options())
            .expect("render")
    });
}
