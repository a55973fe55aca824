//! The live path (`Renderer::render_live`): the interpreted preview while the specialised
//! pipeline builds, then the specialised frame; and the pipeline cache it leans on, which
//! builds each text once and never holds one text's build up behind another's.

mod common;

use common::{compile, renderer};
use sdfc_render::{Drawn, Frame, LiveOptions, RenderError, RenderOptions, Renderer};
use std::time::{Duration, Instant};

const SCENE: &str = "param r = 0.8;\n\
                     light point { position: [3, 4, 2] }\n\
                     render { shadows: hard }\n\
                     scene = sphere(r).translate([0.2, 0.1, 0]) | plane([0, 1, 0], 1);\n";

fn live(grace: Duration, preview_scale: u32) -> LiveOptions {
    LiveOptions {
        start: Instant::now(),
        grace,
        preview_scale: Some(preview_scale),
        emit: sdfc_wgsl::Options::default(),
        preview: None,
    }
}

/// Renders live, recording which shader drew each frame and a copy of it.
fn render_live(
    r: &Renderer,
    program: &sdfc_ir::Program,
    opts: &RenderOptions,
    live: &LiveOptions,
) -> Result<(Vec<(Drawn, Frame)>, sdfc_render::LiveReport), RenderError> {
    let mut frames = Vec::new();
    let (last, report) = r.render_live(program, opts, live, |drawn, frame| {
        frames.push((drawn, frame.clone()));
    })?;
    assert_eq!(frames.last().map(|f| f.1.rgba.clone()), Some(last.rgba));
    Ok((frames, report))
}

#[test]
fn with_no_grace_the_interpreter_draws_a_preview_then_the_specialised_shader_the_frame() {
    // A renderer of its own, so that the scene's pipeline is not yet in its cache.
    let Some(shared) = renderer() else { return };
    let r = Renderer::new().unwrap();
    // The interpreter's pipeline built beforehand (as a live editor does at start-up): its
    // cache hit then comes long before the scene's pipeline is emitted, validated and built.
    r.warm_interpreter().unwrap();
    let c = compile("live", SCENE);
    let opts = RenderOptions {
        params: vec![("r".into(), vec![0.6])],
        aovs: true,
        ..RenderOptions::sized(64, 48)
    };
    let (frames, report) = render_live(&r, c.program(), &opts, &live(Duration::ZERO, 2)).unwrap();
    let kinds: Vec<Drawn> = frames.iter().map(|f| f.0).collect();
    assert_eq!(
        kinds,
        [Drawn::Interpreted, Drawn::Specialised],
        "{report:?}"
    );
    assert_eq!(report.preview_skipped, None);
    // On a CPU device the build starts once the preview is drawn, so that the two do not
    // share the cores; on a GPU it starts at once, beside the preview.
    let interpreted = report.interpreted.unwrap();
    let times = format!(
        "build started at {:?}, preview drawn at {interpreted:?}",
        report.build_started
    );
    if r.adapter_description().software {
        assert!(report.build_started >= interpreted, "{times}");
    } else {
        assert!(report.build_started < interpreted, "{times}");
    }
    let (preview, last) = (&frames[0].1, &frames[1].1);

    // The preview is the interpreted frame at half the size, each pixel repeated 2x2, in
    // direct light only: the scene without its shadows.
    let half = RenderOptions {
        width: 32,
        height: 24,
        ..opts.clone()
    };
    let unshadowed = compile("live", &SCENE.replace("render { shadows: hard }\n", ""));
    let small = shared
        .render_interpreted(unshadowed.program(), &half)
        .unwrap();
    let shadowed = shared.render_interpreted(c.program(), &half).unwrap();
    assert_ne!(small.rgba, shadowed.rgba, "the shadow is visible");
    assert_eq!((preview.width, preview.height), (64, 48));
    let small_aovs = small.aovs.as_ref().unwrap();
    let preview_aovs = preview.aovs.as_ref().unwrap();
    for y in 0..48 {
        for x in 0..64 {
            assert_eq!(
                preview.pixel(x, y),
                small.pixel(x / 2, y / 2),
                "pixel {x},{y}"
            );
            let (i, j) = ((y * 64 + x) as usize, ((y / 2) * 32 + x / 2) as usize);
            assert_eq!(
                preview_aovs.depth[i].to_bits(),
                small_aovs.depth[j].to_bits()
            );
        }
    }

    // The final frame is the specialised render, bit for bit, and the report's WGSL its text.
    let plain = shared.render(&c, &opts).unwrap();
    assert_eq!(last.rgba, plain.rgba);
    assert_eq!(last.aovs, plain.aovs);
    assert_eq!(report.wgsl, c.wgsl);
    assert_eq!(report.first_pixel(), report.interpreted.unwrap());
    // The specialised pipeline was built once, into the cache: rendering again compiles
    // nothing (the interpreter's two variants, warmed, are the other compilations).
    assert_eq!(r.pipeline_compilations(), 3);
    r.render(&c, &opts).unwrap();
    assert_eq!(r.pipeline_compilations(), 3);
}

