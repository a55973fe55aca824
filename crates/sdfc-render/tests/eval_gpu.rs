//! `eval_gpu` (the emitted WGSL run on the device, f32) against the f64 reference evaluator
//! at a few thousand random points per scene. A value passes when
//! `|gpu - cpu| <= REL * |cpu| + ABS`: REL = 1e-5 relative, and an absolute floor ABS = 2e-6
//! for values near zero, where f32 cancellation (`length(p) - r` with |p| of a few units
//! rounds to about 1e-7 absolute, a few of those add up) makes any relative bound meaningless.

mod common;

use common::eval_check::{agree, points, Tolerance};
use common::{compile, compile_file, renderer};

const TOL: Tolerance = Tolerance {
    rel: 1e-5,
    abs: 2e-6,
    skip_near: 0.0,
    spread: 0.0,
};
const POINTS: usize = 3000;

fn check(
    name: &str,
    compiled: &sdfc_wgsl::Compiled,
    pts: &[[f32; 3]],
    time: f32,
    params: &[(String, Vec<f32>)],
) {
    let Some(r) = renderer() else { return };
    match agree(r, compiled, pts, time, params, TOL) {
        Ok(a) => eprintln!(
            "{name}: {} points, worst relative error {:.2e} (|d| > 1e-3), worst absolute {:.2e}",
            pts.len(),
            a.worst_rel,
            a.worst_abs
        ),
        Err(e) => panic!("{name}: {e}"),
    }
}

fn corpus(rel: &str, seed: u64) {
    let compiled = compile_file(rel);
    check(
        rel,
        &compiled,
        &points(seed, POINTS, [-4.0; 3], [4.0; 3]),
        0.0,
        &[],
    );
}

#[test]
fn spec_section10() {
    corpus("examples/spec_section10.sdf", 1);
}

#[test]
fn transforms() {
    corpus("tests/scenes/transforms.sdf", 2);
}

#[test]
fn csg_and_materials() {
    corpus("tests/scenes/csg.sdf", 3);
    corpus("tests/scenes/materials_csg.sdf", 4);
}

#[test]
fn primitives_and_repetition() {
    corpus("tests/scenes/primitives.sdf", 5);
    corpus("tests/scenes/repeat_modifiers.sdf", 6);
}

#[test]
fn math_builtins_and_lambdas() {
    corpus("tests/scenes/math_builtins.sdf", 7);
    corpus("tests/scenes/lambdas_sdf_displace.sdf", 8);
}

/// Noise hashes integers bit for bit on both sides; only the float arithmetic may differ.
#[test]
fn noise_and_fbm() {
    corpus("tests/scenes/noise_fbm.sdf", 10);
}

/// The bound-only operations: their point maps and per-point divisors, in WGSL and on the CPU.
#[test]
fn bound_only_operations() {
    corpus("tests/scenes/stretch.sdf", 11);
    corpus("tests/scenes/shear.sdf", 12);
    corpus("tests/scenes/twist.sdf", 13);
    corpus("tests/scenes/bend.sdf", 14);
    corpus("tests/scenes/warp.sdf", 15);
    corpus("tests/scenes/heightfield.sdf", 16);
}

#[test]
fn params_and_time() {
    let compiled = compile_file("tests/scenes/params_time.sdf");
    let pts = points(9, POINTS, [-4.0; 3], [4.0; 3]);
    check("params_time (defaults)", &compiled, &pts, 0.0, &[]);
    check(
        "params_time (overridden, t = 0.7)",
        &compiled,
        &pts,
        0.7,
        &[
            ("radius".into(), vec![0.5]),
            ("wobble".into(), vec![0.3, 1.5]),
            ("offset".into(), vec![0.5, -0.25, 1.0]),
        ],
    );
}

/// A large flat union, which the compiler splits into group functions.
#[test]
fn large_union_with_groups() {
    let source = sdfc_tests::grid_scene(200);
    let compiled = compile("grid_scene(200)", &source);
    assert!(
        !compiled.program().groups.is_empty(),
        "grid_scene(200) no longer uses group functions; pick a larger scene"
    );
    check(
        "grid_scene(200)",
        &compiled,
        &points(10, POINTS, [-8.0, -1.0, -12.0], [8.0, 12.0, 2.0]),
        0.0,
        &[],
    );
}

/// The same scene with culling (`--cull`): the guarded group calls, run on the device, give
/// the reference's distances.
#[test]
fn large_union_culled() {
    let source = sdfc_tests::grid_scene(200);
    let opts = sdfc_wgsl::Options {
        cull: true,
        ..Default::default()
    };
    let compiled = sdfc_wgsl::compile(&source, &opts).expect("grid_scene(200) compiles");
    assert!(
        compiled.wgsl.contains("if bound"),
        "no early-out in the culled shader"
    );
    check(
        "grid_scene(200), culled",
        &compiled,
        &points(11, POINTS, [-8.0, -1.0, -12.0], [8.0, 12.0, 2.0]),
        0.0,
        &[],
    );
}

/// More points than one dispatch of 65 535 workgroups of 64 takes: batches line up.
#[test]
fn batches_beyond_one_dispatch() {
    let Some(r) = renderer() else { return };
    let compiled = compile("sphere", "scene = sphere(1);");
    let n = 65_535 * 64 + 1000;
    let pts: Vec<[f32; 3]> = (0..n)
        .map(|i| [(i % 1000) as f32 * 0.01, 0.0, 0.0])
        .collect();
    let d = r.eval_gpu(compiled.program(), &pts, 0.0, &[]).unwrap();
    assert_eq!(d.len(), n);
    for (i, (p, v)) in pts.iter().zip(&d).enumerate() {
        assert!((v - (p[0] - 1.0)).abs() < 1e-6, "point {i}: {v} for {p:?}");
    }
}
