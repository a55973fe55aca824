//! Property: for randomly generated valid scenes (the generator of `sdfc_tests::random_scene`,
//! every shape and operation this version implements but the mandelbulb, whose chaotic orbit
//! has its own tolerance in `prims_gpu.rs`), the emitted WGSL evaluated on the device agrees
//! with the f64 reference evaluator at random points.
//!
//! Tolerance: `|gpu - cpu| <= 1e-5 * |cpu| + 2e-6`, the same as the corpus test
//! (`eval_gpu.rs`). Over the 200 cases (200 points each) the worst absolute error measured on
//! lavapipe was 1.1e-6; the test prints the worst figures with `--nocapture`.
//!
//! A second property mixes whole-power mandelbulbs in, with the mandelbulb's tolerance of
//! `prims_gpu.rs`: the same bound plus 4 times each point's conditioning (how far the f64
//! value moves when one coordinate moves by one f32 ulp).

mod common;

use common::eval_check::{agree, Tolerance};
use common::renderer;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use sdfc_tests::random_scene::{shape_with_whole_power_mandelbulbs, shape_without_mandelbulb};

thread_local! {
    /// The worst (relative, absolute) error over the cases so far, printed for the record.
    static WORST: std::cell::RefCell<(f64, f64)> = const { std::cell::RefCell::new((0.0, 0.0)) };
}

const TOL: Tolerance = Tolerance {
    rel: 1e-5,
    abs: 2e-6,
    skip_near: 0.0,
    spread: 0.0,
};

const MANDELBULB_TOL: Tolerance = Tolerance { spread: 4.0, ..TOL };

/// Compiles `scene` and compares device and reference at `pts`.
fn check(scene: &str, pts: &[[f32; 3]], tol: Tolerance) -> Result<(), TestCaseError> {
    let Some(r) = renderer() else { return Ok(()) };
    let src = format!("scene = {scene};\n");
    let compiled = match sdfc_wgsl::compile(&src, &sdfc_wgsl::Options::default()) {
        Ok(c) => c,
        Err(e) => return Err(TestCaseError::fail(format!("{src}\n{e:?}"))),
    };
    match agree(r, &compiled, pts, 0.0, &[], tol) {
        Ok(a) => WORST.with(|w| {
            let mut w = w.borrow_mut();
            w.0 = w.0.max(a.worst_rel);
            w.1 = w.1.max(a.worst_abs);
            eprintln!(
                "worst so far: relative {:.2e} (|d| > 1e-3), absolute {:.2e}",
                w.0, w.1
            );
            Ok(())
        }),
        Err(e) => Err(TestCaseError::fail(format!("{src}{e}"))),
    }
}

proptest! {
    // Each case builds a pipeline on the device (about 0.1-0.5 s on lavapipe), so the case
    // count is kept small; the seed is fixed so CI is repeatable.
    #![proptest_config(Config { cases: 200, rng_seed: RngSeed::Fixed(0x6a9e), failure_persistence: None, ..Config::default() })]

    #[test]
    fn random_scenes_agree_on_the_device(
        scene in shape_without_mandelbulb(),
        pts in prop::collection::vec(prop::array::uniform3(-4.0f32..4.0), 200),
    ) {
        check(&scene, &pts, TOL)?;
    }
}

proptest! {
    #![proptest_config(Config { cases: 40, rng_seed: RngSeed::Fixed(0x6a9f), failure_persistence: None, ..Config::default() })]

    #[test]
    fn random_scenes_with_whole_power_mandelbulbs_agree_on_the_device(
        scene in shape_with_whole_power_mandelbulbs(),
        pts in prop::collection::vec(prop::array::uniform3(-2.0f32..2.0), 200),
    ) {
        check(&scene, &pts, MANDELBULB_TOL)?;
    }
}
