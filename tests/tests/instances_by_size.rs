//! The default rule for large unions (`Instances::Auto`): a root union of
//! `AUTO_INSTANCES` or more instances is emitted as data, a smaller one as code, and
//! the options that ask for code (`Never`, `cull`, `lib`) get code, and so does a crowd.

use sdfc_ir::to_ssa::GROUP_SIZE;
use sdfc_tests::grid_scene;
use sdfc_wgsl::{compile, Compiled, Failure, Instances, Options, AUTO_CROWD, AUTO_INSTANCES};

fn compiled(n: usize, opts: &Options) -> Compiled {
    compile(&grid_scene(n), opts).unwrap_or_else(|f| panic!("grid of {n}: {f}"))
}

/// Whether the union was emitted as data: the buffer exists and the WGSL reads it.
fn as_data(c: &Compiled) -> bool {
    let reads = c.wgsl.contains("scene_data");
    assert_eq!(reads, !c.data.is_empty(), "the WGSL and its data disagree");
    reads
}

#[test]
fn by_default_a_union_is_data_from_the_threshold_up() {
    let below = compiled(AUTO_INSTANCES - 1, &Options::default());
    assert!(
        !as_data(&below),
        "{} instances emitted as data",
        AUTO_INSTANCES - 1
    );
    let at = compiled(AUTO_INSTANCES, &Options::default());
    assert!(as_data(&at), "{AUTO_INSTANCES} instances emitted as code");
    // Every instance has a record of at least three vec4 (48 bytes), and the WGSL no longer
    // holds one block per shape: it is smaller than the code form of a grid three times as
    // large (at 150 it was smaller than the code of the grid one shape smaller; at 100 the
    // data form's parts, the lists, blocks and walks, still outweigh 99 shapes' code: 55.6
    // against 48.5 KB on 2026-12-07, 86 KB for the code of 300), and a grid ten times as
    // large has the same WGSL but for its bounds' numbers (the same kinds of shape and
    // materials).
    assert!(
        at.data.len() >= AUTO_INSTANCES * 48,
        "{} bytes",
        at.data.len()
    );
    let never = Options {
        instances: Instances::Never,
        ..Options::default()
    };
    let code = compiled(3 * AUTO_INSTANCES, &never);
    assert!(
        at.wgsl.len() < code.wgsl.len(),
        "{} bytes against the code's {}",
        at.wgsl.len(),
        code.wgsl.len()
    );
    let larger = compiled(10 * AUTO_INSTANCES, &Options::default());
    assert!(as_data(&larger) && larger.data.len() > 9 * at.data.len());
    assert!(larger.wgsl.len() * 100 < at.wgsl.len() * 101);
    // Asked for, a union of any size from 16 up is data.
    let always = Options {
        instances: Instances::Always,
        ..Options::default()
    };
    assert!(as_data(&compiled(20, &always)));
}

#[test]
fn code_where_asked_for() {
    let n = AUTO_INSTANCES;
    let never = Options {
        instances: Instances::Never,
        ..Options::default()
    };
    assert!(!as_data(&compiled(n, &never)), "Never");
    // Culling is a form of the union's code: asking for it keeps the code.
    let cull = Options {
        cull: true,
        ..Options::default()
    };
    let culled = compiled(n, &cull);
    assert!(
        !as_data(&culled) && !culled.program().groups.is_empty(),
        "cull"
    );
    // The library form has no buffer: by default it is code, and data is refused.
    let lib = Options {
        lib: true,
        ..Options::default()
    };
    assert!(!as_data(&compiled(n, &lib)), "lib");
    let refused = compile(
        &grid_scene(n),
        &Options {
            instances: Instances::Always,
            ..lib
        },
    );
    assert!(matches!(refused, Err(Failure::Usage(_))), "lib with Always");
}

