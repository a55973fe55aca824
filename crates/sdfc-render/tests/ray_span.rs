//! Marching only inside the scene's bounds (`ray_span`): on a bounded scene the rays that
//! miss the bounds take no step, above a floor's half-space the sky's rays take none, and the
//! picture is the reference's (every hit found, at the same depths; no pixel that the
//! reference misses is hit).

mod common;

use common::against_reference::render_against_reference;
use common::{compile, renderer};

#[test]
fn rays_that_miss_the_bounds_take_no_step() {
    let source = "camera { position: [0, 1, 6], target: [0, 0, 0], fov: 50deg }\n\
                  scene = sphere(1) | box([1, 0.5, 1]).translate([1.5, 0, 0]);\n";
    // The box spans about a third of the width and a fifth of the height: most rays miss it.
    idle_and_as_the_reference("bounded", source, 1, 2);
}

#[test]
fn rays_into_the_sky_above_a_floor_take_no_step() {
    // The scene lies below y = 0.6 (a floor's half-space, a sphere sunk into it); the camera
    // at 1.5 looks down a little, the upper third of the image is sky: none of its rays meets
    // the half-space. A floor moved and scaled keeps its bound.
    for floor in [
        "plane([0, 1, 0], 0)",
        "plane([0, 1, 0], 0.5).translate([0, -1, 0]).scale(2)",
    ] {
        let source = format!(
            "camera {{ position: [0, 1.5, 6], target: [0, 0.5, 0], fov: 50deg }}\n\
             scene = {floor} | sphere(1).translate([0, -0.4, 0]);\n"
        );
        idle_and_as_the_reference(floor, &source, 1, 4);
    }
}

/// Renders `source` against the f64 reference: more than `num / den` of the pixels take no
/// step, every hit is found at the reference's depth, and no miss is hit.
fn idle_and_as_the_reference(name: &str, source: &str, num: usize, den: usize) {
    let Some(r) = renderer() else {
        return;
    };
    let c = render_against_reference(r, name, &compile(name, source), 64, 48);
    let steps = &c.frame.aovs.as_ref().expect("AOVs").steps;
    let idle = steps.iter().filter(|&&s| s == 0.0).count();
    let m = &c.metrics;
    eprintln!(
        "{name}: {idle} of {} pixels take no step; mean steps {:.2} (reference {:.2}); \
         hits {}/{}; depth p99.9 {:.2e}",
        steps.len(),
        m.mean_steps_gpu,
        m.mean_steps_reference,
        m.both_hit,
        m.reference_hits,
        m.depth_p999
    );
    assert!(
        idle * den > steps.len() * num,
        "{name}: {idle} pixels without a step"
    );
    assert_eq!(m.both_hit, m.reference_hits, "{name}: hits lost");
    assert_eq!(
        m.mismatch_interior + m.mismatch_silhouette,
        0,
        "{name}: hit/miss mismatches"
    );
    assert!(
        m.depth_p999 <= 1e-4,
        "{name}: depth p99.9 {:e}",
        m.depth_p999
    );
}