#[test]
fn with_an_endless_grace_only_the_specialised_shader_draws() {
    let Some(r) = renderer() else { return };
    let c = compile("live", SCENE);
    let opts = RenderOptions::sized(40, 30);
    let (frames, report) = render_live(r, c.program(), &opts, &live(Duration::MAX, 4)).unwrap();
    assert_eq!(frames.len(), 1);
    assert_eq!(frames[0].0, Drawn::Specialised);
    assert_eq!(frames[0].1.rgba, r.render(&c, &opts).unwrap().rgba);
    assert_eq!(report.interpreted, None);
    assert_eq!(report.preview_skipped, None);
    assert_eq!(report.first_pixel(), report.specialised);
}

#[test]
fn a_scene_beyond_the_interpreter_still_gets_its_frame() {
    // More values live at once than the interpreter has registers (as in
    // sdfc-wgsl/tests/interp.rs): no preview, and the reason why.
    let Some(r) = renderer() else { return };
    let n = sdfc_wgsl::interp::encode::MAX_REGISTERS as usize + 8;
    let terms: Vec<String> = (0..n).map(|i| format!("sin(p.x * {}.5)", i + 1)).collect();
    let src = format!(
        "scene = sdf(|p| length(p) - 1 + 0.001 * ({}) + 0.001 * ({}), lipschitz: 2);\n",
        terms.join(" + "),
        terms.join(" * ")
    );
    let c = compile("too many live values", &src);
    let opts = RenderOptions::sized(16, 16);
    let (frames, report) = render_live(r, c.program(), &opts, &live(Duration::ZERO, 1)).unwrap();
    assert_eq!(frames.len(), 1);
    assert_eq!(frames[0].0, Drawn::Specialised);
    assert_eq!(frames[0].1.rgba, r.render(&c, &opts).unwrap().rgba);
    let why = report.preview_skipped.unwrap();
    assert!(why.contains("live at once"), "{why}");
}

#[test]
fn bad_params_fail_before_any_work() {
    let Some(r) = renderer() else { return };
    let c = compile("live", SCENE);
    let opts = RenderOptions {
        params: vec![("radius".into(), vec![1.0])],
        ..RenderOptions::sized(8, 8)
    };
    let mut called = false;
    let got = r.render_live(c.program(), &opts, &live(Duration::ZERO, 1), |_, _| {
        called = true
    });
    assert!(matches!(got, Err(RenderError::Param(_))), "{got:?}");
    assert!(!called);
    let empty = RenderOptions::sized(0, 8);
    let got = r.render_live(c.program(), &empty, &live(Duration::ZERO, 1), |_, _| {});
    assert!(matches!(got, Err(RenderError::ImageSize(_))), "{got:?}");
}

#[test]
fn threads_asking_for_one_shader_at_once_build_it_once() {
    if renderer().is_none() {
        return;
    }
    let r = Renderer::new().unwrap();
    let c = compile("live", SCENE);
    let opts = RenderOptions::sized(8, 8);
    let frames: Vec<Frame> = std::thread::scope(|s| {
        let threads: Vec<_> = (0..4).map(|_| s.spawn(|| r.render(&c, &opts))).collect();
        threads
            .into_iter()
            .map(|t| t.join().unwrap().unwrap())
            .collect()
    });
    assert_eq!(r.pipeline_compilations(), 1);
    assert!(frames.iter().all(|f| f.rgba == frames[0].rgba));
}

