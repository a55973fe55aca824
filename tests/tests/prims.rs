//! The primitives of spec section 4 beyond the first seven, on the f64 reference evaluator,
//! against references derived independently here:
//!
//! - exact shapes (box_frame, capped_torus, infinite_cylinder, cone, capped_cone, octahedron,
//!   hex_prism, tri_prism, pyramid): generic geometry (2D polygon distances with an even-odd
//!   sign, point-triangle and point-box distances, the distance to a circle arc). A value
//!   passes when `|eval - reference| <= REL * |reference| + ABS`, REL = 1e-6 and
//!   ABS = 1e-9 (both are f64 computations; the absolute term covers values near zero).
//! - bound shapes: the ellipsoid against its true distance found numerically (and
//!   `|d(p) - d(q)| <= |p - q|` on nearby pairs); menger and
//!   sierpinski against independent membership tests (base-3 digits, barycentric binary
//!   digits) for the sign and against sampled member and non-member points for the bound;
//!   the mandelbulb for its bounding sphere, escape sign and finiteness.
//!
//! Argument values are exactly representable in f32 so that the compiler's f32 constants
//! are the values the references use.

use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_wgsl::{compile, Options};

const REL: f64 = 1e-6;
const ABS: f64 = 1e-9;
const POINTS: usize = 4000;

use sdfc_tests::SplitMix;

struct Shape {
    program: sdfc_ir::Program,
}

impl Shape {
    fn new(scene: &str) -> Shape {
        let src = format!("scene = {scene};\n");
        match compile(&src, &Options::default()) {
            Ok(c) => Shape {
                program: c.program().clone(),
            },
            Err(e) => panic!("{scene}: {e:?}"),
        }
    }

    fn at(&self, p: [f64; 3]) -> f64 {
        let prog = &self.program;
        eval_func(&prog.distance, &prog.groups, &Inputs::at(p))[0]
            .scalar()
            .unwrap()
    }
}

fn eval(s: &Shape, p: [f64; 3]) -> f64 {
    s.at(p)
}

/// Compares the evaluator with `reference` at `POINTS` points of the cube [lo, hi]^3 and
/// returns the worst error relative to `|reference|` (where it exceeds 1e-3) and absolute.
fn exact(scene: &str, lo: f64, hi: f64, seed: u64, reference: impl Fn([f64; 3]) -> f64) {
    let s = Shape::new(scene);
    let mut rng = SplitMix(seed);
    let (mut worst_rel, mut worst_abs) = (0f64, 0f64);
    let (mut inside, mut outside) = (0, 0);
    for _ in 0..POINTS {
        let p = rng.point_in([lo; 3], [hi; 3]);
        let got = eval(&s, p);
        let want = reference(p);
        let err = (got - want).abs();
        if want < 0.0 {
            inside += 1;
        } else {
            outside += 1;
        }
        worst_abs = worst_abs.max(err);
        if want.abs() > 1e-3 {
            worst_rel = worst_rel.max(err / want.abs());
        }
        assert!(
            err <= REL * want.abs() + ABS,
            "{scene} at {p:?}: evaluator {got}, reference {want}"
        );
    }
    assert!(
        inside >= POINTS / 200 && outside >= POINTS / 200,
        "{scene}: the points should cover inside ({inside}) and outside ({outside})"
    );
    eprintln!(
        "{scene}: {POINTS} points ({inside} inside), worst relative error {worst_rel:.1e}, \
         worst absolute {worst_abs:.1e}"
    );
}

// ---- independent geometry ----

