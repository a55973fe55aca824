//! Property: the distance of a randomly generated valid scene (`sdfc_tests::random_scene`,
//! without the mandelbulb) that the analysis calls exact is 1-Lipschitz, as a Euclidean
//! distance is: at random pairs of nearby points around the scene its f64 values differ by
//! no more than the points' distance. (Bounds need not be: a fractal's estimate, or a
//! repetition's nearest copies of one, may jump where the copy it measures changes, and stays
//! below the distance; `lipschitz.rs` checks the bound-only operations' divisors.)

use proptest::prelude::any;
use proptest::test_runner::TestCaseError;
use sdfc_ir::analysis::Exactness;
use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_tests::random_scene::{run_counted, shape_without_mandelbulb};
use sdfc_tests::SplitMix;
use sdfc_wgsl::{compile, Options};

const PAIRS: usize = 1_000;

fn check(scene: &str, seed: u64) -> Result<bool, TestCaseError> {
    let src = format!("scene = {scene};\n");
    let c = compile(&src, &Options::default())
        .map_err(|e| TestCaseError::fail(format!("{src}\n{e:?}")))?;
    let p = c.program();
    let root = &p.analysis.nodes[p.scene.root.index()];
    if root.exactness != Exactness::Exact {
        return Ok(false);
    }
    let b = root.bounds;
    let lo =
        b.lo.map(|x| if x.is_finite() { x - 1.0 } else { -4.0 }.max(-6.0));
    let hi =
        b.hi.map(|x| if x.is_finite() { x + 1.0 } else { 4.0 }.min(6.0));
    let f = |x: [f64; 3]| {
        eval_func(&p.distance, &p.groups, &Inputs::at(x))[0]
            .scalar()
            .unwrap_or(f64::NAN)
    };
    let mut r = SplitMix(seed);
    for _ in 0..PAIRS {
        let x = r.point_in(lo, hi);
        let h = 0.05 * r.unit() + 1e-3;
        let dir = [r.unit() - 0.5, r.unit() - 0.5, r.unit() - 0.5];
        let n = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2])
            .sqrt()
            .max(1e-9);
        let y = [0, 1, 2].map(|i| x[i] + h * dir[i] / n);
        let (a, c) = (f(x), f(y));
        let slack = 1e-4 * h + 2e-6 * (1.0 + a.abs().max(c.abs()));
        if (a - c).abs() > h + slack {
            return Err(TestCaseError::fail(format!(
                "{src}: |f({x:?}) - f({y:?})| = |{a} - {c}| = {} over {h} apart ({:?})",
                (a - c).abs(),
                root.exactness
            )));
        }
    }
    Ok(true)
}

#[test]
fn exact_distances_are_1_lipschitz() {
    let exact = run_counted(
        256,
        0x11b5,
        (shape_without_mandelbulb(), any::<u64>()),
        |(scene, seed)| check(&scene, seed),
    );
    assert!(exact >= 64, "only {exact} of 256 scenes were exact");
}
