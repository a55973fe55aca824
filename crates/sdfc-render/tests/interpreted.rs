//! The interpreted marcher against the specialised shader, scene by scene at 64x48: both
//! render the same picture up to float rounding. Tolerances: on pixels both call a hit the
//! depth AOV agrees within 1e-4 relative and the normal within 5e-3 (finite differences
//! divide the distance's rounding by a step of about 1e-4 t, so a last-bit difference in a
//! distance moves a central-difference normal by about 1e-3); at most [`SILHOUETTE_PIXELS`]
//! pixels flip, and only on the f64 reference's edges (a ray grazing a shape's edge can hit
//! it in one marcher and pass it in the other: to the background, on a silhouette, or to a
//! surface behind, on a silhouette or a depth edge; NVIDIA's H200 did the latter on one pixel
//! of the 300-shape grid); the colour's mean
//! absolute difference over all channels is below 1 (0..255). The interpreter evaluates the
//! same operations in a different order and through `vec4` registers, and the device may
//! contract multiply-adds differently in each, so bit equality is not expected.

mod common;

use common::{compile, compile_file, renderer};
use sdfc_render::{Frame, RenderError, RenderOptions};
use sdfc_wgsl::interp::encode_instances::encode_as_data;

const W: u32 = 64;
const H: u32 = 48;
const DEPTH_TOLERANCE: f32 = 1e-4;
const NORMAL_TOLERANCE: f32 = 5e-3;
const SILHOUETTE_PIXELS: usize = 4;
/// Hits whose depths differ by more than this (relative) are on different surfaces.
const OTHER_SURFACE: f32 = 1e-2;
const MEAN_COLOUR_TOLERANCE: f64 = 1.0;

/// Smooth union of three materials, a param-driven rotation (a symbolic matrix), two kinds
/// of light, soft shadows, ambient occlusion, two reflection bounces, fog and antialiasing;
/// `{AA}` is replaced by the antialias setting (see `all_features_at_once`).
const FEATURES: &str = "\
material gold { color: [0.9, 0.7, 0.2], specular: 0.8, shininess: 64, reflectivity: 0.3 }
material floor { color: [0.6, 0.6, 0.6], reflectivity: 0.2 }
param lift = 0.2;
camera { position: [0, 2, 6], target: [0, 0.5, 0], fov: 45deg }
light point { position: [3, 5, 2], color: [1, 0.9, 0.8], intensity: 1.1 }
light directional { direction: [1, -1, -0.5], color: [0.3, 0.4, 0.6], intensity: 0.5 }
render { shadows: soft(8), ao: ao(samples: 4, step: 0.1), reflections: 2, {AA}
         fog: fog(0.05, [0.6, 0.7, 0.8]), background: [0.6, 0.7, 0.8] }
scene = union(sphere(0.8).material(gold),
              torus(0.9, 0.2).rotate_x(lift * 2).translate([0, lift, 0]),
              box([1, 0.4, 1]).rotate_y(20deg).translate([1.2, 0, 0]).color([0.2, 0.5, 0.9]),
              smooth: 0.3).translate([0, 0.8, 0])
      | plane([0, 1, 0], 0).material(floor);
";

/// Every other helper and operation: capsule, cylinder, round box, limited repetition
/// (floored modulo), noise displacement, intersection, subtraction, a rotation by time.
const SHAPES: &str = "\
camera { position: [0, 2, 7], target: [0, 0, 0], fov: 50deg }
render { shadows: hard, normals: central, epsilon: 0.0005 }
scene = capsule([-2, 0, 0], [-1, 1, 0], 0.3)
      | cylinder(0.4, 1).translate([0, 0, 1])
      | round_box([0.8, 0.5, 0.6], 0.1).rotate([1, 1, 0], time).translate([0, -1, 0])
      | sphere(0.2).repeat([0.6, 0, 0.6], count: [3, 1, 3]).translate([0, 1.5, -1])
      | sphere(0.7).displace(|p| 0.05 * noise(p * 4), lipschitz: 1.5).translate([-1, -1, 1])
      | (box(1) & sphere(0.65)).translate([2, -1, 0])
      | (box(0.8) - sphere(0.5)).rotate_z(time).translate([-2.5, 1, -1]);
";

fn options(aovs: bool) -> RenderOptions {
    RenderOptions {
        time: 0.7,
        aovs,
        ..RenderOptions::sized(W, H)
    }
}

