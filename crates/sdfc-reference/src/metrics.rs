//! Error metrics of a GPU frame against the reference: relative depth error, hit/miss
//! mismatches (silhouette pixels apart), normal angular error, colour error, and non-finite
//! AOV values. Inputs are plain slices so any renderer can be compared.

use crate::Image;

/// A GPU frame as plain data, row-major with the top row first.
#[derive(Clone, Copy, Debug)]
pub struct GpuFrame<'a> {
    pub width: u32,
    pub height: u32,
    /// RGBA8, `4 * width * height` bytes.
    pub rgba: &'a [u8],
    /// t along the centre ray; `+inf` on a miss.
    pub depth: &'a [f32],
    /// World-space normal; zero on a miss.
    pub normal: &'a [[f32; 3]],
    /// March steps.
    pub steps: &'a [f32],
}

/// The comparison of one frame with its reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Metrics {
    pub pixels: usize,
    /// Pixels the reference calls a hit.
    pub reference_hits: usize,
    /// Pixels both call a hit (depth and normal errors are over these).
    pub both_hit: usize,
    /// |t_gpu - t_ref| / t_ref over pixels both hit (t_ref = 0, a camera inside a shape:
    /// the absolute error).
    pub depth_median: f64,
    pub depth_p999: f64,
    pub depth_max: f64,
    /// Hit/miss disagreements at pixels whose 3x3 neighbourhood in the reference is all hit
    /// or all miss.
    pub mismatch_interior: usize,
    /// Disagreements at silhouette pixels (the neighbourhood has both).
    pub mismatch_silhouette: usize,
    /// Angle between the normals, degrees, over pixels both hit.
    pub normal_median_deg: f64,
    pub normal_p99_deg: f64,
    pub normal_max_deg: f64,
    /// Mean absolute RGB difference in 0..255 units.
    pub colour_mae: f64,
    /// PSNR of the RGB channels in dB (infinite when identical).
    pub psnr_db: f64,
    /// Pixels with a NaN or infinity in the GPU AOVs (a miss's `+inf` depth excepted).
    pub nonfinite: usize,
    /// Pixels with a negative or NaN GPU depth.
    pub negative_depth: usize,
    pub mean_steps_gpu: f64,
    pub mean_steps_reference: f64,
    /// The pixels with the largest relative depth errors, worst first (at most 5).
    pub worst_depth: Vec<PixelError>,
    /// The pixels with the largest normal errors, worst first (at most 5).
    pub worst_normal: Vec<PixelError>,
    /// Hit/miss disagreements away from silhouettes (at most 5).
    pub interior_mismatches: Vec<PixelError>,
}

/// One pixel's GPU and reference values, to find where an error comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelError {
    pub x: u32,
    pub y: u32,
    pub gpu_depth: f32,
    pub reference_depth: f64,
    /// The angle between the normals, degrees (0 unless both hit).
    pub normal_deg: f64,
}

/// The value at fraction `q` of sorted data (nearest rank); 0 for no data.
pub fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    let i = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

/// True where the reference's 3x3 neighbourhood of (x, y) holds both hits and misses.
pub fn is_silhouette(reference: &Image, x: u32, y: u32) -> bool {
    let me = reference.pixel(x, y).hit;
    (-1i64..=1).any(|dy| {
        (-1i64..=1).any(|dx| {
            let (nx, ny) = (x as i64 + dx, y as i64 + dy);
            nx >= 0
                && ny >= 0
                && nx < reference.width as i64
                && ny < reference.height as i64
                && reference.pixel(nx as u32, ny as u32).hit != me
        })
    })
}

/// True where the hits of the reference's 3x3 neighbourhood of (x, y) lie more than `rel`
/// (relative to the farthest) apart: a depth edge, a shape in front of another, or a crease
/// or fin seen edge on.
pub fn is_depth_edge(reference: &Image, x: u32, y: u32, rel: f64) -> bool {
    let (mut near, mut far) = (f64::INFINITY, 0.0f64);
    for dy in -1i64..=1 {
        for dx in -1i64..=1 {
            let (nx, ny) = (x as i64 + dx, y as i64 + dy);
            if nx < 0 || ny < 0 || nx >= reference.width as i64 || ny >= reference.height as i64 {
                continue;
            }
            let p = reference.pixel(nx as u32, ny as u32);
            if p.hit {
                near = near.min(p.depth);
                far = far.max(p.depth);
            }
        }
    }
    far - near > rel * far
}

/// The angle between two vectors, degrees (180 where either is zero or NaN).
pub fn angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    let la = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let lb = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
    if !(la > 0.0 && lb > 0.0) {
        return 180.0;
    }
    let c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb);
    c.clamp(-1.0, 1.0).acos().to_degrees()
}

