//! Which scenes get the fine pass-by rule (`touch_distance` in `shaders/hit.wgsl`, through
//! `distance_trusted()`, from `Analysis::distance_trusted`):
//! exact distances and the bounds the compiler makes, derives or checks, and not the
//! estimates (the mandelbulb's, an `sdf` with no declared `lipschitz:`, a repeated shape
//! that does not fit its cell). The interpreter's
//! `Frame.switches` bit follows the same predicate (tested on the device in
//! `sdfc-render/tests/passing_by.rs`).

use sdfc_wgsl::{compile, Options};

/// Whether the scene's shader says its distance is trusted.
fn trusted(shape: &str) -> bool {
    let source = format!("scene = {shape};\n");
    let wgsl = compile(&source, &Options::default())
        .unwrap_or_else(|f| panic!("{shape}: {f}"))
        .wgsl;
    let fine = wgsl.contains("fn distance_trusted() -> bool {\n    return true;");
    let coarse = wgsl.contains("fn distance_trusted() -> bool {\n    return false;");
    assert!(
        fine != coarse,
        "{shape}: one distance_trusted, true or false"
    );
    fine
}

#[test]
fn exact_distances_and_proven_bounds_are_trusted() {
    for shape in [
        "sphere(1)",
        "box([1, 2, 3]).rotate_y(30deg) | torus(1, 0.2).translate([3, 0, 0])",
        "box(1) - sphere(1.2)",
        "union(sphere(1), box(0.8).translate([1, 0, 0]), smooth: 0.3)",
        "sphere(0.4).repeat([2, 0, 2])",
        "ellipsoid([1, 2, 3])",
        "menger(iterations: 3) | sierpinski(iterations: 4)",
        "sphere(1).twist(0.5)",
        "sdf(|p| length(p) - 1, lipschitz: 1)",
    ] {
        assert!(trusted(shape), "{shape}");
    }
}

#[test]
fn estimates_are_not_trusted() {
    for shape in [
        "mandelbulb()",
        "sphere(1) | mandelbulb().translate([3, 0, 0])",
        "sdf(|p| length(p) - 1)",
        "box(1) | sdf(|p| p.y + 2)",
        // A repeated shape that does not fit its cell: neither exact nor a bound.
        "sphere(1.5).repeat([2, 0, 2])",
        "union(sphere(1.5).repeat([2, 0, 2]), box(1), smooth: 0.2)",
    ] {
        assert!(!trusted(shape), "{shape}");
    }
}
