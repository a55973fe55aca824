// Plain sphere tracing: step by the distance until it is below the surface threshold.
// A hit is refined to the surface (see `refine`); a ray that only passes a surface by within
// the threshold marches on.
fn march(ro: vec3<f32>, rd: vec3<f32>, pixel: f32) -> Hit {
    var t = 0.0;
    var steps = 0u;
    // Whether the last sample was a surface passed by within the threshold.
    var passing = false;
    loop {
        if steps >= MAX_STEPS || t > MAX_DISTANCE {
            break;
        }
        let d = scene_distance(ro + rd * t);
        steps = steps + 1u;
        // `<=`: at the camera the pixel threshold is 0, and a camera on a surface (d = 0)
        // must hit there rather than step by 0 for ever.
        if d <= surface_epsilon(t, pixel) {
            let refined = refine(ro, rd, t, d, steps, surface_epsilon(t, pixel));
            if refined.hit {
                // A surface refined to beyond MAX_DISTANCE is out of range: a miss.
                return Hit(refined.t, refined.steps, refined.t <= MAX_DISTANCE);
            }
            // The ray passed the surface by: march on from where refinement left it.
            steps = refined.steps;
            t = refined.t;
            passing = true;
            continue;
        }
        passing = false;
        t = t + d;
    }
    return march_end(t, steps, passing);
}
