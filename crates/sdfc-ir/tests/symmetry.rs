//! The axes a shape is mirror-symmetric about (`analysis::symmetry`), which spare a
//! repetition the neighbour's copy along them: primitives, turns about an axis and by 90
//! degrees, moves, mirrors and unions.

fn axes(scene: &str) -> [bool; 3] {
    let src = format!("scene = {scene};");
    let file = sdfc_syntax::parse(&src).expect("parses");
    let (stages, diags) = sdfc_ir::compile(&file, src.len());
    let p = match stages {
        Some(s) => s.program,
        None => panic!("does not compile: {diags:?}"),
    };
    p.analysis.mirror[p.scene.root.index()]
}

#[test]
fn primitives_turns_moves_mirrors_and_unions() {
    assert_eq!(axes("box([1, 2, 3])"), [true; 3]);
    assert_eq!(axes("cone(1, 2)"), [true, false, true]);
    assert_eq!(axes("capsule([0, 0, 0], [1, 0, 0], 0.2)"), [false; 3]);
    assert_eq!(axes("box([1, 2, 3]).rotate_y(30deg)"), [false, true, false]);
    assert_eq!(axes("box([1, 2, 3]).rotate_z(90deg)"), [true; 3]);
    assert_eq!(axes("cone(1, 2).rotate_x(90deg)"), [true, true, false]);
    assert_eq!(
        axes("sphere(1).translate([0, 0.5, 0])"),
        [true, false, true]
    );
    assert_eq!(
        axes("sphere(1).translate([0, 0.5, 0]).scale(2)"),
        [true, false, true]
    );
    assert_eq!(
        axes("capsule([0, 0, 0], [1, 0, 0], 0.2).mirror_x()"),
        [true, false, false]
    );
    assert_eq!(
        axes("sphere(1) | sphere(0.5).translate([1, 0, 0])"),
        [false, true, true]
    );
    assert_eq!(axes("displace(sphere(1), |p| 0.1 * sin(p.x))"), [false; 3]);
    assert_eq!(
        axes("box([1, 1, 1]).round(0.1).repeat([3, 0, 3])"),
        [true; 3]
    );
}
