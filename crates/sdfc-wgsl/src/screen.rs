//! The part of the image whose rays can meet the scene's bounds, so that a host dispatches
//! only those pixels' invocations (shader interface: `frame.flags` bits 8 to 31).
//!
//! Every other primary ray misses the box `ray_span` clips rays to and takes no step; it shows
//! the background, and its secondary rays (shadows, reflections) start only at hits. On a GPU
//! such an invocation is cheap; on llvmpipe it is not: every line of the shader runs under
//! masks for each group of lanes, hit or not, so the 300-shape grid seen from its suite's
//! camera (5% of the image's tiles near the grid) spent most of its frame on rays that never
//! reached the grid (docs/performance.md, "Tiles the scene cannot be in").

use crate::marcher::{camera_basis, root_bounds, span_slabs};
use sdfc_ir::Program;

/// The entry point's line that reads the dispatch's first tile (`shaders/main.wgsl`).
const FIRST_TILE: &str =
    "let first = vec2<u32>((frame.flags >> 8u) & 0xfffu, frame.flags >> 20u) * 8u;";

/// Whether a full shader's entry point reads the dispatch's first tile from `frame.flags`, so
/// that part of the image may be dispatched: every shader sdfc emits does, one emitted before
/// it did or written by hand may not, and is then dispatched whole.
pub fn reads_first_tile(wgsl: &str) -> bool {
    wgsl.contains(FIRST_TILE)
}

/// Pixels `[x0, x1) x [y0, y1)` outside of which no primary ray of the entry point meets the
/// scene's padded bounds (the box of `ray_span`); an empty rectangle where none does. The box's
/// corners projected as the entry point's rays are cast (`camera_ray`, any sample offset in
/// the pixel), widened for the shader's f32 arithmetic (three pixels, more at a very narrow
/// field of view). `None` where that cannot be said: bounds infinite on an axis (a plane, a
/// repetition, a param in the bounds), a corner of the box beside or behind the camera (so
/// the camera may see it all round), or values that are not finite.
pub fn screen_rect(p: &Program, width: u32, height: u32) -> Option<[u32; 4]> {
    let slabs = span_slabs(root_bounds(p), [0.0; 3]);
    let mut lo = [0.0f64; 3];
    let mut hi = [0.0f64; 3];
    for (k, slab) in slabs.iter().enumerate() {
        let (a, b) = (*slab)?;
        lo[k] = a as f64;
        hi[k] = b as f64;
    }
    let (forward, right, up, tan_half) = camera_basis(&p.scene);
    let c = p.scene.camera.position.map(|x| x as f64);
    let dot = |a: [f64; 3], b: [f32; 3]| (0..3).map(|k| a[k] * b[k] as f64).sum::<f64>();
    let (w, h) = (width as f64, height as f64);
    let tan = tan_half as f64;
    let aspect = w / h;
    let (mut x_min, mut x_max) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut y_min, mut y_max) = (f64::INFINITY, f64::NEG_INFINITY);
    for corner in 0..8 {
        let p: [f64; 3] = std::array::from_fn(|k| if corner >> k & 1 == 1 { hi[k] } else { lo[k] });
        let v = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
        let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let z = dot(v, forward);
        // A corner nearly beside the camera projects far off the image, or behind it
        // wraps round: no rectangle then (nor for a NaN).
        if z.is_nan() || z <= 1e-3 * length {
            return None;
        }
        // camera_ray: direction forward + sx tan aspect right + sy tan up, with
        // sx = 2 x / width - 1 and sy = 1 - 2 y / height at pixel position (x, y).
        let sx = dot(v, right) / (z * tan * aspect);
        let sy = dot(v, up) / (z * tan);
        let x = (sx + 1.0) * 0.5 * w;
        let y = (1.0 - sy) * 0.5 * h;
        x_min = x_min.min(x);
        x_max = x_max.max(x);
        y_min = y_min.min(y);
        y_max = y_max.max(y);
    }
    if ![x_min, x_max, y_min, y_max].iter().all(|v| v.is_finite()) {
        return None;
    }
    // A pixel's samples lie in [column, column + 1): the columns from floor(x_min) to
    // floor(x_max), and a margin each side for the shader's f32 arithmetic. Its ray's
    // direction (`camera_ray`: a sum of f32 vectors, normalised) is off by a few units in the
    // last place, an angle of about 2^-24 each; a pixel subtends 2 tan(fov / 2) / height. So
    // two pixels and the pixels 16 such units span, rounded up (one at an ordinary field of
    // view; at 1e-5 degrees and 48 pixels high, 262).
    let margin = margin(h, tan);
    let clamp = |v: f64, n: u32| v.clamp(0.0, n as f64) as u32;
    let x0 = clamp(x_min.floor() - margin, width);
    let x1 = clamp(x_max.floor() + 1.0 + margin, width);
    let y0 = clamp(y_min.floor() - margin, height);
    let y1 = clamp(y_max.floor() + 1.0 + margin, height);
    if x0 >= x1 || y0 >= y1 {
        return Some([0; 4]);
    }
    Some([x0, y0, x1, y1])
}

