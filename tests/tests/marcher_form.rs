//! Which marcher a scene's shader gets (`sdfc_wgsl::marcher`): a union read as data marches
//! its ray's listed instances one by one, refining in the same loop
//! (`shaders/march_instances.wgsl`), after a mixed union's other children alone
//! (`march_rest`, with the loops their distance's cost picks); where the distance is
//! otherwise dear (noise, a fractal, a union of dozens of shapes as code) the march refines
//! in its stepping loop
//! (`shaders/march_merged.wgsl`: one copy of the distance in the march, not two), while a
//! cheap distance refines in a loop of its own (`shaders/refine.wgsl`), with the plain step
//! or the relaxed one in either. Both loops draw the same pictures (the render tests against
//! the f64 reference; docs/performance.md measured them bit for bit); this checks the choice
//! and the copies, which a change to the emitter could silently undo.

use sdfc_tests::grid_scene;
use sdfc_wgsl::{compile, Options, AUTO_INSTANCES};

/// The emitted WGSL of the generated grid of `n` shapes, with `render` appended.
fn wgsl(n: usize, render: &str) -> String {
    let source = format!("{}\n{render}\n", grid_scene(n));
    compile(&source, &Options::default())
        .unwrap_or_else(|f| panic!("grid of {n}: {f}"))
        .wgsl
}

#[test]
fn a_union_read_as_data_refines_in_the_stepping_loop() {
    let alone = wgsl(AUTO_INSTANCES, "");
    assert!(alone.contains("scene_data"), "not the data form");
    // One instance's distance in the march: the stepping loop's, which refinement shares.
    assert_eq!(
        alone
            .matches("instance_distance(ro + rd * t, leaf)")
            .count(),
        1
    );
    assert!(alone.contains("r = refine_start(t, d, eps);"));
    assert!(!alone.contains("fn march_rest("));
    // No refinement loop of its own, so no dead copy of it either.
    assert!(!alone.contains("fn refine("));
    // With a floor beside the instances: the floor marched first, alone, and cheap (a
    // plane), so with its refinement in a loop of its own, by its distance along the ray;
    // then the instances as above.
    let mixed = wgsl_with_floor(AUTO_INSTANCES, "");
    assert!(mixed.contains("scene_data"), "not the data form");
    assert!(mixed.contains("let rest = march_rest(ro, rd, pixel);"));
    assert_eq!(
        mixed.matches("rest_distance_ray(ro + rd * t, rd)").count(),
        2
    );
    assert!(mixed.contains("fn refine("));
    assert_eq!(
        mixed
            .matches("instance_distance(ro + rd * t, leaf)")
            .count(),
        1
    );
    assert!(mixed.contains("r = refine_start(t, d, eps);"));
    // With a fractal beside them instead, the fractal's march refines in its stepping loop.
    let fractal = wgsl_beside(AUTO_INSTANCES, "", "menger(4).translate([0, 0, 20])");
    assert!(fractal.contains("let rest = march_rest(ro, rd, pixel);"));
    assert_eq!(fractal.matches("rest_distance(ro + rd * t)").count(), 1);
    assert!(!fractal.contains("fn refine("));
}

/// [`wgsl`] with a floor plane beside the grid's shapes (a mixed union: the plane stays
/// code).
fn wgsl_with_floor(n: usize, render: &str) -> String {
    wgsl_beside(n, render, "plane([0, 1, 0], -1)")
}

/// [`wgsl`] with `shape` beside the grid's shapes (a mixed union: `shape` stays code).
fn wgsl_beside(n: usize, render: &str, shape: &str) -> String {
    let source = format!("{}\n{render}\n", grid_scene(n)).replacen(
        "scene = union(\n",
        &format!("scene = union(\n    {shape},\n"),
        1,
    );
    assert!(source.contains(shape), "the grid's union has changed");
    compile(&source, &Options::default())
        .unwrap_or_else(|f| panic!("grid of {n} beside {shape}: {f}"))
        .wgsl
}

#[test]
fn a_dear_union_as_code_refines_in_the_stepping_loop_and_a_cheap_one_in_its_own() {
    let dear = wgsl(AUTO_INSTANCES - 1, "");
    assert!(!dear.contains("scene_data"), "not the code form");
    assert_eq!(dear.matches("scene_distance(ro + rd * t)").count(), 1);
    assert!(dear.contains("r = refine_start(t, d, eps);"));
    assert!(!dear.contains("fn refine("));

    let cheap = wgsl(8, "");
    assert!(cheap.contains("fn refine("));
    assert_eq!(cheap.matches("scene_distance(ro + rd * t)").count(), 2);
    assert!(!cheap.contains("r = refine_start(t, d, eps);"));
}

/// The relaxed step's own text (`shaders/march_step_relaxed.wgsl`): its factor's rule.
const RELAXED_STEP: &str = "0.95 * 2.0 / (1.0 + slope)";

