//! `scene_distance_ray(p, rd)`, the distance the marcher steps with where a `displace` or
//! `heightfield` node can divide by its slope along the ray instead of its bound in every
//! direction, and a plane by its slope along the ray (its distance along the ray). Checked
//! with the f64 evaluator over random points and unit directions: (a) along the ray it is
//! 1-Lipschitz (difference quotients at separations from 1e-4 to 1 never exceed 1 + 1e-6),
//! which is what makes a step of its value safe; (b) it has the sign of `scene_distance`
//! (the same surface); (c) it is larger than `scene_distance` somewhere, so the directional
//! bound is really in use.

use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_ir::Program;
use sdfc_tests::SplitMix;
use sdfc_wgsl::{compile, Options};

fn program(src: &str) -> Program {
    match compile(src, &Options::default()) {
        Ok(c) => c.program().clone(),
        Err(e) => panic!("{src}: {e:?}"),
    }
}

fn dist(p: &Program, x: [f64; 3]) -> f64 {
    eval_func(&p.distance, &p.groups, &Inputs::at(x))[0]
        .scalar()
        .expect("a number")
}

fn dist_ray(p: &Program, x: [f64; 3], rd: [f64; 3]) -> f64 {
    let f = p.distance_ray.as_ref().expect("a ray function");
    let mut inputs = Inputs::at(x);
    inputs.ray = rd;
    eval_func(f, &p.groups, &inputs)[0]
        .scalar()
        .expect("a number")
}

fn unit(r: &mut SplitMix) -> [f64; 3] {
    loop {
        let v = [
            r.unit() * 2.0 - 1.0,
            r.unit() * 2.0 - 1.0,
            r.unit() * 2.0 - 1.0,
        ];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if n > 0.1 && n <= 1.0 {
            return v.map(|c| c / n);
        }
    }
}

/// Checks (a), (b) and (c) at `samples` random points of the box `lo..hi`; returns the
/// largest difference quotient along the ray.
fn check(name: &str, src: &str, lo: [f64; 3], hi: [f64; 3], samples: usize) -> f64 {
    let p = program(src);
    assert!(p.distance_ray.is_some(), "{name}: no scene_distance_ray");
    let mut r = SplitMix(0xa10e_5eed);
    let mut worst: f64 = 0.0;
    let mut larger = 0;
    for k in 0..samples {
        let a = [0, 1, 2].map(|i| lo[i] + r.unit() * (hi[i] - lo[i]));
        let rd = unit(&mut r);
        let ga = dist_ray(&p, a, rd);
        let fa = dist(&p, a);
        assert!(
            ga.signum() == fa.signum() || fa.abs() < 1e-9,
            "{name}: at {a:?} along {rd:?} the ray distance {ga} and the distance {fa} differ in sign"
        );
        if ga > fa * (1.0 + 1e-6) + 1e-12 {
            larger += 1;
        }
        let s = [1e-4, 1e-2, 0.3, 1.0][k % 4];
        let b = [0, 1, 2].map(|i| a[i] + rd[i] * s);
        let gb = dist_ray(&p, b, rd);
        worst = worst.max((gb - ga).abs() / s);
    }
    assert!(
        worst <= 1.0 + 1e-6,
        "{name}: slope along the ray {worst} > 1"
    );
    assert!(
        larger > samples / 100,
        "{name}: the ray distance exceeds the distance at only {larger} of {samples} points"
    );
    eprintln!("{name}: largest slope along the ray {worst:.6}, larger than the distance at {larger} of {samples} points");
    worst
}

const RIBS: &str = "displace(sphere(1), |p| sin(30 * p.y) / 16)";

#[test]
fn ribbed_sphere() {
    let src = format!("scene = {RIBS};\n");
    check("ribbed sphere", &src, [-1.5; 3], [1.5; 3], 20_000);
}

/// The direction is turned with the point by rotations; scales, mirrors and repetitions keep
/// it (they change only the scale or signs of its components, which the bound takes in
/// absolute value). A wrong direction in the child's frame would show as a slope above 1.
#[test]
fn ribbed_sphere_under_point_maps() {
    let src = format!(
        "scene = {RIBS}.rotate_x(40deg).rotate_z(25deg).scale(1.5).translate([0.5, 0, 0]).mirror_x()\n\
         | {RIBS}.rotate_y(70deg).repeat([6, 0, 0]).translate([0, 3, 0]);\n"
    );
    check("ribbed spheres, mapped", &src, [-4.0; 3], [4.0; 3], 40_000);
}

#[test]
fn heightfield() {
    let src = "scene = heightfield(|x, z| 0.3 * sin(2 * x) * cos(z));\n";
    check(
        "heightfield",
        src,
        [-4.0, -1.0, -4.0],
        [4.0, 1.5, 4.0],
        20_000,
    );
}

/// Under a twist the direction is no longer known: the twisted part keeps its isotropic
/// divisor, the displaced part beside it still uses the ray.
#[test]
fn beside_a_twist() {
    let src = format!("scene = {RIBS} | box([0.5, 1, 0.5]).twist(1.5).translate([2.5, 0, 0]);\n");
    check(
        "ribbed sphere beside a twist",
        &src,
        [-1.5, -1.5, -1.5],
        [3.5, 1.5, 1.5],
        20_000,
    );
}

