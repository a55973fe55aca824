// The result of marching one ray.
struct Hit {
    t: f32,
    steps: u32,
    hit: bool,
}

// What `radiance` brings back for a camera ray: its colour, its first hit and the normal
// there (the entry point writes the last two as AOVs).
struct Sample {
    color: vec3<f32>,
    hit: Hit,
    normal: vec3<f32>,
}

// The surface threshold the march takes at t: the setting's, and never below two f32 steps
// of t, a step that may not move the ray at all (a finer threshold, `epsilon: 1e-7` or a
// fov of 1e-5 degrees, stalled rays until they ran out of steps).
fn march_threshold(t: f32, pixel: f32) -> f32 {
    return max(surface_epsilon(t, pixel), 2.4e-7 * t);
}

// Whether a march has spent its samples: MAX_STEPS of its own, and MAX_STEPS more in
// refinements that end in a pass by. Both are checked only between refinements, so a march
// takes at most 2 MAX_STEPS + 19 samples (the refinement that ends it, in a hit or a pass,
// takes up to REFINE_SAMPLES, 20). A ray that grazes a surface whose distance is a bound
// divided by a Lipschitz factor (displacement, twist) comes within the threshold again and
// again, and each time up to 20 samples of a refinement crawl on as the march would: counted
// with the march's, they ended such rays at 256, specks along the ribbed blob's silhouette
// of examples/spec_section10.sdf at 512x512 (docs/accuracy.md, "Grazing rays along a ribbed
// silhouette").
fn march_spent(steps: u32, passed: u32) -> bool {
    return steps - passed >= MAX_STEPS || passed >= MAX_STEPS;
}

// The end of a march that left its loop without a hit, at t after `steps` samples, `passed`
// of them in refinements that passed by. Out of steps (`march_spent`) while passing a
// surface by, still within a tenth of the threshold (`passing`), is a hit where the ray is:
// a ray that grazes a silhouette crawls past it in steps of about a hundredth of the
// threshold and can spend the whole budget there, and the pixel's footprint touches that
// surface, so the pixel shows it rather than a hole with the background behind. Further out
// it is not: a ray just above a ground plane stays within the threshold (which grows with t)
// to the horizon, and made a row of false hits at whatever t the steps ran out.
fn march_end(t: f32, steps: u32, passed: u32, passing: bool) -> Hit {
    return Hit(t, steps, passing && march_spent(steps, passed) && t <= MAX_DISTANCE);
}

// How near a ray that passes a surface by without crossing it must come to count as touching
// it (`refine`). Where the scene's distance is trusted never to exceed the true distance
// (`distance_trusted()`, from the compiler's analysis) the samples' rise after their minimum
// proves a pass, so only f32 rounding (a few steps of t) counts; an estimate (the
// mandelbulb's) may rise while its surface is still ahead, and there a hundredth of the
// surface threshold still catches what the field blurs.
fn touch_distance(t: f32, eps: f32) -> f32 {
    if distance_trusted() {
        return min(0.01 * eps, 1e-6 * max(t, 1.0));
    }
    return 0.01 * eps;
}

