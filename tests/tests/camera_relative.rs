//! A camera far from the origin gets camera-relative coordinates in the render shader: the
//! camera at 0, the scene's offsets folded to small exact numbers, point lights moved; the
//! library form and the world-space functions (the reference, `sdfc eval`) stay in world
//! coordinates, and a camera near the origin leaves the shader as written.

use sdfc_wgsl::{compile, Options};

const FAR: &str =
    "camera { position: [100000.5, 100001, 100006], target: [100000, 100000, 100000] }\n\
    light point { position: [100004, 100005, 100003], color: [1, 1, 1], intensity: 1 }\n\
    scene = union(sphere(1), box(1).translate([2, 0, 0])).translate([100000, 100000, 100000]);\n";

#[test]
fn a_far_camera_marches_in_camera_relative_coordinates() {
    let c = compile(FAR, &Options::default()).unwrap_or_else(|e| panic!("{e:?}"));
    assert!(c
        .wgsl
        .contains("const CAMERA_POSITION: vec3<f32> = vec3<f32>(0.0);"));
    // The sphere's centre relative to the camera, exactly: (-0.5, -1, -6).
    assert!(
        c.wgsl.contains("p - vec3<f32>(-0.5, -1.0, -6.0)"),
        "{}",
        c.wgsl
    );
    // The point light relative to the camera.
    assert!(
        c.wgsl.contains("vec3<f32>(3.5, 4.0, -3.0) - p"),
        "{}",
        c.wgsl
    );
    let rel = c.program().relative.as_ref().expect("relative functions");
    assert_eq!(rel.origin, [100000.5, 100001.0, 100006.0]);
    // Same distances at corresponding points, world and relative (f64 evaluator).
    for q in [[0.0, 0.0, 0.0], [-0.5, -1.0, -4.5], [1.3, -0.7, -6.2]] {
        let world: [f64; 3] = std::array::from_fn(|k| q[k] + rel.origin[k] as f64);
        let eval = |f, p| {
            sdfc_ir::eval::eval_func::<f64>(f, &[], &sdfc_ir::eval::Inputs::at(p))[0]
                .scalar()
                .unwrap()
        };
        let (a, b) = (eval(&c.program().distance, world), eval(&rel.distance, q));
        assert!((a - b).abs() < 1e-9, "at {q:?}: world {a}, relative {b}");
    }
    let lib = compile(
        FAR,
        &Options {
            lib: true,
            ..Options::default()
        },
    )
    .unwrap_or_else(|e| panic!("{e:?}"));
    assert!(
        lib.wgsl.contains("vec3<f32>(100000.0, 100000.0, 100000.0)")
            || lib.wgsl.contains("vec3<f32>(100000.0)"),
        "{}",
        lib.wgsl
    );
}

#[test]
fn a_near_camera_keeps_world_coordinates() {
    let c = compile(
        "camera { position: [0, 1, 6] }\nscene = sphere(1).translate([0.5, 0, 0]);\n",
        &Options::default(),
    )
    .unwrap_or_else(|e| panic!("{e:?}"));
    assert!(c.program().relative.is_none());
    assert!(c
        .wgsl
        .contains("const CAMERA_POSITION: vec3<f32> = vec3<f32>(0.0, 1.0, 6.0);"));
    assert!(!c.wgsl.contains("Camera-relative"));
}

/// Shapes whose world-space constants cannot hold their place at 1e5 (f32 steps there are
/// 0.008): a turned box moved out (in the world function its offset `-R T`, folded in f32,
/// is 0.0076 off), a plane whose offset is 1e5, and a repetition moved out along y with the
/// camera 1e5 out along x and z. The reference (and `sdfc eval`) evaluates the
/// camera-relative functions, and there, at points of the exact surfaces, the distances are
/// zero to f32 rounding of small numbers. (The device's f32 side of the same scenes is
/// `stress.rs::far_shapes_get_their_moves_folded_in_f64`.)
#[test]
fn folded_moves_put_far_surfaces_where_they_are() {
    let camera = "camera { position: [100000.5, 100001.2, 100006], target: [100000, 100000.2, 100000], fov: 45deg }\n";
    let (c, s) = (30f64.to_radians().cos() as f32 as f64, 0.5);
    // A point of the turned box's +x face: T + R^T (0.6, 0, 0), R turning about y.
    let face = [1e5 + 0.6 * c, 1e5, 1e5 - 0.6 * s];
    let cases: [(&str, Vec<[f64; 3]>); 3] = [
        (
            "scene = box([1.2, 0.8, 1]).rotate_y(30deg).translate([100000, 100000, 100000]);",
            vec![
                face,
                [1e5, 1e5 + 0.4, 1e5],
                [1e5 + 0.5 * s, 1e5, 1e5 + 0.5 * c],
            ],
        ),
        (
            "scene = plane([0, 1, 0], 100000);",
            vec![[1e5, 1e5, 1e5], [100003.7, 1e5, 99990.1]],
        ),
        (
            // Cells every 1.5: x = 100000.5 and z = 100006.5 are centres.
            "scene = sphere(0.4).repeat([1.5, 0, 1.5]).translate([0, 100000, 0]);",
            vec![
                [100000.5, 100000.4, 100006.5],
                [100000.9, 1e5, 100006.5],
                [100002.0, 1e5, 100006.1],
            ],
        ),
    ];
    for (scene, points) in cases {
        let source = format!("{camera}{scene}\n");
        let compiled = compile(&source, &Options::default()).unwrap_or_else(|e| panic!("{e}"));
        let program = compiled.program();
        assert!(program.relative.is_some(), "{scene}");
        let eval = sdfc_reference::scene::SceneEval::new(program, &[], 0.0);
        for p in points {
            let d = eval.distance(p);
            assert!(d.abs() < 2e-6, "{scene}: {d:e} at {p:?}");
        }
    }
}

