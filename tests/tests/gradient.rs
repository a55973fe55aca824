//! `scene_gradient` (`normals: analytic`, the forward-mode derivative of `scene_distance`)
//! against central differences of the distance, both in f64 with the IR evaluator, at random
//! points of every corpus and example scene and of one scene per primitive.
//!
//! A point is compared only where the distance is smooth there: central differences with
//! steps 1e-5 and 2e-5 agree within 1e-7 (creases, where the two sides' gradients differ,
//! fail that); at least half the points of every scene must be compared. Bounds: the value is
//! the distance's to 1e-12, the gradient within 1e-5 relative to max(1, |gradient|).

use sdfc_ir::diff::gradient;
use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_ir::Program;
use sdfc_tests::{root, sdf_files, SplitMix};
use sdfc_wgsl::{compile, Options};

fn program(src: &str) -> Program {
    match compile(src, &Options::default()) {
        Ok(c) => c.program().clone(),
        Err(e) => panic!("{src}: {e:?}"),
    }
}

struct Report {
    worst: f64,
}

/// Compares at `samples` points of the cube of half size `half`; panics past `tol`.
fn check(name: &str, p: &Program, half: f64, samples: usize, tol: f64) -> Report {
    // Smooth at the scale of the differenced helpers' own stencil, where they are used.
    let (h, agree) = if tol > 1e-4 {
        (2e-4, 1e-5)
    } else {
        (1e-5, 1e-7)
    };
    let g = gradient(&p.distance, &p.groups);
    let all = g.all_groups(&p.groups);
    let mut inputs = Inputs::at([0.0; 3]);
    inputs.params = p.scene.param_values(&[]);
    inputs.time = 0.75;
    let dist = |x: [f64; 3]| {
        let mut i = inputs.clone();
        i.point = x;
        eval_func(&p.distance, &p.groups, &i)[0].scalar().unwrap()
    };
    let central = |x: [f64; 3], h: f64| {
        [0, 1, 2].map(|k| {
            let (mut a, mut b) = (x, x);
            a[k] += h;
            b[k] -= h;
            (dist(a) - dist(b)) / (2.0 * h)
        })
    };
    let mut r = SplitMix(0x9_4ad1e47);
    let mut compared = 0;
    let mut worst: f64 = 0.0;
    for _ in 0..samples {
        let x = r.point_in([-half; 3], [half; 3]);
        let out = {
            let mut i = inputs.clone();
            i.point = x;
            eval_func(&g.func, &all, &i)
        };
        let v = out[0].scalar().unwrap();
        let grad: Vec<f64> = out[1..4].iter().map(|c| c.scalar().unwrap()).collect();
        let d = dist(x);
        assert!(
            (v - d).abs() <= 1e-12 * (1.0 + d.abs()),
            "{name}: gradient function's distance {v} != distance {d} at {x:?}"
        );
        let (f1, f2) = (central(x, h), central(x, 2.0 * h));
        let smooth = (0..3).all(|k| (f1[k] - f2[k]).abs() <= agree * (1.0 + f1[k].abs()));
        if !smooth || !d.is_finite() {
            continue;
        }
        compared += 1;
        let scale = (f1[0] * f1[0] + f1[1] * f1[1] + f1[2] * f1[2])
            .sqrt()
            .max(1.0);
        let err = (0..3).map(|k| (grad[k] - f1[k]).abs()).fold(0.0, f64::max) / scale;
        worst = worst.max(err);
        assert!(
            err <= tol,
            "{name}: gradient {grad:?} vs central differences {f1:?} at {x:?} (error {err:e} > {tol:e})"
        );
    }
    assert!(
        compared * 2 >= samples,
        "{name}: only {compared} of {samples} points were smooth enough to compare"
    );
    eprintln!("{name}: {compared} points, worst relative error {worst:e}");
    Report { worst }
}

