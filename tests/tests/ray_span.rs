//! `ray_span` in the emitted marcher: a slab test against the scene's bounds (the analysis's
//! box of the root, padded) on the axes where they are finite, a one-sided test on an axis
//! bounded at one end (a floor's half-space), and the whole ray otherwise; bounds that
//! depend on time or a param are not taken as finite.

use sdfc_wgsl::{compile, Options};

fn ray_span_of(src: &str) -> String {
    let wgsl = compile(src, &Options::default())
        .unwrap_or_else(|e| panic!("{src}: {e:?}"))
        .wgsl;
    let start = wgsl.find("fn ray_span(").expect("ray_span emitted");
    let end = start + wgsl[start..].find("\n}\n").expect("end of ray_span");
    wgsl[start..end].to_string()
}

const WHOLE_RAY: &str = "return vec2<f32>(0.0, MAX_DISTANCE);";

#[test]
fn a_bounded_scene_gets_a_slab_per_axis() {
    let f = ray_span_of("scene = sphere(1) | box([1, 2, 3]).translate([4, 0, 0]);\n");
    for axis in ["rd.x", "rd.y", "rd.z"] {
        assert!(f.contains(&format!("abs({axis}) > 1e-30")), "{f}");
    }
    // x from -1 to 4.5, padded by a thousandth of the largest size (5.5) and rounded out.
    assert!(f.contains("(-1.0055001 - ro.x)"), "{f}");
    assert!(f.contains("(4.5055003 - ro.x)"), "{f}");
    assert!(!f.contains(WHOLE_RAY), "{f}");
}

#[test]
fn an_unbounded_axis_has_no_slab() {
    // Spheres repeated along x: bounded in y and z only.
    let f = ray_span_of("scene = sphere(0.5).repeat([2, 0, 0]);\n");
    assert!(!f.contains("rd.x"), "{f}");
    assert!(
        f.contains("abs(rd.y) > 1e-30") && f.contains("abs(rd.z) > 1e-30"),
        "{f}"
    );
}

#[test]
fn unbounded_and_moving_scenes_search_the_whole_ray() {
    for src in [
        "scene = sphere(1) | plane([0, 1, 1], 1);\n",
        "scene = sphere(1) | plane([0, 1, 0], 1).rotate([0, 0, 1], 30deg);\n",
        "param r = 1;\nscene = sphere(r);\n",
        "scene = sphere(1).translate([sin(time) * 3, 0, 0]);\n",
    ] {
        let f = ray_span_of(src);
        assert!(f.contains(WHOLE_RAY), "{src}: {f}");
    }
}

#[test]
fn a_floor_bounds_the_scene_above_and_a_ceiling_below() {
    // Under the floor y <= 1 (padded by 1e-3): a rising ray leaves at the floor, a falling
    // one enters there, a level one above it misses; no other axis is tested.
    let f = ray_span_of("scene = sphere(0.5) | plane([0, 1, 0], 1);\n");
    assert!(
        f.contains("if rd.y > 1e-30 {\n        t1 = min(t1, (1.001 - ro.y) / rd.y);"),
        "{f}"
    );
    assert!(
        f.contains("} else if rd.y < -1e-30 {\n        t0 = max(t0, (1.001 - ro.y) / rd.y);"),
        "{f}"
    );
    assert!(
        f.contains("} else if ro.y > 1.001 {\n        t1 = -1.0;"),
        "{f}"
    );
    assert!(!f.contains("rd.x") && !f.contains("rd.z"), "{f}");
    // Above the ceiling y >= 2 (a normal pointing down): the other way round.
    let f = ray_span_of("scene = plane([0, -2, 0], -2);\n");
    assert!(
        f.contains("if rd.y > 1e-30 {\n        t0 = max(t0, (1.999 - ro.y) / rd.y);"),
        "{f}"
    );
    assert!(f.contains("} else if ro.y < 1.999 {"), "{f}");
    // Moved, scaled, intersected with a wall: x >= -3 from the wall, y <= 2 (0.5 - (-0.5)
    // times 2) from the floor.
    let f = ray_span_of(
        "scene = plane([0, 1, 0], 0.5).translate([0, 0.5, 0]).scale(2) & plane([-1, 0, 0], 3);\n",
    );
    assert!(
        f.contains("t1 = min(t1, (2.0010002 - ro.y) / rd.y);"),
        "{f}"
    );
    assert!(
        f.contains("t0 = max(t0, (-3.0010002 - ro.x) / rd.x);"),
        "{f}"
    );
    assert!(!f.contains("rd.z"), "{f}");
}