/// Renders both ways, with AOVs (the primary rays); the colour of such a frame is the one a
/// frame without AOVs has (the AOVs are a separate ray).
fn compare(name: &str, compiled: &sdfc_wgsl::Compiled) {
    compare_with(name, compiled, 0);
}

/// As [`compare`], letting `path_sensitive` hit pixels differ beyond the depth and normal
/// tolerances, anywhere: with over-relaxed marching a last-bit difference in one distance can
/// flip the overshoot test, and the ray then settles on another point of the surface band or
/// on another surface.
fn compare_with(name: &str, compiled: &sdfc_wgsl::Compiled, path_sensitive: usize) {
    let Some(r) = renderer() else { return };
    let program = compiled.program();
    let spec = r.render(compiled, &options(true)).expect("specialised");
    let interp = r
        .render_interpreted(program, &options(true))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let (a, b) = (spec.aovs.as_ref().unwrap(), interp.aovs.as_ref().unwrap());
    // Hit in one and miss in the other; hit on surfaces apart (depths beyond OTHER_SURFACE).
    let (mut hit_miss, mut apart) = (Vec::new(), Vec::new());
    let mut hits = 0;
    let mut outliers = 0;
    let mut worst_depth = 0f32;
    let mut worst_normal = 0f32;
    for i in 0..a.depth.len() {
        let (da, db) = (a.depth[i], b.depth[i]);
        if da.is_finite() != db.is_finite() {
            hit_miss.push(i);
            continue;
        }
        if !da.is_finite() {
            continue;
        }
        hits += 1;
        let depth = (da - db).abs() / da.abs().max(1e-6);
        let normal = (0..3)
            .map(|c| (a.normal[i][c] - b.normal[i][c]).abs())
            .fold(0f32, f32::max);
        if depth > OTHER_SURFACE {
            apart.push(i);
        } else if depth > DEPTH_TOLERANCE || normal > NORMAL_TOLERANCE {
            outliers += 1;
        } else {
            worst_depth = worst_depth.max(depth);
            worst_normal = worst_normal.max(normal);
            continue;
        }
        eprintln!(
            "{name}: pixel {i}: depth {da} / {db}, normal {:?} / {:?}",
            a.normal[i], b.normal[i]
        );
    }
    // Where the scene is path-sensitive, hits on surfaces apart are among its allowance.
    // Elsewhere they are flips, like hit/miss ones: a ray grazing an edge hits it in one
    // marcher and passes it in the other, to the background or to a surface behind. Every
    // flip must be on an edge of the reference: a hit/miss flip on a silhouette, a hit on
    // surfaces apart on a silhouette or a depth edge.
    if path_sensitive > 0 {
        outliers += apart.len();
        apart.clear();
    }
    let flips = hit_miss.len() + apart.len();
    if flips > 0 {
        let reference = reference(program);
        for i in hit_miss {
            assert!(
                silhouette(&reference, i),
                "{name}: pixel {:?} flips between hit and miss (depths {} / {}) off the \
                 reference's silhouettes",
                (i as u32 % W, i as u32 / W),
                a.depth[i],
                b.depth[i]
            );
        }
        for i in apart {
            assert!(
                silhouette(&reference, i) || depth_edge(&reference, i),
                "{name}: pixel {:?} hits surfaces apart (depths {} / {}) off the reference's \
                 silhouettes and depth edges",
                (i as u32 % W, i as u32 / W),
                a.depth[i],
                b.depth[i]
            );
        }
    }
    let colour = mean_colour_difference(&spec, &interp);
    eprintln!(
        "{name}: {hits} hit pixels, {flips} flips, {outliers} path-sensitive pixels, \
         worst relative depth difference of the rest \
         {worst_depth:e}, worst normal difference {worst_normal:e}, mean colour difference \
         {colour:.4}/255"
    );
    assert!(
        hits > 0,
        "{name}: nothing hit; the comparison would be empty"
    );
    assert!(
        flips <= SILHOUETTE_PIXELS,
        "{name}: {flips} pixels flip between hit and miss or between surfaces"
    );
    assert!(
        outliers <= path_sensitive,
        "{name}: {outliers} hit pixels beyond the depth or normal tolerance"
    );
    assert!(
        worst_depth <= DEPTH_TOLERANCE,
        "{name}: depth differs by {worst_depth:e}"
    );
    assert!(
        worst_normal <= NORMAL_TOLERANCE,
        "{name}: normal differs by {worst_normal:e}"
    );
    assert!(
        colour < MEAN_COLOUR_TOLERANCE,
        "{name}: mean colour difference {colour}/255"
    );
}

