//! Sphere tracing to a far smaller threshold than the GPU's, then bisection of the bracketed
//! root: the depth of an exact (or bounded) distance to about 1e-13 relative.

use crate::scene::SceneEval;
use crate::vec::{add, mul, scale, V3};

/// The reference marcher's step limit per ray (the GPU's `max_steps` is at most 100 000).
pub const MAX_STEPS: u32 = 2_000_000;
/// Surface threshold relative to max(t, 1): where sphere tracing stops and bisection starts.
pub const EPSILON: f64 = 1e-9;
/// Bisection stops when the bracket is this narrow relative to max(t, 1).
pub const BRACKET: f64 = 1e-13;

/// One ray's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    pub hit: bool,
    /// Distance along the ray to the surface (on a miss, where marching stopped).
    pub t: f64,
    /// Distance evaluations, refinement included.
    pub steps: u32,
}

/// Marches from `ro` along the unit `rd` up to `max_distance`. A ray that starts inside a
/// shape (negative distance at `ro`) hits at t = 0.
pub fn march(scene: &SceneEval, ro: V3, rd: V3, max_distance: f64) -> RayHit {
    let mut t = 0.0;
    let mut steps = 0u32;
    loop {
        if steps >= MAX_STEPS || t > max_distance {
            return RayHit {
                hit: false,
                t,
                steps,
            };
        }
        let p = add(ro, mul(rd, t));
        let d = scene.distance(p);
        steps += 1;
        if d.is_nan() {
            // A distance that is not a number bounds nothing: nothing can be found here.
            return RayHit {
                hit: false,
                t,
                steps,
            };
        }
        if d < 0.0 && t == 0.0 {
            return RayHit {
                hit: true,
                t: 0.0,
                steps,
            };
        }
        let eps = (EPSILON * t.max(1.0)).max(1e-15 * scale(p));
        if d < eps {
            return refine(scene, ro, rd, t, d, steps, max_distance);
        }
        t += d;
    }
}

/// From `t0` (distance `d0` below the threshold, the surface no nearer than `t0 + d0`), finds
/// a point past the surface by doubling steps, then bisects the bracket.
fn refine(
    scene: &SceneEval,
    ro: V3,
    rd: V3,
    t0: f64,
    d0: f64,
    mut steps: u32,
    max_distance: f64,
) -> RayHit {
    let at = |t: f64| scene.distance(add(ro, mul(rd, t)));
    let mut a = t0 + d0.max(0.0);
    let mut s = d0.abs().max(1e-16 * t0.max(1.0));
    let mut b = None;
    for _ in 0..64 {
        let tb = a + s;
        let db = at(tb);
        steps += 1;
        if db <= 0.0 {
            b = Some(tb);
            break;
        }
        // Still outside, and no surface nearer than tb + db: move the front end on.
        a = tb;
        s = (2.0 * s).max(db);
        if a > max_distance {
            break;
        }
    }
    let Some(mut b) = b else {
        // Never crossed: a ray tangent to the surface; the threshold was met at t0.
        return RayHit {
            hit: t0 <= max_distance,
            t: t0,
            steps,
        };
    };
    while b - a > BRACKET * a.max(1.0) {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        steps += 1;
        if at(m) > 0.0 {
            a = m;
        } else {
            b = m;
        }
    }
    RayHit {
        hit: a <= max_distance,
        t: 0.5 * (a + b),
        steps,
    }
}