#[test]
fn relaxation_takes_its_step_in_either_loop() {
    // A dear distance: the merged loop with the relaxed step (a fractal beside the
    // instances, marched alone first).
    let dear = wgsl_beside(
        AUTO_INSTANCES,
        "render { relaxation: 1.6 }",
        "menger(4).translate([0, 0, 20])",
    );
    assert!(dear.contains("fn march_rest("), "not the mixed data form");
    assert!(dear.contains(RELAXED_STEP));
    assert_eq!(dear.matches("rest_distance(ro + rd * t)").count(), 1);
    assert!(dear.contains("r = refine_start(t, d, eps);"));
    assert!(!dear.contains("fn refine("));
    // Instances alone: each marched with the relaxed step.
    let alone = wgsl(AUTO_INSTANCES, "render { relaxation: 1.6 }");
    assert!(alone.contains(RELAXED_STEP));
    assert_eq!(
        alone
            .matches("instance_distance(ro + rd * t, leaf)")
            .count(),
        1
    );
    assert_eq!(alone.matches("fn march_sampled(").count(), 1);
    // A cheap one: two loops with the relaxed step.
    let cheap = wgsl(8, "render { relaxation: 1.6 }");
    assert!(cheap.contains(RELAXED_STEP));
    assert!(cheap.contains("fn refine("));
    assert_eq!(cheap.matches("scene_distance(ro + rd * t)").count(), 2);
    // Only one step is emitted: without relaxation, the plain one alone.
    assert_eq!(dear.matches("fn march_sampled(").count(), 1);
    assert_eq!(cheap.matches("fn march_sampled(").count(), 1);
    assert!(!wgsl(8, "").contains(RELAXED_STEP));
    assert!(!wgsl(AUTO_INSTANCES, "").contains(RELAXED_STEP));
}

/// Shadow rays of a union read as data are listed and march each instance alone
/// (`shaders/shading/shadow_instances.wgsl`), after a mixed union's other children
/// (`shadow_rest`); a soft shadow whose cone no list's padding can hold keeps the walk
/// (`shadows.rs` in sdfc-wgsl), and the code's shadows sample the scene.
#[test]
fn shadow_rays_of_a_union_read_as_data_take_lists_where_they_can() {
    const LISTED: &str = "ray_start(ro, rd, 0.0, tmax, 0.0, SHADOW_REACH, start);";
    const WALKED: &str = "let step = shadow_sampled(&light, scene_distance(q), t);";
    for shadows in ["hard", "soft(16)", "soft(4)"] {
        let render = format!("render {{ shadows: {shadows} }}");
        let alone = wgsl(AUTO_INSTANCES, &render);
        assert!(alone.contains(LISTED), "{shadows}");
        assert!(!alone.contains("fn shadow_rest(") && !alone.contains(WALKED));
        let mixed = wgsl_with_floor(AUTO_INSTANCES, &render);
        assert!(mixed.contains(LISTED), "{shadows}");
        assert!(mixed.contains("    var light = shadow_rest(ro, rd, tmax);\n"));
        assert!(mixed.contains("let step = shadow_sampled(&light, rest_distance(q), t);"));
        let code = wgsl(8, &render);
        assert!(code.contains(WALKED) && !code.contains(LISTED), "{shadows}");
    }
    // Ambient occlusion of a union read as data lists once along the normal and samples
    // through its list (`ao_below`), a mixed union's other children first, where its samples
    // reach no farther than 0.8 of the instances' spacing; the code's samples the scene.
    let ao = "render { ao: ao() }";
    let alone = wgsl(AUTO_INSTANCES, ao);
    let mixed = wgsl_with_floor(AUTO_INSTANCES, ao);
    for data in [&alone, &mixed] {
        assert!(data.contains("    ao_list(p, n);\n    var occlusion = 0.0;\n"));
        assert!(data.contains("let d = ao_below(p + n * h, h);"));
    }
    assert!(alone.contains("return ray_nearest(q, h, h, true).distance;"));
    assert!(mixed.contains("return ray_nearest(q, h, min(rest_distance(q), h), true).distance;"));
    let code = wgsl(8, ao);
    assert!(code.contains("let d = scene_distance(p + n * h);") && !code.contains("ao_list"));
    // Samples reaching 2.4, past 0.8 of the grid's spacing of 1.5: the walk, without far
    // boxes' bounds, a mixed union's other children first.
    let high = "render { ao: ao(samples: 8, step: 0.3) }";
    let alone = wgsl(AUTO_INSTANCES, high);
    let mixed = wgsl_with_floor(AUTO_INSTANCES, high);
    for data in [&alone, &mixed] {
        assert!(!data.contains("ao_list") && data.contains("let d = ao_below(p + n * h, h);"));
    }
    assert!(alone.contains("return scene_nearest(q, h, 3.0e38).distance;"));
    assert!(mixed.contains("return scene_nearest(q, min(rest_distance(q), h), 3.0e38).distance;"));
    // Padding by the cone of soft(16): t / 15 for exact shapes.
    let soft = wgsl(AUTO_INSTANCES, "render { shadows: soft(16) }");
    assert!(soft.contains("const SHADOW_REACH: f32 = 0.06666667;"));
    // soft(3): t / 2, wider than a list pays for (`SOFT_MOST`): the walk, which takes a far
    // box's distance only where it cannot lower the light.
    let wide = wgsl(AUTO_INSTANCES, "render { shadows: soft(3) }");
    assert!(!wide.contains(LISTED) && !wide.contains(WALKED));
    assert!(wide.contains(
        "let step = shadow_sampled(&light, scene_nearest(q, 3.0e38, light * t / SHADOW_K).distance, t);"
    ));
}
