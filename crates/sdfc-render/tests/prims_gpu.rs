//! Every primitive added after the first seven, evaluated on the device through the emitted
//! WGSL (f32) and compared with the f64 reference evaluator at a few hundred points around
//! it. A value passes when `|gpu - cpu| <= REL * |cpu| + ABS`, REL = 1e-5 and ABS = 2e-6 (as
//! in `eval_gpu.rs`: f32 rounding of values near zero is absolute, not relative).
//!
//! The mandelbulb's estimate is chaotic: each iteration raises the orbit to the `power`th
//! power, multiplying its relative error by about `power`, so an f32 orbit carries the
//! rounding of its input, a few ulps, amplified by the orbit. It is compared with the same
//! bound plus MANDELBULB_SPREAD times the value's conditioning at each point (how much the
//! f64 value moves when one coordinate moves by one f32 ulp, `eval_check::Tolerance`), the
//! error that f32 inputs alone cause. That holds for the trigonometry-free helper of whole
//! powers (`sd_mandelbulb_int`); the device's `acos`, `atan2` and `pow` (`sd_mandelbulb`,
//! fractional powers) add errors of their own, up to 1.6e-3 on lavapipe, which is what
//! MANDELBULB_TRIG_REL allows them.

mod common;

use common::eval_check::{agree, points, Tolerance};
use common::{compile, renderer};

const REL: f64 = 1e-5;
const ABS: f64 = 2e-6;
const POINTS: usize = 400;
const MANDELBULB_SPREAD: f64 = 4.0;
const MANDELBULB_TRIG_REL: f64 = 5e-3;

/// Compares device and reference for `scene` at points of the cube [-size, size]^3;
/// points whose reference value is within `skip_near` of zero are left out.
fn check(scene: &str, size: f32, seed: u64, rel: f64, skip_near: f64) {
    let tol = Tolerance {
        rel,
        abs: ABS,
        skip_near,
        spread: 0.0,
    };
    check_with("", scene, size, seed, tol)
}

/// `check` with items (params) above the scene.
fn check_with(items: &str, scene: &str, size: f32, seed: u64, tol: Tolerance) {
    let Some(r) = renderer() else { return };
    let compiled = compile(scene, &format!("{items}\nscene = {scene};\n"));
    let pts = points(seed, POINTS, [-size; 3], [size; 3]);
    match agree(r, &compiled, &pts, 0.0, &[], tol) {
        Ok(a) => {
            eprintln!(
                "{scene}: {} points, worst relative error {:.1e} (|d| > 1e-3), worst absolute \
                 {:.1e}",
                a.compared, a.worst_rel, a.worst_abs
            );
            assert!(
                a.compared > POINTS / 2,
                "{scene}: only {} points compared",
                a.compared
            );
        }
        Err(e) => panic!("{scene}: {e}"),
    }
}

#[test]
fn exact_primitives_agree() {
    for (scene, size) in [
        ("box_frame([1, 1.5, 2], 0.2)", 1.4),
        ("capped_torus(1, 0.25, 120deg)", 1.5),
        ("capped_torus(0.8, 0.1, 180deg)", 1.2),
        ("infinite_cylinder(0.6)", 1.5),
        ("cone(0.7, 1.5)", 1.6),
        ("capped_cone(1.2, 0.6, 0.2)", 1.2),
        ("octahedron(1.4)", 1.2),
        ("hex_prism(0.5, 1.5)", 1.2),
        ("tri_prism(0.4, 1)", 1.2),
        ("pyramid(1.3)", 1.2),
    ] {
        check(scene, size, 40, REL, 0.0);
    }
}

#[test]
fn bound_primitives_agree() {
    check("ellipsoid([1, 0.5, 0.3])", 1.4, 41, REL, 0.0);
    check("menger()", 0.7, 42, REL, 0.0);
    check("menger(iterations: 6)", 0.7, 43, REL, 0.0);
    check("sierpinski()", 0.7, 44, REL, 0.0);
    check("sierpinski(iterations: 16)", 0.7, 45, REL, 0.0);
}

/// Whole powers: to 1e-5 beyond what the inputs' rounding alone causes, everywhere.
#[test]
fn mandelbulb_agrees_to_its_conditioning() {
    let tol = Tolerance {
        rel: REL,
        abs: ABS,
        skip_near: 0.0,
        spread: MANDELBULB_SPREAD,
    };
    for (scene, seed) in [
        ("mandelbulb()", 46),
        ("mandelbulb(power: 4, iterations: 5)", 47),
        ("mandelbulb(power: 16, iterations: 4)", 50),
        ("mandelbulb(power: 3, iterations: 12)", 51),
    ] {
        check_with("", scene, 1.5, seed, tol);
    }
}

/// Fractional powers go through the device's trigonometry: compared away from the surface.
#[test]
fn mandelbulb_of_a_fractional_power_agrees_away_from_its_surface() {
    check("mandelbulb(power: 7.5)", 1.5, 52, MANDELBULB_TRIG_REL, 0.05);
}

/// Zero sizes (flat or empty shapes) stay finite on both sides and agree; a zero ellipsoid
/// radius can only come from a param (a constant one is an error).
#[test]
fn degenerate_sizes_agree() {
    for scene in [
        "cone(0, 1)",
        "cone(1, 0)",
        "capped_cone(0, 0, 0)",
        "capped_cone(1, 0, 0)",
        "tri_prism(0, 1)",
        "hex_prism(0, 0)",
        "pyramid(0)",
        "octahedron(0)",
        "box_frame(1, 0)",
        "capped_torus(1, 0, 0)",
        "infinite_cylinder(0)",
    ] {
        check(scene, 1.2, 48, REL, 0.0);
    }
    let tol = Tolerance {
        rel: REL,
        abs: ABS,
        skip_near: 0.0,
        spread: 0.0,
    };
    check_with(
        "param radii = [1, 0, 0.5];",
        "ellipsoid(radii)",
        1.2,
        49,
        tol,
    );
}
