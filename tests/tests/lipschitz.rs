//! Safe stepping of the bound-only shape operations, measured on the compiled scene distance
//! with the f64 evaluator: (a) for each bound-only node the emitted distance is 1-Lipschitz
//! over the node's bounding region (difference quotients sampled at random pairs of points
//! never exceed 1 + 1e-6), so the compiler's L covers the un-normalised field's slope; and
//! (b) their meaning against closed forms.

use sdfc_ir::analysis::NodeInfo;
use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_ir::Program;
use sdfc_wgsl::{compile, Options};

fn program(src: &str) -> Program {
    match compile(src, &Options::default()) {
        Ok(c) => {
            assert!(c.warnings.is_empty(), "{src}: warnings {:?}", c.warnings);
            c.program().clone()
        }
        Err(e) => panic!("{src}: {e:?}"),
    }
}

fn dist(p: &Program, x: [f64; 3]) -> f64 {
    eval_func(&p.distance, &p.groups, &Inputs::at(x))[0]
        .scalar()
        .expect("a number")
}

/// The one node of the scene that normalises its field.
fn bound_node(p: &Program) -> &NodeInfo {
    let v: Vec<&NodeInfo> = p.analysis.nodes.iter().filter(|n| n.normalises).collect();
    assert_eq!(v.len(), 1, "expected one bound-only node");
    v[0]
}