/// A displaced shape in a smooth blend keeps the isotropic distance (the blend's surface
/// depends on the values it blends), a heightfield beside it still uses the ray: the sign
/// check of `check` is what catches a ray form that would march to another surface.
#[test]
fn beside_a_smooth_blend() {
    let src = format!(
        "scene = union({RIBS}, box(0.8).rotate_y(30deg), smooth: 0.3)\n\
         | heightfield(|x, z| 0.2 * sin(3 * x) - 1.2);\n"
    );
    check(
        "smooth blend and a heightfield",
        &src,
        [-2.0; 3],
        [2.0; 3],
        40_000,
    );
}

/// A plane divides by its slope along the ray, `|n| . |u|`: a floor, a tilted plane
/// mirrored (where the direction's signs are unknown: `|n . u|` alone would overstep on the
/// mirrored side), mirrored and then turned, turned and then mirrored (the direction lost),
/// elongated, scaled, cut from a box and intersected with a sphere (its value negated or
/// taken where it is the larger), and one in a smooth blend, which keeps its distance (the
/// sign check would catch it otherwise).
#[test]
fn planes() {
    let src = "scene = sphere(1) | plane([0, 1, 0], -2.5)
               | plane([0.6, 0.8, 0], 2).mirror_x()
               | plane([0, 0.8, 0.6], 2.2).mirror_z().rotate_x(30deg)
               | plane([0.6, 0.8, 0], 2.4).rotate_z(20deg).mirror_x()
               | elongate(plane([0.6, 0, 0.8], 2.6), [0.5, 0, 0.3])
               | plane([0, 0, 1], 1.5).scale(2).translate([0, 0, -3])
               | subtract(box(1.2), plane([0.6, 0.8, 0], 0.3)).translate([0, 0, 2.2])
               | intersect(sphere(1.1), plane([0, -0.6, 0.8], 0.2)).translate([2.2, 0, 0])
               | union(box(0.5), plane([1, 0, 0], -1.5), smooth: 0.3);
";
    check("planes", src, [-3.0; 3], [3.0; 3], 40_000);
}

/// A plane below a repetition whose copy fits no cell (the analysis calls it neither a
/// distance nor a bound; a tilted plane repeated along x) keeps its plain distance: that
/// jumps where a cell meets the next and bounds only the distance to the cell's own copy,
/// and its distance along a grazing ray would step past the neighbours' (a slope along the
/// ray of 388 at 40 000 random points when it divided).
#[test]
fn planes_repeated() {
    for src in [
        "scene = plane([0.6, 0.8, 0], 0.4).repeat([3, 0, 0]) | sphere(0.5).translate([0, 2, 0]);\n",
        "scene = plane([0.6, 0.8, 0], 0.4).repeat([3, 0, 0]).translate([0, 1, 0]).mirror_x();\n",
    ] {
        assert!(program(src).distance_ray.is_none(), "{src}");
    }
}

/// The ray distance of a floor is the distance along the ray to it: exact, so one sample
/// of the ray function at a point above the floor lands on it.
#[test]
fn a_floor_is_reached_in_one_step() {
    let p = program(
        "scene = plane([0, 1, 0], 0);
",
    );
    for rd in [[0.0f64, -1.0, 0.0], [0.6, -0.8, 0.0], [0.9998, -0.02, 0.0]] {
        let n = (rd[0] * rd[0] + rd[1] * rd[1] + rd[2] * rd[2]).sqrt();
        let rd = rd.map(|c| c / n);
        let x = [0.0, 2.0, 0.0];
        let t = dist_ray(&p, x, rd);
        let y = x[1] + rd[1] * t;
        assert!(
            y.abs() < 1e-5,
            "along {rd:?}: one step of {t} ends at y = {y}"
        );
    }
}

/// Scenes without such nodes have no ray function: their shaders are unchanged.
#[test]
fn only_where_it_helps() {
    for src in [
        "scene = sphere(1) | box(1).translate([2, 0, 0]);\n",
        "scene = box(1).twist(1);\n",
        "scene = displace(sphere(1), |p| sin(30 * p.y) / 16).twist(1);\n",
        // Below a smooth blend, round or onion, or as a displaced child (as in the spec's
        // section 10 scene), the value itself shapes the surface: no ray form there.
        "scene = union(displace(sphere(1), |p| sin(30 * p.y) / 16), box(1), smooth: 0.3);\n",
        "scene = displace(sphere(1), |p| sin(30 * p.y) / 16).round(0.1);\n",
        "scene = displace(displace(sphere(1), |p| sin(30 * p.y) / 16), |p| sin(20 * p.x) / 20).onion(0.1);\n",
        "scene = union(sphere(1), plane([0, 1, 0], 0.5), smooth: 0.3);\n",
    ] {
        assert!(program(src).distance_ray.is_none(), "{src}");
    }
}

/// The march and the hit refinement call the ray form; the library form (for users' own
/// shaders, which march however they like) has only `scene_distance`.
#[test]
fn the_marcher_calls_it_and_the_library_leaves_it_out() {
    let src = format!("scene = {RIBS};\n");
    let full = compile(&src, &Options::default()).expect("compiles").wgsl;
    assert!(full.contains("fn scene_distance_ray(p: vec3<f32>, rd: vec3<f32>) -> f32"));
    assert_eq!(
        full.matches("scene_distance_ray(ro + rd * t, rd)").count(),
        2,
        "the march loop and the refinement"
    );
    let lib = Options {
        lib: true,
        ..Options::default()
    };
    let lib = compile(&src, &lib).expect("compiles").wgsl;
    assert!(!lib.contains("scene_distance_ray"), "{lib}");
    assert!(lib.contains("fn scene_distance(p: vec3<f32>) -> f32"));
}
