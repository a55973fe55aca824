// The plain march's state between samples (the marchers' loops, `shaders/march_two_loops.wgsl`
// and `shaders/march_merged.wgsl`, take their steps through it; relaxation's steps are
// `shaders/march_step_relaxed.wgsl`'s): where the next sample is taken; whether the last
// sample was a surface passed by within the threshold (`passing`), and whether that pass
// still hugs the surface (`close`: the last sample within a tenth of the threshold; out of
// steps then is a hit, `march_end`, and further out it is not); while passing, the distance
// of the last sample, the over-relaxed step taken from it (0 after a plain step), and
// whether such steps are still tried (`leap`: not after one failed).
struct Stepping {
    t: f32,
    passing: bool,
    close: bool,
    last: f32,
    jump: f32,
    leap: bool,
}

// The state before the first sample: at the start of the ray's stretch `span` (`ray_span`).
fn march_start(span: vec2<f32>) -> Stepping {
    return Stepping(span.x, false, false, 0.0, 0.0, false);
}

// The plain march's step after its sample d at s.t: the threshold there where the sample is
// within it (a surface to refine; t stays), else -1 once t has moved on.
fn march_sampled(s: ptr<function, Stepping>, d: f32, pixel: f32) -> f32 {
    if (*s).jump > 0.0 && d + (*s).last < (*s).jump {
        // The unbounding spheres of the last two samples leave a gap that may hold a
        // surface: step plainly from the last sample instead.
        (*s).t = (*s).t - (*s).jump + (*s).last;
        (*s).jump = 0.0;
        (*s).leap = false;
        return -1.0;
    }
    (*s).jump = 0.0;
    let eps = march_threshold((*s).t, pixel);
    if (*s).passing && d <= eps && d > (*s).last {
        // Receding from a surface passed by, within the threshold: no hit. Refinement would
        // only find the same pass at the cost of a sample; steps of 1.9 d while the spheres
        // chain halve the rest (stress scene tiny_huge ran out of 256 before).
        (*s).last = d;
        (*s).jump = select(0.0, 1.9 * d, (*s).leap);
        (*s).close = d <= 0.1 * eps;
        (*s).t = (*s).t + select(d, (*s).jump, (*s).leap);
        return -1.0;
    }
    // `<=`: at the camera the pixel threshold is 0, and a camera on a surface (d = 0) must
    // hit there rather than step by 0 for ever.
    if d <= eps {
        return eps;
    }
    (*s).passing = false;
    (*s).t = (*s).t + d;
    return -1.0;
}

// The ray passed a surface by: march on from t, where refinement left it (and refinement
// stopped where the distance grew again).
fn march_passed(s: ptr<function, Stepping>, t: f32) {
    (*s).t = t;
    (*s).passing = true;
    (*s).last = 0.0;
    (*s).close = true;
    (*s).leap = true;
}
