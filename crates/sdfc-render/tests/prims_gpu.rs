//! Every primitive added after the first seven, evaluated on the device through the emitted
//! WGSL (f32) and compared with the f64 reference evaluator at a few hundred points around
//! it. A value passes when `|gpu - cpu| <= REL * |cpu| + ABS`, REL = 1e-5 and ABS = 2e-6 (as
//! in `eval_gpu.rs`: f32 rounding of values near zero is absolute, not relative).
//!
//! The mandelbulb is the exception, measured and stated: its iteration is chaotic, so f32
//! and f64 orbits part near the set's boundary (one escapes an iteration earlier), and
//! `pow`, `acos` and `atan2` on the device are only a few ulps accurate; each iteration
//! raises the orbit to the 8th power, multiplying its relative rounding error by about 8, so
//! after a few iterations the f32 estimate carries errors near 1e-3 (lavapipe: 1.0e-3 for
//! power 8, 1.6e-3 for power 4 at the seeds below). It is compared on points where the f64
//! estimate is at least 0.05 away from the surface, to MANDELBULB_REL = 5e-3 relative.

mod common;

use common::eval_check::{agree, points, Tolerance};
use common::{compile, renderer};

const REL: f64 = 1e-5;
const ABS: f64 = 2e-6;
const POINTS: usize = 400;
const MANDELBULB_REL: f64 = 5e-3;

/// Compares device and reference for `scene` at points of the cube [-size, size]^3;
/// points whose reference value is within `skip_near` of zero are left out.
fn check(scene: &str, size: f32, seed: u64, rel: f64, skip_near: f64) {
    check_with("", scene, size, seed, rel, skip_near)
}

/// `check` with items (params) above the scene.
fn check_with(items: &str, scene: &str, size: f32, seed: u64, rel: f64, skip_near: f64) {
    let Some(r) = renderer() else { return };
    let compiled = compile(scene, &format!("{items}\nscene = {scene};\n"));
    let pts = points(seed, POINTS, [-size; 3], [size; 3]);
    let tol = Tolerance {
        rel,
        abs: ABS,
        skip_near,
    };
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

#[test]
fn mandelbulb_agrees_away_from_its_surface() {
    check("mandelbulb()", 1.5, 46, MANDELBULB_REL, 0.05);
    check(
        "mandelbulb(power: 4, iterations: 5)",
        1.5,
        47,
        MANDELBULB_REL,
        0.05,
    );
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
    check_with(
        "param radii = [1, 0, 0.5];",
        "ellipsoid(radii)",
        1.2,
        49,
        REL,
        0.0,
    );
}
