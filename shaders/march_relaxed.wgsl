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
    // Whether that pass still hugs the surface (the last sample within a tenth of the
    // threshold): out of steps then is a hit (`march_end`); further out it is not.
    var close = false;
    // Whether relaxed steps are tried while receding from a pass (not after one failed).
    var leap = false;
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
            leap = false;
        } else {
            // `<=`: at the camera the pixel threshold is 0, and a camera on a surface (d = 0)
            // must hit there rather than step by 0 for ever.
            let eps = surface_epsilon(t, pixel);
            if passing && d <= eps && d > prev_radius {
                // Receding from a surface just passed by, still within the threshold: no
                // refinement, and steps of 1.9 d while the spheres chain (see the plain
                // marcher); once out of the threshold, plain steps as after any pass.
                omega = select(1.0, 1.9, leap);
                step = omega * d;
                close = d <= 0.1 * eps;
                prev_radius = radius;
                t = t + step;
                continue;
            }
            if d <= eps {
                let refined = refine(ro, rd, t, d, steps, eps);
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
                close = true;
                leap = true;
                continue;
            }
            if passing {
                omega = 1.0;
            }
            passing = false;
            step = d * omega;
        }
        prev_radius = radius;
        t = t + step;
    }
    return march_end(t, steps, passing && close);
}