/// The f64 reference of the frames compared (the centre ray of each pixel, as the AOVs).
fn reference(program: &sdfc_wgsl::Program) -> sdfc_reference::Image {
    sdfc_reference::render(
        program,
        &sdfc_reference::Options {
            time: options(false).time as f64,
            ..sdfc_reference::Options::sized(W, H)
        },
    )
}

/// Whether a pixel (by index) lies on a silhouette of the reference: its 3x3 neighbourhood
/// holds both hits and misses.
fn silhouette(reference: &sdfc_reference::Image, i: usize) -> bool {
    sdfc_reference::metrics::is_silhouette(reference, i as u32 % W, i as u32 / W)
}

/// Whether a pixel (by index) lies on a depth edge of the reference, where a shape stands in
/// front of another: the hits of its 3x3 neighbourhood are more than [`OTHER_SURFACE`] apart.
fn depth_edge(reference: &sdfc_reference::Image, i: usize) -> bool {
    sdfc_reference::metrics::is_depth_edge(
        reference,
        i as u32 % W,
        i as u32 / W,
        OTHER_SURFACE as f64,
    )
}

fn mean_colour_difference(a: &Frame, b: &Frame) -> f64 {
    let sum: u64 = a
        .rgba
        .iter()
        .zip(&b.rgba)
        .map(|(x, y)| x.abs_diff(*y) as u64)
        .sum();
    sum as f64 / a.rgba.len() as f64
}

/// A scene 1e5 from the origin, seen from beside it: the interpreter marches the
/// camera-relative functions as the specialised shader does (in world coordinates its
/// normals were 81 degrees off and a hit was missed). A point light moves with the camera.
#[test]
fn far_from_the_origin() {
    let source = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/stress/offset_1e5.sdf"),
    )
    .unwrap()
        + "light point { position: [100003, 100004, 100005], intensity: 1 }\n";
    let c = compile("offset_1e5 with a point light", &source);
    assert!(c.program().relative.is_some());
    compare("offset_1e5 with a point light", &c);
}

#[test]
fn a_sphere() {
    compare("sphere", &compile("sphere", "scene = sphere(1);\n"));
}

#[test]
fn the_spec_section_10_scene() {
    compare(
        "spec_section10",
        &compile_file("examples/spec_section10.sdf"),
    );
}

// These four scenes once differed on lavapipe in runs of up to 8 pixels along rows (one SIMD
// register of lanes). The cause (2026-12-03): gallivm ends every loop of an invocation once
// 65 535 loop trips have been taken in all, and it counts a trip for each loop reached, even
// by lanes that all skip it. Each interpreted instruction reached the loops of the four
// fractal cases as well as its own trip (six in all), so rays stopped part way. Fractals now
// run one iteration per trip, constants are operands (half the instructions of a union), and
// where a pixel's code is still cut short the renderer draws again with two instructions per
// trip, or reports it (`the_trip_budget_is_reported_where_even_two_per_trip_run_out`).
#[test]
fn smooth_union_materials_shadows_ao_reflections_fog() {
    compare(
        "features",
        &compile("features", &FEATURES.replace("{AA}", "")),
    );
}

#[test]
fn antialiasing_with_shadows_and_ao() {
    let src = FEATURES
        .replace("{AA}", "antialias: 2,")
        .replace("reflections: 2,", "");
    compare("features_aa", &compile("features_aa", &src));
}

/// Antialiasing, reflections and shadows together: the AOV ray, marched after the colour
/// loop, was the first to run out of lavapipe's loop budget (a miss after one step on whole
/// 8-pixel rows). On lavapipe this frame is drawn with two instructions per trip.
#[test]
fn all_features_at_once() {
    compare(
        "features_all",
        &compile("features_all", &FEATURES.replace("{AA}", "antialias: 2,")),
    );
}

#[test]
fn every_helper_and_operation() {
    compare("shapes", &compile("shapes", SHAPES));
}

#[test]
fn a_union_split_into_groups() {
    // The benchmark's 300-shape grid fits the register file (56 of 64 registers, since
    // the encoder schedules a union's material child by child).
    let big = compile("grid_300", &sdfc_tests::grid_scene(300));
    assert!(sdfc_wgsl::interp::encode::encode(big.program()).is_ok());
    let src = sdfc_tests::grid_scene(40);
    let c = compile("grid_40", &src);
    assert!(
        !c.program().groups.is_empty(),
        "the union was not split into groups"
    );
    compare("grid_40", &c);
}

