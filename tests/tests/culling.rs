//! Culled unions (`crates/sdfc-ir/src/to_ssa/cull.rs`): the bounding-box early-outs change
//! how much is evaluated, and the field only far from every shape. Near the surface (plain
//! distance below [`EXACT_WITHIN`]), with exact shapes, the distance and the material of
//! the culled program equal those of the plain one at thousands of points (to f64 rounding,
//! 1e-12). With bound-only shapes (ellipsoid, twist, smooth blends, mirrors), whose values
//! lie below their true distance, a skipped child may leave the union's value higher than the
//! plain one, but never above the true distance (the skipped child's box is farther); the
//! test asserts `plain <= culled` with the same sign there. Farther away a part may answer
//! with its box's distance: positive, and for exact shapes no more than the plain value.

use sdfc_ir::eval::{eval_func, eval_func_work, Inputs};
use sdfc_reference::camera::Camera;
use sdfc_tests::grid_scene;
use sdfc_wgsl::{compile, emit_validated, lower_live, Compiled, Options};

/// Where the plain distance is below this, the culled one must equal it: a culled part is
/// exact within its box's half-diagonal of its box, and no part of these scenes is smaller
/// than a unit box (half-diagonal 0.87; the smallest shape, a 0.3 sphere, alone is 0.52).
const EXACT_WITHIN: f64 = 0.5;

fn both(src: &str) -> (Compiled, Compiled) {
    let culled = compile(
        src,
        &Options {
            cull: true,
            ..Options::default()
        },
    )
    .expect("culled compiles");
    let plain = compile(src, &Options::default()).expect("plain compiles");
    (culled, plain)
}

fn points(seed: u64, n: usize, lo: [f64; 3], hi: [f64; 3]) -> Vec<[f64; 3]> {
    let mut rng = sdfc_tests::SplitMix(seed);
    (0..n).map(|_| rng.point_in(lo, hi)).collect()
}

fn same_field(name: &str, src: &str, lo: [f64; 3], hi: [f64; 3]) {
    compare(name, src, lo, hi, true)
}

fn compare(name: &str, src: &str, lo: [f64; 3], hi: [f64; 3], exact: bool) {
    let (culled, plain) = both(src);
    let (c, p) = (culled.program(), plain.program());
    assert!(c.culls(), "{name}: no guarded call in the culled program");
    assert!(!p.culls(), "{name}: guarded calls without culling");
    let mut near = 0;
    for pt in points(7, 2000, lo, hi) {
        let at = Inputs::at(pt);
        let dc = eval_func(&c.distance, &c.groups, &at)[0].scalar().unwrap();
        let dp = eval_func(&p.distance, &p.groups, &at)[0].scalar().unwrap();
        let tol = 1e-12 * dp.abs().max(1.0);
        if dp >= EXACT_WITHIN {
            // Far from every shape a part may answer with its box's distance: a lower bound,
            // never a false hit.
            assert!(
                dc > 0.0 && (!exact || dc <= dp + tol),
                "{name}: distance at {pt:?}: culled {dc}, plain {dp} (far field)"
            );
            continue;
        }
        near += 1;
        if !exact {
            assert!(
                dc >= dp - tol && (dc > 0.0) == (dp > 0.0),
                "{name}: distance at {pt:?}: culled {dc}, plain {dp}"
            );
            continue;
        }
        assert!(
            (dc - dp).abs() <= tol,
            "{name}: distance at {pt:?}: culled {dc}, plain {dp}"
        );
        let mc = eval_func(&c.material, &c.groups, &at);
        let mp = eval_func(&p.material, &p.groups, &at);
        assert_eq!(mc, mp, "{name}: material at {pt:?}");
    }
    assert!(near >= 100, "{name}: only {near} points near the surface");
}

#[test]
fn grid_of_300_shapes_culled_equals_plain() {
    same_field(
        "grid_scene(300)",
        &grid_scene(300),
        [-12.0, -2.0, -14.0],
        [12.0, 14.0, 4.0],
    );
}

/// A ground plane and infinite repetition (unbounded, never skipped) among bounded shapes.
fn mixed_scene(kinds: &[&str]) -> String {
    let mut s = String::from(
        "material red { color: [1, 0, 0] }\nscene = union(\n  plane([0, 1, 0], -1),\n",
    );
    for i in 0..40 {
        let (x, z) = ((i % 8) as f64 * 1.3 - 5.0, (i / 8) as f64 * -1.4);
        let mat = if i % 3 == 0 { ".material(red)" } else { "" };
        s += &format!(
            "  {}{mat}.translate([{x}, {}, {z}]),\n",
            kinds[i % kinds.len()],
            (i % 4) as f64 * 0.3
        );
    }
    s + "  sphere(0.2).repeat([0, 0, 3]).translate([0, 3, 0])\n);\n"
}