/// A deterministic generator of numbers in [0, 1) (64-bit LCG, top 53 bits).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The largest `|f(a) - f(b)| / |a - b|` over random pairs in `lo..hi`, at separations
/// from 1e-4 to about 1.
fn max_quotient(p: &Program, lo: [f64; 3], hi: [f64; 3], pairs: usize) -> f64 {
    let mut r = Lcg(0x5eed);
    let mut best: f64 = 0.0;
    for k in 0..pairs {
        let a = [0, 1, 2].map(|i| lo[i] + r.next() * (hi[i] - lo[i]));
        let dir = [r.next() - 0.5, r.next() - 0.5, r.next() - 0.5];
        let len = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
        let step = [1e-4, 1e-2, 0.3, 1.0][k % 4] / len;
        let b = [0, 1, 2].map(|i| (a[i] + dir[i] * step).clamp(lo[i], hi[i]));
        let sep = (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt();
        if sep < 1e-6 {
            continue;
        }
        best = best.max((dist(p, a) - dist(p, b)).abs() / sep);
    }
    best
}

/// Checks (a) for one scene and prints the figures: the emitted slope (must stay at most 1)
/// and the un-normalised field's slope (emitted times L) next to the compiler's L.
fn check_bound(name: &str, src: &str) {
    let p = program(src);
    let node = bound_node(&p).clone();
    let l = node.lipschitz.expect("a constant L");
    let b = node.bounds;
    // Unbounded axes: sample a region of half-width 3.
    let lo = b.lo.map(|x| if x.is_finite() { x } else { -3.0 });
    let hi = b.hi.map(|x| if x.is_finite() { x } else { 3.0 });
    let q = max_quotient(&p, lo, hi, 20000);
    eprintln!(
        "{name}: emitted slope {q:.5} <= 1; field slope {:.5} vs compiler L {l:.5}",
        q * l
    );
    assert!(
        q <= 1.0 + 1e-6,
        "{name}: the emitted distance has slope {q}"
    );
    assert!(q > 0.3, "{name}: the sampling saw almost no change ({q})");
}

#[test]
fn stretch_is_1_lipschitz() {
    check_bound("stretch", "scene = sphere(1).stretch([2, 1, 0.5]);");
}

#[test]
fn shear_is_1_lipschitz() {
    check_bound("shear", "scene = box([1, 2, 1]).shear([0.5, 0, 0.25]);");
}

#[test]
fn twist_is_1_lipschitz() {
    check_bound("twist", "scene = box([1, 3, 1]).twist(1.5);");
}

#[test]
fn bend_is_1_lipschitz() {
    check_bound("bend", "scene = box([4, 0.5, 1]).bend(0.5);");
}

#[test]
fn derived_displace_is_1_lipschitz() {
    check_bound(
        "displace",
        "scene = sphere(1).displace(|p| sin(30 * p.y) / 16);",
    );
    // The tutorials' 2.875 is what the compiler derives.
    let p = program("scene = sphere(1).displace(|p| sin(30 * p.y) / 16);");
    assert_eq!(bound_node(&p).lipschitz, Some(2.875));
}

#[test]
fn warp_is_1_lipschitz() {
    check_bound(
        "warp",
        "scene = box(1).warp(|p| p + [0, 0.2 * sin(2 * p.x), 0]);",
    );
}

#[test]
fn heightfield_is_1_lipschitz() {
    check_bound(
        "heightfield",
        "scene = heightfield(|x, z| 0.3 * sin(x) * cos(z));",
    );
}

#[test]
fn sdf_is_1_lipschitz() {
    check_bound(
        "sdf",
        "scene = sdf(|p| length(p * [1, 2, 1]) - 1, lipschitz: 2);",
    );
}

#[test]
fn stretched_sphere_is_the_ellipsoid() {
    let p = program("scene = sphere(1).stretch([2, 1, 0.5]);");
    let mut r = Lcg(7);
    let mut checked = 0;
    for _ in 0..5000 {
        let x = [0, 1, 2].map(|_| r.next() * 6.0 - 3.0);
        let e = (x[0] / 2.0).powi(2) + x[1].powi(2) + (x[2] / 0.5).powi(2) - 1.0;
        if e.abs() < 1e-6 {
            continue;
        }
        let d = dist(&p, x);
        assert_eq!(d < 0.0, e < 0.0, "at {x:?}: distance {d}, ellipsoid {e}");
        checked += 1;
    }
    assert!(checked > 4900);
}

#[test]
fn shear_moves_the_surface_by_the_forward_map() {
    let (kxy, kxz, kyz) = (0.5, -0.3, 0.25);
    let p = program(&format!("scene = sphere(1).shear([{kxy}, {kxz}, {kyz}]);"));
    let fwd = |u: [f64; 3]| [u[0] + kxy * u[1] + kxz * u[2], u[1] + kyz * u[2], u[2]];
    let mut r = Lcg(11);
    for _ in 0..500 {
        let v = [0, 1, 2].map(|_| r.next() - 0.5);
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let u = v.map(|x| x / l);
        // The image of the unit sphere is the surface; inside and outside map likewise.
        assert!(dist(&p, fwd(u)).abs() < 1e-6, "on the surface at {u:?}");
        assert!(dist(&p, fwd(u.map(|x| x * 0.9))) < 0.0);
        assert!(dist(&p, fwd(u.map(|x| x * 1.1))) > 0.0);
    }
}

#[test]
fn twist_turns_each_slice_by_k_y() {
    let k = 0.8;
    let plain = program("scene = box([1, 2, 1]);");
    let twisted = program(&format!("scene = box([1, 2, 1]).twist({k});"));
    let still = program("scene = box([1, 2, 1]).twist(0);");
    let mut r = Lcg(3);
    for _ in 0..2000 {
        let u = [0, 1, 2].map(|_| r.next() * 3.0 - 1.5);
        // twist(0) is the child, distance for distance.
        assert_eq!(dist(&still, u), dist(&plain, u));
        // A point of the box's surface, turned by k y about y (+z toward +x), is on the
        // twisted surface; the sign of every point follows the same map.
        let t = k * u[1];
        let (s, c) = t.sin_cos();
        let p = [u[0] * c + u[2] * s, u[1], -u[0] * s + u[2] * c];
        let (dp, du) = (dist(&twisted, p), dist(&plain, u));
        assert_eq!(dp < 0.0, du < 0.0, "at {u:?}");
        assert!(dp.abs() <= du.abs() + 1e-9, "a bound: {dp} vs {du}");
    }
}

#[test]
fn zero_bend_and_identity_warp_are_the_child() {
    let plain = program("scene = box([2, 1, 1]);");
    let bent = program("scene = box([2, 1, 1]).bend(0);");
    let warped = program("scene = box([2, 1, 1]).warp(|p| p);");
    let mut r = Lcg(5);
    for _ in 0..1000 {
        let u = [0, 1, 2].map(|_| r.next() * 4.0 - 2.0);
        assert_eq!(dist(&bent, u), dist(&plain, u));
        assert_eq!(dist(&warped, u), dist(&plain, u));
    }
}

#[test]
fn heightfield_sign_is_above_or_below_the_terrain() {
    let p = program("scene = heightfield(|x, z| 0.5 * sin(x) + 0.25 * cos(2 * z));");
    let mut r = Lcg(9);
    for _ in 0..2000 {
        let u = [0, 1, 2].map(|_| r.next() * 8.0 - 4.0);
        let h = 0.5 * u[0].sin() + 0.25 * (2.0 * u[2]).cos();
        if (u[1] - h).abs() < 1e-9 {
            continue;
        }
        let d = dist(&p, u);
        assert_eq!(d > 0.0, u[1] > h, "at {u:?}");
        // A bound: never more than the vertical gap.
        assert!(d.abs() <= (u[1] - h).abs() + 1e-12);
    }
}

#[test]
fn exact_scenes_have_no_bound_only_node_and_stay_exact() {
    let p = program("scene = sphere(1) | box(1).rotate_y(30deg).translate([2, 0, 0]);");
    assert!(p.analysis.nodes.iter().all(|n| !n.normalises));
    assert_eq!(
        p.analysis.nodes[p.scene.root.index()].exactness,
        sdfc_ir::analysis::Exactness::Exact
    );
}

#[test]
fn a_too_small_declared_bound_is_a_warning_at_its_span() {
    let src = "scene = sdf(|p| 3 * length(p) - 1, lipschitz: 2);";
    let c = compile(src, &Options::default()).expect("warnings do not fail");
    assert_eq!(c.warnings.len(), 1, "{:?}", c.warnings);
    let w = &c.warnings[0];
    assert!(!w.is_error());
    assert_eq!(&src[w.span.range()], "2");
    assert!(w.message.contains("too small"), "{}", w.message);
    // A correct declaration draws nothing.
    let ok = compile(
        "scene = sdf(|p| 3 * length(p) - 1, lipschitz: 3);",
        &Options::default(),
    )
    .expect("compiles");
    assert!(ok.warnings.is_empty(), "{:?}", ok.warnings);
}

/// Points of the surface of `box([1, 3, 1]).twist(k)`: a grid on the box's faces, each turned
/// by `k y` about y.
fn twisted_box_surface(k: f64) -> Vec<[f64; 3]> {
    let h = [0.5, 1.5, 0.5];
    let n = 48;
    let mut out = Vec::new();
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            for i in 0..=n {
                for j in 0..=n {
                    let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
                    let mut u = [0.0; 3];
                    u[axis] = sign * h[axis];
                    u[a] = -h[a] + 2.0 * h[a] * i as f64 / n as f64;
                    u[b] = -h[b] + 2.0 * h[b] * j as f64 / n as f64;
                    let (s, c) = (k * u[1]).sin_cos();
                    out.push([u[0] * c + u[2] * s, u[1], -u[0] * s + u[2] * c]);
                }
            }
        }
    }
    out
}

/// Sphere tracing steps by the distance: at no point may it exceed the distance to any point
/// of the surface. Checked for the twisted box at points near it and far from the twist axis
/// (outside the child's bounds, where the divisor grows with the distance from the axis).
#[test]
fn twist_never_oversteps_near_or_far() {
    let k = 1.5;
    let p = program(&format!("scene = box([1, 3, 1]).twist({k});"));
    let surface = twisted_box_surface(k);
    let mut r = Lcg(21);
    let mut tightest = f64::INFINITY;
    for n in 0..400 {
        let reach = if n % 2 == 0 { 1.5 } else { 6.0 };
        let x = [0, 1, 2].map(|_| (r.next() * 2.0 - 1.0) * reach);
        let d = dist(&p, x);
        if d <= 0.0 {
            continue;
        }
        let nearest = surface
            .iter()
            .map(|s| (0..3).map(|i| (x[i] - s[i]).powi(2)).sum::<f64>().sqrt())
            .fold(f64::INFINITY, f64::min);
        assert!(
            d <= nearest + 1e-9,
            "at {x:?}: step {d} but a surface point is {nearest} away"
        );
        tightest = tightest.min(nearest - d);
    }
    eprintln!("twist: smallest margin between the step and a surface point {tightest:.5}");
}
