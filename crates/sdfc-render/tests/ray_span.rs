//! Marching only inside the scene's bounds (`ray_span`): on a bounded scene the rays that
//! miss the bounds take no step, and the picture is the reference's (every hit found, at
//! the same depths; no pixel that the reference misses is hit).

mod common;

use common::against_reference::render_against_reference;
use common::{compile, renderer};

#[test]
fn rays_that_miss_the_bounds_take_no_step() {
    let Some(r) = renderer() else {
        return;
    };
    let source = "camera { position: [0, 1, 6], target: [0, 0, 0], fov: 50deg }\n\
                  scene = sphere(1) | box([1, 0.5, 1]).translate([1.5, 0, 0]);\n";
    let c = render_against_reference(r, "bounded", &compile("bounded", source), 64, 48);
    let steps = &c.frame.aovs.as_ref().expect("AOVs").steps;
    let idle = steps.iter().filter(|&&s| s == 0.0).count();
    let m = &c.metrics;
    eprintln!(
        "{idle} of {} pixels take no step; mean steps {:.2} (reference {:.2}); hits {}/{}; \
         depth p99.9 {:.2e}",
        steps.len(),
        m.mean_steps_gpu,
        m.mean_steps_reference,
        m.both_hit,
        m.reference_hits,
        m.depth_p999
    );
    // The box spans about a third of the width and a fifth of the height: most rays miss it.
    assert!(idle > steps.len() / 2, "{idle} pixels without a step");
    assert_eq!(m.both_hit, m.reference_hits, "hits lost");
    assert_eq!(
        m.mismatch_interior + m.mismatch_silhouette,
        0,
        "hit/miss mismatches"
    );
    assert!(m.depth_p999 <= 1e-4, "depth p99.9 {:e}", m.depth_p999);
}