/// Every corpus scene and example.
#[test]
fn corpus_and_examples() {
    let mut files = sdf_files(&root().join("scenes"));
    files.extend(sdf_files(&root().join("../examples")));
    assert!(files.len() > 20);
    for f in files {
        let name = f.file_name().unwrap().to_string_lossy().to_string();
        let src = std::fs::read_to_string(&f).unwrap();
        check(&name, &program(&src), 3.0, 300, 1e-5);
    }
}

/// One scene per primitive, turned and moved so that every axis of the chain rule counts.
#[test]
fn every_primitive() {
    let shapes = [
        "sphere(0.8)",
        "box([1, 0.6, 0.8])",
        "round_box([1, 0.6, 0.8], 0.1)",
        "torus(0.8, 0.25)",
        "cylinder(0.5, 1.2)",
        "infinite_cylinder(0.4)",
        "capsule([-0.5, 0, 0], [0.4, 0.3, 0.2], 0.3)",
        "ellipsoid([1, 0.5, 0.7])",
        "octahedron(0.9)",
        "hex_prism(0.5, 0.8)",
        "tri_prism(0.5, 0.8)",
        "plane([1, 2, 0.5], 0.2)",
        "cone(0.6, 1.1)",
        "box_frame([1, 0.8, 0.6], 0.1)",
        "capped_torus(0.7, 0.15, 100deg)",
        "capped_cone(1, 0.5, 0.2)",
        "pyramid(1.2)",
        "menger(iterations: 3)",
        "sierpinski(iterations: 4)",
        "mandelbulb()",
        "mandelbulb(power: 5, iterations: 4)",
        "mandelbulb(power: 6.5, iterations: 4)",
        "sdf(|p| length(p) - 0.7 + 0.1 * noise(p * 2), lipschitz: 1.5)",
        "sdf(|p| p.y - 0.3 * fbm(p, octaves: 4), lipschitz: 2)",
    ];
    let mut worst: f64 = 0.0;
    for s in shapes {
        let src = format!("scene = {s}.rotate([1, 2, 3], 0.7).translate([0.1, -0.2, 0.3]);");
        let rep = check(s, &program(&src), 1.5, 400, 1e-5);
        worst = worst.max(rep.worst);
    }
    eprintln!("worst over the primitives: {worst:e}");
}

/// Operations: CSG with smooth blends, repetition, mirrors, elongation, rounding, onion,
/// scale, the bound-only maps (twist, bend, stretch, shear, warp) and displacement.
#[test]
fn operations() {
    let scenes = [
        "union(sphere(1), box([1, 1, 1]).translate([0.8, 0, 0]), smooth: 0.3)",
        "subtract(box(1.5), sphere(0.9), smooth: 0.2)",
        "intersect(sphere(1.2), box(1.6), smooth: 0.1)",
        "xor(sphere(1), box(1.4))",
        "sphere(0.3).repeat([1, 0, 1.3])",
        "sphere(0.3).repeat([0.9, 0.9, 0], count: [3, 2, 1])",
        "torus(1, 0.2).mirror_x().translate([0.5, 0, 0]).elongate([0.2, 0, 0.1])",
        "box(1).round(0.1).onion(0.05).scale(1.3)",
        "box([0.6, 2, 0.6]).twist(0.8)",
        "box([2, 0.3, 0.5]).bend(0.4)",
        "sphere(1).stretch([1.5, 0.7, 1])",
        "box(1).shear([0.3, 0.1, 0.2])",
        "sphere(0.8).warp(|p| p + 0.1 * sin(3 * p.yzx), lipschitz: 1.4)",
        "sphere(1).displace(|p| sin(10 * p.y) * cos(7 * p.x) / 20, lipschitz: 1)",
        "heightfield(|x, z| 0.3 * sin(x) * cos(1.3 * z), lipschitz: 0.6)",
    ];
    for s in scenes {
        check(s, &program(&format!("scene = {s};")), 1.8, 300, 1e-5);
    }
}
