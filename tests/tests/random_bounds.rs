//! Property: for randomly generated valid scenes (`sdfc_tests::random_scene`), the
//! analysis's box and outside factor hold. At random points outside the scene's box the f64
//! distance is positive (no surface lies outside it: `ray_span`, the tiles and the data
//! form's culling leave such rays out) and at least the factor times the distance to the box
//! (shadow rays stop by it: `bounds_outside`). `outside_factor.rs` checks chosen scenes of
//! each construct; this one checks what the constructs do to each other, nested.

use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_tests::random_scene::{run_counted, shape};
use sdfc_tests::SplitMix;
use sdfc_wgsl::{compile, Options};

/// How far around the box points are sampled, and how many.
const REACH: f64 = 3.0;
const POINTS: usize = 1_500;

/// Checks one scene at `POINTS` points around its box; whether its box is finite anywhere.
fn check(scene: &str, seed: u64) -> Result<bool, TestCaseError> {
    let src = format!("scene = {scene};\n");
    let c = match compile(&src, &Options::default()) {
        Ok(c) => c,
        Err(e) => return Err(TestCaseError::fail(format!("{src}\n{e:?}"))),
    };
    let p = c.program();
    let root = &p.analysis.nodes[p.scene.root.index()];
    let (b, factor) = (root.bounds, root.outside);
    prop_assert!(
        factor.is_finite() && (0.0..=1.0).contains(&factor),
        "{src}: factor {factor}"
    );
    if (0..3).all(|i| !b.lo[i].is_finite() && !b.hi[i].is_finite()) {
        // Unbounded on every axis: no point is outside.
        return Ok(false);
    }
    let lo = b.lo.map(|x| if x.is_finite() { x - REACH } else { -REACH });
    let hi = b.hi.map(|x| if x.is_finite() { x + REACH } else { REACH });
    let mut r = SplitMix(seed);
    for _ in 0..POINTS {
        let x = r.point_in(lo, hi);
        let gap = (0..3)
            .map(|i| (b.lo[i] - x[i]).max(x[i] - b.hi[i]).max(0.0).powi(2))
            .sum::<f64>()
            .sqrt();
        if gap <= 0.0 {
            continue;
        }
        let d = eval_func(&p.distance, &p.groups, &Inputs::at(x))[0]
            .scalar()
            .unwrap_or(f64::NAN);
        // The evaluator rounds the scene's constants as f32: a little slack for that.
        let slack = 1e-5 * (1.0 + gap + x.iter().fold(0.0f64, |m, v| m.max(v.abs())));
        prop_assert!(
            d > -slack,
            "{src}: a surface outside the box {b:?} at {x:?} (distance {d})"
        );
        prop_assert!(
            d >= factor * gap - slack,
            "{src}: at {x:?}, {gap} outside the box {b:?}, the distance {d} is below {factor} times it"
        );
    }
    Ok(true)
}

#[test]
fn no_surface_outside_the_box_and_the_factor_holds() {
    let bounded = run_counted(256, 0xb0c5, (shape(), any::<u64>()), |(scene, seed)| {
        check(&scene, seed)
    });
    // Planes, repetitions and `sdf` leave many scenes unbounded: enough must not be.
    assert!(
        bounded >= 64,
        "only {bounded} of 256 scenes had a finite box"
    );
}
