//! Inputs at the documented limits (docs/language.md, "Limits"): a file of the maximum size,
//! scenes that grow exponentially through `let` or `fn`, nesting past the limit. Each must
//! compile or be refused with its limit's diagnostic, never exhaust memory or the stack.
//!
//! Compile time stays bounded because no emitted function grows with the input: naga's WGSL
//! front end is quadratic in the size of one function, so the structural property asserted
//! here (every function has at most `MAX_FUNCTION_NODES` nodes) is what keeps time linear.
//! The times themselves are measured by the `max_size` benchmark of `benches/compile.rs`.

use sdfc_ir::scene::limits::{MAX_INLINED_CALLS, MAX_MAGNITUDE, MAX_NODES, MAX_SHAPE_INSTANCES};
use sdfc_syntax::MAX_SOURCE_BYTES;
use sdfc_tests::{doubling_lets, max_size_union};
use sdfc_wgsl::{compile, Compiled, Failure, Options};

/// The largest function the compiler may emit for the scenes below: a group function holds
/// at most 32 union children (or one outlined shape of under 64 nodes plus calls), each a few
/// dozen nodes.
const MAX_FUNCTION_NODES: usize = 4_000;

fn compiled(name: &str, src: &str) -> Compiled {
    match compile(src, &Options::default()) {
        Ok(c) => c,
        Err(Failure::Diagnostics(d)) => panic!("{name}: {:?}", d[0].message),
        Err(f) => panic!("{name}: {f}"),
    }
}

/// The message of the first error, which the scene must produce.
fn refused(name: &str, src: &str) -> String {
    match compile(src, &Options::default()) {
        Ok(_) => panic!("{name}: compiled, expected a limit error"),
        Err(Failure::Diagnostics(d)) => {
            let e = d.iter().find(|d| d.is_error()).expect("an error");
            assert!(
                e.span.end as usize <= src.len(),
                "{name}: span out of bounds"
            );
            e.message.clone()
        }
        Err(f) => panic!("{name}: {f}"),
    }
}

fn largest_function(c: &Compiled) -> usize {
    let p = c.program();
    std::iter::once(&p.distance)
        .chain(std::iter::once(&p.material))
        .chain(&p.groups)
        .map(|f| f.graph.len())
        .max()
        .unwrap_or(0)
}

#[test]
fn a_flat_union_of_the_maximum_file_size_compiles_in_small_functions() {
    let src = max_size_union(MAX_SOURCE_BYTES);
    let n = src.matches("sphere").count();
    assert!(src.len() <= MAX_SOURCE_BYTES && n > 20_000);
    let c = compiled("flat union", &src);
    let largest = largest_function(&c);
    assert!(
        largest <= MAX_FUNCTION_NODES,
        "{n} spheres: a function of {largest} nodes"
    );
    // One byte more than the limit is refused, with the limit named.
    let over = format!("{src}{}", " ".repeat(MAX_SOURCE_BYTES + 1 - src.len()));
    let msg = refused("oversized file", &over);
    assert!(msg.contains("larger than"), "{msg}");
}

/// A union written as a chain of `|`, far longer than the expression depth limit, is the
/// same scene as the `union(...)` call: the same WGSL, its shapes as code and as data.
#[test]
fn a_long_chain_of_bars_is_the_union_call() {
    let call = max_size_union(60_000);
    let items: Vec<&str> = call
        .lines()
        .filter_map(|l| l.trim().strip_suffix(','))
        .collect();
    assert!(
        items.len() > 4 * sdfc_syntax::MAX_EXPR_DEPTH,
        "{}",
        items.len()
    );
    let bars = format!("scene = {};\n", items.join("\n  | "));
    for instances in [sdfc_wgsl::Instances::Auto, sdfc_wgsl::Instances::Never] {
        let opts = Options {
            instances,
            ..Options::default()
        };
        let emitted = |name: &str, src: &str| match compile(src, &opts) {
            Ok(c) => (c.wgsl, c.data),
            Err(Failure::Diagnostics(d)) => panic!("{name}: {:?}", d[0].message),
            Err(f) => panic!("{name}: {f}"),
        };
        let (call, bars) = (emitted("call", &call), emitted("bars", &bars));
        assert!(call == bars, "{instances:?}: the two forms differ");
        assert_eq!(call.1.is_empty(), instances == sdfc_wgsl::Instances::Never);
    }
}

