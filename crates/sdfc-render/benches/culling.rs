//! Culling benchmark, issue 6's criterion: the generated grid's union from the suite's camera
//! (60 away, most rays miss the grid) and from close by (every ray marches through it), drawn
//! as code without culling (the baseline), as code with bounding-box early-outs (`sdfc compile
//! --cull`) and as data (`--instances`: each ray lists the instances whose boxes it passes and
//! marches them alone, what `sdfc render` does from `AUTO_INSTANCES` shapes), at 160x120 (or
//! `SDFC_BENCH_SIZE=WxH`: a GPU needs more pixels than that to fill it), on one device in one
//! run.
//!
//! Before divan's table it prints, per scene and form, the median device time of frames drawn
//! in turn (timestamp queries where the adapter has them, else wall time), the speed against
//! the baseline, and the form's error against the f64 reference renderer (`sdfc-reference`):
//! hits, hit/miss mismatches, depth p99.9 (relative) and normal median, so that each speed
//! is read at its error. `SDFC_BENCH_REFERENCE=0` leaves the reference out: the CPU takes
//! about a minute for the close-by grid at 160x120 on two cores.
//!
//! `cargo bench -p sdfc-render --bench culling`

use sdfc_render::{Frame, RenderOptions, Renderer};
use sdfc_wgsl::{Compiled, Instances, Options};
use std::sync::OnceLock;
use std::time::Duration;

#[path = "../tests/common/against_reference.rs"]
#[allow(dead_code)]
mod reference_metrics;

/// The scenes: the grid's size and camera.
const SCENES: [(usize, bool); 3] = [(300, false), (300, true), (100, true)];

/// Frames of each form drawn in turn, after a warm-up of all.
const FRAMES: usize = 15;

/// The forms compared, the baseline first.
#[derive(Clone, Copy, Debug)]
enum Form {
    Code,
    Cull,
    Data,
}

impl Form {
    const ALL: [Form; 3] = [Form::Code, Form::Cull, Form::Data];

    fn name(self) -> &'static str {
        match self {
            Form::Code => "code (no culling)",
            Form::Cull => "code --cull",
            Form::Data => "data (per-ray lists)",
        }
    }

    fn options(self) -> Options {
        let (cull, instances) = match self {
            Form::Code => (false, Instances::Never),
            Form::Cull => (true, Instances::Never),
            Form::Data => (false, Instances::Always),
        };
        Options {
            cull,
            instances,
            ..Options::default()
        }
    }
}

fn renderer() -> &'static Renderer {
    static R: OnceLock<Renderer> = OnceLock::new();
    R.get_or_init(|| Renderer::new().unwrap_or_else(|e| panic!("cannot render: {e}")))
}

fn source(n: usize, close: bool) -> String {
    if close {
        sdfc_tests::grid_scene_close(n)
    } else {
        sdfc_tests::grid_scene(n)
    }
}

fn compiled(n: usize, close: bool, form: Form) -> Compiled {
    let c = sdfc_wgsl::compile(&source(n, close), &form.options())
        .unwrap_or_else(|_| panic!("the {n}-shape grid does not compile"));
    // The comparison means nothing if a form silently fell back to another.
    assert_eq!(
        !c.data.is_empty(),
        matches!(form, Form::Data),
        "{}: the union is not in the form asked for",
        form.name()
    );
    c
}

fn options() -> RenderOptions {
    let (w, h) = sdfc_tests::bench_size();
    RenderOptions::sized(w, h)
}

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

/// The median device time (wall time where there are no timestamps) of each form's frames,
/// drawn in turn after a warm-up of all, so that every form is timed at the same clocks.
fn times(forms: &[Compiled]) -> Vec<Duration> {
    let r = renderer();
    let draw = |c: &Compiled| {
        let f = r.render(c, &options())?;
        Ok::<_, sdfc_render::RenderError>(f.device_time.unwrap_or(f.wall_time))
    };
    sdfc_tests::warm_up(|| forms.iter().try_for_each(|c| draw(c).map(drop))).expect("render");
    let mut t = vec![Vec::new(); forms.len()];
    for _ in 0..FRAMES {
        for (c, t) in forms.iter().zip(&mut t) {
            t.push(draw(c).expect("render"));
        }
    }
    t.into_iter().map(median).collect()
}

/// The form's frame with its AOVs (depth, normal, steps), for the reference's metrics.
fn frame(c: &Compiled) -> Frame {
    renderer()
        .render(
            c,
            &RenderOptions {
                aovs: true,
                ..options()
            },
        )
        .expect("render")
}

/// The frame's error against the f64 reference, in a line.
fn error(f: &Frame, reference: &sdfc_reference::Image) -> String {
    let m = reference_metrics::frame_metrics(f, reference);
    format!(
        "hits {}/{}, mismatches {} + {}, depth p99.9 {:.2e}, normal median {:.3} deg",
        m.both_hit,
        m.reference_hits,
        m.mismatch_interior,
        m.mismatch_silhouette,
        m.depth_p999,
        m.normal_median_deg,
    )
}

fn main() {
    let r = renderer();
    println!("adapter: {}", r.adapter_description());
    let (w, h) = sdfc_tests::bench_size();
    let with_reference = std::env::var("SDFC_BENCH_REFERENCE").map_or(true, |v| v != "0");
    println!(
        "image: {w}x{h}, grid scenes of spheres, boxes and tori; median of {FRAMES} frames each, \
         drawn in turn"
    );
    for (n, close) in SCENES {
        let camera = if close {
            "close by"
        } else {
            "the suite's camera"
        };
        println!("\n{n} shapes, {camera}:");
        let forms: Vec<Compiled> = Form::ALL.iter().map(|&f| compiled(n, close, f)).collect();
        let medians = times(&forms);
        let reference = with_reference.then(|| {
            sdfc_reference::render(forms[0].program(), &sdfc_reference::Options::sized(w, h))
        });
        for ((form, c), t) in Form::ALL.iter().zip(&forms).zip(&medians) {
            let speed = medians[0].as_secs_f64() / t.as_secs_f64();
            let err = reference
                .as_ref()
                .map_or(String::new(), |reference| error(&frame(c), reference));
            println!(
                "  {:<22} {:>10} {speed:>7.2}x  {err}",
                form.name(),
                format!("{t:.2?}")
            );
        }
    }
    println!();
    divan::main();
}

/// Wall time of a whole frame of the 300-shape grid from the suite's camera, in each form.
#[divan::bench(args = ["code", "cull", "data"], sample_count = 10, sample_size = 1)]
fn grid_300(bencher: divan::Bencher, form: &str) {
    let form = match form {
        "code" => Form::Code,
        "cull" => Form::Cull,
        _ => Form::Data,
    };
    let r = renderer();
    let c = compiled(300, false, form);
    r.render(&c, &options()).expect("render");
    bencher.bench_local(|| r.render(&c, &options()).expect("render"));
}