/// Scenes moved up by 1e5 and seen from 1e5 out along x and z too, against the same scenes
/// where they are: `s.translate(T)` at q is `s` at q - T. The moved scene's reference
/// evaluates its camera-relative functions near the camera; the other has its camera at the
/// origin, so it evaluates the world functions, in f64, exact at any distance. The move goes
/// down through each kind of node (turns, scales, infinite repetition modulo its period,
/// planes, limited repetition, a smooth union) and is checked against that independent
/// evaluation, to f32 rounding of the offsets it becomes (relative to their size: 1e5 where
/// a bounded shape is 1e5 from the camera).
#[test]
fn a_scene_moved_far_out_is_the_scene_where_it_was() {
    const T: [f64; 3] = [0.0, 100000.0, 0.0];
    const EYE: [f64; 3] = [100000.5, 100001.25, 100006.0];
    let shapes = [
        "sphere(0.4).repeat([1.5, 0, 1.5]).rotate_y(30deg)",
        "plane([1, 0, 1], 0.25).rotate_z(20deg)",
        "box([1, 0.5, 2]).translate([0.3, 0.2, 0.1]).scale(2.5)",
        "sphere(0.3).repeat([1.25, 1.25, 0.75]).scale(0.5).rotate_x(10deg)",
        "sphere(0.2).repeat([1, 0, 1], count: [5, 1, 5])",
        "union(plane([0, 1, 0], -1), torus(1, 0.2).repeat([3, 0, 3]), smooth: 0.3)",
    ];
    let points: Vec<[f64; 3]> = (0..27)
        .map(|i| {
            let k = |j: u32| ((i / 3usize.pow(j)) % 3) as f64 - 1.0;
            [
                EYE[0] + 0.37 * k(0) + 0.1,
                EYE[1] + 0.83 * k(1) - 1.0,
                EYE[2] + 1.9 * k(2) - 4.0,
            ]
        })
        .collect();
    for shape in shapes {
        let near = format!(
            "camera {{ position: [0.5, 1.25, 6], target: [0, 0, 0] }}\nlet s = {shape};\nscene = s;\n"
        );
        let far = format!(
            "camera {{ position: [{}, {}, {}], target: [100000, 100000, 100000] }}\n\
             let s = {shape};\nscene = s.translate([{}, {}, {}]);\n",
            EYE[0], EYE[1], EYE[2], T[0], T[1], T[2]
        );
        let (near, far) = (
            compile(&near, &Options::default()).unwrap_or_else(|e| panic!("{e}")),
            compile(&far, &Options::default()).unwrap_or_else(|e| panic!("{e}")),
        );
        assert!(near.program().relative.is_none() && far.program().relative.is_some());
        let (en, ef) = (
            sdfc_reference::scene::SceneEval::new(near.program(), &[], 0.0),
            sdfc_reference::scene::SceneEval::new(far.program(), &[], 0.0),
        );
        for q in &points {
            let p: [f64; 3] = std::array::from_fn(|k| q[k] - T[k]);
            let (a, b) = (en.distance(p), ef.distance(*q));
            assert!(
                (a - b).abs() <= 2e-6 + 1e-7 * a.abs(),
                "{shape}: {a} where it was, {b} moved, at {p:?}"
            );
        }
    }
}

/// The move stops where carrying it would cost: a shared `let` doubled at each of 14 levels
/// is moved as a whole (copied per move, its WGSL grew from 81 KB to 4 MB), and a chain of
/// tiny scales keeps the move in range (divided by 1e-12 four times it overflowed f32 and
/// made "not finite" errors in a scene that compiles seen from near the origin).
#[test]
fn the_move_neither_copies_shared_shapes_nor_overflows() {
    let mut doubling = String::from("let l0 = sphere(0.5);\n");
    for i in 1..=14 {
        doubling += &format!(
            "let l{i} = union(l{}, l{}.translate([{}, 0, 0]));\n",
            i - 1,
            i - 1,
            1 << i
        );
    }
    let wgsl = |camera_z: f64, scene: &str| {
        let source = format!(
            "camera {{ position: [0, 1, {camera_z}], target: [0, 0, 0], fov: 45deg }}\n{scene}"
        );
        compile(&source, &Options::default())
            .unwrap_or_else(|e| panic!("{e}"))
            .wgsl
            .len()
    };
    let shared = format!("{doubling}scene = l14.translate([0, 0, 100000]);\n");
    let (near, far) = (wgsl(100.0, &shared), wgsl(100000.0, &shared));
    assert!(
        far < 2 * near,
        "{far} bytes seen from far, {near} from near"
    );
    let tiny = "scene = sphere(1).scale(1e-12).scale(1e-12).scale(1e-12).scale(1e-12);\n";
    wgsl(100000.0, tiny);
}