/// `bounds_outside`, which shadow rays read to stop once they have left the scene's bounds
/// for good: the same padded box as `ray_span`, open ends clamped to +-3e38; emitted only
/// with shadows, and answering "inside" everywhere for a scene without finite bounds.
fn bounds_outside_of(src: &str) -> Option<String> {
    let wgsl = compile(src, &Options::default())
        .unwrap_or_else(|e| panic!("{src}: {e:?}"))
        .wgsl;
    let start = wgsl.find("fn bounds_outside(")?;
    let end = start + wgsl[start..].find("\n}\n").expect("end of bounds_outside");
    Some(wgsl[start..end].to_string())
}

/// The numbers of `bounds_outside`'s `clamp(p, lo, hi)`: lo then hi, x y z each (an open
/// end as +-3e38).
fn shadow_box(f: &str) -> [f32; 6] {
    let at = f.find("clamp(p, ").expect("a clamp") + "clamp(p, ".len();
    let end = at + f[at..].find(");").expect("its end");
    let mut v = Vec::new();
    for part in f[at..end].split("vec3<f32>(").skip(1) {
        let nums: Vec<f32> = part
            .trim_end_matches([')', ',', ' '])
            .split(", ")
            .map(|x| x.trim_end_matches(')').parse().expect("a float"))
            .collect();
        v.extend(if nums.len() == 1 {
            vec![nums[0]; 3]
        } else {
            nums
        });
    }
    v.try_into().expect("six numbers")
}

#[test]
fn shadow_rays_stop_just_outside_ray_spans_box() {
    // ray_span's padded ends (a_bounded_scene_gets_a_slab_per_axis), widened by 1e-5 of the
    // largest coordinate (4.5): f32 rounding and the culled union's slack.
    let f = bounds_outside_of(
        "render { shadows: soft(8) }\nscene = sphere(1) | box([1, 2, 3]).translate([4, 0, 0]);\n",
    )
    .expect("emitted with shadows");
    let b = shadow_box(&f);
    assert!(b[0] < -1.0055001 && b[0] > -1.0056, "{f}");
    assert!(b[3] > 4.5055003 && b[3] < 4.5056, "{f}");
    // A floor: only the top is finite.
    let f =
        bounds_outside_of("render { shadows: hard }\nscene = sphere(0.5) | plane([0, 1, 0], 1);\n")
            .expect("emitted with hard shadows");
    let b = shadow_box(&f);
    assert_eq!([b[0], b[2], b[3], b[5]], [-3e38, -3e38, 3e38, 3e38], "{f}");
    assert!(b[4] > 1.001 && b[4] < 1.0011, "{f}");
    // Unbounded: never left.
    let f = bounds_outside_of(
        "render { shadows: soft(8) }\nscene = sphere(1) | plane([0, 1, 1], 1);\n",
    )
    .expect("emitted");
    assert!(f.contains("return vec3<f32>(0.0);"), "{f}");
    // No shadows, no test.
    assert!(bounds_outside_of("scene = sphere(1);\n").is_none());
}

