//! Property: randomly generated valid scenes (`sdfc_tests::random_scene`, without the
//! mandelbulb, whose estimate is no bound) draw on the device what the f64 reference
//! renderer draws (`sdfc-reference`: sphere tracing to 1e-9 of t, then bisection), away from
//! edges. A hole (the reference hits, the device misses) or a false hit (the other way)
//! whose reference 3x3 neighbourhood is all misses, or all hits within 1% of one depth, is a
//! bug of the field, the bounds (`ray_span`, the tiles) or the marcher; edges may round
//! either way under the pixel's threshold. Also no NaN or Inf in any AOV, and the interpreted
//! marcher (the live preview's) hits where the specialised shader does, away from the same
//! edges. 48x36 pixels, the spec's default camera. (400 scenes with another seed passed.)

mod common;

use common::against_reference::{render_against_reference, Compared};
use common::renderer;
use proptest::test_runner::TestCaseError;
use sdfc_ir::analysis::Exactness;
use sdfc_reference::metrics;
use sdfc_tests::random_scene::{run_counted, shape_without_mandelbulb};

const W: u32 = 48;
const H: u32 = 36;

/// Whether the reference's 3x3 neighbourhood of (x, y) holds a silhouette (hits and misses)
/// or a depth edge (hits more than 1% apart): a thin fin or a crease seen edge on, or a
/// surface grazed in front of another, which the pixel's threshold may take or pass either
/// way.
fn edge(reference: &sdfc_reference::Image, x: u32, y: u32) -> bool {
    metrics::is_silhouette(reference, x, y) || metrics::is_depth_edge(reference, x, y, 0.01)
}

fn check(r: &sdfc_render::Renderer, scene: &str) -> Result<(), TestCaseError> {
    let src = format!("scene = {scene};\n");
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
    let off: Vec<(u32, u32, bool)> = (0..H)
        .flat_map(|y| (0..W).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let device = aovs.depth[(y * W + x) as usize].is_finite();
            device != reference.pixel(x, y).hit && !edge(&reference, x, y)
        })
        .map(|(x, y)| (x, y, reference.pixel(x, y).hit))
        .collect();
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
            depth[i].is_finite() != aovs.depth[i].is_finite() && !edge(&reference, x, y)
        })
        .collect();
    if !interp_off.is_empty() || depth.iter().any(|d| d.is_nan()) {
        return Err(TestCaseError::fail(format!(
            "{src}: the interpreter's hits differ from the specialised shader's away from \
             edges at {interp_off:?}"
        )));
    }
    if m.nonfinite > 0 || !off.is_empty() {
        return Err(TestCaseError::fail(format!(
            "{src}: non-finite {}, pixels off the reference away from silhouettes (x, y, \
             reference hit) {off:?}",
            m.nonfinite
        )));
    }
    Ok(())
}

#[test]
fn random_scenes_draw_what_the_reference_draws() {
    let Some(r) = renderer() else { return };
    run_counted(48, 0x0de5, shape_without_mandelbulb(), |scene| {
        check(r, &scene).map(|()| true)
    });
}
