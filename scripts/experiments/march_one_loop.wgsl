// The plain marcher before 2026-12-04: one loop, refinement called inside it (the baseline
// of scripts/gpu-bench.sh's `marcher_loops`; docs/performance.md, "The marcher's two loops"),
// with the two step budgets of 2026-12-07 (`march_spent`) so that it takes the same samples.
// Plain sphere tracing: step by the distance until it is below the surface threshold.
// A hit is refined to the surface (see `refine`); a ray that only passes a surface by within
// the threshold marches on.
fn march(ro: vec3<f32>, rd: vec3<f32>, pixel: f32) -> Hit {
    // Only the stretch inside the scene's bounds can hold a surface.
    let span = ray_span(ro, rd);
    var t = span.x;
    // Every sample, and those of refinements that passed by (`march_spent`).
    var steps = 0u;
    var passed = 0u;
    // Whether the last sample was a surface passed by within the threshold.
    var passing = false;
    // Whether that pass still hugs the surface (the last sample within a tenth of the
    // threshold): out of steps then is a hit (`march_end`); further out it is not.
    var close = false;
    // While passing: the distance of the last sample, the over-relaxed step taken from it (0
    // after a plain step), and whether such steps are still tried (not after one failed).
    var last = 0.0;
    var jump = 0.0;
    var leap = false;
    loop {
        if march_spent(steps, passed) || t > span.y {
            break;
        }
        let d = scene_distance(ro + rd * t);
        steps = steps + 1u;
        if jump > 0.0 && d + last < jump {
            // The unbounding spheres of the last two samples leave a gap that may hold a
            // surface: step plainly from the last sample instead.
            t = t - jump + last;
            jump = 0.0;
            leap = false;
            continue;
        }
        jump = 0.0;
        // A step below two f32 steps of t may not move the ray at all: a finer threshold
        // (`epsilon: 1e-7`, a fov of 1e-5 degrees) stalled rays until they ran out of steps.
        let eps = max(surface_epsilon(t, pixel), 2.4e-7 * t);
        if passing && d <= eps && d > last {
            // Receding from a surface passed by, within the threshold: no hit. Refinement
            // would only find the same pass at the cost of a sample; steps of 1.9 d while the
            // spheres chain halve the rest (stress scene tiny_huge ran out of 256 before).
            last = d;
            jump = select(0.0, 1.9 * d, leap);
            close = d <= 0.1 * eps;
            t = t + select(d, jump, leap);
            continue;
        }
        // `<=`: at the camera the pixel threshold is 0, and a camera on a surface (d = 0)
        // must hit there rather than step by 0 for ever.
        if d <= eps {
            let refined = refine(ro, rd, t, d, steps, eps);
            if refined.hit {
                // A surface refined to beyond MAX_DISTANCE is out of range: a miss.
                return Hit(refined.t, refined.steps, refined.t <= MAX_DISTANCE);
            }
            // The ray passed the surface by: march on from where refinement left it (and
            // refinement stopped where the distance grew again).
            passed = passed + refined.steps - steps;
            steps = refined.steps;
            t = refined.t;
            passing = true;
            last = 0.0;
            close = true;
            leap = true;
            continue;
        }
        passing = false;
        t = t + d;
    }
    return march_end(t, steps, passed, passing && close);
}
