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

// The end of a march that left its loop without a hit, at t after `steps` samples. Out of
// steps while passing a surface by, still within a tenth of the threshold (`passing`), is a
// hit where the ray is: a ray that grazes a silhouette crawls past it in steps of about a
// hundredth of the threshold and can spend the whole budget there, and the pixel's footprint
// touches that surface, so the pixel shows it rather than a hole with the background behind.
// Further out it is not: a ray just above a ground plane stays within the threshold (which
// grows with t) to the horizon, and made a row of false hits at whatever t the steps ran out.
fn march_end(t: f32, steps: u32, passing: bool) -> Hit {
    return Hit(t, steps, passing && steps >= MAX_STEPS && t <= MAX_DISTANCE);
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

// Refines a hit found within the surface threshold (distance d0 at t0) to the surface itself.
// In front of the surface (d > 0) each step goes at least the plain step t + d (a distance
// bound never overestimates, so the surface is at least that far) and follows the secant
// through the last two samples where it goes further, at most 256 plain steps: the secant
// converges fast where the ray meets the surface at a grazing angle. Once a sample lies behind
// the surface (d <= 0) the surface is bracketed and Illinois-style false position narrows the
// bracket. If the distance grows again while still positive, the ray passes the surface by
// within the threshold without meeting it: that is no hit, and marching goes on (`hit`
// false) from the last sample, or from the end of the stretch the samples' unbounding
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
// Out of iterations without a crossing, marching goes on from the last sample, unless the ray
// came within a hundredth of the threshold `eps`: that still hits, as before, at the sample
// nearest the surface. In the crevice where two surfaces touch, or where the distance's
// rounding noise is as large as the threshold, passing by would crawl on in tiny steps until
// the step budget runs out. A pass told by the samples' rise after their minimum is decided
// by `touch_distance` instead (finer for a trusted distance).
fn refine(ro: vec3<f32>, rd: vec3<f32>, t0: f32, d0: f32, steps0: u32, eps: f32) -> Hit {
    var steps = steps0;
    if d0 <= 0.0 && t0 <= 0.0 {
        return Hit(0.0, steps, true);
    }
    // The nearest sample known to be in front (ta, da > 0) and, once bracketed, the nearest
    // sample behind (tb, db <= 0).
    var ta = t0;
    var da = d0;
    var tb = t0;
    var db = d0;
    var bracketed = d0 <= 0.0;
    var side = 0;
    var t = t0;
    var d = d0;
    var tp = t0;
    var dp = d0;
    var reach = t0 + d0;
    // Where the first gap longer than the threshold that a secant step left unsampled begins
    // (3e38: none). Such a step is taken as a bet that the samples close in on a surface
    // (its distance fell below a tenth of the last); if they pass one by instead, the
    // gap is unexplored, and marching goes on from its start: a secant from a sample near
    // one shape to one near another skipped a shape between them whole (a hole in the
    // 300-shape grid from close by, docs/performance.md).
    var gap = 3.0e38;
    var dmin = d0;
    var tmin = t0;
    // The longest secant step, in plain steps.
    var cap = 256.0;
    for (var i = 0u; i < 20u; i = i + 1u) {
        // Converged: d below 1e-7 of max(t, 1), and (from the second sample on) t within 1e-6
        // of t of the surface by the slope of the last two samples: at a grazing angle a
        // distance of 1e-7 t still left t off by 3.5e-6 t, and near the camera (tiny_huge,
        // t = 0.03) a distance of 1e-7 left it off by 4e-5 t.
        let near = abs(d) <= 1e-7 * max(t, 1.0);
        if near && (i == 0u || abs(d * (t - tp)) <= 1e-6 * t * abs(d - dp)) {
            return Hit(t, steps, true);
        }
        var next = t + d;
        var secant_step = false;
        if bracketed && da > 0.0 && tb > ta {
            // False position inside the bracket; the midpoint if it degenerates.
            next = tb - db * (tb - ta) / (db - da);
            if !(next > ta && next < tb) {
                next = 0.5 * (ta + tb);
            }
        } else if !bracketed && i > 0u {
            let slope = d - dp;
            if slope >= 0.0 && dmin > touch_distance(t, eps) {
                // Closest approach passed without a crossing: no surface here. Nearer than
                // `touch_distance` the samples go on and the ray counts as touching: for a
                // trusted distance only rounding's few steps of t (a hundredth of the pixel
                // threshold made false hits at silhouettes: 19 in the 300-shape grid from
                // close by at 256x192), for an estimate a hundredth of the threshold (the
                // mandelbulb's rises while its surface is still ahead).
                return Hit(min(max(reach, t), gap), steps, false);
            }
            let secant = t - d * (t - tp) / slope;
            if slope < 0.0 && secant > next {
                next = min(secant, t + cap * d);
                secant_step = next > t + d;
            }
        }
        // The sample before (tp, dp), put back with it if this step is not taken.
        let tq = tp;
        let dq = dp;
        tp = t;
        dp = d;
        t = max(next, 0.0);
        d = scene_distance(ro + rd * t);
        steps = steps + 1u;
        if secant_step && t - abs(d) > tp + dp + eps && abs(d) > 0.1 * dp {
            cap = 0.25 * (t - tp) / dp;
            t = tp;
            d = dp;
            tp = tq;
            dp = dq;
            continue;
        }
        if secant_step && t - abs(d) > tp + dp + eps {
            gap = min(gap, tp + dp);
        }
        cap = min(4.0 * cap, 256.0);
        if d > 0.0 {
            if t - d <= reach {
                reach = max(reach, t + d);
            }
            if d < dmin {
                dmin = d;
                tmin = t;
            }
            if !bracketed || t > ta {
                if side == 1 {
                    db = 0.5 * db;
                }
                ta = t;
                da = d;
                side = 1;
            }
        } else {
            if !bracketed || t < tb {
                if side == -1 {
                    da = 0.5 * da;
                }
                tb = t;
                db = d;
                side = -1;
            }
            if !bracketed && d0 > 0.0 {
                ta = tp;
                da = dp;
            }
            bracketed = true;
        }
    }
    if !bracketed && dmin > 0.01 * eps {
        // Out of iterations in front of the surface, never within a hundredth of the
        // threshold: no crossing found yet, so marching goes on.
        return Hit(min(max(reach, t), gap), steps, false);
    }
    // Bracketed: the crossing. Touching without a crossing: the sample nearest the surface
    // (the last one could be further on, where the ray has left the surface: 0.24 from a
    // sphere passed by 5e-4, tests/passing_by.rs).
    return Hit(select(t, tmin, !bracketed), steps, true);
}