/// A chain of numbers joined by `|` is an error at each: the compiler stops at a hundred,
/// as the parser does, and says so last (rendering ten thousand snippets took seconds).
#[test]
fn errors_past_a_hundred_are_cut_short() {
    let src = format!("scene = {};\n", vec!["1"; 10_000].join(" | "));
    let message = |d: &sdfc_syntax::diag::Diagnostic| d.message.clone();
    let diags = match compile(&src, &Options::default()) {
        Err(Failure::Diagnostics(d)) => d,
        Ok(_) => panic!("numbers joined by `|` compiled"),
        Err(f) => panic!("{f}"),
    };
    let limit = sdfc_syntax::MAX_DIAGNOSTICS;
    assert_eq!(diags.len(), limit + 1);
    assert!(diags[..limit]
        .iter()
        .all(|d| message(d).contains("needs shapes")));
    assert_eq!(
        message(&diags[limit]),
        format!("too many errors; stopping after {limit}")
    );
    // Where the first error left out starts: the 101st `1`.
    assert_eq!(diags[limit].span.start as usize, 8 + 4 * limit);
}

#[test]
fn doubling_lets_below_the_limit_are_emitted_once_per_let() {
    // 15 levels unfold into about 98 000 shapes, under the limit of 100 000.
    let src = doubling_lets(15);
    let c = compiled("15 doubling lets", &src);
    let largest = largest_function(&c);
    assert!(
        largest <= MAX_FUNCTION_NODES,
        "a function of {largest} nodes"
    );
    // 2^15 spheres of radius 0.25 at x = sum of a subset of 1..=15: every integer from 0 to
    // 120 is such a sum, so the distance at (x, 1, 0) is 0.75 for those x.
    let p = c.program();
    for x in [0.0, 7.0, 120.0] {
        let d = sdfc_ir::eval::eval_func::<f64>(
            &p.distance,
            &p.groups,
            &sdfc_ir::eval::Inputs::at([x, 1.0, 0.0]),
        )[0]
        .scalar()
        .unwrap();
        assert!((d - 0.75).abs() < 1e-6, "distance at x = {x}: {d}");
    }
}

#[test]
fn doubling_lets_past_the_limit_are_refused() {
    // 16 levels: about 196 000 shapes; 60 levels: about 10^18 (a count that must not overflow).
    for levels in [16, 60] {
        let msg = refused("doubling lets", &doubling_lets(levels));
        assert!(
            msg.contains(&format!("more than the limit of {MAX_SHAPE_INSTANCES}")),
            "{levels} levels: {msg}"
        );
    }
}

#[test]
fn doubling_fns_hit_the_node_limit() {
    // About six new nodes a call, so the graph passes the node limit (at some 350 000 calls)
    // before the count of calls passes its own (see the next test).
    let mut src = String::from("fn f0(p) = length(p) - 1;\n");
    for k in 1..40 {
        src += &format!(
            "fn f{k}(p) = min(f{}(p), f{}(p + [{k}, 0, 0])) + abs(p.x - {k}) * 0.001;\n",
            k - 1,
            k - 1
        );
    }
    src += "scene = sdf(|p| f39(p));\n";
    let msg = refused("doubling fns", &src);
    assert!(
        msg.contains(&format!("grows past {MAX_NODES} nodes")),
        "{msg}"
    );
}

/// Found by the CLI audit of 2026-12-04: each level calls the one below twice with the same
/// argument, so hash-consing keeps the graph at a node a level while the inlining doubles; 26
/// levels (776 bytes) took 42 s and compiled, 39 never finished. The count of calls inlined
/// is bounded now, whatever the graph's size.
#[test]
fn doubling_fns_of_equal_values_hit_the_call_limit() {
    let mut src = String::from("param r = 1;\nfn f0(x) = x;\n");
    for k in 1..40 {
        src += &format!("fn f{k}(x) = f{0}(x) + f{0}(x);\n", k - 1);
    }
    src += "scene = sphere(f39(r));\n";
    let msg = refused("doubling fns of equal values", &src);
    assert!(
        msg.contains(&format!("more than {MAX_INLINED_CALLS} `fn` calls")),
        "{msg}"
    );
    // Under the limit the same pattern compiles: 2^19 calls of a level-19 chain.
    let mut ok = String::from("param r = 1;\nfn f0(x) = x;\n");
    for k in 1..19 {
        ok += &format!("fn f{k}(x) = f{0}(x) + f{0}(x);\n", k - 1);
    }
    ok += "scene = sphere(f18(r) / 100000);\n";
    compiled("a chain under the call limit", &ok);
}

/// Found by the language audit of 2026-12-04: finite but huge sizes made the emitted WGSL
/// invalid (an internal error, exit 2): `-inf.0` in `ray_span` where the bounds left f32's
/// range, and constant expressions that overflow, which WGSL makes an error (a capsule's
/// `dot(b - a, b - a)` under analytic normals). Arguments past the limit are now the user's
/// error, placed at the argument; at the limit every primitive's shader validates.
/// `scene` must be refused with the magnitude limit's message.
fn refused_past_the_magnitude_limit(scene: &str) {
    let msg = refused(scene, scene);
    assert!(
        msg.contains(&format!("must be at most {MAX_MAGNITUDE:e} in magnitude")),
        "{scene}: {msg}"
    );
}

