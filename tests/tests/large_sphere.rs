//! A large sphere whose surface passes near the origin is evaluated relative to its surface
//! (`to_ssa::Builder::sphere_near_origin`): in f32, `|x - c| - r` is only good to ulp(|c|),
//! the rewritten form to a small fraction of |x| near the origin. Checked with the f32
//! evaluator (what the GPU computes) against the exact distance in f64.

use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_ir::ops::{Helper, Op};
use sdfc_tests::SplitMix;
use sdfc_wgsl::{compile, Options};

fn program(src: &str) -> sdfc_ir::Program {
    compile(src, &Options::default())
        .unwrap_or_else(|e| panic!("{src}: {e:?}"))
        .program()
        .clone()
}

fn uses_sd_sphere(p: &sdfc_ir::Program) -> bool {
    p.distance
        .graph
        .nodes()
        .any(|(_, n)| n.op == Op::Helper(Helper::SdSphere))
}

/// The stress suite's radius-300 sphere 0.01 below the origin: at points within 0.1 of the
/// origin the f32 distance is within 2e-8 of the exact one (the plain form's error there is
/// up to ulp(300) / 2 = 1.5e-5).
#[test]
fn large_sphere_near_the_origin_is_exact_to_f32_rounding_of_the_point() {
    let p = program("scene = sphere(300).translate([0, 0, -300.01]);");
    assert!(!uses_sd_sphere(&p), "the plain form was emitted");
    let mut r = SplitMix(0x5e1f_5e1f);
    let mut worst: f64 = 0.0;
    let mut plain_worst: f64 = 0.0;
    for _ in 0..2000 {
        let x = r.point_in([-0.1; 3], [0.1; 3]).map(|c| c as f32);
        let d32 = eval_func(&p.distance, &p.groups, &Inputs::at(x))[0]
            .scalar()
            .unwrap() as f64;
        let xd = x.map(|c| c as f64);
        let exact =
            (xd[0] * xd[0] + xd[1] * xd[1] + (xd[2] + 300.01f32 as f64).powi(2)).sqrt() - 300.0;
        worst = worst.max((d32 - exact).abs());
        // The plain form in f32, as sd_sphere computes it.
        let q = [x[0], x[1], x[2] + 300.01f32];
        let plain = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt() - 300.0;
        plain_worst = plain_worst.max((plain as f64 - exact).abs());
    }
    eprintln!("worst f32 error {worst:e} (plain form {plain_worst:e})");
    assert!(
        worst <= 2e-8,
        "f32 distance error {worst:e} near the origin"
    );
    assert!(
        worst * 100.0 <= plain_worst,
        "the rewritten form ({worst:e}) is not far better than the plain one ({plain_worst:e})"
    );
}

/// Small spheres, and large ones whose surface is far from the origin, keep the plain form.
#[test]
fn other_spheres_keep_the_plain_form() {
    for s in [
        "sphere(1).translate([0, 1, 0])",
        "sphere(10).translate([0, -10, 0])",
        "sphere(300).translate([0, 0, -600])",
        "sphere(300)",
    ] {
        assert!(uses_sd_sphere(&program(&format!("scene = {s};"))), "{s}");
    }
}
