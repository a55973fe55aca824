//! `eval_gpu` (the emitted WGSL run on the device, f32) against the f64 reference evaluator
//! at a few thousand random points per scene. A value passes when
//! `|gpu - cpu| <= REL * |cpu| + ABS`: REL = 1e-5 relative, and an absolute floor ABS = 2e-6
//! for values near zero, where f32 cancellation (`length(p) - r` with |p| of a few units
//! rounds to about 1e-7 absolute, a few of those add up) makes any relative bound meaningless.

mod common;

use common::{compile, compile_file, renderer};
use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_ir::value::Value;

const REL: f64 = 1e-5;
const ABS: f64 = 2e-6;
const POINTS: usize = 3000;

/// A small deterministic generator (SplitMix64): no dependency, same points every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn points(seed: u64, lo: [f32; 3], hi: [f32; 3]) -> Vec<[f32; 3]> {
    let mut rng = Rng(seed);
    (0..POINTS)
        .map(|_| {
            let mut p = [0.0f32; 3];
            for k in 0..3 {
                p[k] = lo[k] + (hi[k] - lo[k]) * rng.next() as f32;
            }
            p
        })
        .collect()
}

fn check(
    name: &str,
    compiled: &sdfc_wgsl::Compiled,
    pts: &[[f32; 3]],
    time: f32,
    params: &[(String, Vec<f32>)],
) {
    let Some(r) = renderer() else { return };
    let program = compiled.program();
    let gpu = r
        .eval_gpu(program, pts, time, params)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(gpu.len(), pts.len());
    let mut param_values: Vec<Value<f64>> = program
        .scene
        .params
        .iter()
        .map(|p| p.default.cast())
        .collect();
    for (n, v) in params {
        let i = program
            .scene
            .params
            .iter()
            .position(|p| &p.name == n)
            .unwrap();
        let comps: Vec<f64> = v.iter().map(|&c| c as f64).collect();
        param_values[i] = Value::from_comps(program.scene.params[i].ty, &comps);
    }
    let mut worst_rel: f64 = 0.0;
    let mut worst_abs: f64 = 0.0;
    let mut failures = Vec::new();
    for (p, &g) in pts.iter().zip(&gpu) {
        let inputs = Inputs {
            point: [p[0] as f64, p[1] as f64, p[2] as f64],
            params: param_values.clone(),
            time: time as f64,
        };
        let c = eval_func(&program.distance, &program.groups, &inputs)[0]
            .scalar()
            .unwrap();
        let err = (g as f64 - c).abs();
        worst_abs = worst_abs.max(err);
        if c.abs() > 1e-3 {
            worst_rel = worst_rel.max(err / c.abs());
        }
        if err.is_nan() || err > REL * c.abs() + ABS {
            failures.push((*p, g, c));
        }
    }
    eprintln!(
        "{name}: {} points, worst relative error {worst_rel:.2e} (|d| > 1e-3), worst absolute \
         {worst_abs:.2e}",
        pts.len()
    );
    assert!(
        failures.is_empty(),
        "{name}: {} of {} points off by more than {REL:e} relative + {ABS:e}; first \
         (point, gpu, cpu): {:?}",
        failures.len(),
        pts.len(),
        &failures[..failures.len().min(5)]
    );
}

fn corpus(rel: &str, seed: u64) {
    let compiled = compile_file(rel);
    check(rel, &compiled, &points(seed, [-4.0; 3], [4.0; 3]), 0.0, &[]);
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
    let pts = points(9, [-4.0; 3], [4.0; 3]);
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
        &points(10, [-8.0, -1.0, -12.0], [8.0, 12.0, 2.0]),
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