/// `AUTO_INSTANCES` spheres about one point, each moved by a few hundredths: every box holds
/// the crowd's middle, more than a ray's list holds.
fn crowd(n: usize) -> String {
    let mut s = String::from("scene = union(\n");
    for i in 0..n {
        let k = i as f64;
        s += &format!(
            "    sphere(0.5).translate([{:.4}, {:.4}, {:.4}]),\n",
            0.03 * k.sin(),
            0.03 * (1.7 * k).cos(),
            0.03 * (2.3 * k).sin()
        );
    }
    s + ");\n"
}

#[test]
fn by_default_a_crowd_stays_code() {
    // A ray through more boxes at one place than its list holds walks the whole hierarchy
    // at every step there: the rule keeps such a union code, asked for it is data.
    let src = crowd(AUTO_INSTANCES);
    let auto = compile(&src, &Options::default()).expect("compiles");
    assert!(!as_data(&auto), "a crowd emitted as data by default");
    let always = Options {
        instances: Instances::Always,
        ..Options::default()
    };
    let asked = compile(&src, &always).expect("compiles");
    assert!(as_data(&asked));
    // The limit is what a ray's list holds.
    assert!(
        asked
            .wgsl
            .contains(&format!("const RAY_LIST: u32 = {AUTO_CROWD}u;")),
        "the list's size is not AUTO_CROWD"
    );
    // A grid is no crowd: one box holds each point.
    assert!(as_data(&compiled(AUTO_INSTANCES, &Options::default())));
}

/// A grid of `n` with `extra` as more children of its union.
fn grid_with(n: usize, extra: &str) -> String {
    let src = grid_scene(n);
    let cut = src.rfind(");").expect("the union's end");
    format!("{}    {extra},\n{}", &src[..cut], &src[cut..])
}

/// A floor beside the instances leaves the union data, and the other children's march
/// (`march_rest`) steps with the floor's distance along the ray, as the code form's march
/// does. A displacement that divides by its slope along the ray keeps the union code (the
/// walk has no ray function); one in a smooth blend, which does not divide, leaves it data,
/// floor or not. Asked for data, a union of 20 (fewer children than a group function's);
/// by default one of `AUTO_INSTANCES`, whose code form keeps the floor out of its group
/// functions, which never see the ray's direction.
#[test]
fn a_floor_leaves_the_union_data_and_a_displacement_along_the_ray_does_not() {
    let always = Options {
        instances: Instances::Always,
        ..Options::default()
    };
    let never = Options {
        instances: Instances::Never,
        ..Options::default()
    };
    let floor = "plane([0, 1, 0], -1)";
    let ribs = "displace(sphere(1), |p| sin(30 * p.y) / 16).translate([0, 8, 0])";
    let blended =
        "union(displace(sphere(1), |p| sin(30 * p.y) / 16), box(0.8), smooth: 0.3).translate([0, 8, 0])";
    for (n, opts) in [(20, &always), (AUTO_INSTANCES, &Options::default())] {
        for (extra, data) in [
            (floor.to_string(), true),
            (format!("{blended}, {floor}"), true),
            (format!("{ribs}, {floor}"), n > GROUP_SIZE),
        ] {
            let src = grid_with(n, &extra);
            let c = compile(&src, opts).unwrap_or_else(|f| panic!("{extra}: {f}"));
            assert_eq!(as_data(&c), data, "{n}: {extra}");
            let sample = if data {
                "rest_distance_ray(ro + rd * t, rd)"
            } else {
                "scene_distance_ray(ro + rd * t, rd)"
            };
            assert!(c.wgsl.contains(sample), "{n}: {extra}: no {sample}");
            // As code, the floor steps along the ray too.
            let code = compile(&src, &never).unwrap_or_else(|f| panic!("{extra}: {f}"));
            assert!(
                code.wgsl.contains("scene_distance_ray(ro + rd * t, rd)"),
                "{n}: {extra}: the code form marches plainly"
            );
        }
    }
}