/// The benchmark's 300-shape grid: about 1 100 instructions per distance, so that on
/// lavapipe a hit pixel's normals ran out of the loop budget (30 of 3 072 pixels flipped
/// between hit and miss before constants were operands, 6 normals were wrong after); drawn
/// there with two instructions per trip.
#[test]
fn the_300_shape_grid() {
    compare(
        "grid_300",
        &compile("grid_300", &sdfc_tests::grid_scene(300)),
    );
}

/// A culled union (`--cull`): the interpreter skips a part's code where the specialised
/// shader skips its call, so both draw the culled field. Twenty shapes (five parts of
/// four) seen from close by.
#[test]
fn a_culled_union_of_20_shapes() {
    // Closer than the grid's own camera, so that the shapes fill the picture.
    let src = sdfc_tests::grid_scene(20).replace(
        "camera { position: [0, 20, 60], target: [0, 0, 0], fov: 50deg }",
        "camera { position: [-1, 5, 7], target: [-2, 1.5, -2], fov: 50deg }",
    );
    assert!(src.contains("[-1, 5, 7]"), "the grid's camera line changed");
    let opts = sdfc_wgsl::Options {
        cull: true,
        ..Default::default()
    };
    let c = sdfc_wgsl::compile(&src, &opts).unwrap_or_else(|_| panic!("the grid compiles"));
    let code = sdfc_wgsl::interp::encode::encode(c.program()).unwrap();
    let skip = sdfc_wgsl::interp::opcodes::Opcode::SkipUnlessLess.code();
    assert!(code.code.iter().any(|i| i[0] == skip), "nothing culled");
    compare("culled grid_20", &c);
}

#[test]
fn the_render_test_scenes() {
    let dir = common::root().join("crates/sdfc-render/tests/scenes");
    let paths = sdfc_tests::sdf_files(&dir);
    assert!(paths.len() >= 10, "the render test scenes are missing");
    for p in paths {
        let rel = p
            .strip_prefix(common::root())
            .unwrap()
            .to_string_lossy()
            .to_string();
        // Over-relaxation through a displaced surface (see `compare_with`): 10 far pixels
        // (t 16 to 84) differ on lavapipe; at most 15 (0.5% of the image) may.
        // The interpreter has no gradient code: `normals: analytic` falls back to the
        // tetrahedron there (docs/language.md), which differs from the gradient along the
        // scene's creases by more than the normal tolerance: 9 of 414 hit pixels on lavapipe,
        // at most 15 may.
        let allowed = if rel.ends_with("relaxation.sdf") || rel.ends_with("normals_analytic.sdf") {
            15
        } else {
            0
        };
        compare_with(&rel, &compile_file(&rel), allowed);
    }
}

#[test]
fn one_pipeline_for_every_interpreted_scene() {
    // A renderer of its own, so other tests' pipelines do not count.
    let Some(_) = renderer() else { return };
    let r = sdfc_render::Renderer::new().expect("a second renderer");
    let sphere = compile("sphere", "scene = sphere(1);\n");
    let features = compile("features", &FEATURES.replace("{AA}", ""));
    let opts = RenderOptions::sized(16, 12);
    r.render_interpreted(sphere.program(), &opts).unwrap();
    assert_eq!(r.pipeline_compilations(), 1);
    r.render_interpreted(features.program(), &opts).unwrap();
    r.render_interpreted(sphere.program(), &RenderOptions::sized(8, 8))
        .unwrap();
    assert_eq!(r.pipeline_compilations(), 1);
    // The specialised shader of a scene is a pipeline of its own.
    r.render(&sphere, &opts).unwrap();
    assert_eq!(r.pipeline_compilations(), 2);
    // A union read as data runs on the variant that walks it: one more, for every such
    // union.
    for n in [20, 40] {
        let grid = compile("grid", &sdfc_tests::grid_scene(n));
        let code = encode_as_data(grid.program()).unwrap().unwrap();
        r.render_bytecode(grid.program(), &code, &opts).unwrap();
        assert_eq!(r.pipeline_compilations(), 3);
    }
}

