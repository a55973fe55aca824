// Over-relaxed sphere tracing (Keinert et al. 2014), one step at a time: steps of up to
// RELAXATION times the distance while consecutive unbounding spheres overlap; when they stop
// overlapping the step has overshot, so it is taken back and the next step is plain. The
// same interface as the plain step (`shaders/march_step.wgsl`), so the marchers' loops
// (`shaders/march_two_loops.wgsl`, `shaders/march_merged.wgsl`) take either.
//
// The state between samples: where the next sample is taken (`t`); whether the last sample
// was a surface passed by within the threshold (`passing`) and whether that pass still hugs
// the surface (`close`, as in the plain step); the last sample's radius (|d|) and the step
// taken from it, which the next sample checks; whether relaxed steps are still tried while
// receding from a pass (`leap`: not after one failed); whether the last step was taken back
// (`retry`: the next one is plain); and the end of the ray's stretch (`end`).
struct Stepping {
    t: f32,
    passing: bool,
    close: bool,
    radius: f32,
    step: f32,
    leap: bool,
    retry: bool,
    end: f32,
}

// The state before the first sample: at the start of the ray's stretch `span` (`ray_span`).
fn march_start(span: vec2<f32>) -> Stepping {
    return Stepping(span.x, false, false, 0.0, 0.0, false, false, span.y);
}

// The relaxed march's step after its sample d at s.t: the threshold there where the sample
// is within it (a surface to refine; t stays), else -1 once t has moved on.
fn march_sampled(s: ptr<function, Stepping>, d: f32, pixel: f32) -> f32 {
    let radius = abs(d);
    // A step longer than the last distance is checked: the unbounding spheres of the two
    // samples must overlap, or the step may have jumped a surface.
    if (*s).step > (*s).radius && radius + (*s).radius < (*s).step {
        // Back to a plain step from the last sample: t - step + radius.
        (*s).step = (*s).radius - (*s).step;
        (*s).retry = true;
        (*s).leap = false;
    } else {
        let eps = march_threshold((*s).t, pixel);
        if (*s).passing && d <= eps && d > (*s).radius {
            // Receding from a surface just passed by, still within the threshold: no
            // refinement, and steps of 1.9 d while the spheres chain (see the plain step).
            (*s).step = select(1.0, 1.9, (*s).leap) * d;
            (*s).close = d <= 0.1 * eps;
            (*s).radius = radius;
            (*s).t = (*s).t + (*s).step;
            return -1.0;
        }
        // `<=`: at the camera the pixel threshold is 0, and a camera on a surface (d = 0)
        // must hit there rather than step by 0 for ever.
        if d <= eps {
            return eps;
        }
        (*s).passing = false;
        // Where the distance falls along the ray as a plane's would, the step to a sphere
        // that just touches this one is 2d / (1 + slope) (Balint and Valasek 2018): the
        // factor is at most RELAXATION, and the last two samples give the slope. Head on
        // (slope 1) that is a plain step, so the fallback rarely fires; at a grazing angle or
        // in open space it is the full factor. With no slope yet (the ray's first sample, or
        // the first step after a pass by or a step taken back) the step is plain: the full
        // factor there overshot rays that meet a surface head on (a sample taken back, or a
        // refinement from behind the surface), so that relaxation took more steps than the
        // plain marcher on the sphere, the ribbed sphere and the fractals
        // (docs/performance.md, "Relaxation: no factor before the slope").
        var w = 1.0;
        if RELAXATION > 1.0 && !(*s).retry && (*s).step > 0.0 {
            let slope = clamp(((*s).radius - radius) / (*s).step, 0.0, 1.0);
            w = min(RELAXATION, max(1.0, 0.95 * 2.0 / (1.0 + slope)));
        }
        (*s).retry = false;
        (*s).step = d * w;
        if (*s).t + (*s).step > (*s).end {
            // A relaxed step out of the span would end the march unchecked: the overshoot
            // test needs the next sample (a 300-shape grid 50 from the camera missed every
            // pixel at relaxation 1.9).
            (*s).step = d;
        }
    }
    (*s).radius = radius;
    (*s).t = (*s).t + (*s).step;
    return -1.0;
}

// The ray passed a surface by: march on from t, where refinement left it (and refinement
// stopped where the distance grew again), receding from it.
fn march_passed(s: ptr<function, Stepping>, t: f32) {
    (*s).t = t;
    (*s).radius = 0.0;
    (*s).step = 0.0;
    (*s).passing = true;
    (*s).close = true;
    (*s).leap = true;
}
