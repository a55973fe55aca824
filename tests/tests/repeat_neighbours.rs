//! Property: a repetition of a copy that fits its cell is the union of its copies. For
//! randomly generated shapes (`sdfc_tests::random_scene`) whose distance the analysis calls
//! exact and whose box is finite, `repeat` with a period just wider than the box, limited and
//! infinite, gives at random points the f64 distance of the explicit union of translated
//! copies. The copy's own cell alone is not enough where the copy is not symmetric about a
//! repeated axis (a turned bar, a moved sphere, a cone): there the neighbour on the point's
//! side is nearer, and `to_ssa` evaluates it too.

use proptest::prelude::any;
use proptest::test_runner::TestCaseError;
use sdfc_ir::analysis::Exactness;
use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_ir::Program;
use sdfc_tests::random_scene::{run_counted, shape_without_mandelbulb};
use sdfc_tests::SplitMix;
use sdfc_wgsl::{compile, Options};

fn program(src: &str) -> Result<Program, TestCaseError> {
    compile(src, &Options::default())
        .map(|c| c.program().clone())
        .map_err(|e| TestCaseError::fail(format!("{src}\n{e:?}")))
}

fn dist(p: &Program, x: [f64; 3]) -> f64 {
    eval_func(&p.distance, &p.groups, &Inputs::at(x))[0]
        .scalar()
        .unwrap_or(f64::NAN)
}

/// Compares `shape` repeated along x and y with the union of its copies; false where the
/// shape is not exact or not bounded.
fn check(shape: &str, seed: u64) -> Result<bool, TestCaseError> {
    let alone = program(&format!("scene = {shape};\n"))?;
    let root = &alone.analysis.nodes[alone.scene.root.index()];
    let b = root.bounds;
    if root.exactness != Exactness::Exact
        || (0..3).any(|i| !b.lo[i].is_finite() || !b.hi[i].is_finite())
    {
        return Ok(false);
    }
    // Periods a little wider than the box needs to fit its cell, centred on the origin.
    let period = [0, 1].map(|i| 2.0 * b.lo[i].abs().max(b.hi[i].abs()) + 0.05);
    let (px, py) = (format!("{:.4}", period[0]), format!("{:.4}", period[1]));
    let (px_f, py_f): (f64, f64) = (px.parse().unwrap(), py.parse().unwrap());
    let copies = |nx: i32, ny: i32| {
        let mut parts = Vec::new();
        for i in -nx..=nx {
            for j in -ny..=ny {
                parts.push(format!(
                    "({shape}).translate([{}, {}, 0])",
                    i as f64 * px_f,
                    j as f64 * py_f
                ));
            }
        }
        program(&format!("scene = union({});\n", parts.join(", ")))
    };
    let limited = program(&format!(
        "scene = ({shape}).repeat([{px}, {py}, 0], count: [3, 3, 1]);\n"
    ))?;
    let infinite = program(&format!("scene = ({shape}).repeat([{px}, 0, 0]);\n"))?;
    let union3 = copies(1, 1)?;
    let union7 = copies(3, 0)?;
    let mut r = SplitMix(seed);
    for _ in 0..400 {
        // Around the limited block (and beyond its ends), and the middle of the infinite row.
        let x = r.point_in(
            [-2.5 * px_f, -2.5 * py_f, b.lo[2] - 1.0],
            [2.5 * px_f, 2.5 * py_f, b.hi[2] + 1.0],
        );
        let (a, u) = (dist(&limited, x), dist(&union3, x));
        let slack = 1e-5 * (1.0 + u.abs() + px_f + py_f);
        if (a - u).abs() > slack {
            return Err(TestCaseError::fail(format!(
                "{shape} repeated [{px}, {py}, 0], count [3, 3, 1]: at {x:?} {a}, its copies' union {u}"
            )));
        }
        let y = [x[0] * 0.4, x[1], x[2]];
        let (a, u) = (dist(&infinite, y), dist(&union7, y));
        if (a - u).abs() > slack {
            return Err(TestCaseError::fail(format!(
                "{shape} repeated [{px}, 0, 0]: at {y:?} {a}, its copies' union {u}"
            )));
        }
    }
    Ok(true)
}

#[test]
fn a_repetition_is_the_union_of_its_copies() {
    let checked = run_counted(
        128,
        0x4e16,
        (shape_without_mandelbulb(), any::<u64>()),
        |(shape, seed)| check(&shape, seed),
    );
    assert!(
        checked >= 24,
        "only {checked} of 128 shapes were exact and bounded"
    );
}

/// The shapes the bug showed on: a tilted bar, a moved sphere, a cone (symmetric about y
/// only), each repeated along x, at points between the copies.
#[test]
fn tilted_moved_and_one_sided_copies() {
    for shape in [
        "box([1.8, 0.06, 0.06]).rotate_z(48deg)",
        "sphere(0.3).translate([0.35, 0.2, 0])",
        "cone(0.5, 1).rotate_z(90deg)",
    ] {
        assert!(
            check(shape, 7).unwrap_or_else(|e| panic!("{e}")),
            "{shape}: not checked"
        );
    }
}