// The refinement of a hit found within the surface threshold (distance d0 at t0) to the
// surface itself (`refine_start`, then `refine_next` and `refine_sampled` in turn).
// In front of the surface (d > 0) each step goes at least the plain step t + d (a distance
// bound never overestimates, so the surface is at least that far) and follows the secant
// through the last two samples where it goes further, at most 256 plain steps: the secant
// converges fast where the ray meets the surface at a grazing angle. Once a sample lies behind
// the surface (d <= 0) the surface is bracketed and Illinois-style false position narrows the
// bracket. If the distance grows again while still positive, the ray passes the surface by
// within the threshold without meeting it: that is no hit, and marching goes on
// (`REFINE_PASS`) from the last sample, or from the end of the stretch the samples' unbounding
// spheres cover where that is further, but never beyond a gap longer than the threshold that
// a secant step left unsampled (see `gap`). A ray that starts inside a shape (d0 <= 0 at t0 = 0)
// hits at t = 0; t never goes behind its origin.
//
// A secant step is a bet that the field is straight. It is not taken when its sample leaves
// a gap longer than the threshold between its unbounding sphere and that of the sample it
// started from, and its distance (in front or behind) is above a tenth of the one it started
// from: the field was not straight, and a ridge may hide in the gap. The secant is then tried
// at a quarter of that length (down to the plain step), and grows back fourfold with each
// sample taken. Taking such samples skipped ridges of examples/terrain.sdf (9 holes, depth
// errors up to 0.38 relative at 256x192). Shorter gaps are left: near a convex surface, at a
// sphere's silhouette, every secant step lands short of it with such a gap, and refusing them
// left depth errors of 2e-3 there.
//
// A secant step kept (its sample near the surface, within a tenth of the distance it started
// from) is still a bet on the gap it left: on the terrain's fbm, or along a row of shapes, the
// field can cross zero in the gap and come back, and the step land near another crossing
// behind it by chance, which the bracket then converges to (examples/terrain.sdf at 128x96,
// pixel (112, 21): from 24.02 a step of 4.3 landed at 28.30 with d = -9e-4, and the hit at
// 28.18 hid the terrain at 24.25). So GAP_PROBES samples, evenly spaced in the gap, check it
// first: one that lies more than a tenth of the start's distance below the chord from the
// start's sample to the landing's means the field dips where the step did not look, and the
// step is refused as above; so is a probe behind the surface. A straight field lies on its
// chords. A convex shape's lies below them, but by at most a quarter of the landing's distance
// (a secant of a convex field lands short, its distance at least four times the chord's
// largest dip), within the tenth allowed, so silhouettes keep their steps. A kept step costs
// up to three samples more; they count against the refinement's REFINE_SAMPLES, and none are
// taken when too few are left (a landing that leaves exactly three ends the refinement: at
// false position in the bracket from the step's start if the landing is behind the surface),
// so a refinement still takes at most REFINE_SAMPLES. The hazard is made rarer, not ruled
// out: only sphere tracing the gap would prove it empty. At 256x192 against the f64
// reference the terrain's pixels whose depth is off by more than 1e-3 went from 75 to 23
// (docs/accuracy.md).
//
// Out of iterations (REFINE_SAMPLES) with a crossing bracketed, the hit is where false
// position puts it in the bracket (`bracket_position`). Without a crossing, marching goes on
// from the last sample, unless the ray came within a hundredth of the threshold `eps` and
// its newest sample did not rise from the one before: that still hits, as before, at the
// sample nearest the surface. In the crevice where two surfaces touch, or where the
// distance's rounding noise is as large as the threshold, passing by would crawl on in tiny
// steps until the step budget runs out. A pass told by the samples' rise after their minimum
// is decided by `touch_distance` instead (finer for a trusted distance), whether samples are
// left or not.
//
// What `refine_next` asks for: a sample at the state's t, or the end of the refinement, a hit
// at t or a pass by (marching goes on from t).
const REFINE_SAMPLE: u32 = 0u;
const REFINE_HIT: u32 = 1u;
const REFINE_PASS: u32 = 2u;
// The most samples a refinement takes, probes included.
const REFINE_SAMPLES: u32 = 20u;
// The samples that check a kept secant step's gap (`gap_probe`).
const GAP_PROBES: u32 = 3u;

// A refinement under way (`refine` in `shaders/refine.wgsl`, or the march's own loop in
// `shaders/march_merged.wgsl`): the newest sample (t, d), the one before it (tp, dp) and the
// one before that (tq, dq, put back with it if a secant step is refused), the nearest sample
// known in front (ta, da > 0) and, once bracketed, the nearest behind (tb, db <= 0), with
// `side` the one last moved (bracketed from the first sample behind on: a first sample
// behind the surface starts bracketed); the threshold eps; `reach`,
// the end of the stretch the samples' unbounding spheres cover; `gap`, where the first gap
// longer than the threshold that a secant step left unsampled begins (3e38: none); `dmin`,
// the least distance in front, at `tmin`; `cap`, the longest secant step in plain steps;
// `i`, the samples taken; and whether the last step was a secant step. A secant step that
// leaves a gap is a bet that the samples close in on a surface; if they pass one by
// instead, the gap is unexplored, and marching goes on from its start: a secant from a
// sample near one shape to one near another skipped a shape between them whole (a hole in
// the 300-shape grid from close by, docs/performance.md). While the gap of a kept step is
// probed, `probing` counts the probes left, `tl` is the landing's t and d its distance.
struct Refining {
    t: f32,
    d: f32,
    tp: f32,
    dp: f32,
    tq: f32,
    dq: f32,
    ta: f32,
    da: f32,
    tb: f32,
    db: f32,
    bracketed: bool,
    side: i32,
    eps: f32,
    reach: f32,
    gap: f32,
    dmin: f32,
    tmin: f32,
    cap: f32,
    i: u32,
    secant_step: bool,
    probing: u32,
    tl: f32,
}

