//! A ray that passes a surface by, nearer than a hundredth of the pixel threshold but without
//! crossing it: the centre ray of a 33x33 image (exactly the camera's axis) passes a unit
//! sphere 10 away at 5e-4, a fifth of a hundredth of the threshold there (1.4e-3 at fov 50).
//!
//! For a trusted distance (exact, or a bound the compiler made, derived or checked: here a
//! `sdf` with a declared `lipschitz:`) the refinement tells the pass by the samples' rise
//! after their minimum and the pixel misses, as the f64 reference does (it had hit 0.73
//! beyond the closest approach, where the ray is 0.24 from the sphere). For an estimate (an
//! `sdf` with no declared bound, as the mandelbulb's) a rise does not prove a pass (the
//! mandelbulb's rises while its surface is still ahead), and such a pass still counts as
//! touching, at the sample nearest the surface. The interpreter decides all three as the
//! specialised shader does (its `Frame.switches` bit).

mod common;

use common::{compile, renderer};
use sdfc_render::{Frame, RenderOptions};

const SIZE: u32 = 33;
/// The pixel whose ray is the camera's axis.
const CENTRE: usize = (SIZE / 2 * SIZE + SIZE / 2) as usize;

/// The scene with its shape written by `shape`, 5e-4 off the camera's axis at 10 away.
fn scene(shape: &str) -> String {
    format!(
        "camera {{ position: [0, 0, 0], target: [0, 0, -1], fov: 50deg }}\n\
         scene = {shape}.translate([1.0005, 0, -10]);\n"
    )
}

/// The centre pixel's depth, specialised and interpreted.
fn centre_depths(compiled: &sdfc_wgsl::Compiled) -> Option<(f32, f32)> {
    let r = renderer()?;
    let options = RenderOptions {
        aovs: true,
        ..RenderOptions::sized(SIZE, SIZE)
    };
    let depth = |f: Frame| f.aovs.expect("AOVs were asked for").depth[CENTRE];
    let spec = r.render(compiled, &options).expect("specialised");
    let interp = r
        .render_interpreted(compiled.program(), &options)
        .expect("interpreted");
    Some((depth(spec), depth(interp)))
}

/// Checks that the centre pixel misses on the device, in the interpreter and in the
/// reference; nothing without a device.
fn check_miss(name: &str, shape: &str) {
    let compiled = compile(name, &scene(shape));
    let Some((spec, interp)) = centre_depths(&compiled) else {
        return;
    };
    let reference = sdfc_reference::render(
        compiled.program(),
        &sdfc_reference::Options::sized(SIZE, SIZE),
    );
    let centre = reference.pixel(SIZE / 2, SIZE / 2);
    assert!(
        !centre.hit,
        "{name}: the reference hits at {}",
        centre.depth
    );
    assert!(spec.is_infinite(), "{name}, specialised: a hit at {spec}");
    assert!(
        interp.is_infinite(),
        "{name}, interpreted: a hit at {interp}"
    );
}

#[test]
fn an_exact_surface_passed_by_is_a_miss() {
    check_miss("passing_by_exact", "sphere(1)");
}

#[test]
fn a_declared_bound_passed_by_is_a_miss() {
    check_miss(
        "passing_by_declared",
        "sdf(|p| length(p) - 1, lipschitz: 1)",
    );
}

#[test]
fn an_estimate_passed_by_within_a_hundredth_of_the_threshold_touches() {
    let compiled = compile("passing_by_estimate", &scene("sdf(|p| length(p) - 1)"));
    let Some((spec, interp)) = centre_depths(&compiled) else {
        return;
    };
    // Touching, at the sample nearest the surface: within 1.4e-3 of it, so within 0.05 of
    // the closest approach at 10 (it had been the last sample, at 10.8, where the ray is
    // 0.28 from the sphere).
    for (form, t) in [("specialised", spec), ("interpreted", interp)] {
        assert!((t - 10.0).abs() < 0.05, "{form}: depth {t}");
    }
}
