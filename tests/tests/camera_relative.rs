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
