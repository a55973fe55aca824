// Refines a hit found within the surface threshold (distance d0 at t0) to the surface, in a
// loop of its own (the two-loop marcher, `shaders/march_two_loops.wgsl`): the steps are
// `refine_next` and `refine_sampled` in `shaders/hit.wgsl`, which describes them.
fn refine(ro: vec3<f32>, rd: vec3<f32>, t0: f32, d0: f32, steps0: u32, eps: f32) -> Hit {
    var steps = steps0;
    var r = refine_start(t0, d0, eps);
    var next = REFINE_SAMPLE;
    loop {
        next = refine_next(&r);
        if next != REFINE_SAMPLE {
            break;
        }
        let t = r.t;
        refine_sampled(&r, scene_distance(ro + rd * t));
        steps = steps + 1u;
    }
    return Hit(r.t, steps, next == REFINE_HIT);
}