#[test]
fn the_preview_scale_follows_the_device() {
    let Some(r) = renderer() else { return };
    let auto = LiveOptions::default();
    assert_eq!(auto.grace, Duration::ZERO);
    let scale = if r.adapter_description().software {
        8
    } else {
        4
    };
    assert_eq!(auto.preview_scale_on(r), scale);
    let chosen = LiveOptions {
        preview_scale: Some(0),
        ..LiveOptions::default()
    };
    assert_eq!(chosen.preview_scale_on(r), 1, "a scale of 0 is taken as 1");
}

#[test]
fn a_superseded_render_gives_up_without_its_frames() {
    let Some(r) = renderer() else { return };
    let c = compile("live", SCENE);
    let opts = RenderOptions::sized(16, 12);
    // Superseded from the start: nothing drawn.
    let mut frames = 0;
    let got = r
        .render_live_until(
            c.program(),
            &opts,
            &live(Duration::ZERO, 1),
            || true,
            |_, _| frames += 1,
        )
        .unwrap();
    assert!(got.is_none());
    assert_eq!(frames, 0);

    // Superseded by the preview itself (as an edit just after it would): no final frame.
    let fresh = Renderer::new().unwrap();
    fresh.warm_interpreter().unwrap();
    let previewed = std::cell::Cell::new(false);
    let mut drawn = Vec::new();
    let got = fresh
        .render_live_until(
            c.program(),
            &opts,
            &live(Duration::ZERO, 2),
            || previewed.get(),
            |kind, _| {
                previewed.set(true);
                drawn.push(kind);
            },
        )
        .unwrap();
    assert!(got.is_none());
    assert_eq!(drawn, [Drawn::Interpreted]);
    // The builder, left to finish on its own thread, leaves the device as it was.
    fresh.wait_for_background_work();
    r.wait_for_background_work();
    assert_eq!(
        fresh.render(&c, &opts).unwrap().rgba,
        r.render(&c, &opts).unwrap().rgba
    );
}

#[test]
fn a_grace_delays_the_preview_and_does_not_lose_it() {
    // A grace of 30 ms (longer than the live path's poll) against a 300-shape grid, whose
    // pipeline (WGSL emitted and validated twice, built, a pixel drawn) takes far longer
    // than that: the preview is started after the grace, and drawn. The camera is moved by a
    // hair from the clock, so that no earlier run has built this shader: from Mesa's disk
    // cache the grid's pipeline was ready after 35 ms, and with the cores shared by the other
    // tests the specialised frame came before the preview's turn.
    if renderer().is_none() {
        return;
    }
    let r = Renderer::new().unwrap();
    r.warm_interpreter().unwrap();
    let nudge = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos() % 1000);
    let scene = sdfc_tests::grid_scene(300).replace(
        "position: [0, 20, 60]",
        &format!("position: [0, {}, 60]", 20.0 + nudge as f64 * 1e-4),
    );
    assert!(
        scene.contains("position: [0, 20"),
        "the grid's camera has changed"
    );
    let c = compile("grid", &scene);
    let opts = RenderOptions::sized(16, 12);
    let (frames, report) =
        render_live(&r, c.program(), &opts, &live(Duration::from_millis(30), 4)).unwrap();
    let kinds: Vec<Drawn> = frames.iter().map(|f| f.0).collect();
    assert_eq!(
        kinds,
        [Drawn::Interpreted, Drawn::Specialised],
        "{report:?}"
    );
    assert!(
        report.interpreted.unwrap() >= Duration::from_millis(30),
        "{report:?}"
    );
}

/// The 300-shape grid from close by, where its plain preview runs out of lavapipe's loop
/// budget on many pixels (see the next test).
fn close_grid() -> String {
    sdfc_tests::grid_scene(300).replace(
        "camera { position: [0, 20, 60], target: [0, 0, 0], fov: 50deg }",
        "camera { position: [-1, 5, 7], target: [-2, 1.5, -2], fov: 50deg }",
    )
}

