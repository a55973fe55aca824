// Over-relaxed sphere tracing (Keinert et al. 2014): steps of RELAXATION times the distance
// while consecutive unbounding spheres overlap; when they stop overlapping the step has
// overshot, so it is taken back and marching goes on plainly.
fn march(ro: vec3<f32>, rd: vec3<f32>, pixel: f32) -> Hit {
    var t = 0.0;
    var steps = 0u;
    var omega = RELAXATION;
    var prev_radius = 0.0;
    var step = 0.0;
    // Whether the last sample was a surface passed by within the threshold.
    var passing = false;
    loop {
        if steps >= MAX_STEPS || t > MAX_DISTANCE {
            break;
        }
        let d = scene_distance(ro + rd * t);
        steps = steps + 1u;
        let radius = abs(d);
        let overshot = omega > 1.0 && radius + prev_radius < step;
        if overshot {
            step = step - omega * step;
            omega = 1.0;
        } else {
            // `<=`: at the camera the pixel threshold is 0, and a camera on a surface (d = 0)
            // must hit there rather than step by 0 for ever.
            if d <= surface_epsilon(t, pixel) {
                let refined = refine(ro, rd, t, d, steps, surface_epsilon(t, pixel));
                if refined.hit {
                    // A surface refined to beyond MAX_DISTANCE is out of range: a miss.
                    return Hit(refined.t, refined.steps, refined.t <= MAX_DISTANCE);
                }
                // The ray passed the surface by: march on plainly from where refinement
                // left it.
                steps = refined.steps;
                t = refined.t;
                omega = 1.0;
                prev_radius = 0.0;
                step = 0.0;
                passing = true;
                continue;
            }
            passing = false;
            step = d * omega;
        }
        prev_radius = radius;
        t = t + step;
    }
    return march_end(t, steps, passing);
}
