//! Property: randomly generated *valid* scenes (every shape and operation this version
//! implements, nested, with random sizes) always compile; their WGSL passes naga in full and
//! library form; and the f64 reference distance is finite wherever it is sampled. The GPU
//! agreement half of this check lives with the renderer's tests.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_wgsl::{compile, Options};

fn num(lo: f64, hi: f64) -> impl Strategy<Value = String> {
    (lo..hi).prop_map(|x| format!("{x:.3}"))
}

fn vec3(lo: f64, hi: f64) -> impl Strategy<Value = String> {
    (num(lo, hi), num(lo, hi), num(lo, hi)).prop_map(|(a, b, c)| format!("[{a}, {b}, {c}]"))
}

fn primitive() -> impl Strategy<Value = String> {
    prop_oneof![
        num(0.1, 2.0).prop_map(|r| format!("sphere({r})")),
        vec3(0.1, 2.0).prop_map(|s| format!("box({s})")),
        (0.4f64..2.0, 0.0f64..1.0)
            .prop_map(|(s, f)| format!("round_box({s:.3}, {:.3})", s * 0.5 * f)),
        (num(0.5, 2.0), num(0.05, 0.4)).prop_map(|(a, b)| format!("torus({a}, {b})")),
        (num(0.1, 1.0), num(0.1, 2.0)).prop_map(|(a, b)| format!("cylinder({a}, {b})")),
        (vec3(-1.0, 1.0), vec3(-1.0, 1.0), num(0.05, 0.5))
            .prop_map(|(a, b, r)| format!("capsule({a}, {b}, {r})")),
        (vec3(-1.0, 1.0), num(-1.0, 1.0))
            .prop_map(|(n, h)| format!("plane({n} + [0, 0.01, 0], {h})")),
        num(0.2, 1.5).prop_map(|r| format!("sdf(|p| length(p) - {r})")),
        more_primitives(),
        fractals(),
    ]
}

fn more_primitives() -> impl Strategy<Value = String> {
    prop_oneof![
        (0.4f64..2.0, 0.0f64..1.0)
            .prop_map(|(s, f)| format!("box_frame({s:.3}, {:.3})", s * 0.5 * f)),
        (num(0.5, 2.0), num(0.05, 0.4), num(0.0, 180.0))
            .prop_map(|(a, b, t)| format!("capped_torus({a}, {b}, {t}deg)")),
        num(0.1, 1.0).prop_map(|r| format!("infinite_cylinder({r})")),
        (num(0.0, 1.0), num(0.0, 2.0)).prop_map(|(r, h)| format!("cone({r}, {h})")),
        (num(0.0, 2.0), num(0.0, 1.0), num(0.0, 1.0))
            .prop_map(|(h, a, b)| format!("capped_cone({h}, {a}, {b})")),
        vec3(0.05, 1.5).prop_map(|r| format!("ellipsoid({r})")),
        num(0.0, 2.0).prop_map(|s| format!("octahedron({s})")),
        (num(0.0, 1.0), num(0.0, 2.0)).prop_map(|(r, h)| format!("hex_prism({r}, {h})")),
        (num(0.0, 1.0), num(0.0, 2.0)).prop_map(|(r, h)| format!("tri_prism({r}, {h})")),
        num(0.0, 2.0).prop_map(|h| format!("pyramid({h})")),
    ]
}

fn fractals() -> impl Strategy<Value = String> {
    prop_oneof![
        (num(2.0, 12.0), 1u32..10)
            .prop_map(|(n, i)| format!("mandelbulb(power: {n}, iterations: {i})")),
        (1u32..6).prop_map(|i| format!("menger(iterations: {i})")),
        (1u32..12).prop_map(|i| format!("sierpinski(iterations: {i})")),
    ]
}