// The refinement of a sample within the threshold eps, distance d0 at t0.
fn refine_start(t0: f32, d0: f32, eps: f32) -> Refining {
    return Refining(t0, d0, t0, d0, t0, d0, t0, d0, t0, d0, d0 <= 0.0, 0, eps, t0 + d0, 3.0e38,
        d0, t0, 256.0, 0u, false, 0u, t0);
}

// The refinement's next move from its newest sample: the end (a hit or a pass by, at r.t),
// or the next sample's t in r.t.
fn refine_next(r: ptr<function, Refining>) -> u32 {
    if (*r).probing > 0u {
        return REFINE_SAMPLE;
    }
    let t = (*r).t;
    let d = (*r).d;
    if (*r).i == 0u && d <= 0.0 && t <= 0.0 {
        // A ray that starts inside a shape hits at its origin (t never goes behind it).
        (*r).t = 0.0;
        return REFINE_HIT;
    }
    // Converged: d below 1e-7 of max(t, 1), and (from the second sample on) t within 1e-6 of
    // t of the surface by the slope of the last two samples: at a grazing angle a distance of
    // 1e-7 t still left t off by 3.5e-6 t, and near the camera (tiny_huge, t = 0.03) a
    // distance of 1e-7 left it off by 4e-5 t. Before the end of the samples, so that a last
    // sample that converged is the hit.
    let near = abs(d) <= 1e-7 * max(t, 1.0);
    if near && ((*r).i == 0u || abs(d * (t - (*r).tp)) <= 1e-6 * t * abs(d - (*r).dp)) {
        return REFINE_HIT;
    }
    if (*r).i >= REFINE_SAMPLES {
        // The pass by that a sample left would decide (below): the newest sample rose from
        // the one before it, and the nearest was not touching.
        let rose = d >= (*r).dp && (*r).dmin > touch_distance(t, (*r).eps);
        if !(*r).bracketed && ((*r).dmin > 0.01 * (*r).eps || rose) {
            // Out of iterations in front of the surface, never within a hundredth of the
            // threshold, or risen again: no crossing found yet, so marching goes on. (Taken
            // for a touch, a rise seen by the twentieth sample made a hit 0.045 short of the
            // terrain at t = 9.87: examples/terrain.sdf, 128x96, pixel (90, 36).)
            (*r).t = min(max((*r).reach, t), (*r).gap);
            return REFINE_PASS;
        }
        // Bracketed: the crossing, where false position puts it in the bracket (the newest
        // sample is one of its ends, and where probes or refused steps spent the samples the
        // bracket can still be 0.01 wide: t = 5.4 on examples/terrain.sdf, 256x192), kept
        // inside it (rounding can put it just below ta; NaN, from a flushed db - da, only
        // where db = 0, at tb). Touching without a crossing: the sample nearest the surface
        // (the last one could be further on, where the ray has left the surface: 0.24 from a
        // sphere passed by 5e-4, tests/passing_by.rs).
        (*r).t = select(t, (*r).tmin, !(*r).bracketed);
        if (*r).bracketed && (*r).da > 0.0 && (*r).tb > (*r).ta {
            let inside = bracket_position(r);
            let clamped = select((*r).tb, (*r).ta, inside < (*r).ta);
            (*r).t = select(clamped, inside, inside >= (*r).ta && inside <= (*r).tb);
        }
        return REFINE_HIT;
    }
    var next = t + d;
    var secant_step = false;
    if (*r).bracketed && (*r).da > 0.0 && (*r).tb > (*r).ta {
        // False position inside the bracket; the midpoint if it degenerates.
        let ta = (*r).ta;
        let tb = (*r).tb;
        next = bracket_position(r);
        if !(next > ta && next < tb) {
            next = 0.5 * (ta + tb);
        }
    } else if !(*r).bracketed && (*r).i > 0u {
        let slope = d - (*r).dp;
        if slope >= 0.0 && (*r).dmin > touch_distance(t, (*r).eps) {
            // Closest approach passed without a crossing: no surface here. Nearer than
            // `touch_distance` the samples go on and the ray counts as touching: for a
            // trusted distance only rounding's few steps of t (a hundredth of the pixel
            // threshold made false hits at silhouettes: 19 in the 300-shape grid from close
            // by at 256x192), for an estimate a hundredth of the threshold (the mandelbulb's
            // rises while its surface is still ahead).
            (*r).t = min(max((*r).reach, t), (*r).gap);
            return REFINE_PASS;
        }
        let secant = t - d * (t - (*r).tp) / slope;
        if slope < 0.0 && secant > next {
            next = min(secant, t + (*r).cap * d);
            secant_step = next > t + d;
        }
    }
    (*r).secant_step = secant_step;
    (*r).tq = (*r).tp;
    (*r).dq = (*r).dp;
    (*r).tp = t;
    (*r).dp = d;
    (*r).t = max(next, 0.0);
    return REFINE_SAMPLE;
}

