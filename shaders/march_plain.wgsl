// Plain sphere tracing: step by the distance until it is below the surface threshold.
// A hit is refined by a few more plain steps, which shrinks the depth error of an exact
// distance far below the threshold at almost no cost.
fn march(ro: vec3<f32>, rd: vec3<f32>, pixel: f32) -> Hit {
    var t = 0.0;
    var steps = 0u;
    loop {
        if steps >= MAX_STEPS || t > MAX_DISTANCE {
            break;
        }
        let d = scene_distance(ro + rd * t);
        steps = steps + 1u;
        if d < surface_epsilon(t, pixel) {
            return refine(ro, rd, t, d, steps);
        }
        t = t + d;
    }
    return Hit(t, steps, false);
}
