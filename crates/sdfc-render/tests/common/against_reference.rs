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
    let reference =
        sdfc_reference::render(compiled.program(), &sdfc_reference::Options::sized(w, h));
    let metrics = frame_metrics(&frame, &reference);
    Compared {
        frame,
        reference,
        metrics,
    }
}

/// The metrics of a device frame rendered with AOVs against the reference of its size. (Also
/// the culling bench's and `compare_shader`'s, which include this file.)
pub fn frame_metrics(frame: &Frame, reference: &sdfc_reference::Image) -> Metrics {
    let aovs = frame
        .aovs
        .as_ref()
        .expect("the frame was rendered with AOVs");
    metrics::compare(
        &GpuFrame {
            width: frame.width,
            height: frame.height,
            rgba: &frame.rgba,
            depth: &aovs.depth,
            normal: &aovs.normal,
            steps: &aovs.steps,
        },
        reference,
    )
}

/// Whether the reference's 3x3 neighbourhood of (x, y) holds a silhouette (hits and misses)
/// or a depth edge (hits more than 1% apart): a thin fin or a crease seen edge on, or a
/// surface grazed in front of another, which the pixel's threshold may take or pass either
/// way. A pixel on the image's border counts as one: its neighbourhood is cut, and a
/// silhouette beyond the border cannot be seen (a random field of Sierpinski dust gave a
/// false hit there whose neighbours inside the image all missed).
pub fn is_edge(reference: &sdfc_reference::Image, x: u32, y: u32) -> bool {
    x == 0
        || y == 0
        || x + 1 == reference.width
        || y + 1 == reference.height
        || metrics::is_silhouette(reference, x, y)
        || metrics::is_depth_edge(reference, x, y, 0.01)
}

/// The pixels whose hit or miss in `depth` (a device frame's depth AOV) differs
/// from the reference's away from edges ([`is_edge`]), as (x, y, the reference's hit).
pub fn off_the_reference(
    reference: &sdfc_reference::Image,
    depth: &[f32],
) -> Vec<(u32, u32, bool)> {
    let (w, h) = (reference.width, reference.height);
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            depth[(y * w + x) as usize].is_finite() != reference.pixel(x, y).hit
                && !is_edge(reference, x, y)
        })
        .map(|(x, y)| (x, y, reference.pixel(x, y).hit))
        .collect()
}

/// The median angle, in degrees, between `normal` (a device frame's normal AOV) and the
/// reference's normals over the pixels both hit away from edges ([`is_edge`]) and creases
/// (a hit of the reference's 3x3 neighbourhood whose normal is more than a degree from the
/// pixel's): where the surface is smooth across the pixel, so that the normal is defined
/// whatever the method's step. `None` where no pixel is such.
pub fn smooth_normal_median(
    reference: &sdfc_reference::Image,
    depth: &[f32],
    normal: &[[f32; 3]],
) -> Option<f64> {
    let (w, h) = (reference.width, reference.height);
    let crease = |x: u32, y: u32| {
        let n = reference.pixel(x, y).normal;
        (y.saturating_sub(1)..(y + 2).min(h))
            .flat_map(|j| (x.saturating_sub(1)..(x + 2).min(w)).map(move |i| (i, j)))
            .any(|(i, j)| {
                let r = reference.pixel(i, j);
                r.hit && metrics::angle_deg(r.normal, n) > 1.0
            })
    };
    let mut errors: Vec<f64> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let i = (y * w + x) as usize;
            reference.pixel(x, y).hit
                && depth[i].is_finite()
                && !is_edge(reference, x, y)
                && !crease(x, y)
        })
        .map(|(x, y)| {
            let n = normal[(y * w + x) as usize].map(f64::from);
            metrics::angle_deg(n, reference.pixel(x, y).normal)
        })
        .collect();
    if errors.is_empty() {
        return None;
    }
    errors.sort_by(f64::total_cmp);
    Some(errors[errors.len() / 2])
}

/// The 99.9th percentile of the relative depth error of `depth` (a device frame's depth AOV)
/// against the reference over the pixels both hit away from edges ([`is_edge`]), where the
/// pixel's surface is one surface; `None` where no pixel is such.
pub fn interior_depth_p999(reference: &sdfc_reference::Image, depth: &[f32]) -> Option<f64> {
    let w = reference.width;
    let mut errors: Vec<f64> = (0..reference.height)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter_map(|(x, y)| {
            let (d, r) = (depth[(y * w + x) as usize], reference.pixel(x, y));
            (r.hit && d.is_finite() && !is_edge(reference, x, y))
                .then(|| (f64::from(d) - r.depth).abs() / r.depth.max(1e-30))
        })
        .collect();
    if errors.is_empty() {
        return None;
    }
    errors.sort_by(f64::total_cmp);
    Some(metrics::percentile(&errors, 0.999))
}

/// How many pixels two frames' depths part at (hit against miss, or more than 1e-4 apart),
/// and at how many of them `data`'s is farther from the reference than `code`'s.
pub fn parted(data: &[f32], code: &[f32], reference: &sdfc_reference::Image) -> (usize, usize) {
    let error = |depth: f32, r: &sdfc_reference::Pixel| match (depth.is_finite(), r.hit) {
        (true, true) => (f64::from(depth) - r.depth).abs() / r.depth,
        (false, false) => 0.0,
        _ => f64::INFINITY,
    };
    let (mut apart, mut worse) = (0, 0);
    for ((&a, &b), r) in data.iter().zip(code).zip(&reference.pixels) {
        let parts = if a.is_finite() && b.is_finite() {
            (a - b).abs() > 1e-4 * b.abs()
        } else {
            a.is_finite() != b.is_finite()
        };
        if parts {
            apart += 1;
            worse += usize::from(error(a, r) > error(b, r));
        }
    }
    (apart, worse)
}
