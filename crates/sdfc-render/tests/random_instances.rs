//! Property: random unions emitted as data (`sdfc_tests::random_instances`: 16 to 39
//! primitives of every kind an instance may be, turned about any axis, scaled, coloured,
//! sometimes beside a floor, a smooth blend or a fractal) draw on the device what the f64
//! reference draws, away from edges, as `random_holes.rs` asks of any scene: the data form's
//! specialised shader, the interpreter's walk where the union is of instances alone
//! (`encode_as_data`), and the same union as code culled (`--cull`). Also no NaN or Inf, the
//! data form's median depth within 1e-5 of the reference's, and where the data form and the
//! code form part (a grazing edge that their different bounds send either way), the data
//! form no farther from the reference on more than a few pixels. 48x36 pixels, the spec's
//! default camera; a third of the unions moved 1e5 from the origin with the camera.

mod common;

use common::against_reference::{off_the_reference, parted, render_against_reference, Compared};
use common::renderer;
use proptest::test_runner::TestCaseError;
use sdfc_render::{RenderOptions, Renderer};
use sdfc_tests::random_instances::instance_union;
use sdfc_tests::random_scene::{cases, run_counted, seed};
use sdfc_wgsl::interp::encode_instances::encode_as_data;
use sdfc_wgsl::{Instances, Options};

const W: u32 = 48;
const H: u32 = 36;

/// How many pixels may part from the code form's with the data form's farther from the
/// reference: at a grazing edge the marcher's path decides, and the two forms' paths differ
/// where their bounds do (`instances.rs` allows the same).
const PARTED_WORSE: usize = 2;

fn compile(
    src: &str,
    instances: Instances,
    cull: bool,
) -> Result<sdfc_wgsl::Compiled, TestCaseError> {
    let opts = Options {
        instances,
        cull,
        ..Options::default()
    };
    sdfc_wgsl::compile(src, &opts).map_err(|e| TestCaseError::fail(format!("{src}\n{e:?}")))
}

/// Fails with `what` where `depth` hits off the reference away from edges or holds a NaN.
fn against(
    src: &str,
    what: &str,
    reference: &sdfc_reference::Image,
    depth: &[f32],
) -> Result<(), TestCaseError> {
    let off = off_the_reference(reference, depth);
    if !off.is_empty() || depth.iter().any(|d| d.is_nan()) {
        return Err(TestCaseError::fail(format!(
            "{src}{what}: pixels off the reference away from edges (x, y, reference hit) {off:?}"
        )));
    }
    Ok(())
}

/// A frame of W x H with its AOVs.
fn aov_options() -> RenderOptions {
    RenderOptions {
        aovs: true,
        ..RenderOptions::sized(W, H)
    }
}

/// The depth AOV of `compiled`'s frame; `what` names the form in a failure.
fn depth_of(
    r: &Renderer,
    src: &str,
    what: &str,
    compiled: &sdfc_wgsl::Compiled,
) -> Result<Vec<f32>, TestCaseError> {
    let frame = r
        .render(compiled, &aov_options())
        .map_err(|e| TestCaseError::fail(format!("{src}: {what}: {e}")))?;
    Ok(frame.aovs.expect("AOVs").depth)
}

fn check(r: &Renderer, src: &str) -> Result<bool, TestCaseError> {
    let data = compile(src, Instances::Always, false)?;
    if data.data.is_empty() {
        // Not found as instances (it must be, but `taken` below counts how often).
        return Ok(false);
    }
    let Compared {
        frame,
        reference,
        metrics: m,
    } = render_against_reference(r, "random instances", &data, W, H);
    let depth = &frame.aovs.as_ref().expect("AOVs").depth;
    if m.nonfinite > 0 || m.depth_median > 1e-5 {
        return Err(TestCaseError::fail(format!(
            "{src}: {} non-finite, depth median {:e} against the reference",
            m.nonfinite, m.depth_median
        )));
    }
    against(src, " as data", &reference, depth)?;

    let code = compile(src, Instances::Never, false)?;
    let code_depth = depth_of(r, src, "code", &code)?;
    let (apart, worse) = parted(depth, &code_depth, &reference);
    if worse > PARTED_WORSE {
        return Err(TestCaseError::fail(format!(
            "{src}: {worse} of the {apart} pixels where the data form parts from the code are \
             farther from the reference"
        )));
    }

    // The same union as code with bounding-box early-outs (`--cull`).
    let culled = compile(src, Instances::Never, true)?;
    against(
        src,
        " culled",
        &reference,
        &depth_of(r, src, "culled", &culled)?,
    )?;

    if let Some(bytecode) = encode_as_data(code.program()) {
        let bytecode = bytecode.map_err(|e| TestCaseError::fail(format!("{src}: {e:?}")))?;
        let interp = r
            .render_bytecode(code.program(), &bytecode, &aov_options())
            .map_err(|e| TestCaseError::fail(format!("{src}: interpreted: {e}")))?;
        against(
            src,
            " interpreted",
            &reference,
            &interp.aovs.as_ref().expect("AOVs").depth,
        )?;
    }
    Ok(true)
}

#[test]
fn random_unions_as_data_draw_what_the_reference_draws() {
    let Some(r) = renderer() else { return };
    let cases = cases(24);
    let taken = run_counted(cases, seed(0x1257), instance_union(), |src| check(r, &src));
    assert_eq!(
        taken, cases as usize,
        "every random union is found as instances"
    );
}