fn len(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Distance from p to the segment a-b (any dimension up to 3, padded with zeros).
fn seg3(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = sub(b, a);
    let t = (dot(sub(p, a), ab) / dot(ab, ab)).clamp(0.0, 1.0);
    len(sub(
        p,
        [a[0] + ab[0] * t, a[1] + ab[1] * t, a[2] + ab[2] * t],
    ))
}

/// Signed distance to a simple polygon in 2D: the nearest edge, negative inside
/// (even-odd crossing count).
fn polygon(p: [f64; 2], v: &[[f64; 2]]) -> f64 {
    let mut d = f64::INFINITY;
    let mut inside = false;
    for i in 0..v.len() {
        let (a, b) = (v[i], v[(i + 1) % v.len()]);
        d = d.min(seg3(
            [p[0], p[1], 0.0],
            [a[0], a[1], 0.0],
            [b[0], b[1], 0.0],
        ));
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    if inside {
        -d
    } else {
        d
    }
}

/// Distance from p to the filled triangle abc: the plane distance when the projection falls
/// inside (all three edge tests agree with the normal), else the nearest edge.
fn triangle(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let n = cross(sub(b, a), sub(c, a));
    let inside = [(a, b), (b, c), (c, a)]
        .iter()
        .all(|(u, v)| dot(cross(sub(*v, *u), sub(p, *u)), n) >= 0.0);
    if inside {
        dot(sub(p, a), n).abs() / len(n)
    } else {
        seg3(p, a, b).min(seg3(p, b, c)).min(seg3(p, c, a))
    }
}

/// Distance from p to the axis-aligned box [lo, hi] (0 inside).
fn aabb(p: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> f64 {
    len([0, 1, 2].map(|i| (lo[i] - p[i]).max(p[i] - hi[i]).max(0.0)))
}

/// A prism: the 2D signed distance `d2` of the cross-section and `dz = |z| - half length`.
fn prism(d2: f64, dz: f64) -> f64 {
    if d2 > 0.0 && dz > 0.0 {
        (d2 * d2 + dz * dz).sqrt()
    } else {
        d2.max(dz)
    }
}

// ---- exact shapes ----

#[test]
fn box_frame_is_the_twelve_bars() {
    for (scene, b, w) in [
        ("box_frame([1, 1.5, 2], 0.25)", [0.5, 0.75, 1.0], 0.25),
        ("box_frame(2, 0.5)", [1.0, 1.0, 1.0], 0.5),
    ] {
        // The bars as boxes: four along each axis, at the (+-, +-) corners of the other two.
        let mut bars = Vec::new();
        for axis in 0..3 {
            let (j, k) = ((axis + 1) % 3, (axis + 2) % 3);
            for sj in [-1.0, 1.0] {
                for sk in [-1.0, 1.0] {
                    let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
                    lo[axis] = -b[axis];
                    hi[axis] = b[axis];
                    for (i, s) in [(j, sj), (k, sk)] {
                        let (x0, x1) = (s * b[i], s * (b[i] - w));
                        lo[i] = f64::min(x0, x1);
                        hi[i] = f64::max(x0, x1);
                    }
                    bars.push((lo, hi));
                }
            }
        }
        // The complement within the box: three tunnels (two coordinates deeper than w).
        let tunnels: Vec<([f64; 3], [f64; 3])> = (0..3)
            .map(|axis| {
                let mut lo = [0.0; 3];
                let mut hi = [0.0; 3];
                for i in 0..3 {
                    let h = if i == axis { b[i] } else { b[i] - w };
                    lo[i] = -h;
                    hi[i] = h;
                }
                (lo, hi)
            })
            .collect();
        exact(scene, -1.3, 1.3, 11, |p| {
            let out = bars
                .iter()
                .map(|(lo, hi)| aabb(p, *lo, *hi))
                .fold(f64::INFINITY, f64::min);
            if out > 0.0 {
                return out;
            }
            let to_outside = (0..3)
                .map(|i| b[i] - p[i].abs())
                .fold(f64::INFINITY, f64::min);
            let to_tunnel = tunnels
                .iter()
                .map(|(lo, hi)| aabb(p, *lo, *hi))
                .fold(f64::INFINITY, f64::min);
            -to_outside.min(to_tunnel)
        });
    }
}

#[test]
fn capped_torus_is_the_distance_to_an_arc() {
    for (scene, big, small, deg, size) in [
        ("capped_torus(1, 0.25, 120deg)", 1.0, 0.25, 120.0, 1.6),
        ("capped_torus(0.75, 0.125, 45deg)", 0.75, 0.125, 45.0, 0.9),
        ("capped_torus(1, 0.25, 180deg)", 1.0, 0.25, 180.0, 1.6),
    ] {
        // The compiler's f32 sine and cosine of the (f32) angle.
        let a = f64::to_radians(deg) as f32;
        let a = a.min(f32::from_bits(std::f32::consts::PI.to_bits() - 1)) as f64;
        let (s, c) = (a.sin() as f32 as f64, a.cos() as f32 as f64);
        let half = s.atan2(c);
        exact(scene, -size, size, 12, |p| {
            // The angle of the point's xy projection, measured from +y.
            let phi = p[0].atan2(p[1]).abs();
            let d = if phi <= half {
                let rho = p[0].hypot(p[1]);
                (rho - big).hypot(p[2])
            } else {
                let end = |sx: f64| len(sub(p, [sx * big * s, big * c, 0.0]));
                end(1.0).min(end(-1.0))
            };
            d - small
        });
    }
}

#[test]
fn infinite_cylinder_is_radial() {
    exact("infinite_cylinder(0.75)", -2.0, 2.0, 13, |p| {
        p[0].hypot(p[2]) - 0.75
    });
}

#[test]
fn cone_is_a_triangle_of_revolution() {
    for (scene, r, h) in [("cone(0.75, 1.5)", 0.75, 1.5), ("cone(1, 0.5)", 1.0, 0.5)] {
        exact(scene, -1.5, 1.75, 14, |p| {
            let rho = p[0].hypot(p[2]);
            polygon([rho, p[1]], &[[-r, 0.0], [r, 0.0], [0.0, h]])
        });
    }
}

#[test]
fn capped_cone_is_a_trapezoid_of_revolution() {
    for (scene, h, r1, r2) in [
        ("capped_cone(1.5, 0.75, 0.25)", 1.5, 0.75, 0.25),
        ("capped_cone(1, 0.25, 0.625)", 1.0, 0.25, 0.625),
        ("capped_cone(1, 0.5, 0.5)", 1.0, 0.5, 0.5),
    ] {
        let y = h / 2.0;
        exact(scene, -1.25, 1.25, 15, |p| {
            let rho = p[0].hypot(p[2]);
            polygon([rho, p[1]], &[[-r1, -y], [r1, -y], [r2, y], [-r2, y]])
        });
    }
}

#[test]
fn octahedron_is_its_eight_faces() {
    // Full size 1.5: vertices at 0.75 on the axes.
    let s = 0.75;
    exact("octahedron(1.5)", -1.2, 1.2, 16, |p| {
        let sum = p[0].abs() + p[1].abs() + p[2].abs();
        if sum <= s {
            return -(s - sum) / 3f64.sqrt();
        }
        let mut d = f64::INFINITY;
        for sx in [-s, s] {
            for sy in [-s, s] {
                for sz in [-s, s] {
                    d = d.min(triangle(p, [sx, 0.0, 0.0], [0.0, sy, 0.0], [0.0, 0.0, sz]));
                }
            }
        }
        d
    });
}

#[test]
fn hex_prism_is_an_extruded_hexagon() {
    let (r, h) = (0.5, 1.5);
    let big = 2.0 * r / 3f64.sqrt();
    let hexagon: Vec<[f64; 2]> = (0..6)
        .map(|k| {
            let t = (60.0 * k as f64).to_radians();
            [big * t.cos(), big * t.sin()]
        })
        .collect();
    exact("hex_prism(0.5, 1.5)", -1.2, 1.2, 17, |p| {
        prism(polygon([p[0], p[1]], &hexagon), p[2].abs() - h / 2.0)
    });
}

#[test]
fn tri_prism_is_an_extruded_triangle() {
    let (r, h) = (0.375, 1.0);
    let c = 3f64.sqrt() * r;
    let tri = [[0.0, 2.0 * r], [-c, -r], [c, -r]];
    exact("tri_prism(0.375, 1)", -1.2, 1.2, 18, |p| {
        prism(polygon([p[0], p[1]], &tri), p[2].abs() - h / 2.0)
    });
}

#[test]
fn pyramid_is_its_five_faces() {
    for (scene, h) in [("pyramid(1.25)", 1.25), ("pyramid(0.5)", 0.5)] {
        let apex = [0.0, h, 0.0];
        let corners = [
            [0.5, 0.0, 0.5],
            [-0.5, 0.0, 0.5],
            [-0.5, 0.0, -0.5],
            [0.5, 0.0, -0.5],
        ];
        // Outward side-face planes (unit normal, offset): n . p <= o inside.
        let sides: Vec<([f64; 3], f64)> = (0..4)
            .map(|i| {
                let (a, b) = (corners[i], corners[(i + 1) % 4]);
                let n = cross(sub(b, a), sub(apex, a));
                let l = len(n);
                let n = n.map(|x| -x / l);
                // Orient outward: the centre of the base is inside.
                let n = if dot(n, sub([0.0, 0.01, 0.0], a)) > 0.0 {
                    n.map(|x| -x)
                } else {
                    n
                };
                (n, dot(n, a))
            })
            .collect();
        exact(scene, -0.8, h + 0.2, 19, |p| {
            let depth = sides
                .iter()
                .map(|(n, o)| o - dot(*n, p))
                .fold(p[1], f64::min);
            if depth >= 0.0 {
                return -depth;
            }
            let mut d = triangle(p, corners[0], corners[1], corners[2])
                .min(triangle(p, corners[0], corners[2], corners[3]));
            for i in 0..4 {
                d = d.min(triangle(p, corners[i], corners[(i + 1) % 4], apex));
            }
            d
        });
    }
}

// ---- bound shapes ----

/// The true distance to the ellipsoid with semi-axes r: the nearest point is
/// `x_i = p_i r_i^2 / (r_i^2 + t)` with t the root of `sum (r_i p_i / (r_i^2 + t))^2 = 1`
/// beyond `-min(r)^2`, where that sum decreases; found by bisection.
fn ellipsoid_distance(p: [f64; 3], r: [f64; 3]) -> f64 {
    let f = |t: f64| {
        (0..3)
            .map(|i| (r[i] * p[i] / (r[i] * r[i] + t)).powi(2))
            .sum::<f64>()
            - 1.0
    };
    let rmin2 = r.iter().fold(f64::INFINITY, |a, b| a.min(*b)).powi(2);
    let mut lo = -rmin2 + 1e-15;
    let mut hi = 1.0;
    while f(hi) > 0.0 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let t = 0.5 * (lo + hi);
    let x = [0, 1, 2].map(|i| p[i] * r[i] * r[i] / (r[i] * r[i] + t));
    len(sub(p, x))
}

#[test]
fn ellipsoid_is_a_bound_with_the_right_sign() {
    let r = [1.0, 0.5, 0.25];
    let s = Shape::new("ellipsoid([1, 0.5, 0.25])");
    let mut rng = SplitMix(20);
    let (mut worst_ratio, mut inside) = (f64::INFINITY, 0);
    for _ in 0..POINTS {
        let p = rng.point_in([-1.2; 3], [1.2; 3]);
        let d = eval(&s, p);
        let truth = ellipsoid_distance(p, r);
        let k = (0..3).map(|i| (p[i] / r[i]).powi(2)).sum::<f64>();
        if k < 1.0 {
            inside += 1;
            assert!(d < 0.0, "inside point {p:?} got {d}");
        } else {
            assert!(d > 0.0, "outside point {p:?} got {d}");
        }
        assert!(
            d.abs() <= truth * (1.0 + 1e-9) + 1e-12,
            "{p:?}: |{d}| exceeds the true distance {truth}"
        );
        if truth > 1e-3 {
            worst_ratio = worst_ratio.min(d.abs() / truth);
        }
        let step = rng.point_in([-0.05; 3], [0.05; 3]);
        let q = [0, 1, 2].map(|i| p[i] + step[i]);
        assert!(
            (eval(&s, q) - d).abs() <= len(step) * (1.0 + 1e-9) + 1e-12,
            "Lipschitz above 1 between {p:?} and {q:?}"
        );
    }
    assert!(inside > 100, "only {inside} points inside");
    eprintln!(
        "ellipsoid: {POINTS} points ({inside} inside); |d| / true distance >= {worst_ratio:.3}"
    );
}

/// Checks a bound shape against a membership test: the sign agrees wherever |d| > 1e-9,
/// |d| never exceeds the distance to a sampled point of the other side, and
/// |d(p) - d(q)| <= |p - q| (Lipschitz 1) on random nearby pairs.
fn bound_by_membership(scene: &str, member: impl Fn([f64; 3]) -> bool, seed: u64) {
    let s = Shape::new(scene);
    let mut rng = SplitMix(seed);
    let samples: Vec<([f64; 3], bool)> = (0..40_000)
        .map(|_| {
            let p = rng.point_in([-0.55; 3], [0.55; 3]);
            (p, member(p))
        })
        .collect();
    let members: Vec<[f64; 3]> = samples.iter().filter(|s| s.1).map(|s| s.0).collect();
    let others: Vec<[f64; 3]> = samples.iter().filter(|s| !s.1).map(|s| s.0).collect();
    assert!(members.len() > 200 && others.len() > 200);
    let nearest = |p: [f64; 3], set: &[[f64; 3]]| {
        set.iter()
            .map(|q| len(sub(p, *q)))
            .fold(f64::INFINITY, f64::min)
    };
    let mut inside = 0;
    for i in 0..POINTS / 4 {
        // Half the points near a member (where the sign is interesting), half anywhere.
        let p = if i % 2 == 0 {
            let m = members[(rng.unit() * members.len() as f64) as usize];
            let j = rng.point_in([-0.02; 3], [0.02; 3]);
            [0, 1, 2].map(|k| m[k] + j[k])
        } else {
            rng.point_in([-0.7; 3], [0.7; 3])
        };
        let d = eval(&s, p);
        assert!(d.is_finite(), "{scene} at {p:?}: {d}");
        let m = member(p);
        if d.abs() > 1e-9 {
            assert_eq!(d < 0.0, m, "{scene} at {p:?}: d = {d}, member: {m}");
        }
        if m {
            inside += 1;
            assert!(
                -d <= nearest(p, &others) + 1e-12,
                "{scene} at {p:?}: depth {d}"
            );
        } else {
            assert!(d <= nearest(p, &members) + 1e-12, "{scene} at {p:?}: {d}");
        }
        let step = rng.point_in([-0.05; 3], [0.05; 3]);
        let q = [0, 1, 2].map(|i| p[i] + step[i]);
        let dq = eval(&s, q);
        assert!(
            (d - dq).abs() <= len(step) * (1.0 + 1e-9) + 1e-12,
            "{scene}: Lipschitz above 1 between {p:?} ({d}) and {q:?} ({dq})"
        );
    }
    assert!(inside > 20, "{scene}: only {inside} test points inside");
    eprintln!("{scene}: {} points ({inside} inside) passed", POINTS / 4);
}

/// In the level-n Menger sponge of side 1: for each level, at most one of the base-3 digits
/// of the three coordinates (shifted to [0, 1]) is the middle digit.
fn in_menger(p: [f64; 3], n: u32) -> bool {
    if p.iter().any(|x| x.abs() > 0.5) {
        return false;
    }
    let mut scale = 1.0;
    for _ in 0..n {
        scale *= 3.0;
        let middle = p
            .iter()
            .filter(|x| (((*x + 0.5) * scale).floor() as i64).rem_euclid(3) == 1)
            .count();
        if middle >= 2 {
            return false;
        }
    }
    true
}

/// In the level-n Sierpinski tetrahedron on the corners (0.5,0.5,0.5), (-0.5,-0.5,0.5),
/// (-0.5,0.5,-0.5), (0.5,-0.5,-0.5): the barycentric coordinates are all >= 0 and at each
/// binary place exactly one of them has the digit 1.
fn in_sierpinski(p: [f64; 3], n: u32) -> bool {
    let v = [
        [0.5, 0.5, 0.5],
        [-0.5, -0.5, 0.5],
        [-0.5, 0.5, -0.5],
        [0.5, -0.5, -0.5],
    ];
    // p = sum l_i v_i with sum l_i = 1; as v_i . v_i = 3/4 and v_i . v_j = -1/4,
    // p . v_j = l_j - 1/4.
    let l: Vec<f64> = v.iter().map(|vi| 0.25 + dot(p, *vi)).collect();
    if l.iter().any(|x| *x < 0.0) {
        return false;
    }
    let mut scale = 1.0;
    for _ in 0..n {
        scale *= 2.0;
        let ones = l
            .iter()
            .filter(|x| ((*x * scale).floor() as i64).rem_euclid(2) == 1)
            .count();
        if ones != 1 {
            return false;
        }
    }
    true
}

#[test]
fn menger_sign_and_bound() {
    bound_by_membership("menger(iterations: 3)", |p| in_menger(p, 3), 21);
    bound_by_membership("menger()", |p| in_menger(p, 4), 22);
}

#[test]
fn sierpinski_sign_and_bound() {
    bound_by_membership("sierpinski(iterations: 3)", |p| in_sierpinski(p, 3), 23);
    bound_by_membership("sierpinski(iterations: 5)", |p| in_sierpinski(p, 5), 24);
}

#[test]
fn sierpinski_barycentric_coordinates_reproduce_the_point() {
    // The membership test's coordinates: the corners themselves have l = e_i.
    let corner = [0.5, -0.5, -0.5];
    assert!(in_sierpinski(corner.map(|x| x * 0.999), 6));
    assert!(
        !in_sierpinski([0.0; 3], 1),
        "the centre is in the removed octahedron"
    );
}

/// Whether the orbit of c under the power-n triplex map (pole along y) leaves radius 2
/// within `iters` steps.
fn escapes(c: [f64; 3], n: f64, iters: u32) -> bool {
    let mut z = c;
    for _ in 0..iters {
        let r = len(z);
        if r > 2.0 {
            return true;
        }
        // Spherical coordinates with the polar angle from +y.
        let polar = if r > 0.0 { (z[1] / r).acos() } else { 0.0 };
        let azimuth = z[2].atan2(z[0]);
        let rn = r.powf(n);
        z = [
            rn * (n * polar).sin() * (n * azimuth).cos() + c[0],
            rn * (n * polar).cos() + c[1],
            rn * (n * polar).sin() * (n * azimuth).sin() + c[2],
        ];
    }
    len(z) > 2.0
}

#[test]
fn mandelbulb_bounding_sphere_sign_and_finiteness() {
    for (scene, n, iters, bound) in [
        ("mandelbulb()", 8.0, 8, 1.2),
        ("mandelbulb(power: 3, iterations: 12)", 3.0, 12, 2f64.sqrt()),
    ] {
        let s = Shape::new(scene);
        let bound = bound as f32 as f64;
        let mut rng = SplitMix(25);
        // On the bounding sphere itself the estimate must stay clear of zero, or rays stop on
        // the sphere instead of the fractal.
        for k in 0..200 {
            let t = k as f64 * 0.1;
            let dir = [
                t.cos() * (0.7 * t).sin(),
                (0.7 * t).cos(),
                t.sin() * (0.7 * t).sin(),
            ];
            let q = dir.map(|c| c * bound * 1.0001);
            assert!(
                eval(&s, q) > 0.01,
                "{scene}: {} at {q:?} on the sphere",
                eval(&s, q)
            );
        }
        let mut escaping = 0;
        for _ in 0..POINTS {
            let p = rng.point_in([-1.6; 3], [1.6; 3]);
            let d = eval(&s, p);
            assert!(d.is_finite(), "{scene} at {p:?}: {d}");
            let lp = len(p);
            if lp > bound * (1.0 + 1e-6) {
                // Outside the bounding sphere no point is in the set.
                assert!(escapes(p, n, 200), "{scene}: {p:?} beyond the bound stays");
            }
            if lp > 1.25 * bound * (1.0 + 1e-6) {
                // Far outside: the sphere's distance.
                assert!((d - (lp - bound)).abs() <= 1e-12, "{scene} at {p:?}: {d}");
            } else if escapes(p, n, iters) {
                escaping += 1;
                assert!(d > 0.0, "{scene}: escaping point {p:?} got {d}");
            }
            // The origin is in the set (its orbit stays 0): no estimate may exceed |p|.
            assert!(d <= lp + 1e-12, "{scene} at {p:?}: {d} > |p|");
        }
        assert!(escaping > 100, "{scene}: only {escaping} escaping points");
        // The origin (orbit 0) is inside; the poles and the axes stay finite.
        assert!(eval(&s, [0.0; 3]) <= 0.0, "{scene} at the origin");
        for p in [
            [0.0, 0.5, 0.0],
            [0.0, -0.3, 0.0],
            [1e-30, 0.0, 0.0],
            [0.0, 0.0, 0.7],
        ] {
            let d = eval(&s, p);
            assert!(d.is_finite(), "{scene} at {p:?}: {d}");
        }
    }
}

/// Whole powers take the trigonometry-free helper; it computes the trigonometric formula's
/// value (both in f64 here) at every point where that value is well conditioned: there the
/// two agree to 1e-9 relative, where the conditioning (the most the value moves when p moves
/// by 1e-12) is at most 1e-9 relative itself.
#[test]
fn the_whole_power_mandelbulb_is_the_trigonometric_one() {
    use sdfc_ir::prim_dist::{mandelbulb, mandelbulb_int};
    let mut rng = SplitMix(26);
    for n in 2..=16u32 {
        let bound = 2f64.powf(1.0 / (n as f64 - 1.0)).max(1.2); // the bounding radius
        let (mut compared, mut worst) = (0, 0.0f64);
        for _ in 0..POINTS {
            let p = rng.point_in([-1.5; 3], [1.5; 3]);
            let trig = mandelbulb(p, n as f64, 8.0, bound);
            let moved = mandelbulb([p[0] + 1e-12, p[1], p[2]], n as f64, 8.0, bound);
            if (moved - trig).abs() > 1e-9 * trig.abs() {
                continue;
            }
            compared += 1;
            let err = (mandelbulb_int(p, n, 8.0, bound) - trig).abs() / trig.abs().max(1e-9);
            worst = worst.max(err);
            assert!(err <= 1e-9, "power {n} at {p:?}: {err:e}");
        }
        assert!(compared > POINTS / 2, "power {n}: {compared} compared");
        eprintln!("power {n}: {compared} points, worst {worst:.1e}");
    }
}

#[test]
fn a_whole_power_needs_no_trigonometry() {
    for (scene, helper, not) in [
        ("mandelbulb()", "sd_mandelbulb_int(", "sd_mandelbulb("),
        (
            "mandelbulb(power: 3)",
            "sd_mandelbulb_int(",
            "sd_mandelbulb(",
        ),
        (
            "mandelbulb(power: 7.5)",
            "sd_mandelbulb(",
            "sd_mandelbulb_int(",
        ),
    ] {
        let wgsl = compile(&format!("scene = {scene};\n"), &Options::default())
            .unwrap()
            .wgsl;
        assert!(wgsl.contains(helper), "{scene}: no {helper}");
        assert!(!wgsl.contains(not), "{scene}: {not} emitted");
    }
}

// ---- argument checks ----

fn error_of(scene: &str) -> String {
    let src = format!("scene = {scene};\n");
    match compile(&src, &Options::default()) {
        Ok(_) => panic!("{scene} should not compile"),
        Err(sdfc_wgsl::Failure::Diagnostics(d)) => {
            sdfc_syntax::diag::render_with("t.sdf", &src, &d, false)
        }
        Err(e) => panic!("{scene}: {e:?}"),
    }
}

#[test]
fn bad_arguments_are_diagnosed_where_written() {
    for (scene, message) in [
        (
            "menger(iterations: 0)",
            "must be a whole number from 1 to 8, found 0",
        ),
        (
            "menger(iterations: 2.5)",
            "must be a whole number from 1 to 8, found 2.5",
        ),
        ("sierpinski(iterations: 21)", "from 1 to 20, found 21"),
        ("mandelbulb(iterations: 33)", "from 1 to 32, found 33"),
        (
            "mandelbulb(power: 1)",
            "`power` must be from 2 to 16, found 1",
        ),
        (
            "mandelbulb(power: [1, 2, 3])",
            "`power` must be a number, found a vec3",
        ),
        (
            "cone(-1, 2)",
            "the base radius must not be negative, found -1",
        ),
        (
            "capped_cone(1, 0.5, -0.5)",
            "the top radius `r2` must not be negative",
        ),
        ("octahedron(-2)", "the size must not be negative"),
        ("hex_prism(0.5, -1)", "the length must not be negative"),
        ("pyramid(-1)", "the height must not be negative"),
        (
            "ellipsoid([1, 0, 1])",
            "the radii of an ellipsoid must be positive",
        ),
        ("ellipsoid([1, -1, 1])", "must not be negative"),
        ("box_frame(1, 0.6)", "bar thickness 0.6 is more than half"),
        ("capped_torus(1, 0.2, 200deg)", "must be from 0 to pi"),
        ("infinite_cylinder(-0.5)", "the radius must not be negative"),
        ("tri_prism(0.5)", "`tri_prism` is missing `h`"),
    ] {
        let text = error_of(scene);
        assert!(
            text.contains(message),
            "{scene}: expected `{message}` in\n{text}"
        );
        assert!(
            text.contains("t.sdf:1:"),
            "{scene}: no line and column in\n{text}"
        );
    }
}

#[test]
fn every_new_primitive_is_exact_or_documented_as_a_bound() {
    use sdfc_ir::shape::Prim;
    for p in [
        Prim::Ellipsoid,
        Prim::Mandelbulb,
        Prim::Menger,
        Prim::Sierpinski,
    ] {
        assert!(!p.exact(), "{}", p.name());
    }
    for p in [
        Prim::BoxFrame,
        Prim::CappedTorus,
        Prim::InfiniteCylinder,
        Prim::Cone,
        Prim::CappedCone,
        Prim::Octahedron,
        Prim::HexPrism,
        Prim::TriPrism,
        Prim::Pyramid,
    ] {
        assert!(p.exact(), "{}", p.name());
    }
}

/// Every scene in `examples/` (the gallery's, rendered by scripts/render-docs.sh).
#[test]
fn the_examples_compile_without_warnings() {
    let dir = sdfc_tests::root().join("../examples");
    let paths = sdfc_tests::sdf_files(&dir);
    // The gallery's scenes at least; a lost or renamed one would go unchecked otherwise.
    for name in [
        "primitives",
        "fractals",
        "spec_section10",
        "ribbed_sphere",
        "sphere_box",
        "sphere_grid",
        "soft_shadows",
        "ambient_occlusion",
        "reflections",
        "terrain",
    ] {
        assert!(
            paths.iter().any(|p| p.ends_with(format!("{name}.sdf"))),
            "examples/{name}.sdf is missing"
        );
    }
    for path in &paths {
        let name = path.display();
        let src = std::fs::read_to_string(path).unwrap();
        match compile(&src, &Options::default()) {
            Ok(c) => assert!(c.warnings.is_empty(), "{name}: {:?}", c.warnings),
            Err(e) => panic!("{name}: {e:?}"),
        }
    }
}

/// Zero sizes make flat or empty shapes, never NaN: the divisions are guarded.
#[test]
fn degenerate_sizes_stay_finite() {
    let mut rng = SplitMix(26);
    for scene in [
        "cone(0, 1)",
        "cone(1, 0)",
        "capped_cone(0, 0, 0)",
        "tri_prism(0, 1)",
        "hex_prism(0, 0)",
        "pyramid(0)",
        "octahedron(0)",
        "box_frame(1, 0)",
        "box_frame(0, 0)",
        "capped_torus(1, 0, 0)",
        "capped_torus(0, 0, 90deg)",
        "infinite_cylinder(0)",
    ] {
        let s = Shape::new(scene);
        for _ in 0..200 {
            let p = rng.point_in([-1.0; 3], [1.0; 3]);
            assert!(eval(&s, p).is_finite(), "{scene} at {p:?}");
        }
        assert!(eval(&s, [0.0; 3]).is_finite(), "{scene} at the origin");
    }
}
