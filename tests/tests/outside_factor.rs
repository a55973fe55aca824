//! The analysis's bounds and outside factor (`NodeInfo::outside`), checked with the f64
//! evaluator: at random points outside a scene's box its distance is positive (no surface
//! lies outside the box) and at least the factor times the distance to the box, which is
//! what lets shadow rays stop once they have left the box for good (`bounds_outside`), and
//! what `ray_span` and the tiles rely on to leave rays out.

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

/// Samples points around the box (within `reach` of it; open sides clamped to it) and
/// returns how many were outside it.
fn check(scene: &str, reach: f64) -> usize {
    let src = format!("scene = {scene};\n");
    let p = program(&src);
    let root = &p.analysis.nodes[p.scene.root.index()];
    let (b, factor) = (root.bounds, root.outside);
    let lo = b.lo.map(|x| if x.is_finite() { x - reach } else { -reach });
    let hi = b.hi.map(|x| if x.is_finite() { x + reach } else { reach });
    let mut r = SplitMix(0x0075_1de5);
    let mut outside = 0;
    for _ in 0..20_000 {
        let x = [0, 1, 2].map(|i| lo[i] + r.unit() * (hi[i] - lo[i]));
        let gap: f64 = (0..3)
            .map(|i| (b.lo[i] - x[i]).max(x[i] - b.hi[i]).max(0.0).powi(2))
            .sum::<f64>()
            .sqrt();
        if gap <= 0.0 {
            continue;
        }
        outside += 1;
        let d = eval_func(&p.distance, &p.groups, &Inputs::at(x))[0]
            .scalar()
            .expect("a number") as f64;
        assert!(d > 0.0, "{scene}: a surface outside the box at {x:?} ({d})");
        // The evaluator works in f32 values: a little slack for their rounding.
        assert!(
            d >= factor * gap - 1e-5 * (1.0 + gap),
            "{scene}: at {x:?}, {gap} outside the box, the distance {d} is below {factor} times it"
        );
    }
    assert!(outside > 1_000, "{scene}: only {outside} points outside");
    outside
}

#[test]
fn exact_shapes_and_what_keeps_their_factor() {
    for scene in [
        "box([1, 2, 3]) | sphere(1).translate([4, 0, 0]) | plane([0, 1, 0], -2)",
        "box([1, 1, 1]).round(0.2).rotate_y(30deg).scale(2)",
        "torus(1, 0.25).onion(0.05).rotate_x(40deg)",
        "subtract(box([1, 1, 1]), sphere(1.2))",
        "sphere(0.4).repeat([2, 0, 2]) | plane([0, 1, 0], -1)",
        "sphere(0.4).translate([0.5, 0, 0]).repeat([2, 0, 0], count: [3, 1, 1])",
        "box([1, 0.5, 0.5]).translate([0.7, 0, 0]).mirror_x()",
        "torus(0.5, 0.1).elongate([1, 0, 0.5])",
        "intersect(sphere(1), box([2, 2, 2]).translate([1, 1, 1]))",
        "intersect(sphere(1), box([2, 2, 2]).translate([1, 1, 1]), box([1.6, 3, 3]))",
    ] {
        check(scene, 3.0);
    }
}

#[test]
fn bounds_with_a_factor_below_one() {
    for scene in [
        "ellipsoid([1, 0.5, 0.25]).rotate_z(20deg)",
        "displace(sphere(1), |p| sin(30 * p.y) / 16)",
        "heightfield(|x, z| 0.3 * sin(2 * x) * cos(1.5 * z), lipschitz: 0.6)",
        "heightfield(|x, z| 1.5 * fbm([x, 0, z] * 0.35, octaves: 6), lipschitz: 1.7)",
    ] {
        check(scene, 3.0);
    }
}

/// A smooth union folds its children pairwise, each blend up to k/4 below the lesser of
/// its two: three children one on another drop by 0.39 k, and many by up to k. Its box
/// must take that in (it grew by k/4 for any count, and three unit spheres blended with
/// k = 1 reached 1.39 where the box ended at 1.25).
#[test]
fn smooth_unions_of_many_children() {
    for scene in [
        "union(sphere(1), sphere(1).translate([0.01, 0, 0]), sphere(1).translate([0, 0, 0.01]), smooth: 1)",
        "union(sphere(1), sphere(1), sphere(1), sphere(1), sphere(1), sphere(1), smooth: 0.5)",
        "union(box([1, 1, 1]), sphere(0.8).translate([0.5, 0, 0]), smooth: 0.3)",
        // Displaced children (factor 1 / 2.875): the box grows by k / 4 over that factor.
        // Two alike blend k / 4 below either everywhere, so the bound is tight next to the
        // box (with the box grown by k / 4 only, their surface lay 0.3 outside it).
        "union(displace(sphere(1), |p| sin(30 * p.y) / 16, lipschitz: 2.875), box([1.4, 1.4, 1.4]).rotate_y(30deg), smooth: 0.3)",
        "union(displace(sphere(1), |p| sin(30 * p.y) / 16, lipschitz: 2.875), displace(sphere(1), |p| sin(30 * p.y) / 16, lipschitz: 2.875).translate([0.001, 0, 0]), smooth: 0.8)",
    ] {
        check(scene, 3.0);
    }
}

/// The fractals' factors (the Menger sponge and the mandelbulb 1, the Sierpinski
/// tetrahedron 1/3), and what `round`, `onion` and `displace` do to a child whose factor is
/// below 1: its box grows by their reach over the factor. (It grew by the reach alone: a
/// Sierpinski tetrahedron rounded by 0.143 had surface 0.02 outside its box, found by
/// `random_bounds.rs`; a displaced thin ellipsoid too.)
#[test]
fn fractals_and_what_rounds_or_displaces_a_bound() {
    for scene in [
        "menger(iterations: 3)",
        "sierpinski(iterations: 1)",
        "sierpinski(iterations: 6).rotate_y(20deg)",
        "mandelbulb(power: 8, iterations: 6)",
        "sierpinski(iterations: 1).round(0.143)",
        "sierpinski(iterations: 3).onion(0.1)",
        "menger(iterations: 2).round(0.2)",
        "ellipsoid([1, 0.2, 0.2]).round(0.1)",
        "displace(ellipsoid([1, 0.2, 0.2]), |p| sin(20 * p.x) / 10, lipschitz: 3)",
        "displace(sierpinski(iterations: 2), |p| sin(20 * p.y) / 16, lipschitz: 2.25)",
        // Smooth intersections and subtractions keep the plain ones' factors, and xor its
        // children's least, so what rounds them keeps a box (it had none for a moment).
        "subtract(box([1, 1, 1]), sphere(0.6), smooth: 0.1).round(0.05)",
        "intersect(sphere(1), box([1.5, 1.5, 1.5]).rotate_y(20deg), smooth: 0.2).onion(0.05)",
        "xor(box([1, 1, 1]), sphere(0.7)).round(0.1)",
        "displace(subtract(box([1, 1, 1]), sphere(0.6), smooth: 0.1), |p| sin(9 * p.x) / 20)",
    ] {
        check(scene, 3.0);
    }
}