/// Where the preview's depths may differ from the final frame's: on grazing rays. At 24x18
/// the hit test accepts a point within half a pixel's footprint of a surface (about 0.4
/// units at the grid's depth), and where a ray passes that close to a shape without
/// touching it, where it stops depends on the path of its relaxed steps, which the two
/// programs' roundings (and a union read as data, whose field away from the shapes is its
/// boxes' bound) change: one such pixel of the 300-shape grid's 432 stopped at 15.59 in the
/// preview and 15.50 in the final frame.
const GRAZING: usize = 2;

/// Asserts that `actual`'s hits and depths (within 1e-4) are `expected`'s but on at most
/// [`GRAZING`] pixels; returns the number of hits.
fn same_depths_but_grazing(expected: &[f32], actual: &[f32]) -> usize {
    let differ: Vec<(usize, f32, f32)> = expected
        .iter()
        .zip(actual)
        .enumerate()
        .filter(|(_, (e, a))| {
            e.is_finite() != a.is_finite() || (e.is_finite() && (*e - *a).abs() > 1e-4 * *e)
        })
        .map(|(i, (e, a))| (i, *e, *a))
        .collect();
    assert!(
        differ.len() <= GRAZING,
        "(pixel, final, preview) differ: {differ:?}"
    );
    expected.iter().filter(|d| d.is_finite()).count()
}

/// `src`'s root union with its first sphere made a shell, which keeps the union code: a
/// union of instances has primitives only (`sdfc_ir::instances`), and is previewed as data.
fn as_code(src: &str) -> String {
    assert!(
        src.contains("sphere(0.3)"),
        "the grid's first sphere has changed"
    );
    src.replacen("sphere(0.3)", "sphere(0.3).onion(0.05)", 1)
}

/// `sdfc_wgsl::lower_live` lowers a large union twice: plainly for the specialised shader
/// and with culling for the preview, whose bytecode jumps over the parts a step does not
/// need. From close by, the 300-shape grid's culled preview (a shell among its children
/// keeps the union code) is drawn whole (no pixel cut short, where the plain preview lost 63
/// of 432 on lavapipe), with the final frame's hits and depths (the culled field is exact
/// near the surface). A small scene is lowered once.
#[test]
fn a_large_union_is_previewed_culled() {
    let Some(_) = renderer() else { return };
    let small = sdfc_wgsl::lower_live(SCENE, &Default::default()).unwrap();
    assert!(small.preview.is_none() && !small.stages.program.culls());
    let lowered = sdfc_wgsl::lower_live(&as_code(&close_grid()), &Default::default()).unwrap();
    let preview = lowered
        .preview
        .as_ref()
        .expect("a culled program for the preview");
    assert!(preview.culls() && !lowered.stages.program.culls());
    previewed_whole(&lowered, false);
}

/// A root union of 16 or more constant shapes is previewed as data: the interpreter walks
/// the instances in their hierarchy of boxes (`encode_as_data`) instead of running the
/// union's code, so that the preview costs what the shapes near each ray cost. From close
/// by, the 300-shape grid's preview is drawn whole, with the final frame's hits and depths
/// (but for grazing rays), and `lower_live` does not lower it culled.
#[test]
fn a_union_of_instances_is_previewed_as_data() {
    let Some(_) = renderer() else { return };
    let lowered = sdfc_wgsl::lower_live(&close_grid(), &Default::default()).unwrap();
    // Not lowered culled: the preview reads the data.
    assert!(lowered.preview.is_none());
    previewed_whole(&lowered, true);
}

