//! A proptest generator of random *valid* scenes: every shape and operation this version
//! implements, nested, with random sizes. Shared by the compile property test and the GPU
//! agreement test of the renderer.

use proptest::prelude::*;

/// A number in `lo..hi`, printed with three decimals as a scene would spell it.
pub fn num(lo: f64, hi: f64) -> impl Strategy<Value = String> {
    (lo..hi).prop_map(|x| format!("{x:.3}"))
}

/// A vec3 literal with components in `lo..hi`.
pub fn vec3(lo: f64, hi: f64) -> impl Strategy<Value = String> {
    (num(lo, hi), num(lo, hi), num(lo, hi)).prop_map(|(a, b, c)| format!("[{a}, {b}, {c}]"))
}

/// One primitive call with valid arguments.
pub fn primitive() -> impl Strategy<Value = String> {
    prop_oneof![
        num(0.1, 2.0).prop_map(|r| format!("sphere({r})")),
        vec3(0.1, 2.0).prop_map(|s| format!("box({s})")),
        (0.4f64..2.0, 0.0f64..0.99)
            .prop_map(|(s, f)| format!("round_box({s:.3}, {:.3})", s * 0.5 * f)),
        (num(0.5, 2.0), num(0.05, 0.4)).prop_map(|(a, b)| format!("torus({a}, {b})")),
        (num(0.1, 1.0), num(0.1, 2.0)).prop_map(|(a, b)| format!("cylinder({a}, {b})")),
        (vec3(-1.0, 1.0), vec3(-1.0, 1.0), num(0.05, 0.5))
            .prop_map(|(a, b, r)| format!("capsule({a}, {b}, {r})")),
        (vec3(-1.0, 1.0), num(-1.0, 1.0))
            .prop_map(|(n, h)| format!("plane({n} + [0, 0.01, 0], {h})")),
        num(0.2, 1.5).prop_map(|r| format!("sdf(|p| length(p) - {r})")),
        more_primitives(),
        (1u32..6).prop_map(|i| format!("menger(iterations: {i})")),
        (1u32..12).prop_map(|i| format!("sierpinski(iterations: {i})")),
    ]
}

/// The primitives of the shape library beyond the first seven.
pub fn more_primitives() -> impl Strategy<Value = String> {
    prop_oneof![
        (0.4f64..2.0, 0.0f64..0.99)
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

/// The mandelbulb, apart, with a power that is mostly fractional: its orbit is chaotic, and
/// through the device's trigonometry f32 (GPU) and f64 (CPU) evaluations part by up to 1e-3,
/// so the GPU agreement test leaves it out (`crates/sdfc-render/tests/prims_gpu.rs` checks
/// it, and whole powers to their conditioning).
pub fn mandelbulb() -> impl Strategy<Value = String> {
    (num(2.0, 12.0), 1u32..10).prop_map(|(n, i)| format!("mandelbulb(power: {n}, iterations: {i})"))
}

/// A shape expression: primitives under up to four levels of operations.
pub fn shape() -> impl Strategy<Value = String> {
    shape_of(prop_oneof![4 => primitive(), 1 => mandelbulb()].boxed())
}

/// A mandelbulb of a whole power, which the trigonometry-free helper computes: on the device
/// it agrees with f64 to 1e-5 beyond its conditioning (`prims_gpu.rs`).
pub fn whole_power_mandelbulb() -> impl Strategy<Value = String> {
    (2u32..=12, 1u32..10).prop_map(|(n, i)| format!("mandelbulb(power: {n}, iterations: {i})"))
}

/// Like [`shape`], with whole-power mandelbulbs among the primitives.
pub fn shape_with_whole_power_mandelbulbs() -> impl Strategy<Value = String> {
    shape_of(prop_oneof![3 => primitive(), 1 => whole_power_mandelbulb()].boxed())
}

/// Like [`shape`], without the mandelbulb: for comparisons of f32 with f64 at 1e-5.
pub fn shape_without_mandelbulb() -> impl Strategy<Value = String> {
    shape_of(primitive().boxed())
}

fn shape_of(leaves: BoxedStrategy<String>) -> impl Strategy<Value = String> {
    leaves.prop_recursive(4, 24, 3, |inner| {
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

/// Runs `check` on `cases` values of `strategy` drawn from the fixed `seed`, failing the
/// test with proptest's smallest failing case; returns how many cases `check` took (returned
/// true for), so that a property test can ask that enough of its random scenes were of the
/// kind it checks.
pub fn run_counted<S: Strategy>(
    cases: u32,
    seed: u64,
    strategy: S,
    check: impl Fn(S::Value) -> Result<bool, TestCaseError>,
) -> usize {
    let config = proptest::test_runner::Config {
        cases,
        rng_seed: proptest::test_runner::RngSeed::Fixed(seed),
        failure_persistence: None,
        ..proptest::test_runner::Config::default()
    };
    let taken = std::cell::Cell::new(0usize);
    let result = proptest::test_runner::TestRunner::new(config).run(&strategy, |value| {
        if check(value)? {
            taken.set(taken.get() + 1);
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    taken.get()
}

/// How many cases a random test runs: `default`, or `SDFC_RANDOM_CASES` where set (to run
/// thousands once, by hand, as the docs' figures were).
pub fn cases(default: u32) -> u32 {
    std::env::var("SDFC_RANDOM_CASES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(default)
}

/// The seed of a random test: `default`, or `SDFC_RANDOM_SEED` where set.
pub fn seed(default: u64) -> u64 {
    std::env::var("SDFC_RANDOM_SEED")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(default)
}