fn shape() -> impl Strategy<Value = String> {
    primitive().prop_recursive(4, 24, 3, |inner| {
        prop_oneof![
            (
                inner.clone(),
                inner.clone(),
                prop::option::of(num(0.0, 0.5))
            )
                .prop_map(|(a, b, k)| match k {
                    Some(k) => format!("union({a}, {b}, smooth: {k})"),
                    None => format!("({a} | {b})"),
                }),
            (
                inner.clone(),
                inner.clone(),
                prop::option::of(num(0.0, 0.5))
            )
                .prop_map(|(a, b, k)| match k {
                    Some(k) => format!("intersect({a}, {b}, smooth: {k})"),
                    None => format!("({a} & {b})"),
                }),
            (
                inner.clone(),
                inner.clone(),
                prop::option::of(num(0.0, 0.5))
            )
                .prop_map(|(a, b, k)| match k {
                    Some(k) => format!("subtract({a}, {b}, smooth: {k})"),
                    None => format!("({a} - {b})"),
                }),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("xor({a}, {b})")),
            (inner.clone(), vec3(-3.0, 3.0)).prop_map(|(a, v)| format!("{a}.translate({v})")),
            (inner.clone(), 0usize..3, num(-180.0, 180.0))
                .prop_map(|(a, axis, t)| format!("{a}.rotate_{}({t}deg)", ["x", "y", "z"][axis])),
            (inner.clone(), vec3(-1.0, 1.0), num(-3.0, 3.0))
                .prop_map(|(a, axis, t)| format!("{a}.rotate({axis} + [0.01, 0, 0], {t})")),
            (inner.clone(), num(0.2, 3.0)).prop_map(|(a, f)| format!("{a}.scale({f})")),
            (inner.clone(), 0usize..3)
                .prop_map(|(a, axis)| format!("{a}.mirror_{}()", ["x", "y", "z"][axis])),
            (inner.clone(), vec3(0.0, 4.0))
                .prop_map(|(a, p)| format!("{a}.repeat({p} + [1, 0, 0])")),
            (inner.clone(), vec3(1.0, 4.0), 1u32..4, 1u32..4)
                .prop_map(|(a, p, n, m)| format!("{a}.repeat({p}, count: [{n}, {m}, 1])")),
            (inner.clone(), vec3(0.0, 1.0)).prop_map(|(a, h)| format!("{a}.elongate({h})")),
            (inner.clone(), num(0.0, 0.3)).prop_map(|(a, r)| format!("{a}.round({r})")),
            (inner.clone(), num(0.01, 0.3)).prop_map(|(a, t)| format!("{a}.onion({t})")),
            (inner.clone(), vec3(0.0, 1.0)).prop_map(|(a, c)| format!("{a}.color({c})")),
            (inner, num(1.0, 40.0)).prop_map(|(a, k)| format!(
                "displace({a}, |p| sin({k} * p.y) / 32, lipschitz: {:.3})",
                1.0 + k.parse::<f64>().unwrap_or(40.0) / 32.0
            )),
        ]
    })
}

proptest! {
    #![proptest_config(Config { cases: 256, rng_seed: RngSeed::Fixed(0x5dfc), failure_persistence: None, ..Config::default() })]

    #[test]
    fn random_valid_scenes_compile_and_validate(scene in shape(), pts in prop::collection::vec(prop::array::uniform3(-4.0f64..4.0), 16)) {
        let src = format!("scene = {scene};\n");
        let c = match compile(&src, &Options::default()) {
            Ok(c) => c,
            Err(e) => return Err(TestCaseError::fail(format!("{src}\n{e:?}"))),
        };
        let lib = compile(&src, &Options { lib: true, import_path: None });
        prop_assert!(lib.is_ok(), "{src}: library form failed");
        let p = c.program();
        for pt in pts {
            let d = eval_func(&p.distance, &p.groups, &Inputs::at(pt))[0].scalar().unwrap_or(f64::NAN);
            prop_assert!(d.is_finite(), "{src}: distance {d} at {pt:?}");
        }
    }
}
