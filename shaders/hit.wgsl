// The result of marching one ray.
struct Hit {
    t: f32,
    steps: u32,
    hit: bool,
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

// Refines a hit found within the surface threshold (distance d0 at t0) to the surface itself.
// In front of the surface (d > 0) each step goes at least the plain step t + d (a distance
// bound never overestimates, so the surface is at least that far) and follows the secant
// through the last two samples where it goes further, at most 256 plain steps: the secant
// converges fast where the ray meets the surface at a grazing angle. Once a sample lies behind
// the surface (d <= 0) the surface is bracketed and Illinois-style false position narrows the
// bracket. If the distance grows again while still positive, the ray passes the surface by
// within the threshold without meeting it: that is no hit, and marching goes on (`hit`
// false) from the furthest t up to which the samples' unbounding spheres leave the ray free
// (a secant step may have jumped past a surface that the march must still find). A ray that
// starts inside a shape (d0 <= 0 at t0 = 0) hits at t = 0; t never goes behind its origin.
// A ray that comes within a hundredth of the threshold `eps` still hits, as before: in the
// crevice where two surfaces touch, or where the distance's rounding noise is as large as
// the threshold, passing by would crawl on in tiny steps until the step budget runs out.
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
    var dmin = d0;
    for (var i = 0u; i < 12u; i = i + 1u) {
        if abs(d) <= 1e-7 * max(t, 1.0) {
            break;
        }
        var next = t + d;
        if bracketed && da > 0.0 && tb > ta {
            // False position inside the bracket; the midpoint if it degenerates.
            next = tb - db * (tb - ta) / (db - da);
            if !(next > ta && next < tb) {
                next = 0.5 * (ta + tb);
            }
        } else if !bracketed && i > 0u {
            let slope = d - dp;
            if slope >= 0.0 && dmin > 0.01 * eps {
                // Closest approach passed without a crossing: no surface here.
                return Hit(reach, steps, false);
            }
            let secant = t - d * (t - tp) / slope;
            if slope < 0.0 && secant > next {
                next = min(secant, t + 256.0 * d);
            }
        }
        tp = t;
        dp = d;
        t = max(next, 0.0);
        d = scene_distance(ro + rd * t);
        steps = steps + 1u;
        if d > 0.0 {
            if t - d <= reach {
                reach = max(reach, t + d);
            }
            dmin = min(dmin, d);
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
    return Hit(t, steps, true);
}