/// Renders `lowered` live at 24x18 (its preview as `lower_live` chose, at full size) on a
/// renderer of its own, and checks the preview: drawn on a CPU device (the specialised
/// pipeline takes lavapipe seconds to build), from data or not as `as_data` says, no pixel
/// cut short, and the final frame's hits and depths but on grazing rays.
fn previewed_whole(lowered: &sdfc_wgsl::Lowered, as_data: bool) {
    let r = Renderer::new().unwrap();
    r.warm_interpreter().unwrap();
    let options = LiveOptions {
        preview: lowered.preview.clone(),
        ..live(Duration::ZERO, 1)
    };
    let opts = RenderOptions {
        aovs: true,
        ..RenderOptions::sized(24, 18)
    };
    let (frames, report) = render_live(&r, &lowered.stages.program, &opts, &options).unwrap();
    let summary = format!(
        "preview {:?}, {} pixels cut, skipped: {:?}",
        report.interpreted, report.preview_cut, report.preview_skipped
    );
    eprintln!("grid_300 close, preview as data {as_data}: {summary}");
    if r.adapter_description().software {
        assert!(report.interpreted.is_some(), "{summary}");
    }
    if report.interpreted.is_none() {
        return;
    }
    assert_eq!(report.preview_as_data, as_data, "{summary}");
    assert_eq!(report.preview_cut, 0, "{summary}");
    let (first, last) = (&frames[0].1, &frames[1].1);
    let (a, b) = (first.aovs.as_ref().unwrap(), last.aovs.as_ref().unwrap());
    let hits = same_depths_but_grazing(&b.depth, &a.depth);
    assert!(hits > 100, "{hits} hits");
}

/// A preview that lavapipe's loop budget (65 535 trips per invocation) cuts short on more
/// than a tenth of its pixels is skipped with the reason; one with fewer is drawn, and the
/// report counts them. The 300-shape grid needs about 1 100 instructions per distance: on
/// lavapipe, from close by (24x18) 63 of 432 pixels ran out, from its own camera (20x15) 2
/// of 300. A GPU has no such budget. (The grids' unions are kept code, [`as_code`]: as data
/// their previews run a few hundred instructions per distance.)
#[test]
fn a_preview_cut_short_by_the_loop_budget_is_counted_or_skipped() {
    let Some(shared) = renderer() else { return };
    let grid = as_code(&sdfc_tests::grid_scene(300));
    let close = as_code(&close_grid());
    for (name, src, (w, h)) in [("close", close, (24, 18)), ("far", grid, (20, 15))] {
        // A renderer of its own, so that the scene's pipeline is not in its cache.
        let r = Renderer::new().unwrap();
        r.warm_interpreter().unwrap();
        let c = compile(name, &src);
        let opts = RenderOptions::sized(w, h);
        let (frames, report) =
            render_live(&r, c.program(), &opts, &live(Duration::ZERO, 1)).unwrap();
        assert_eq!(frames.last().unwrap().0, Drawn::Specialised);
        if !shared.adapter_description().software {
            assert_eq!(report.preview_cut, 0, "{name}: {report:?}");
        }
        match (&report.interpreted, &report.preview_skipped) {
            (Some(_), _) => {
                assert!(
                    report.preview_cut * 10 <= (w * h) as usize,
                    "{name}: {report:?}"
                );
                assert_eq!(frames.len(), 2, "{name}");
            }
            (None, Some(why)) => assert!(
                why.contains("loop trips") && report.preview_cut == 0,
                "{name}: {why}"
            ),
            // The specialised pipeline was ready first.
            (None, None) => {}
        }
        eprintln!(
            "grid_300 {name}: preview {:?}, {} pixels cut, skipped: {:?}",
            report.interpreted, report.preview_cut, report.preview_skipped
        );
    }
}

/// With `instances` in the emit options, the final frame is the union's data form: the
/// picture `render` draws from the same scene compiled with `instances`, and its WGSL reads
/// the data.
#[test]
fn the_final_frame_can_read_the_union_as_data() {
    let Some(r) = renderer() else { return };
    let source = sdfc_tests::grid_scene(40);
    let opts = RenderOptions::sized(40, 30);
    let emit = sdfc_wgsl::Options {
        instances: sdfc_wgsl::Instances::Always,
        ..sdfc_wgsl::Options::default()
    };
    let data = sdfc_wgsl::compile(&source, &emit).unwrap();
    assert!(!data.data.is_empty());
    let live = LiveOptions {
        emit,
        ..live(Duration::MAX, 4)
    };
    let (frames, report) = render_live(r, data.program(), &opts, &live).unwrap();
    assert_eq!(frames.len(), 1);
    assert_eq!(frames[0].0, Drawn::Specialised);
    assert_eq!(report.wgsl, data.wgsl);
    assert_eq!(frames[0].1.rgba, r.render(&data, &opts).unwrap().rgba);
}
