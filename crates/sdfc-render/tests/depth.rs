//! The depth AOV against closed-form ray intersections computed in f64 on the CPU, with the
//! rays of spec section 8 and the default `epsilon: pixel`: the median relative depth error
//! over pixels both call a hit must be below 1e-4, and hit/miss must agree on every pixel
//! away from a silhouette (a pixel whose 3x3 neighbourhood the reference sees all hit or all
//! miss).

mod common;

use common::{compile, renderer};
use sdfc_render::RenderOptions;

const W: u32 = 128;
const H: u32 = 96;

type V = [f64; 3];

fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn mul(a: V, s: f64) -> V {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn normalize(a: V) -> V {
    mul(a, 1.0 / dot(a, a).sqrt())
}
fn f64s(v: [f32; 3]) -> V {
    [v[0] as f64, v[1] as f64, v[2] as f64]
}

/// The camera rays of spec section 8, in f64, from the compiled scene's camera.
struct Camera {
    position: V,
    forward: V,
    right: V,
    up: V,
    tan_half_fov: f64,
}

impl Camera {
    fn of(program: &sdfc_ir::Program) -> Camera {
        let c = &program.scene.camera;
        let position = f64s(c.position);
        let forward = normalize(sub(f64s(c.target), position));
        let right = normalize(cross(forward, f64s(c.up)));
        let up = cross(right, forward);
        Camera {
            position,
            forward,
            right,
            up,
            tan_half_fov: (c.fov as f64 / 2.0).tan(),
        }
    }

    fn ray(&self, i: u32, j: u32) -> V {
        let sx = 2.0 * (i as f64 + 0.5) / W as f64 - 1.0;
        let sy = 1.0 - 2.0 * (j as f64 + 0.5) / H as f64;
        let aspect = W as f64 / H as f64;
        normalize(add(
            add(
                self.forward,
                mul(self.right, sx * self.tan_half_fov * aspect),
            ),
            mul(self.up, sy * self.tan_half_fov),
        ))
    }
}

/// Rotation about a unit axis by `angle` (right-hand rule, Rodrigues), applied to `v`.
fn rotate(axis: V, angle: f64, v: V) -> V {
    let (s, c) = angle.sin_cos();
    add(
        add(mul(v, c), mul(cross(axis, v), s)),
        mul(axis, dot(axis, v) * (1.0 - c)),
    )
}

fn sphere_t(o: V, d: V, centre: V, r: f64) -> Option<f64> {
    let oc = sub(o, centre);
    let b = dot(oc, d);
    let c = dot(oc, oc) - r * r;
    let disc = b * b - c;
    if disc < 0.0 {
        return None;
    }
    let t = -b - disc.sqrt();
    (t > 0.0).then_some(t)
}

/// Slab method in the box's own frame; `half` are the half extents.
fn box_t(o: V, d: V, half: V) -> Option<f64> {
    let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        let t1 = (-half[k] - o[k]) / d[k];
        let t2 = (half[k] - o[k]) / d[k];
        near = near.max(t1.min(t2));
        far = far.min(t1.max(t2));
    }
    (near <= far && near > 0.0).then_some(near)
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    let i = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[i]
}

/// Renders `source` with AOVs and compares its depth with `reference(origin, dir)`.
fn check_depth(name: &str, source: &str, reference: impl Fn(V, V) -> Option<f64>) {
    let Some(r) = renderer() else { return };
    let compiled = compile(name, source);
    let frame = r
        .render(
            &compiled,
            &RenderOptions {
                width: W,
                height: H,
                aovs: true,
                ..RenderOptions::default()
            },
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let depth = &frame.aovs.as_ref().unwrap().depth;
    let cam = Camera::of(compiled.program());
    let refs: Vec<Option<f64>> = (0..H)
        .flat_map(|j| (0..W).map(move |i| (i, j)))
        .map(|(i, j)| reference(cam.position, cam.ray(i, j)))
        .collect();
    let mut errors = Vec::new();
    let mut interior_errors = Vec::new();
    let mut disagree = Vec::new();
    let mut silhouette = 0;
    for j in 0..H {
        for i in 0..W {
            let k = (j * W + i) as usize;
            let (gpu, cpu) = (depth[k], refs[k]);
            let interior = (-1i32..=1).all(|dj| {
                (-1i32..=1).all(|di| {
                    let (x, y) = (i as i32 + di, j as i32 + dj);
                    x < 0
                        || y < 0
                        || x >= W as i32
                        || y >= H as i32
                        || refs[(y as u32 * W + x as u32) as usize].is_some() == cpu.is_some()
                })
            });
            if let (true, Some(t)) = (gpu.is_finite(), cpu) {
                let e = ((gpu as f64 - t) / t).abs();
                errors.push(e);
                if interior {
                    interior_errors.push(e);
                }
            }
            if gpu.is_finite() != cpu.is_some() {
                if interior {
                    disagree.push((i, j, gpu, cpu));
                } else {
                    silhouette += 1;
                }
            }
        }
    }
    assert!(
        errors.len() > (W * H / 10) as usize,
        "{name}: only {} hit pixels",
        errors.len()
    );
    errors.sort_by(|a, b| a.total_cmp(b));
    interior_errors.sort_by(|a, b| a.total_cmp(b));
    let median = percentile(&errors, 0.5);
    eprintln!(
        "{name}: {} hit pixels, relative depth error median {median:.3e}, 99.9th percentile \
         {:.3e}, max {:.3e}; away from silhouettes ({} pixels) median {:.3e}, 99.9th \
         percentile {:.3e}, max {:.3e}; {silhouette} silhouette pixels disagree on hit/miss",
        errors.len(),
        percentile(&errors, 0.999),
        errors.last().unwrap(),
        interior_errors.len(),
        percentile(&interior_errors, 0.5),
        percentile(&interior_errors, 0.999),
        interior_errors.last().unwrap(),
    );
    assert!(
        disagree.is_empty(),
        "{name}: hit/miss disagrees away from silhouettes at (x, y, gpu depth, reference) {:?}",
        &disagree[..disagree.len().min(10)]
    );
    assert!(
        median < 1e-4,
        "{name}: median relative depth error {median:e}"
    );
}

#[test]
fn sphere_depth_matches_the_closed_form() {
    let centre = [0.2, -0.1, 0.3];
    let radius = 1.1;
    check_depth(
        "sphere",
        "camera { position: [0.3, 0.8, 4], target: [0, 0, 0], fov: 50deg }\n\
         scene = sphere(1.1).translate([0.2, -0.1, 0.3]);\n",
        |o, d| sphere_t(o, d, centre, radius),
    );
}

#[test]
fn rotated_box_depth_matches_the_slab_method() {
    // box([1.6, 1.0, 1.2]).rotate([1, 2, 0.5], 35deg).translate(c): a world point p is
    // R^T (p - c) in the box's frame.
    let axis = normalize([1.0, 2.0, 0.5]);
    let angle = 35f64.to_radians();
    let c = [0.1, 0.2, -0.3];
    check_depth(
        "rotated box",
        "camera { position: [1.5, 1.2, 4.5], target: [0, 0, 0], fov: 30deg }\n\
         scene = box([1.6, 1.0, 1.2]).rotate([1, 2, 0.5], 35deg).translate([0.1, 0.2, -0.3]);\n",
        |o, d| {
            let lo = rotate(axis, -angle, sub(o, c));
            let ld = rotate(axis, -angle, d);
            box_t(lo, ld, [0.8, 0.5, 0.6])
        },
    );
}
