// Over-relaxed sphere tracing (Keinert et al. 2014): steps of up to RELAXATION times the
// distance while consecutive unbounding spheres overlap; when they stop overlapping the step
// has overshot, so it is taken back and marching goes on plainly.
//
// Two loops, as in the plain marcher: refinement (a loop) called inside the stepping loop
// cost every step a second distance evaluation on llvmpipe, which runs a loop's first trip
// whatever its lanes' masks.
fn march(ro: vec3<f32>, rd: vec3<f32>, pixel: f32) -> Hit {
    // Only the stretch inside the scene's bounds can hold a surface.
    let span = ray_span(ro, rd);
    var t = span.x;
    var steps = 0u;
    var prev_radius = 0.0;
    var step = 0.0;
    // Whether the last sample was a surface passed by within the threshold.
    var passing = false;
    // Whether that pass still hugs the surface (the last sample within a tenth of the
    // threshold): out of steps then is a hit (`march_end`); further out it is not.
    var close = false;
    // Whether relaxed steps are tried while receding from a pass (not after one failed).
    var leap = false;
    // Whether the last step was taken back: the next one is plain.
    var retry = false;
    loop {
        // Set when a sample comes within the threshold: its distance and the threshold.
        var near = false;
        var dn = 0.0;
        var eps_n = 0.0;
        loop {
            if steps >= MAX_STEPS || t > span.y {
                break;
            }
            let d = scene_distance(ro + rd * t);
            steps = steps + 1u;
            let radius = abs(d);
            // A step longer than the last distance is checked: the unbounding spheres of the
            // two samples must overlap, or the step may have jumped a surface.
            let overshot = step > prev_radius && radius + prev_radius < step;
            if overshot {
                // Back to a plain step from the last sample: t - step + prev_radius.
                step = prev_radius - step;
                retry = true;
                leap = false;
            } else {
                let eps = march_threshold(t, pixel);
                // `<=`: at the camera the pixel threshold is 0, and a camera on a surface (d =
                // 0) must hit there rather than step by 0 for ever.
                if passing && d <= eps && d > prev_radius {
                    // Receding from a surface just passed by, still within the threshold: no
                    // refinement, and steps of 1.9 d while the spheres chain (see the plain
                    // marcher).
                    step = select(1.0, 1.9, leap) * d;
                    close = d <= 0.1 * eps;
                    prev_radius = radius;
                    t = t + step;
                    continue;
                }
                if d <= eps {
                    near = true;
                    dn = d;
                    eps_n = eps;
                    break;
                }
                passing = false;
                // Where the distance falls along the ray as a plane's would, the step to a
                // sphere that just touches this one is 2d / (1 + slope) (Balint and Valasek
                // 2018): the factor is at most RELAXATION, and the last two samples give the
                // slope. Head on (slope 1) that is a plain step, so the fallback rarely fires;
                // at a grazing angle or in open space it is the full factor.
                var w = select(RELAXATION, 1.0, retry);
                retry = false;
                if w > 1.0 && step > 0.0 {
                    let slope = clamp((prev_radius - radius) / step, 0.0, 1.0);
                    w = min(RELAXATION, max(1.0, 0.95 * 2.0 / (1.0 + slope)));
                }
                step = d * w;
                if t + step > span.y {
                    // A relaxed step out of the span would end the march unchecked: the
                    // overshoot test needs the next sample (a 300-shape grid 50 from the camera
                    // missed every pixel at relaxation 1.9).
                    step = d;
                }
            }
            prev_radius = radius;
            t = t + step;
        }
        if !near {
            break;
        }
        let refined = refine(ro, rd, t, dn, steps, eps_n);
        if refined.hit {
            // A surface refined to beyond MAX_DISTANCE is out of range: a miss.
            return Hit(refined.t, refined.steps, refined.t <= MAX_DISTANCE);
        }
        // The ray passed the surface by: march on plainly from where refinement left it.
        steps = refined.steps;
        t = refined.t;
        prev_radius = 0.0;
        step = 0.0;
        passing = true;
        close = true;
        leap = true;
    }
    return march_end(t, steps, passing && close);
}
