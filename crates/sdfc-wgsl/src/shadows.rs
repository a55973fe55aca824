//! The shadow rays' part of the marcher (spec section 7): none, hard or soft, marched through
//! the scene's distance, or for a union read as data through each shadow ray's list
//! (`shaders/shading/shadow_instances.wgsl`), and `bounds_outside`, where they stop.

use crate::literal::{float, vec3};
use crate::marcher::{all_open, View};
use crate::parts;
use sdfc_ir::rounding::{f32_down, f32_up};
use sdfc_ir::scene::Shadows;
use std::fmt::Write;

/// How far a hard shadow ray's list pads each box, times the t of its far side, over the
/// instances' outside factor f: outside the padding an instance's distance is at least f
/// times it, 2e-5 t plus f times the 1e-3 every box has, which for f of [`HARD_LEAST`] or
/// more is above the hit test's threshold, 1e-5 (1 + t)
/// (`shaders/shading/shadow_hard_sample.wgsl`), out to the padding's edge.
const HARD_REACH: f64 = 2e-5;
const HARD_LEAST: f64 = 0.02;

/// The largest padding a soft shadow ray's list takes, times the t of a box's far side:
/// beyond it (a small `k`) the lists hold most of the instances near the ray, and the walk
/// answers instead. Measured on lavapipe: see docs/performance.md, "Shadow rays through the
/// ray's list".
const SOFT_MOST: f64 = 1.0 / 3.0;

/// The shadow function `shadow(ro, rd, tmax)` the shading calls, and what it needs; nothing
/// without shadows.
pub fn emit(shadows: Shadows, view: &View) -> String {
    // Each kind's sample, plain march, and list padding (none: no list pays).
    let f = view.instances_outside;
    let (hard, sample, plain, reach) = match shadows {
        Shadows::None => return String::new(),
        Shadows::Hard => (
            true,
            parts::SHADOW_HARD_SAMPLE,
            parts::SHADOW_HARD,
            (f >= HARD_LEAST).then(|| HARD_REACH / f),
        ),
        Shadows::Soft(k) => (
            false,
            parts::SHADOW_SOFT_SAMPLE,
            parts::SHADOW_SOFT,
            soft_reach(k as f64, f).filter(|r| *r <= SOFT_MOST),
        ),
    };
    let mut s = bounds_outside(view, hard);
    s += "\n";
    s += sample;
    s += "\n";
    match reach.filter(|_| view.ray_lists) {
        Some(reach) => {
            let _ = writeln!(
                s,
                "// How far each box is padded for a shadow ray's list, times the t of its far side:\n\
                 // no instance outside it can darken the ray.\nconst SHADOW_REACH: f32 = {};\n",
                float(f32_up(reach))
            );
            if view.rest.is_some() {
                // A mixed union's other children first, alone: the plain march over them.
                s += &plain
                    .replacen("fn shadow(", "fn shadow_rest(", 1)
                    .replace("scene_distance(q)", "rest_distance(q)");
                s += "\n";
                s += &parts::SHADOW_INSTANCES.replacen(
                    LIGHT_START,
                    "    var light = shadow_rest(ro, rd, tmax);\n",
                    1,
                );
            } else {
                s += parts::SHADOW_INSTANCES;
            }
        }
        // The scene's distance at every step: for a union read as data, the walk. A soft
        // shadow's walk takes a far box's distance for its instances' only where that cannot
        // lower the light (`k h / t` no less than it): a bound there darkened penumbrae, and
        // the grid on a floor with `soft(2)` parted from its code on 1371 channels at
        // 160x120 (docs/performance.md, "Soft shadows' walk").
        None if view.ray_lists && !hard => {
            let below = view.walk_below("q", None);
            s += &plain.replacen(
                SOFT_SAMPLE,
                &format!(
                    "shadow_sampled(&light, scene_nearest(q, {below}, light * t / SHADOW_K).distance, t)"
                ),
                1,
            );
        }
        None => s += plain,
    }
    s += "\n";
    s
}

/// The first line of `shaders/shading/shadow_instances.wgsl`'s function: the light before
/// any sample. A test checks it is there.
const LIGHT_START: &str = "    var light = 1.0;\n";

/// A soft shadow's sample of the scene (`shaders/shading/shadow_soft.wgsl`), which a union
/// read as data walks. A test checks it is there.
const SOFT_SAMPLE: &str = "shadow_sampled(&light, scene_distance(q), t)";