/// Compares `gpu` with `reference` (same size, or the metrics cover nothing).
pub fn compare(gpu: &GpuFrame, reference: &Image) -> Metrics {
    let n = (gpu.width as usize) * (gpu.height as usize);
    let same = gpu.width == reference.width
        && gpu.height == reference.height
        && gpu.rgba.len() == 4 * n
        && gpu.depth.len() == n
        && gpu.normal.len() == n
        && gpu.steps.len() == n
        && reference.pixels.len() == n;
    let n = if same { n } else { 0 };
    let mut depth_err = Vec::new();
    let mut worst: Vec<(f64, PixelError)> = Vec::new();
    let mut interior_list = Vec::new();
    let mut normal_err = Vec::new();
    let (mut interior, mut silhouette, mut nonfinite, mut negative) = (0, 0, 0, 0);
    let (mut abs_sum, mut sq_sum) = (0.0, 0.0);
    let (mut steps_gpu, mut steps_ref) = (0.0, 0.0);
    for i in 0..n {
        let (x, y) = (
            (i % gpu.width as usize) as u32,
            (i / gpu.width as usize) as u32,
        );
        let r = &reference.pixels[i];
        let (d, nrm, s) = (gpu.depth[i], gpu.normal[i], gpu.steps[i]);
        let bad = d.is_nan()
            || d == f32::NEG_INFINITY
            || nrm.iter().any(|c| !c.is_finite())
            || !s.is_finite();
        if bad {
            nonfinite += 1;
        }
        if d.is_nan() || d < 0.0 {
            negative += 1;
        }
        let gpu_hit = d.is_finite();
        let mut pe = PixelError {
            x,
            y,
            gpu_depth: d,
            reference_depth: r.depth,
            normal_deg: 0.0,
        };
        if gpu_hit != r.hit {
            if is_silhouette(reference, x, y) {
                silhouette += 1;
            } else {
                interior += 1;
                if interior_list.len() < 5 {
                    interior_list.push(pe);
                }
            }
        } else if gpu_hit {
            let e = (d as f64 - r.depth).abs();
            let e = if r.depth > 0.0 { e / r.depth } else { e };
            depth_err.push(e);
            pe.normal_deg = angle_deg(nrm.map(|c| c as f64), r.normal);
            normal_err.push(pe.normal_deg);
            worst.push((e, pe));
        }
        for c in 0..3 {
            let e = gpu.rgba[4 * i + c] as f64 - r.rgba[c] as f64;
            abs_sum += e.abs();
            sq_sum += e * e;
        }
        steps_gpu += if s.is_finite() { s as f64 } else { 0.0 };
        steps_ref += r.steps as f64;
    }
    let mut worst_normal: Vec<PixelError> = worst.iter().map(|w| w.1).collect();
    worst_normal.sort_by(|a, b| b.normal_deg.total_cmp(&a.normal_deg));
    worst_normal.truncate(5);
    worst.sort_by(|a, b| b.0.total_cmp(&a.0));
    worst.truncate(5);
    let nan_last = |v: &mut Vec<f64>| v.sort_by(|a, b| a.total_cmp(b));
    nan_last(&mut depth_err);
    nan_last(&mut normal_err);
    let samples = (3 * n).max(1) as f64;
    let mse = sq_sum / samples;
    Metrics {
        pixels: n,
        reference_hits: reference.pixels.iter().take(n).filter(|p| p.hit).count(),
        both_hit: depth_err.len(),
        depth_median: percentile(&depth_err, 0.5),
        depth_p999: percentile(&depth_err, 0.999),
        depth_max: depth_err.last().copied().unwrap_or(0.0),
        mismatch_interior: interior,
        mismatch_silhouette: silhouette,
        normal_median_deg: percentile(&normal_err, 0.5),
        normal_p99_deg: percentile(&normal_err, 0.99),
        normal_max_deg: normal_err.last().copied().unwrap_or(0.0),
        colour_mae: abs_sum / samples,
        psnr_db: if mse > 0.0 {
            10.0 * (255.0 * 255.0 / mse).log10()
        } else {
            f64::INFINITY
        },
        nonfinite,
        negative_depth: negative,
        mean_steps_gpu: steps_gpu / n.max(1) as f64,
        mean_steps_reference: steps_ref / n.max(1) as f64,
        worst_depth: worst.into_iter().map(|w| w.1).collect(),
        worst_normal,
        interior_mismatches: interior_list,
    }
}

/// The column names of [`row`], for tables.
pub const COLUMNS: [&str; 12] = [
    "hits",
    "depth med",
    "depth p99.9",
    "miss int",
    "miss sil",
    "normal med°",
    "normal p99°",
    "colour MAE",
    "PSNR dB",
    "NaN/Inf",
    "steps gpu",
    "steps ref",
];

/// One table row of the metrics, in the order of [`COLUMNS`].
pub fn row(m: &Metrics) -> [String; 12] {
    [
        format!("{}/{}", m.both_hit, m.reference_hits),
        format!("{:.2e}", m.depth_median),
        format!("{:.2e}", m.depth_p999),
        m.mismatch_interior.to_string(),
        m.mismatch_silhouette.to_string(),
        format!("{:.3}", m.normal_median_deg),
        format!("{:.3}", m.normal_p99_deg),
        format!("{:.2}", m.colour_mae),
        format!("{:.1}", m.psnr_db),
        m.nonfinite.to_string(),
        format!("{:.1}", m.mean_steps_gpu),
        format!("{:.1}", m.mean_steps_reference),
    ]
}
