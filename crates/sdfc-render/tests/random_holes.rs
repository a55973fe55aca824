//! Property: randomly generated valid scenes (`sdfc_tests::random_scene`, without the
//! mandelbulb, whose estimate is no bound) draw on the device what the f64 reference
//! renderer draws (`sdfc-reference`: sphere tracing to 1e-9 of t, then bisection), away from
//! edges. A hole (the reference hits, the device misses) or a false hit (the other way)
//! whose reference 3x3 neighbourhood is all misses, or all hits within 1% of one depth, is a
//! bug of the field, the bounds (`ray_span`, the tiles) or the marcher; edges may round
//! either way under the pixel's threshold. Also no NaN or Inf in any AOV, the product's bars
//! away from edges (depth within 1e-4 relative on 99.9% of the hits; normals within 0.1
//! degree, median, where the surface is smooth), and the interpreted marcher (the live
//! preview's) hits where the specialised shader does, away from the same edges. 48x36
//! pixels, the spec's default camera; again with the scene and the camera moved 1e5 out on
//! every axis. (Thousands of scenes with other seeds passed: `SDFC_RANDOM_CASES`,
//! `SDFC_RANDOM_SEED`; docs/accuracy.md.)

mod common;

use common::against_reference::{
    interior_depth_p999, is_edge, off_the_reference, render_against_reference,
    smooth_normal_median, Compared,
};
use common::renderer;
use proptest::test_runner::TestCaseError;
use sdfc_ir::analysis::Exactness;
use sdfc_tests::random_scene::{cases, run_counted, seed, shape_without_mandelbulb};

const W: u32 = 48;
const H: u32 = 36;

/// The most the depth of 99.9% of the hits away from edges may be off the reference's,
/// relative (the product's bar).
const DEPTH_P999: f64 = 1e-4;

/// The most the median normal may be off the reference's, in degrees (the product's bar).
const NORMAL_MEDIAN_DEG: f64 = 0.1;

/// Checks `scene` seen by the spec's default camera, or with the camera moved `far` along
/// every axis and the scene with it.
fn check(r: &sdfc_render::Renderer, scene: &str, far: f64) -> Result<(), TestCaseError> {
    let src = if far == 0.0 {
        format!("scene = {scene};\n")
    } else {
        format!(
            "camera {{ position: [{far}, {far}, {}], target: [{far}, {far}, {far}] }}\n\
             scene = ({scene}).translate([{far}, {far}, {far}]);\n",
            far + 5.0
        )
    };
    let compiled = sdfc_wgsl::compile(&src, &sdfc_wgsl::Options::default())
        .map_err(|e| TestCaseError::fail(format!("{src}\n{e:?}")))?;
    let p = compiled.program();
    if p.analysis.nodes[p.scene.root.index()].exactness == Exactness::Neither {
        // A repetition whose copy does not fit its cell: no bound, so neither marcher can
        // be right everywhere (`sdfc compile --explain` says so).
        return Ok(());
    }
    let Compared {
        frame,
        reference,
        metrics: m,
    } = render_against_reference(r, "random", &compiled, W, H);
    let aovs = frame.aovs.as_ref().expect("AOVs");
    let off = off_the_reference(&reference, &aovs.depth);
    // The interpreted marcher (the live preview) draws the same hits, by the same rule.
    let interp = r
        .render_interpreted(
            p,
            &sdfc_render::RenderOptions {
                aovs: true,
                ..sdfc_render::RenderOptions::sized(W, H)
            },
        )
        .map_err(|e| TestCaseError::fail(format!("{src}: interpreted: {e}")))?;
    let depth = &interp.aovs.as_ref().expect("AOVs").depth;
    let interp_off: Vec<(u32, u32)> = (0..H)
        .flat_map(|y| (0..W).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let i = (y * W + x) as usize;
            depth[i].is_finite() != aovs.depth[i].is_finite() && !is_edge(&reference, x, y)
        })
        .collect();
    if !interp_off.is_empty() || depth.iter().any(|d| d.is_nan()) {
        return Err(TestCaseError::fail(format!(
            "{src}: the interpreter's hits differ from the specialised shader's away from \
             edges at {interp_off:?}"
        )));
    }
    // Normals are held to the product's bar (median over smooth pixels), but where the
    // camera is inside the solid (every ray hits at t = 0, where the difference normal's step
    // is the least there is), and 1e5 out where the scene's smallest size is not known
    // (`Analysis::feature` 0: a lambda's `sdf`, a warp): the step's floor is then the
    // point's size, small near the camera beside the shapes' numbers (docs/accuracy.md,
    // "Normals near the camera").
    let inside = reference.pixels.iter().any(|p| p.hit && p.depth == 0.0);
    let skip_normals = inside || (far != 0.0 && p.analysis.feature == 0.0);
    let normal_median = smooth_normal_median(&reference, &aovs.depth, &aovs.normal);
    let normals_off = !skip_normals && normal_median.is_some_and(|n| n > NORMAL_MEDIAN_DEG);
    let depth_p999 = interior_depth_p999(&reference, &aovs.depth);
    let depth_off = depth_p999.is_some_and(|d| d > DEPTH_P999);
    if m.nonfinite > 0 || !off.is_empty() || depth_off || normals_off {
        return Err(TestCaseError::fail(format!(
            "{src}: non-finite {}, depth p99.9 {:?} (away from edges), normal median {:?} \
             degrees (smooth pixels), pixels off the reference away from silhouettes (x, y, \
             reference hit) {off:?}",
            m.nonfinite, depth_p999, normal_median
        )));
    }
    Ok(())
}

#[test]
fn random_scenes_draw_what_the_reference_draws() {
    let Some(r) = renderer() else { return };
    run_counted(
        cases(48),
        seed(0x0de5),
        shape_without_mandelbulb(),
        |scene| check(r, &scene, 0.0).map(|()| true),
    );
}

/// The same 1e5 from the origin on every axis: the renderer marches camera-relative
/// coordinates, with the move folded into the scene in f64 (docs/accuracy.md).
#[test]
fn random_scenes_far_from_the_origin_draw_what_the_reference_draws() {
    let Some(r) = renderer() else { return };
    run_counted(
        cases(24),
        seed(0xfa7),
        shape_without_mandelbulb(),
        |scene| check(r, &scene, 1e5).map(|()| true),
    );
}
