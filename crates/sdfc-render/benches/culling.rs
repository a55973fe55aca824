//! Culling benchmark: the same large unions compiled with and without bounding-box
//! early-outs (`sdfc compile --cull`), rendered at 160x120 (or `SDFC_BENCH_SIZE=WxH`: a GPU
//! needs more pixels than that to fill it) on the same device in one run.
//! Before divan's table it prints, per scene, device time (timestamp queries where the
//! adapter has them, else wall time), both ways, their ratio, and the largest depth difference
//! between the two pictures and how many pixels differ by more than 1e-4 relative (the culled
//! field equals the plain one near exact shapes, so the error should be the same).
//!
//! `cargo bench -p sdfc-render --bench culling`

use sdfc_render::{RenderOptions, Renderer};
use sdfc_wgsl::{Compiled, Options};
use std::sync::OnceLock;
use std::time::Duration;

const SIZES: [usize; 2] = [100, 300];

fn renderer() -> &'static Renderer {
    static R: OnceLock<Renderer> = OnceLock::new();
    R.get_or_init(|| Renderer::new().unwrap_or_else(|e| panic!("cannot render: {e}")))
}

fn compiled(n: usize, cull: bool) -> Compiled {
    let opts = Options {
        cull,
        ..Options::default()
    };
    sdfc_wgsl::compile(&sdfc_tests::grid_scene(n), &opts)
        .unwrap_or_else(|_| panic!("grid_scene({n}) does not compile"))
}

fn options() -> RenderOptions {
    let (w, h) = sdfc_tests::bench_size();
    RenderOptions::sized(w, h)
}

/// Mean device time (wall time where there are no timestamps) of a few frames of each, drawn
/// in turn after a warm-up of both, so that both are timed at the same device clocks.
fn times(a: &Compiled, b: &Compiled) -> (Duration, Duration) {
    let r = renderer();
    let draw = |c: &Compiled| {
        let f = r.render(c, &options())?;
        Ok::<_, sdfc_render::RenderError>(f.device_time.unwrap_or(f.wall_time))
    };
    sdfc_tests::warm_up(|| draw(a).and(draw(b)).map(drop)).expect("render");
    let frames = 5;
    let (mut ta, mut tb) = (Duration::ZERO, Duration::ZERO);
    for _ in 0..frames {
        ta += draw(a).expect("render");
        tb += draw(b).expect("render");
    }
    (ta / frames, tb / frames)
}

fn depth(c: &Compiled) -> Vec<f32> {
    let f = renderer()
        .render(
            c,
            &RenderOptions {
                aovs: true,
                ..options()
            },
        )
        .expect("render");
    f.aovs.expect("aovs").depth
}

/// Whether two depths agree to 1e-4 relative (a hit and a miss, inf and finite, do not).
fn within(a: f32, b: f32) -> bool {
    a.is_finite() && b.is_finite() && (a - b).abs() <= 1e-4 * a.abs().max(b.abs())
}

fn main() {
    let r = renderer();
    println!("adapter: {}", r.adapter_description());
    let (w, h) = sdfc_tests::bench_size();
    println!("image: {w}x{h}, grid scenes of spheres, boxes and tori");
    println!(
        "{:<10} {:>12} {:>12} {:>8} {:>22} {:>8}",
        "shapes", "plain", "culled", "speedup", "max depth difference", "pixels"
    );
    for n in SIZES {
        let (plain, culled) = (compiled(n, false), compiled(n, true));
        let (tp, tc) = times(&plain, &culled);
        let (dp, dc) = (depth(&plain), depth(&culled));
        let diff = dp
            .iter()
            .zip(&dc)
            .filter(|(a, b)| a.is_finite() || b.is_finite())
            .map(|(a, b)| if a == b { 0.0 } else { (a - b).abs() })
            .fold(0.0f32, f32::max);
        // Pixels whose depth differs by more than 1e-4 relative (or that hit in one only).
        let differ = dp
            .iter()
            .zip(&dc)
            .filter(|(a, b)| a != b && !within(**a, **b))
            .count();
        println!(
            "{n:<10} {:>12} {:>12} {:>7.2}x {diff:>22.3e} {differ:>8}",
            format!("{tp:.2?}"),
            format!("{tc:.2?}"),
            tp.as_secs_f64() / tc.as_secs_f64()
        );
    }
    println!();
    divan::main();
}

/// Wall time of a whole frame, plain and culled, for the 300-shape grid.
#[divan::bench(args = [false, true], sample_count = 10, sample_size = 1)]
fn grid_300(bencher: divan::Bencher, cull: bool) {
    let r = renderer();
    let c = compiled(300, cull);
    r.render(&c, &options()).expect("render");
    bencher.bench_local(|| r.render(&c, &options()).expect("render"));
}
