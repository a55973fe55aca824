//! The meaning of shapes, transforms and operators, checked through the f64 evaluator against
//! closed-form distances (spec sections 4-5: right-handed rotations, full sizes, materials).

use sdfc_ir::eval::{eval_graph, Inputs};
use sdfc_ir::value::Value;
use sdfc_ir::Program;

fn program(src: &str) -> Program {
    let file = sdfc_syntax::parse(src).expect("parses");
    let (stages, diags) = sdfc_ir::compile(&file, src.len());
    match stages {
        Some(s) => s.program,
        None => panic!("does not compile: {diags:?}"),
    }
}

fn dist(src: &str, p: [f64; 3]) -> f64 {
    let prog = program(src);
    let v = eval_graph(&prog.distance.graph, &prog.distance.results, &Inputs::at(p));
    v[0].scalar().unwrap()
}

fn albedo(src: &str, p: [f64; 3]) -> [f64; 4] {
    let prog = program(src);
    match eval_graph(
        &prog.material.graph,
        &prog.material.results,
        &Inputs::<f64>::at(p),
    )[0]
    {
        Value::V4(a) => a,
        v => panic!("albedo is {v:?}"),
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * (1.0 + b.abs())
}

macro_rules! check {
    ($scene:expr, $p:expr, $want:expr) => {{
        let got = dist(concat!("scene = ", $scene, ";"), $p);
        assert!(
            close(got, $want),
            "{} at {:?}: got {got}, want {}",
            $scene,
            $p,
            $want
        );
    }};
}

#[test]
fn primitives_use_full_sizes() {
    check!("sphere(1)", [3.0, 0.0, 0.0], 2.0);
    check!("box([2, 4, 6])", [3.0, 0.0, 0.0], 2.0);
    check!("box([2, 4, 6])", [0.0, 0.0, 0.0], -1.0);
    check!("box(2)", [2.0, 2.0, 1.0], 2f64.sqrt());
    check!("round_box([2, 2, 2], 0.25)", [3.0, 0.0, 0.0], 2.0);
    // Inner half extent 1 - 0.25; the corner distance is sqrt(2) * 1.25, less the rounding.
    check!(
        "round_box([2, 2, 2], 0.25)",
        [2.0, 2.0, 0.0],
        1.25 * 2f64.sqrt() - 0.25
    );
    check!("plane([0, 2, 0], 1)", [5.0, 3.0, 0.0], 2.0);
    check!("torus(2, 0.5)", [2.0, 0.0, 0.0], -0.5);
    check!("torus(2, 0.5)", [0.0, 1.0, 0.0], 5f64.sqrt() - 0.5);
    check!("cylinder(1, 4)", [0.0, 3.0, 0.0], 1.0);
    check!("cylinder(1, 4)", [3.0, 0.0, 0.0], 2.0);
    check!("capsule([0, 0, 0], [0, 2, 0], 0.5)", [0.0, 4.0, 0.0], 1.5);
    check!("capsule([0, 0, 0], [0, 2, 0], 0.5)", [1.0, 1.0, 0.0], 0.5);
    check!("capsule([1, 1, 1], [1, 1, 1], 0.5)", [1.0, 3.0, 1.0], 1.5);
    check!("sdf(|p| length(p) - 2, lipschitz: 2)", [4.0, 0.0, 0.0], 1.0);
}

#[test]
fn transforms_follow_the_spec() {
    check!("sphere(1).translate([2, 0, 0])", [2.0, 0.0, 0.0], -1.0);
    check!("sphere(1).scale(2)", [3.0, 0.0, 0.0], 1.0);
    // A positive angle about +y turns +z toward +x: a bar along z ends up along x.
    check!("box([0.2, 0.2, 2]).rotate_y(90deg)", [0.9, 0.0, 0.0], -0.1);
    check!(
        "box([0.2, 0.2, 2]).rotate([0, 5, 0], 90deg)",
        [0.9, 0.0, 0.0],
        -0.1
    );
    // About +x, +y turns toward +z; about +z, +x turns toward +y.
    check!(
        "sphere(0.5).translate([0, 1, 0]).rotate_x(90deg)",
        [0.0, 0.0, 1.0],
        -0.5
    );
    check!(
        "sphere(0.5).translate([1, 0, 0]).rotate_z(90deg)",
        [0.0, 1.0, 0.0],
        -0.5
    );
    // Left to right: rotate, then move.
    check!(
        "sphere(0.5).translate([1, 0, 0]).rotate_y(90deg).translate([0, 3, 0])",
        [0.0, 3.0, -1.0],
        -0.5
    );
    check!(
        "sphere(1).translate([2, 0, 0]).mirror_x()",
        [-2.0, 0.0, 0.0],
        -1.0
    );
    check!(
        "sphere(1).translate([0, 0, 2]).mirror_z()",
        [0.0, 0.0, -2.0],
        -1.0
    );
    check!("sphere(1).elongate([1, 0, 0])", [1.5, 0.0, 0.0], -0.5);
    check!("box(2).round(0.5)", [2.0, 0.0, 0.0], 0.5);
    check!("sphere(1).onion(0.1)", [0.0, 0.0, 0.0], 0.9);
}

#[test]
fn repetition() {
    check!("sphere(0.3).repeat([3, 0, 3])", [3.0, 0.0, -6.0], -0.3);
    check!("sphere(0.3).repeat([3, 0, 3])", [1.4, 0.0, 0.0], 1.1);
    // y is not repeated: far above, the distance keeps growing.
    check!("sphere(0.3).repeat([3, 0, 3])", [0.0, 10.0, 0.0], 9.7);
    // Two copies along x, centred: at x = -1 and x = 1.
    check!(
        "sphere(0.5).repeat([2, 0, 0], count: [2, 1, 1])",
        [1.0, 0.0, 0.0],
        -0.5
    );
    check!(
        "sphere(0.5).repeat([2, 0, 0], count: [2, 1, 1])",
        [-1.0, 0.0, 0.0],
        -0.5
    );
    check!(
        "sphere(0.5).repeat([2, 0, 0], count: [2, 1, 1])",
        [4.0, 0.0, 0.0],
        2.5
    );
    // Three copies: at -2, 0, 2.
    check!(
        "sphere(0.5).repeat([2, 2, 2], count: 3)",
        [2.0, -2.0, 0.0],
        -0.5
    );
    check!(
        "sphere(0.5).repeat([2, 2, 2], count: 3)",
        [6.0, 0.0, 0.0],
        3.5
    );
}

#[test]
fn combinations() {
    check!(
        "sphere(1) | sphere(1).translate([3, 0, 0])",
        [1.5, 0.0, 0.0],
        0.5
    );
    check!(
        "sphere(2) & sphere(2).translate([3, 0, 0])",
        [1.5, 0.0, 0.0],
        -0.5
    );
    check!("sphere(2) - sphere(1)", [0.0, 0.0, 0.0], 1.0);
    check!("xor(sphere(2), sphere(1))", [0.0, 0.0, 0.0], 1.0);
    check!("xor(sphere(2), sphere(1))", [1.5, 0.0, 0.0], -0.5);
    check!(
        "union(sphere(1), sphere(1).translate([3, 0, 0]), smooth: 0)",
        [1.5, 0.0, 0.0],
        0.5
    );
    // Smooth union at the midpoint: both distances 0.5, h = 0.5, d = 0.5 - k/4.
    check!(
        "union(sphere(1), sphere(1).translate([3, 0, 0]), smooth: 1)",
        [1.5, 0.0, 0.0],
        0.25
    );
    check!(
        "intersect(sphere(2), sphere(2).translate([3, 0, 0]), smooth: 1)",
        [1.5, 0.0, 0.0],
        -0.25
    );
    // iq's smooth subtraction: a = 0, b = -0.5, h = 0.75, d = mix(a, -b, h) + k h (1 - h).
    check!(
        "subtract(sphere(2), sphere(1).translate([2.5, 0, 0]), smooth: 1)",
        [2.0, 0.0, 0.0],
        0.5625
    );
}

#[test]
fn expressions_fold_like_wgsl() {
    check!("sphere(7 % 3 + -7 % 3)", [5.0, 0.0, 0.0], 2.0);
    check!(
        "sphere(max(abs(-1), 0.5) * [2, 3, 4].y / 3)",
        [5.0, 0.0, 0.0],
        4.0
    );
    check!("sphere(select(1, 2, 3 > 2))", [5.0, 0.0, 0.0], 3.0);
    check!("sphere(length([3, 4]))", [5.0, 0.0, 0.0], 0.0);
}

#[test]
fn params_and_time_stay_symbolic() {
    let prog = program("param r = 1; scene = sphere(r + time);");
    let inputs = Inputs {
        point: [5.0, 0.0, 0.0],
        ray: [0.0; 3],
        params: vec![Value::F(2.0)],
        time: 0.5,
    };
    let d = eval_graph(&prog.distance.graph, &prog.distance.results, &inputs)[0];
    assert_eq!(d, Value::F(2.5));
}

#[test]
fn materials_follow_the_nearer_shape_and_blend_when_smooth() {
    let src = "material a { color: [1, 0, 0] } material b { color: [0, 0, 1] }
        scene = sphere(1).material(a) | sphere(1).translate([3, 0, 0]).material(b);";
    assert_eq!(albedo(src, [-1.0, 0.0, 0.0])[..3], [1.0, 0.0, 0.0]);
    assert_eq!(albedo(src, [4.0, 0.0, 0.0])[..3], [0.0, 0.0, 1.0]);
    let smooth = "material a { color: [1, 0, 0] } material b { color: [0, 0, 1] }
        scene = union(sphere(1).material(a), sphere(1).translate([3, 0, 0]).material(b), smooth: 1);";
    let mid = albedo(smooth, [1.5, 0.0, 0.0]);
    assert!(close(mid[0], 0.5) && close(mid[2], 0.5), "{mid:?}");
    // The innermost material wins; an outer one fills the parts without one.
    let nested = "material a { color: [1, 0, 0] } material b { color: [0, 1, 0] }
        scene = (sphere(1).material(a) | sphere(1).translate([3, 0, 0])).material(b);";
    assert_eq!(albedo(nested, [-1.0, 0.0, 0.0])[..3], [1.0, 0.0, 0.0]);
    assert_eq!(albedo(nested, [4.0, 0.0, 0.0])[..3], [0.0, 1.0, 0.0]);
    let colored = "scene = sphere(1).color([0.25, 0.5, 1]);";
    assert_eq!(albedo(colored, [2.0, 0.0, 0.0])[..3], [0.25, 0.5, 1.0]);
}

#[test]
fn transform_chains_merge_into_one_map() {
    let prog = program("scene = sphere(1).translate([1, 0, 0]).translate([0, 2, 0]).rotate_y(10deg).rotate_y(20deg);");
    let text = sdfc_ir::dump::scene_text(&prog.scene);
    assert_eq!(text.matches("affine").count(), 1, "{text}");
    let a = dist("scene = sphere(1).translate([1, 0, 0]).translate([0, 2, 0]).rotate_y(10deg).rotate_y(20deg);", [0.3, 1.7, 0.2]);
    let b = dist(
        "scene = sphere(1).translate([1, 2, 0]).rotate_y(30deg);",
        [0.3, 1.7, 0.2],
    );
    assert!((a - b).abs() < 1e-6, "{a} {b}");
}

/// `pow` means what the device computes, `exp2(y * log2(x))`: a negative base is NaN (the
/// evaluator had `powf`'s -8 for `pow(-2, 3)` where the device gives NaN), and so is
/// `pow(0, 0)`; positive bases keep their values.
#[test]
fn pow_has_the_devices_meaning() {
    let cube = |x: f64| dist("scene = sdf(|p| pow(p.x, 3));", [x, 0.0, 0.0]);
    assert!(close(cube(2.0), 8.0), "{}", cube(2.0));
    assert!(close(cube(0.5), 0.125), "{}", cube(0.5));
    assert!(cube(-2.0).is_nan(), "{}", cube(-2.0));
    let zero = dist("scene = sdf(|p| pow(p.x, p.y));", [0.0, 0.0, 0.0]);
    assert!(zero.is_nan(), "pow(0, 0): {zero}");
}

/// An unused `fn` is checked with its parameters unknown: what depends on them raises no
/// error, so a library of helpers compiles whether or not the scene calls them.
#[test]
fn unused_fns_with_parameters_compile_cleanly() {
    let src = "material red { color: [1, 0, 0] }\n\
               fn moved(s, r) = s.translate([r, 0, 0]) | sphere(r).material(red);\n\
               fn blend(a, b, k = 0.5) = union(a, b, smooth: k);\n\
               fn ring(r) = sdf(|p| length(p.xz) - r, lipschitz: 1).color([1, 0, 0]);\n\
               scene = sphere(1);\n";
    let file = sdfc_syntax::parse(src).expect("parses");
    let (stages, diags) = sdfc_ir::compile(&file, src.len());
    assert!(stages.is_some(), "{diags:?}");
    assert!(diags.is_empty(), "{diags:?}");
}

fn diagnostics_of(src: &str) -> Vec<String> {
    let file = sdfc_syntax::parse(src).expect("parses");
    let (_, diags) = sdfc_ir::compile(&file, src.len());
    diags.into_iter().map(|d| d.message).collect()
}

/// Review of 2026-12-04: an anonymous material (`.color`) had no entry in the table of
/// material spans, so a named material after one was looked up at the wrong index (a panic
/// past the end), and so was a duplicate `material` item.
#[test]
fn colours_and_named_materials_mix_in_any_order() {
    let src = "let a = sphere(1).color([1, 0, 0]);\n\
               material red { color: [0, 1, 0] }\n\
               scene = sphere(1).material(red) | a;\n";
    assert!(diagnostics_of(src).is_empty());
    let twice = "let a = sphere(1).color([1, 0, 0]);\n\
                 material red { color: [0, 1, 0] }\n\
                 material red { color: [0, 1, 1] }\n\
                 scene = sphere(1).material(red) | a;\n";
    let d = diagnostics_of(twice);
    assert!(d.iter().any(|m| m.contains("already defined")), "{d:?}");
}

/// A mistake in a `fn` is reported once, however many times the fn is lowered (two calls,
/// or the unused-`fn` check and a call from another unused fn), and the diagnostics come in
/// the order of the text; a material defined below an unused fn that names it is reported
/// even where the fn's shape is a parameter.
#[test]
fn fn_mistakes_are_reported_once_in_text_order() {
    let d = diagnostics_of(
        "fn f(x) = foo + x;\nfn g(y) = f(1) + y;\nscene = sphere(f(1)) | sphere(f(2));\n",
    );
    assert_eq!(d.iter().filter(|m| m.contains("`foo`")).count(), 1, "{d:?}");
    let d = diagnostics_of("fn late(x) = bar;\nlet k = baz;\nscene = sphere(1);\n");
    assert_eq!(d.len(), 2, "{d:?}");
    assert!(d[0].contains("`bar`") && d[1].contains("`baz`"), "{d:?}");
    let d = diagnostics_of(
        "fn f(s) = s.material(red);\nmaterial red { color: [1, 0, 0] }\nscene = sphere(1);\n",
    );
    assert!(
        d.iter().any(|m| m.contains("used before it is defined")),
        "{d:?}"
    );
}
