//! A proptest generator of random unions that the data form takes (`sdfc_ir::instances`):
//! from 16 to 39 bounded primitives with constant arguments, each under random moves, turns
//! about any axis, uniform scales and colours, spread in front of the spec's default
//! camera; sometimes with other children beside them (a floor, a smooth blend, a fractal),
//! which make the union mixed. Shared by the device test of the data form against the f64
//! reference.

use crate::random_scene::{more_primitives, num, vec3};
use proptest::prelude::*;

/// One bounded primitive with constant arguments: every kind an instance may be.
fn bounded_primitive() -> impl Strategy<Value = String> {
    prop_oneof![
        num(0.1, 0.8).prop_map(|r| format!("sphere({r})")),
        vec3(0.05, 0.8).prop_map(|s| format!("box({s})")),
        (0.2f64..0.8, 0.0f64..0.99)
            .prop_map(|(s, f)| format!("round_box({s:.3}, {:.3})", s * 0.5 * f)),
        (num(0.2, 0.7), num(0.02, 0.2)).prop_map(|(a, b)| format!("torus({a}, {b})")),
        (num(0.05, 0.5), num(0.05, 0.8)).prop_map(|(a, b)| format!("cylinder({a}, {b})")),
        (vec3(-0.5, 0.5), vec3(-0.5, 0.5), num(0.02, 0.3))
            .prop_map(|(a, b, r)| format!("capsule({a}, {b}, {r})")),
        more_primitives()
            .prop_filter("bounded", |p| !p.starts_with("infinite"))
            .prop_map(|p| format!("{p}.scale(0.4)")),
    ]
}

/// A constant map or colour applied to an instance.
fn map() -> impl Strategy<Value = String> {
    prop_oneof![
        vec3(-0.5, 0.5).prop_map(|v| format!(".translate({v})")),
        (0usize..3, num(-180.0, 180.0))
            .prop_map(|(axis, t)| format!(".rotate_{}({t}deg)", ["x", "y", "z"][axis])),
        (vec3(-1.0, 1.0), num(-3.0, 3.0))
            .prop_map(|(axis, t)| format!(".rotate({axis} + [0.01, 0, 0], {t})")),
        num(0.3, 2.0).prop_map(|f| format!(".scale({f})")),
        vec3(0.0, 1.0).prop_map(|c| format!(".color({c})")),
    ]
}

/// One instance: a primitive under up to four maps, then moved to a random place in view.
fn instance() -> impl Strategy<Value = String> {
    (
        bounded_primitive(),
        prop::collection::vec(map(), 0..4),
        (num(-3.0, 3.0), num(-2.0, 2.0), num(-4.0, 1.0)),
    )
        .prop_map(|(p, maps, (x, y, z))| format!("{p}{}.translate([{x}, {y}, {z}])", maps.concat()))
}

/// A child that is not an instance, which makes the union mixed.
fn other_child() -> impl Strategy<Value = String> {
    prop_oneof![
        num(-2.5, -1.5).prop_map(|h| format!("plane([0, 1, 0], {h})")),
        (vec3(-2.0, 2.0), num(0.1, 0.5)).prop_map(|(c, k)| format!(
            "union(sphere(0.5), box([0.4, 0.4, 0.4]).translate([0.5, 0, 0]), smooth: {k}).translate({c})"
        )),
        (1u32..4, vec3(-2.0, 2.0))
            .prop_map(|(i, c)| format!("menger(iterations: {i}).scale(0.6).translate({c})")),
    ]
}

/// A scene of a random union of instances, with zero to two other children; one time in
/// three moved 1e5 along x with its camera (the renderer's camera-relative frame).
pub fn instance_union() -> impl Strategy<Value = String> {
    (
        prop::collection::vec(instance(), 16..40),
        prop::collection::vec(other_child(), 0..3),
        prop_oneof![2 => Just(0.0), 1 => Just(1e5)],
    )
        .prop_map(|(instances, others, x)| {
            let children: Vec<String> = instances.into_iter().chain(others).collect();
            let union = format!("union(\n    {}\n)", children.join(",\n    "));
            if x == 0.0 {
                format!("scene = {union};\n")
            } else {
                format!(
                    "camera {{ position: [{x}, 0, 5], target: [{x}, 0, 0] }}\n\
                     scene = {union}.translate([{x}, 0, 0]);\n"
                )
            }
        })
}
