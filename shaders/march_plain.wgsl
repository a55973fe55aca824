// Plain sphere tracing: step by the distance until it is below the surface threshold.
// A hit is refined to the surface (see `refine`); a ray that only passes a surface by within
// the threshold marches on.
//
// Two loops: the inner one steps until a sample comes within the threshold, the outer one
// refines it and marches on after a pass. Refinement is a loop of its own, and llvmpipe runs
// the first trip of a loop whatever its lanes' masks (its `if` is a mask, not a branch):
// called inside the stepping loop it cost every step a second distance evaluation (lavapipe,
// 128x96: terrain 21.4 -> 14.2 ms a frame, the same steps and picture).
fn march(ro: vec3<f32>, rd: vec3<f32>, pixel: f32) -> Hit {
    // Only the stretch inside the scene's bounds can hold a surface.
    let span = ray_span(ro, rd);
    var t = span.x;
    var steps = 0u;
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
            if jump > 0.0 && d + last < jump {
                // The unbounding spheres of the last two samples leave a gap that may hold a
                // surface: step plainly from the last sample instead.
                t = t - jump + last;
                jump = 0.0;
                leap = false;
                continue;
            }
            jump = 0.0;
            let eps = march_threshold(t, pixel);
            if passing && d <= eps && d > last {
                // Receding from a surface passed by, within the threshold: no hit. Refinement
                // would only find the same pass at the cost of a sample; steps of 1.9 d while
                // the spheres chain halve the rest (stress scene tiny_huge ran out of 256
                // before).
                last = d;
                jump = select(0.0, 1.9 * d, leap);
                close = d <= 0.1 * eps;
                t = t + select(d, jump, leap);
                continue;
            }
            // `<=`: at the camera the pixel threshold is 0, and a camera on a surface (d = 0)
            // must hit there rather than step by 0 for ever.
            if d <= eps {
                near = true;
                dn = d;
                eps_n = eps;
                break;
            }
            passing = false;
            t = t + d;
        }
        if !near {
            break;
        }
        let refined = refine(ro, rd, t, dn, steps, eps_n);
        if refined.hit {
            // A surface refined to beyond MAX_DISTANCE is out of range: a miss.
            return Hit(refined.t, refined.steps, refined.t <= MAX_DISTANCE);
        }
        // The ray passed the surface by: march on from where refinement left it (and
        // refinement stopped where the distance grew again).
        steps = refined.steps;
        t = refined.t;
        passing = true;
        last = 0.0;
        close = true;
        leap = true;
    }
    return march_end(t, steps, passing && close);
}