#[test]
fn sizes_past_the_magnitude_limit_are_refused_and_at_it_compile() {
    for scene in [
        "scene = sphere(3.4028234e38);",
        "scene = sphere(2).scale(2e38);",
        "scene = hex_prism(3e38, 1);",
        "render { normals: analytic }\nscene = capsule([0, 0, 0], [1e20, 0, 0], 1);",
        "render { normals: analytic }\nscene = cone(1e30, 1e30);",
        "render { normals: analytic }\nscene = pyramid(1e30);",
    ] {
        refused_past_the_magnitude_limit(scene);
    }
    for normals in ["central", "analytic"] {
        for shape in [
            "cone(1e12, 1e12)",
            "capsule([0, 0, 0], [1e12, -1e12, 1e12], 1e12)",
            "pyramid(1e12)",
            "hex_prism(1e12, 1e12)",
            "torus(1e12, 1e12)",
            "capped_cone(1e12, 1e12, 1e12)",
            "ellipsoid([1e12, 1e12, 1e-3])",
            "box(1e12).round(1e12)",
            // Bounds past f32's range: `ray_span` leaves that axis unclipped.
            "sphere(1e12).scale(1e12).scale(1e12).scale(1e12)",
            "sphere(0.1).repeat([1e38, 0, 0], count: [100000, 1, 1])",
        ] {
            let scene = format!("render {{ normals: {normals} }}\nscene = {shape};\n");
            compiled(&scene, &scene);
        }
    }
}

/// A param's default past the limit is refused like a constant size (a 1e20 position made
/// the shape vanish: its length overflowed); at the limit it compiles.
#[test]
fn param_values_past_the_magnitude_limit_are_refused() {
    for scene in [
        "param c = [1e20, 0, 0];\nscene = sphere(1).translate(c);",
        "param r = -2e12;\nscene = sphere(r);",
    ] {
        refused_past_the_magnitude_limit(scene);
    }
    compiled(
        "at the limit",
        "param c = [1e12, -1e12, 0];\nscene = sphere(1).translate(c);",
    );
}

#[test]
fn parentheses_nested_past_the_limit_are_refused_without_overflow() {
    let depth = 200_000;
    let src = format!(
        "scene = {}sphere(1){};\n",
        "(".repeat(depth),
        ")".repeat(depth)
    );
    let msg = refused("deep parentheses", &src);
    assert!(msg.contains("nested too deeply"), "{msg}");
}

/// Fuzzer finds: unclosed parentheses inside lambdas (`|p| a * (|p| a * (...`) made pest's
/// backtracking exponential (minutes for 2.8 kB), because the expression loop parsed again,
/// after the lambda, whatever the lambda's body had failed to take. The grammar now ends an
/// expression at a lambda, so both files parse without touching the parser's call budget
/// and every error in them is reported.
#[test]
fn exponential_backtracking_finds_parse_with_ordinary_diagnostics() {
    for name in [
        "exponential_backtracking.sdf",
        "exponential_backtracking_2.sdf",
    ] {
        let path = sdfc_tests::root().join("regressions").join(name);
        let src = std::fs::read_to_string(&path).expect("regression file");
        let diags = sdfc_syntax::parse(&src).expect_err("the file is broken");
        assert!(
            diags.iter().all(|d| !d.message.contains("too tangled")),
            "{name}: {diags:?}"
        );
        assert!(diags.len() >= 4, "{name}: every item's error is reported");
    }
}

/// Unclosed constructs nested 100 deep: were any of them exponential, as `|p| a * (` was,
/// pest would run into its call budget (2^100 calls) and the item would be "too tangled".
#[test]
fn nested_unclosed_constructs_parse_in_linear_time() {
    let patterns = [
        "|p| a * (",
        "f(|p| a * (",
        "(|p| a * (",
        "sdf(|p| a | ",
        "|p| a | |q| (",
        "f(",
        "x.f(",
        "[",
        "f(a: ",
        "-(",
        "[|p| ",
    ];
    for pattern in patterns {
        let src = format!("scene = {};\n", pattern.repeat(100));
        let diags = sdfc_syntax::parse(&src).expect_err("unclosed");
        assert!(
            diags.iter().all(|d| !d.message.contains("too tangled")),
            "`{pattern}` x 100: {diags:?}"
        );
    }
}

/// The call budget stays as a safety net, with its own diagnostic: a 1 MiB chain `1+1+...`
/// is valid syntax but needs more than 32 rule calls a byte.
#[test]
fn an_item_past_the_call_budget_gets_a_diagnostic() {
    let body = "1+".repeat((sdfc_syntax::MAX_SOURCE_BYTES - 64) / 2);
    let src = format!("let a = 1;\nscene = {body}1;\n");
    let diags = sdfc_syntax::parse(&src).expect_err("too big an item");
    assert_eq!(diags.len(), 1, "{diags:?}");
    assert!(diags[0].message.contains("too tangled"), "{diags:?}");
}
