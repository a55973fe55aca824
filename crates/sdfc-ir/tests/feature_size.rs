//! The size of a scene's smallest feature (`Analysis::feature`), below which the difference
//! normals' step does not go: boxes' largest half-extents (at most 16 times their smallest),
//! times the scales above them; 0
//! where a shape's size is not known.

fn feature(src: &str) -> f64 {
    let file = sdfc_syntax::parse(src).expect("parses");
    let (stages, diags) = sdfc_ir::compile(&file, src.len());
    match stages {
        Some(s) => s.program.analysis.feature,
        None => panic!("does not compile: {diags:?}"),
    }
}

fn close(a: f64, b: f64) -> bool {
    // The scene's constants are f32.
    (a - b).abs() <= 1e-6 * b.abs().max(1e-3)
}

#[test]
fn the_smallest_shape_in_the_scenes_units() {
    for (scene, want) in [
        ("scene = sphere(1);", 1.0),
        // A box's size is its largest half-extent, but at most 16 times its smallest.
        ("scene = box([0.2, 4, 1]);", 1.6),
        ("scene = box([0.4, 4, 1]);", 2.0),
        ("scene = sphere(1).scale(2);", 2.0),
        ("scene = sphere(1).scale(2).scale(0.25);", 0.5),
        (
            "scene = sphere(1).scale(0.5) | box([4, 4, 4]).translate([9, 0, 0]);",
            0.5,
        ),
        // A shape reached under two scales takes the smaller.
        (
            "let s = sphere(1);\nscene = s.scale(3) | s.scale(0.25).translate([5, 0, 0]);",
            0.25,
        ),
        // Nothing bounded: no floor.
        ("scene = plane([0, 1, 0], 0);", 0.0),
        ("scene = sphere(1) | plane([0, 1, 0], 2);", 1.0),
        // A leaf of unknown size may be the smallest: no floor.
        ("scene = box([4, 4, 4]) | sdf(|p| length(p) - 0.001);", 0.0),
        (
            "param r = 0.001;\nscene = box([4, 4, 4]) | sphere(r).translate([3, 0, 0]);",
            0.0,
        ),
        ("scene = box([4, 4, 4]) | infinite_cylinder(0.001);", 0.0),
        // A stretch or a displacement may make a shape smaller than its box.
        (
            "scene = box([4, 4, 4]) | sphere(1).stretch([0.01, 0.01, 0.01]);",
            0.0,
        ),
        (
            "scene = box([4, 4, 4]) | displace(sphere(1), |p| 0.999, lipschitz: 1);",
            0.0,
        ),
    ] {
        let got = feature(scene);
        assert!(close(got, want), "{scene}: {got}, not {want}");
    }
}

#[test]
fn a_scale_that_is_a_param_gives_no_floor_below_it() {
    let got = feature("param k = 2;\nscene = sphere(1).scale(k);");
    assert_eq!(got, 0.0);
}