/// A union read as data answers, beyond its hierarchy's root box, the distance to that box,
/// which is padded by a thousandth of its size and 1e-3 (more than ray_span's box on a
/// one-sided axis): the shadow rays' box takes it in.
#[test]
fn shadow_rays_stop_outside_a_data_unions_root_box() {
    let mut union = String::from("union(");
    for i in 0..40 {
        let (x, z) = ((i % 8) as f32 * 0.9 - 3.2, (i / 8) as f32 * -0.9);
        union += &format!("sphere(0.35).translate([{x}, 0.35, {z}]), ");
    }
    union += ")";
    let src = format!("render {{ shadows: soft(8) }}\nscene = plane([0, 1, 0], 0) | {union};\n");
    let opts = Options {
        instances: sdfc_wgsl::Instances::Always,
        ..Options::default()
    };
    let c = compile(&src, &opts).expect("compiles");
    assert!(!c.data.is_empty(), "read as data");
    let word = |i: usize| f32::from_le_bytes(c.data[4 * i..4 * i + 4].try_into().expect("4"));
    // Node 0: centre (words 0..3), skip, half (words 4..7).
    let top = word(1) + word(5);
    let start = c.wgsl.find("fn bounds_outside(").expect("emitted");
    let end = start + c.wgsl[start..].find("\n}\n").expect("its end");
    let b = shadow_box(&c.wgsl[start..end]);
    assert!(top > 0.701, "the root box's top {top} is above ray_span's");
    assert!(
        b[4] >= top,
        "the shadow box's top {} is below the root box's {top}",
        b[4]
    );
}

/// `OUTSIDE_FACTOR` of a scene with soft shadows.
fn outside_factor_of(src: &str) -> f32 {
    let wgsl = compile(src, &Options::default())
        .unwrap_or_else(|e| panic!("{src}: {e:?}"))
        .wgsl;
    let key = "const OUTSIDE_FACTOR: f32 = ";
    let at = wgsl.find(key).expect("the factor") + key.len();
    let end = at + wgsl[at..].find(';').expect("its end");
    wgsl[at..end].parse().expect("a float")
}

#[test]
fn the_outside_factor_follows_the_distance() {
    let soft = "render { shadows: soft(8) }\nscene = ";
    let cases: &[(&str, f32)] = &[
        // Exact distances, and what keeps them so outside the box.
        (
            "box([1, 2, 3]) | sphere(1).translate([4, 0, 0]) | plane([0, 1, 0], 0)",
            1.0,
        ),
        (
            "union(sphere(1), sphere(1).translate([1.5, 0, 0]), smooth: 0.3)",
            1.0,
        ),
        ("box([1, 1, 1]).round(0.2).rotate_y(30deg).scale(2)", 1.0),
        ("subtract(box([1, 1, 1]), sphere(1.2))", 1.0),
        ("sphere(0.4).repeat([2, 0, 2])", 1.0),
        // A heightfield of slope 1.7 divides by sqrt(1 + 1.7^2) = 1.972...
        (
            "heightfield(|x, z| 0.5 * sin(x), lipschitz: 1.7)",
            0.5070201,
        ),
        // An intersection: by the child whose box is the intersection's, else 1 / sqrt(n).
        ("intersect(sphere(1), box([4, 4, 4]))", 1.0),
        (
            "intersect(sphere(1), box([2, 2, 2]).translate([1, 1, 1]))",
            0.70710677,
        ),
        // An ellipsoid's bound: min(r) / max(r).
        ("ellipsoid([1, 0.5, 0.25])", 0.25),
        // A smooth intersection is never below the plain one: the same factor.
        (
            "intersect(sphere(1), box([0.8, 0.8, 0.8]), smooth: 0.2)",
            1.0,
        ),
        // Unknown: a twist's bound, an `sdf`.
        ("box([0.5, 1, 0.5]).twist(1) | plane([0, 1, 0], 0)", 0.0),
        ("sdf(|p| length(p) - 1)", 0.0),
    ];
    for (scene, want) in cases {
        let src = format!("{soft}{scene};\n");
        let got = outside_factor_of(&src);
        assert!(
            (got - want).abs() <= 1e-6 * want.max(1.0),
            "{scene}: {got}, expected {want}"
        );
        // A soft shadow never stops where the factor is unknown.
        let f = bounds_outside_of(&src).expect("emitted");
        assert_eq!(
            *want == 0.0,
            f.contains("return vec3<f32>(0.0);"),
            "{scene}: {f}"
        );
    }
}

#[test]
fn hard_shadows_stop_at_the_bounds_whatever_the_distance() {
    // The box holds every surface: a hard shadow ray that has left it meets none.
    let f = bounds_outside_of(
        "render { shadows: hard }\nscene = box([0.5, 1, 0.5]).twist(1) | plane([0, 1, 0], 0);\n",
    )
    .expect("emitted");
    assert!(f.contains("clamp(p, "), "{f}");
}
