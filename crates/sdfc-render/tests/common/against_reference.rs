//! A device render next to the f64 reference render of the same scene, and the metrics of
//! one against the other (`sdfc_reference::metrics`).

use sdfc_reference::metrics::{self, GpuFrame, Metrics};
use sdfc_render::{Frame, RenderOptions, Renderer};

/// The device frame (with AOVs), the reference image, and the metrics.
pub struct Compared {
    pub frame: Frame,
    pub reference: sdfc_reference::Image,
    pub metrics: Metrics,
}

/// Renders `compiled` at `w` x `h` on the device and with the reference, and compares them;
/// panics (failing the test, named `name`) if the device render fails.
pub fn render_against_reference(
    r: &Renderer,
    name: &str,
    compiled: &sdfc_wgsl::Compiled,
    w: u32,
    h: u32,
) -> Compared {
    let frame = r
        .render(
            compiled,
            &RenderOptions {
                aovs: true,
                ..RenderOptions::sized(w, h)
            },
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let aovs = frame.aovs.as_ref().expect("AOVs were asked for");
    let reference =
        sdfc_reference::render(compiled.program(), &sdfc_reference::Options::sized(w, h));
    let metrics = metrics::compare(
        &GpuFrame {
            width: w,
            height: h,
            rgba: &frame.rgba,
            depth: &aovs.depth,
            normal: &aovs.normal,
            steps: &aovs.steps,
        },
        &reference,
    );
    Compared {
        frame,
        reference,
        metrics,
    }
}
