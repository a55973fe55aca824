//! The size of a scene's smallest shape (`Analysis::feature`), below which the difference
//! normals' step does not go: boxes' largest half-extents, times the scales above them.

fn feature(src: &str) -> f64 {
    let file = sdfc_syntax::parse(src).expect("parses");
    let (stages, diags) = sdfc_ir::compile(&file, src.len());
    match stages {
        Some(s) => s.program.analysis.feature,
        None => panic!("does not compile: {diags:?}"),
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1.0)
}

#[test]
fn the_smallest_shape_in_the_scenes_units() {
    for (scene, want) in [
        ("scene = sphere(1);", 1.0),
        // A box's size is its largest half-extent: its numbers are that large.
        ("scene = box([0.2, 4, 1]);", 2.0),
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
    ] {
        let got = feature(scene);
        assert!(close(got, want), "{scene}: {got}, not {want}");
    }
}

#[test]
fn a_scale_that_is_a_param_gives_no_floor_below_it() {
    let got = feature("param k = 2;\nscene = sphere(1).scale(k);");
    assert!(got <= 1.0 + 1e-9, "{got}");
}