#[test]
fn params_and_time_reach_the_interpreter() {
    let Some(r) = renderer() else { return };
    let c = compile_file("crates/sdfc-render/tests/scenes/params_time.sdf");
    let opts = RenderOptions {
        time: 1.3,
        params: vec![
            ("radius".into(), vec![0.9]),
            ("offset".into(), vec![0.1, 0.2, -0.1]),
            ("tint".into(), vec![0.5, 0.1, 0.1]),
        ],
        aovs: true,
        ..RenderOptions::sized(W, H)
    };
    let spec = r.render(&c, &opts).unwrap();
    let interp = r.render_interpreted(c.program(), &opts).unwrap();
    let defaults = r
        .render_interpreted(
            c.program(),
            &RenderOptions {
                params: vec![],
                ..opts.clone()
            },
        )
        .unwrap();
    assert!(mean_colour_difference(&spec, &interp) < MEAN_COLOUR_TOLERANCE);
    assert!(
        mean_colour_difference(&interp, &defaults) > 1.0,
        "the param overrides changed nothing"
    );
    // Errors come as in the specialised path.
    let bad = RenderOptions {
        params: vec![("nope".into(), vec![1.0])],
        ..RenderOptions::sized(W, H)
    };
    assert!(matches!(
        r.render_interpreted(c.program(), &bad),
        Err(RenderError::Param(_))
    ));
}

/// A union too large for even two instructions per trip on lavapipe is refused with the
/// reason, not drawn with holes: 1 000 shapes (about 3 700 instructions per distance) seen
/// from close by. A GPU has no such budget and draws it.
#[test]
fn the_trip_budget_is_reported_where_even_two_per_trip_run_out() {
    let Some(r) = renderer() else { return };
    let c = compile("grid_1000", &close_grid_1000());
    match r.render_interpreted(c.program(), &RenderOptions::sized(8, 6)) {
        Ok(frame) => assert!(
            !r.adapter_description().software,
            "lavapipe drew the 1 000-shape union within its loop budget: {} bytes",
            frame.rgba.len()
        ),
        Err(e) => {
            let text = e.to_string();
            assert!(
                matches!(e, RenderError::Interpreter(_)) && text.contains("loop trips"),
                "{text}"
            );
            assert!(r.adapter_description().software, "{text}");
            eprintln!("grid_1000: {text}");
        }
    }
}

/// The 1 000-shape grid seen from close by: too large for lavapipe's loop budget.
fn close_grid_1000() -> String {
    let src = sdfc_tests::grid_scene(1000);
    let close = src.replace(
        "camera { position: [0, 20, 60], target: [0, 0, 0], fov: 50deg }",
        "camera { position: [-1, 5, 7], target: [-2, 1.5, -2], fov: 50deg }",
    );
    assert_ne!(src, close, "the generated grid's camera has changed");
    close
}

/// On a CPU device a frame is probed first, so that a scene the loop budget cannot draw is
/// refused by a probe of 16 pixels across instead of after the frame was drawn twice (72 s
/// for the 5 000-shape union at 160x120 on lavapipe, 6 s with the probe). The reason names
/// what would draw it: `--instances` for a union of instances (which the interpreter then
/// walks as data, and draws), else `--cull`, which this program does not use.
#[test]
fn a_probe_refuses_what_the_loop_budget_cannot_draw() {
    let Some(r) = renderer() else { return };
    let opts = RenderOptions::sized(64, 48);
    // A shell among the shapes keeps the union code.
    let shell = close_grid_1000().replacen("sphere(0.3)", "sphere(0.3).onion(0.05)", 1);
    for (name, src, named) in [
        ("grid_1000", close_grid_1000(), "`--instances`"),
        ("grid_1000 with a shell", shell, "`--cull`"),
    ] {
        let c = compile(name, &src);
        match r.render_interpreted(c.program(), &opts) {
            Ok(_) => assert!(
                !r.adapter_description().software,
                "{name}: lavapipe drew the 1 000-shape union within its loop budget"
            ),
            Err(e) => {
                let text = e.to_string();
                assert!(
                    text.contains("of 192 pixels of a 16x12 probe") && text.contains(named),
                    "{name}: {text}"
                );
            }
        }
    }
    // As the reason says: read as data, the union is drawn.
    let c = compile("grid_1000", &close_grid_1000());
    let code = encode_as_data(c.program()).unwrap().unwrap();
    let frame = r
        .render_bytecode(c.program(), &code, &opts)
        .expect("drawn as data");
    let drawn = frame
        .rgba
        .chunks(4)
        .filter(|p| p[..3] != frame.rgba[..3])
        .count();
    assert!(drawn > 0, "an image of one colour");
}