// False position in the bracket (ta, da > 0) to (tb, db <= 0), with Illinois' halved ends:
// the next sample inside a bracket, and the hit of a refinement out of samples.
fn bracket_position(r: ptr<function, Refining>) -> f32 {
    return (*r).tb - (*r).db * ((*r).tb - (*r).ta) / ((*r).db - (*r).da);
}

// Where the next probe of a kept secant step's gap is taken: GAP_PROBES of them, evenly
// spaced from the end of the unbounding sphere of (tp, dp) to the start of the landing's.
fn gap_probe(r: ptr<function, Refining>) -> f32 {
    let start = (*r).tp + (*r).dp;
    let k = f32(GAP_PROBES + 1u - (*r).probing) / f32(GAP_PROBES + 1u);
    return start + k * ((*r).tl - abs((*r).d) - start);
}

// The refinement's state after its sample at r.t.
fn refine_sampled(r: ptr<function, Refining>, sample: f32) {
    var t = (*r).t;
    var d = sample;
    let tp = (*r).tp;
    let dp = (*r).dp;
    (*r).i = (*r).i + 1u;
    var leaves_gap = true;
    var refused = false;
    if (*r).probing > 0u {
        // A probe of a kept secant step's gap: behind the surface, or more than a tenth of
        // dp below the chord from (tp, dp) to the landing (tl, its distance kept in d), the
        // field dips where the step did not look, and the step is refused.
        (*r).probing = (*r).probing - 1u;
        refused = d <= 0.0 || (d - dp + 0.1 * dp) * ((*r).tl - tp) < ((*r).d - dp) * (t - tp);
        if !refused && (*r).probing > 0u {
            (*r).t = gap_probe(r);
            return;
        }
        (*r).probing = 0u;
        t = (*r).tl;
        d = (*r).d;
        (*r).t = t;
    } else {
        leaves_gap = (*r).secant_step && t - abs(d) > tp + dp + (*r).eps;
        refused = leaves_gap && abs(d) > 0.1 * dp;
        if leaves_gap && !refused && (*r).i + GAP_PROBES <= REFINE_SAMPLES {
            // A kept secant step: its gap is probed first (where the samples left allow).
            (*r).probing = GAP_PROBES;
            (*r).tl = t;
            (*r).d = d;
            (*r).t = gap_probe(r);
            return;
        }
    }
    if refused {
        // A refused secant step: back to the sample before it, and a quarter of the length.
        (*r).cap = 0.25 * (t - tp) / dp;
        (*r).t = tp;
        (*r).d = dp;
        (*r).tp = (*r).tq;
        (*r).dp = (*r).dq;
        return;
    }
    if leaves_gap {
        (*r).gap = min((*r).gap, tp + dp);
    }
    (*r).cap = min(4.0 * (*r).cap, 256.0);
    (*r).d = d;
    if d > 0.0 {
        if t - d <= (*r).reach {
            (*r).reach = max((*r).reach, t + d);
        }
        if d < (*r).dmin {
            (*r).dmin = d;
            (*r).tmin = t;
        }
        if !(*r).bracketed || t > (*r).ta {
            if (*r).side == 1 {
                (*r).db = 0.5 * (*r).db;
            }
            (*r).ta = t;
            (*r).da = d;
            (*r).side = 1;
        }
    } else {
        if !(*r).bracketed || t < (*r).tb {
            if (*r).side == -1 {
                (*r).da = 0.5 * (*r).da;
            }
            (*r).tb = t;
            (*r).db = d;
            (*r).side = -1;
        }
        if !(*r).bracketed {
            (*r).ta = tp;
            (*r).da = dp;
        }
        (*r).bracketed = true;
    }
}
