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
/// scene's padded bounds (the box of `ray_span`) within MAX_DISTANCE; an empty rectangle where
/// none does. The box, closed on its open sides by the cube of MAX_DISTANCE about the camera
/// and cut by a plane just ahead of the camera, is projected as the entry point's rays are
/// cast (`camera_ray`, any sample offset in the pixel), widened for the shader's f32
/// arithmetic (three pixels, more at a very narrow field of view). `None` where that cannot
/// be said: the camera inside the box (it may see it all round), or values that are not
/// finite.
pub fn screen_rect(p: &Program, width: u32, height: u32) -> Option<[u32; 4]> {
    let slabs = span_slabs(root_bounds(p), [0.0; 3]);
    let c = p.scene.camera.position.map(|x| x as f64);
    // Every point a primary ray reaches lies within MAX_DISTANCE of the camera (its
    // direction is normalised; a thousandth more for f32's).
    let reach = 1.001 * p.scene.render.max_distance as f64;
    let mut lo = [0.0f64; 3];
    let mut hi = [0.0f64; 3];
    for (k, slab) in slabs.iter().enumerate() {
        lo[k] = slab
            .lo
            .map_or(f64::NEG_INFINITY, f64::from)
            .max(c[k] - reach);
        hi[k] = slab.hi.map_or(f64::INFINITY, f64::from).min(c[k] + reach);
        if lo[k] > hi[k] {
            return Some([0; 4]);
        }
    }
    // How far the camera is outside the box (along an axis): every point of the box is at
    // least that far from it.
    let outside = (0..3)
        .map(|k| (lo[k] - c[k]).max(c[k] - hi[k]))
        .fold(0.0f64, f64::max);
    if outside.is_nan() || outside <= 0.0 {
        return None;
    }
    let (forward, right, up, tan_half) = camera_basis(&p.scene);
    let dot = |a: [f64; 3], b: [f32; 3]| (0..3).map(|k| a[k] * b[k] as f64).sum::<f64>();
    let (w, h) = (width as f64, height as f64);
    let tan = tan_half as f64;
    let aspect = w / h;
    // A pixel's ray through a point at depth z passes within z tan(fov / 2) sqrt(aspect^2 + 1)
    // of the view axis; at depths below `near` that is under half the distance to the box,
    // so no ray meets the box there, and the box is cut at `near` (a box reaching behind the
    // camera projects to a finite rectangle, its near side far off the image).
    let spread = tan * (aspect * aspect + 1.0).sqrt();
    let near = outside / (2.0 * (1.0 + spread * spread).sqrt());
    let corner = |i: usize| -> [f64; 3] {
        std::array::from_fn(|k| if i >> k & 1 == 1 { hi[k] } else { lo[k] })
    };
    let depth = |q: [f64; 3]| dot([q[0] - c[0], q[1] - c[1], q[2] - c[2]], forward);
    let mut points = Vec::with_capacity(20);
    for i in 0..8 {
        let a = corner(i);
        if depth(a) >= near {
            points.push(a);
        }
        // The box's edges from this corner that cross the cut.
        for k in (0..3).filter(|k| i >> k & 1 == 0) {
            let b = corner(i | 1 << k);
            let (za, zb) = (depth(a), depth(b));
            if (za < near) != (zb < near) {
                let s = (near - za) / (zb - za);
                points.push(std::array::from_fn(|j| a[j] + s * (b[j] - a[j])));
            }
        }
    }
    let (mut x_min, mut x_max) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut y_min, mut y_max) = (f64::INFINITY, f64::NEG_INFINITY);
    for q in &points {
        let v = [q[0] - c[0], q[1] - c[1], q[2] - c[2]];
        // Never below the cut, however the interpolation rounded.
        let z = dot(v, forward).max(near);
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
    if points.is_empty() {
        return Some([0; 4]);
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
    fn behind_the_camera_aside_or_out_of_reach_an_empty_rectangle() {
        let behind = format!("{CAMERA}scene = sphere(1).translate([0, 0, 20]);");
        assert_eq!(screen_rect(&program(&behind), 64, 48), Some([0; 4]));
        let aside = format!("{CAMERA}scene = sphere(1).translate([40, 0, 0]);");
        assert_eq!(screen_rect(&program(&aside), 64, 48), Some([0; 4]));
        let far = format!(
            "{CAMERA}render {{ max_distance: 50 }}\nscene = sphere(1).translate([0, 0, -60]);"
        );
        assert_eq!(screen_rect(&program(&far), 64, 48), Some([0; 4]));
    }

    #[test]
    fn no_rectangle_for_a_camera_inside_the_bounds() {
        let plane = format!("{CAMERA}scene = sphere(1) | plane([0, 1, 0], 1);");
        assert_eq!(screen_rect(&program(&plane), 64, 48), None);
        let inside = format!("{CAMERA}scene = box([20, 20, 20]);");
        assert_eq!(screen_rect(&program(&inside), 64, 48), None);
    }

    #[test]
    fn a_floor_below_the_camera_leaves_out_the_sky() {
        // Looking level from 2 above the floor: the horizon is the middle row.
        let floor = "camera { position: [0, 2, 10], target: [0, 2, 0], fov: 50deg }\n\
                     scene = plane([0, 1, 0], 0) | sphere(1);";
        let [x0, y0, x1, y1] = screen_rect(&program(floor), 64, 48).expect("a rectangle");
        assert_eq!((x0, x1, y1), (0, 64, 48));
        assert!((20..24).contains(&y0), "{y0}");
        // A ceiling above it: the sky only.
        let ceiling = floor.replace("plane([0, 1, 0], 0) | sphere(1)", "plane([0, -1, 0], -4)");
        let [_, y0, _, y1] = screen_rect(&program(&ceiling), 64, 48).expect("a rectangle");
        assert_eq!(y0, 0);
        assert!((24..28).contains(&y1), "{y1}");
    }

    /// The f64 stretch of the ray from `c` along `d` (normalised) inside `[lo, hi]`,
    /// limited to `[0, reach]`: whether it is not empty.
    fn meets(c: [f64; 3], d: [f64; 3], lo: [f64; 3], hi: [f64; 3], reach: f64) -> bool {
        let (mut t0, mut t1) = (0.0f64, reach);
        for k in 0..3 {
            let (a, b) = ((lo[k] - c[k]) / d[k], (hi[k] - c[k]) / d[k]);
            let (a, b) = if a.is_nan() {
                (f64::NEG_INFINITY, f64::INFINITY)
            } else {
                (a, b)
            };
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        t0 <= t1
    }

    #[test]
    fn every_pixel_whose_ray_meets_the_bounds_lies_in_the_rectangle() {
        // Each pixel's corners and centre, cast in f64 as the entry point casts them, against
        // the box `ray_span` clips to; half-spaces, boxes reaching behind the camera, boxes
        // cut by MAX_DISTANCE, cameras looking every way.
        let scenes = [
            "plane([0, 1, 0], 0.5)",
            "plane([0, -1, 0], -3) & plane([1, 0, 0], 1)",
            "plane([0, 0, 1], 0).translate([0, 0, -2])",
            "box([40, 1, 40]).translate([0, -2, 0])",
            "box([1, 1, 30])",
            "sphere(2).translate([3, 1, -8])",
            "box([100, 0.5, 2]).translate([0, 0, -35])",
        ];
        let cameras = [
            ("[0, 2.5, 6]", "[0, 0.3, 0]"),
            ("[0, 2, 10]", "[0, 2, 0]"),
            ("[5, 6, 3]", "[0, 0, 0]"),
            ("[0, 2, 4]", "[0, 10, 0]"),
        ];
        for scene in scenes {
            for (position, target) in cameras {
                let source = format!(
                    "camera {{ position: {position}, target: {target}, fov: 60deg }}\n\
                     render {{ max_distance: 40 }}\nscene = {scene};"
                );
                let p = program(&source);
                let (w, h) = (48u32, 32u32);
                let rect = screen_rect(&p, w, h);
                let Some([x0, y0, x1, y1]) = rect else {
                    continue;
                };
                let slabs = span_slabs(root_bounds(&p), [0.0; 3]);
                let lo = slabs.map(|s| s.lo.map_or(f64::NEG_INFINITY, f64::from));
                let hi = slabs.map(|s| s.hi.map_or(f64::INFINITY, f64::from));
                let (f, r, u, tan) = camera_basis(&p.scene);
                let c = p.scene.camera.position.map(f64::from);
                let tan = tan as f64;
                let aspect = w as f64 / h as f64;
                for y in 0..h {
                    for x in 0..w {
                        let inside = (x0..x1).contains(&x) && (y0..y1).contains(&y);
                        for (ox, oy) in [
                            (0.0, 0.0),
                            (0.999, 0.0),
                            (0.0, 0.999),
                            (0.999, 0.999),
                            (0.5, 0.5),
                        ] {
                            let sx = 2.0 * (x as f64 + ox) / w as f64 - 1.0;
                            let sy = 1.0 - 2.0 * (y as f64 + oy) / h as f64;
                            let d: [f64; 3] = std::array::from_fn(|k| {
                                f[k] as f64
                                    + sx * tan * aspect * r[k] as f64
                                    + sy * tan * u[k] as f64
                            });
                            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                            let d = d.map(|v| v / l);
                            let hit = meets(c, d, lo, hi, p.scene.render.max_distance as f64);
                            assert!(
                                inside || !hit,
                                "{source}: pixel ({x}, {y}) meets the bounds outside {rect:?}"
                            );
                        }
                    }
                }
            }
        }
    }
}
