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

/// Pixels `[x0, x1) x [y0, y1)` outside of which no primary ray of the entry point meets the
/// scene's padded bounds (the box of `ray_span`); an empty rectangle where none does. The box's
/// corners projected as the entry point's rays are cast (`camera_ray`, any sample offset in
/// the pixel), widened by two pixels for the shader's f32 arithmetic. `None` where that cannot
/// be said: bounds infinite on an axis (a plane, a repetition, a param in the bounds), a
/// corner of the box beside or behind the camera (so the camera may see it all round), or
/// values that are not finite.
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
    // floor(x_max), two more each side.
    let clamp = |v: f64, n: u32| v.clamp(0.0, n as f64) as u32;
    let x0 = clamp(x_min.floor() - 2.0, width);
    let x1 = clamp(x_max.floor() + 3.0, width);
    let y0 = clamp(y_min.floor() - 2.0, height);
    let y1 = clamp(y_max.floor() + 3.0, height);
    if x0 >= x1 || y0 >= y1 {
        return Some([0; 4]);
    }
    Some([x0, y0, x1, y1])
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