/// How far a soft shadow ray's list pads each box, times the t of its far side, for the
/// sharpness `k` and a distance at least `outside` times the distance to each instance's box
/// (`View::instances_outside`): outside the padding, at t no more than the far side's t plus
/// the padding, an instance's distance h is at least `outside` times the padding, so
/// `k h / t` is at least 1 and cannot lower the light (beyond, h grows with t - t_far as
/// fast). None where no padding can (`k outside` at most 1, or the factor unknown): the
/// walk then.
fn soft_reach(k: f64, outside: f64) -> Option<f64> {
    let kf = k * outside.clamp(0.0, 1.0);
    (kf > 1.0).then(|| 1.0 / (kf - 1.0))
}

/// `bounds_outside(p)`: how far p lies outside the box shadow rays stop at
/// ([`crate::marcher::shadow_slabs`]: `ray_span`'s, a little wider), per axis (0 inside),
/// which shadow rays read to stop where no surface can darken them any more
/// (`shaders/shading/shadow_hard.wgsl`, `shadow_soft.wgsl`); for soft shadows also
/// `OUTSIDE_FACTOR` ([`View::outside`]), by which the scene's distance outside the box is at
/// least the distance to it. An unbounded axis clamps to +-3e38 (no f32 point lies beyond).
/// Where nothing can stop a shadow ray (a scene unbounded on every axis; soft shadows where
/// the factor is unknown) the box is never left, and the driver folds the test away.
pub(crate) fn bounds_outside(view: &View, hard: bool) -> String {
    let slabs = view.shadow;
    let factor = f32_down(view.outside.clamp(0.0, 1.0));
    let mut s = String::new();
    if !hard {
        let _ = writeln!(
            s,
            "// Outside the scene's bounds its distance is at least OUTSIDE_FACTOR times the distance\n\
             // to them (0: not known), so a soft shadow's cone that has left them for good stays free.\n\
             const OUTSIDE_FACTOR: f32 = {};\n",
            float(factor)
        );
    }
    s +=
        "// How far p lies outside the scene's bounds (padded), per axis (0 inside): shadow rays\n\
          // stop once they leave them for good.\n\
          fn bounds_outside(p: vec3<f32>) -> vec3<f32> {\n";
    if all_open(&slabs) || (!hard && factor == 0.0) {
        s += "    return vec3<f32>(0.0);\n}\n";
        return s;
    }
    let lo = slabs.map(|s| s.lo.unwrap_or(-3.0e38));
    let hi = slabs.map(|s| s.hi.unwrap_or(3.0e38));
    let _ = writeln!(
        s,
        "    return p - clamp(p, {}, {});\n}}",
        vec3(lo),
        vec3(hi)
    );
    s
}

#[cfg(test)]
mod tests {
    use super::{soft_reach, HARD_LEAST, HARD_REACH, LIGHT_START, SOFT_SAMPLE};
    use crate::parts;

    /// The text `emit` rewrites for a mixed union is there, once.
    #[test]
    fn the_listed_shadow_starts_from_the_light() {
        assert_eq!(parts::SHADOW_INSTANCES.matches(LIGHT_START).count(), 1);
        assert_eq!(parts::SHADOW_SOFT.matches(SOFT_SAMPLE).count(), 1);
        for plain in [parts::SHADOW_HARD, parts::SHADOW_SOFT] {
            assert_eq!(plain.matches("fn shadow(").count(), 1);
            assert_eq!(plain.matches("scene_distance(q)").count(), 1);
        }
    }

    /// The padding keeps every instance outside it from darkening the ray: at t up to the
    /// far side's t0 plus the padding, `k * outside * padding / t` is at least 1; beyond,
    /// the distance is at least `outside * (t - t0)`. And a hard shadow's padding keeps the
    /// hit test's threshold out at its edge, from the least factor it takes on.
    #[test]
    fn the_lists_paddings_keep_out_what_could_darken() {
        for (k, f) in [(16.0, 1.0), (8.0, 0.5), (2.5, 1.0), (64.0, 0.0625)] {
            let reach = soft_reach(k, f).expect("a reach");
            for t0 in [0.01, 1.0, 100.0] {
                let pad = reach * t0;
                assert!(
                    k * f * pad / (t0 + pad) >= 1.0 - 1e-12,
                    "k {k} f {f} t0 {t0}"
                );
            }
        }
        assert_eq!(soft_reach(16.0, 0.0), None);
        assert_eq!(soft_reach(1.0, 1.0), None);
        assert_eq!(soft_reach(4.0, 0.25), None);
        for f in [HARD_LEAST, 0.5, 1.0] {
            for t0 in [0.0, 1.0, 1e3, 1e6] {
                let pad = HARD_REACH / f * t0 + 1e-3;
                for t in [t0, t0 + pad] {
                    assert!(f * pad >= 1e-5 * (1.0 + t), "f {f} t0 {t0} t {t}");
                }
            }
        }
    }
}