/// The pixels added on each side of the projected box for an image `height` pixels high
/// under a field of view of `2 atan(tan_half)` (see `screen_rect`).
fn margin(height: f64, tan_half: f64) -> f64 {
    2.0 + (16.0 * f64::from(f32::EPSILON) * 0.5 * height / (2.0 * tan_half)).ceil()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn program(source: &str) -> Program {
        crate::compile(source, &crate::Options::default())
            .unwrap_or_else(|f| panic!("{f:?}"))
            .stages
            .program
    }

    const CAMERA: &str = "camera { position: [0, 0, 10], target: [0, 0, 0], fov: 50deg }\n";

    #[test]
    fn the_entry_point_reads_the_first_tile() {
        assert!(reads_first_tile(crate::parts::MAIN));
        let wgsl = crate::compile("scene = sphere(1);", &crate::Options::default())
            .unwrap()
            .wgsl;
        assert!(reads_first_tile(&wgsl));
        assert!(reads_first_tile(&crate::interp::emit()));
        assert!(!reads_first_tile(
            &wgsl.replace(FIRST_TILE, "let first = vec2<u32>(0u);")
        ));
    }

    #[test]
    fn the_margin_grows_where_a_pixel_is_finer_than_f32_directions() {
        let tan = |degrees: f64| (0.5 * degrees.to_radians()).tan();
        assert_eq!(margin(48.0, tan(50.0)), 3.0);
        assert_eq!(margin(1080.0, tan(50.0)), 3.0);
        // 1e-5 degrees (tests/stress/narrow_fov.sdf): a pixel is 4e-9 radians, f32's
        // directions are good to about 6e-8.
        assert!(margin(48.0, tan(1e-5)) > 200.0);
    }

    #[test]
    fn a_sphere_ahead_covers_the_middle_and_not_the_corners() {
        let p = program(&format!("{CAMERA}scene = sphere(1);"));
        let [x0, y0, x1, y1] = screen_rect(&p, 160, 120).expect("a bounded scene ahead");
        // The unit sphere 10 away under a 50 degree field of view: a radius of about
        // 1 / (10 tan 25deg) of half the height, 12.9 pixels, plus the padding.
        assert!(
            x0 > 0 && y0 > 0 && x1 < 160 && y1 < 120,
            "{x0} {y0} {x1} {y1}"
        );
        assert!(x0 <= 80 - 13 && x1 >= 80 + 13, "{x0} {x1}");
        assert!(y0 <= 60 - 13 && y1 >= 60 + 13, "{y0} {y1}");
        assert!(x1 - x0 < 40 && y1 - y0 < 40, "{x0} {y0} {x1} {y1}");
    }

    #[test]
    fn behind_the_camera_no_rectangle_and_off_the_image_an_empty_one() {
        let behind = format!("{CAMERA}scene = sphere(1).translate([0, 0, 20]);");
        assert_eq!(screen_rect(&program(&behind), 64, 48), None);
        let aside = format!("{CAMERA}scene = sphere(1).translate([40, 0, 0]);");
        assert_eq!(screen_rect(&program(&aside), 64, 48), Some([0; 4]));
    }

    #[test]
    fn no_rectangle_for_unbounded_scenes_or_a_camera_inside_the_bounds() {
        let plane = format!("{CAMERA}scene = sphere(1) | plane([0, 1, 0], 1);");
        assert_eq!(screen_rect(&program(&plane), 64, 48), None);
        let inside = format!("{CAMERA}scene = box([20, 20, 20]);");
        assert_eq!(screen_rect(&program(&inside), 64, 48), None);
    }
}