#[test]
fn exact_shapes_with_a_ground_plane_culled_equals_plain() {
    let kinds = [
        "sphere(0.4)",
        "box([0.6, 0.3, 0.5]).rotate_y(20deg)",
        "torus(0.4, 0.1).rotate_x(90deg)",
        "capsule([0, 0, 0], [0.3, 0.5, 0], 0.1)",
        "cone(0.3, 0.6)",
        "octahedron(0.7).scale(0.8)",
        "box_frame([0.6, 0.6, 0.6], 0.05)",
        "hex_prism(0.3, 0.5).round(0.05)",
    ];
    same_field(
        "exact kinds",
        &mixed_scene(&kinds),
        [-7.0, -2.0, -8.0],
        [7.0, 4.0, 2.0],
    );
}

#[test]
fn bound_shapes_culled_stays_between_plain_and_true() {
    let kinds = [
        "ellipsoid([0.4, 0.2, 0.3])",
        "twist(box([0.2, 0.6, 0.2]), 1)",
        "union(sphere(0.2), box(0.3).translate([0.3, 0, 0]), smooth: 0.1)",
        "box_frame([0.6, 0.6, 0.6], 0.05).translate([0.5, 0, 0]).mirror_x()",
        "stretch(sphere(0.3), [1, 2, 1])",
        "menger(iterations: 2)",
    ];
    compare(
        "bound kinds",
        &mixed_scene(&kinds),
        [-7.0, -2.0, -8.0],
        [7.0, 4.0, 2.0],
        false,
    );
}

/// What culling saves where a shader's branches are real (a GPU's uniform branches): the
/// nodes evaluated per distance call, culled against plain, at every step of 32x24 rays
/// sphere-traced from the scene's camera through the 300-shape grid. Near a shape only its
/// part of the hierarchy runs, so the culled program must do at most a fifth of the plain
/// one's work (the 5x), with the same values (checked above).
#[test]
fn grid_of_300_shapes_culled_does_a_fifth_of_the_work() {
    let (culled, plain) = both(&grid_scene(300));
    let (c, p) = (culled.program(), plain.program());
    let camera = Camera::of(&p.scene.camera);
    let eye = camera.position;
    let (w, h) = (32, 24);
    let (mut wc, mut wp, mut steps) = (0usize, 0usize, 0usize);
    for j in 0..h {
        for i in 0..w {
            let rd = camera.ray(i as f64 + 0.5, j as f64 + 0.5, w as f64, h as f64);
            let mut t = 0.0;
            for _ in 0..256 {
                let at = Inputs::at([0, 1, 2].map(|k| eye[k] + t * rd[k]));
                let (dc, n) = eval_func_work(&c.distance, &c.groups, &at);
                wc += n;
                wp += eval_func_work(&p.distance, &p.groups, &at).1;
                steps += 1;
                let d = dc[0].scalar().unwrap();
                if d < 1e-4 * t || t > 150.0 {
                    break;
                }
                t += d;
            }
        }
    }
    let ratio = wp as f64 / wc as f64;
    eprintln!(
        "grid_scene(300), {steps} steps: plain {} nodes a step, culled {}: {ratio:.2}x less work",
        wp / steps,
        wc / steps
    );
    assert!(ratio >= 5.0, "culling saves only {ratio:.2}x of the work");
}

/// The live path's lowering (`lower_live`): a large union comes with a culled program for
/// the interpreted preview, and its own program is the plain one, whose WGSL is byte for
/// byte what `compile` gives; with `cull` asked for, a union too small to cull, or a union
/// of instances (previewed from data), there is one program.
#[test]
fn the_live_path_previews_a_large_union_culled() {
    // A shell among the shapes keeps the union code (a union of instances has primitives
    // only).
    let grid = grid_scene(40).replacen("sphere(0.3)", "sphere(0.3).onion(0.05)", 1);
    let live = lower_live(&grid, &Options::default()).expect("lowers");
    let preview = live.preview.as_deref().expect("a culled preview program");
    assert!(preview.culls() && !live.stages.program.culls());
    let wgsl = emit_validated(&live.stages.program, &Options::default()).expect("emits");
    assert_eq!(wgsl, compile(&grid, &Options::default()).unwrap().wgsl);
    let instances = lower_live(&grid_scene(40), &Options::default()).expect("lowers");
    assert!(instances.preview.is_none() && !instances.stages.program.culls());
    let wgsl = emit_validated(&instances.stages.program, &Options::default()).expect("emits");
    assert_eq!(
        wgsl,
        compile(&grid_scene(40), &Options::default()).unwrap().wgsl
    );
    let culling = Options {
        cull: true,
        ..Options::default()
    };
    let asked = lower_live(&grid, &culling).expect("lowers");
    assert!(asked.preview.is_none() && asked.stages.program.culls());
    let small = lower_live(&grid_scene(8), &Options::default()).expect("lowers");
    assert!(small.preview.is_none() && !small.stages.program.culls());
    // A mistake is reported as `lower` reports it.
    let broken = "scene = spher(1);";
    let (Err(sdfc_wgsl::Failure::Diagnostics(d)), Err(sdfc_wgsl::Failure::Diagnostics(e))) = (
        lower_live(broken, &Options::default()),
        sdfc_wgsl::lower(broken, &Options::default()),
    ) else {
        panic!("a misspelt primitive lowers");
    };
    assert_eq!(format!("{d:?}"), format!("{e:?}"));
}
