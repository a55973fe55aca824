//! Ambient occlusion's part of the marcher (spec section 7): its samples along the normal
//! through the scene's distance, or for a union read as data through one list along the
//! normal (`shaders/shading/ambient_occlusion_list.wgsl`), or through the walk where its
//! samples reach farther than [`LIST_MOST`] of the instances' spacing.

use crate::literal::float;
use crate::marcher::View;
use crate::parts;
use sdfc_ir::scene::Ao;
use std::fmt::Write;

/// The highest sample, over the instances' spacing (`Instances::spacing`), up to which the
/// list pays: above it each sample's list holds more instances than the walk (which skips
/// every box no nearer than the best so far) evaluates. Measured on lavapipe, the list
/// against the walk on the 300-shape grid on a floor, spacing 1.5: 1.7x at a reach of 0.17
/// spacings, 1.4x at 0.67, 1.1x at 0.8, 1.0x at 1 (0.86x with three samples), 0.70x at 1.6
/// (docs/performance.md, "Ambient occlusion through one list").
const LIST_MOST: f64 = 0.8;

/// Ambient occlusion's sample (`shaders/shading/ambient_occlusion.wgsl`), at height h along
/// the normal; a test checks it is there.
pub(crate) const AO_SAMPLE: &str = "scene_distance(p + n * h)";

/// The first line of `ambient_occlusion`, before which a union read as data makes its list,
/// and the bound of `ao_below`'s list (`shaders/shading/ambient_occlusion_list.wgsl`), which
/// a mixed union's other children lower; tests check they are there.
const AO_START: &str = "    var occlusion = 0.0;\n";
const AO_BELOW: &str = "ray_nearest(q, h, h, true)";

/// `ambient_occlusion(p, n)` and what it needs, for `ao`.
pub fn emit(ao: &Ao, view: &View) -> String {
    if !view.ray_lists {
        return parts::AMBIENT_OCCLUSION.to_string();
    }
    // Each sample needs the distance only up to its height (`clamp(h - d, 0, h)`); a mixed
    // union's other children bound it first.
    let below = view.walk_below("q", Some("h"));
    let reach = f64::from(ao.step) * f64::from(ao.samples);
    let mut s = if lists(reach, view.instances_spacing) {
        let list = format!("ray_nearest(q, h, {below}, true)");
        let mut s = parts::AMBIENT_OCCLUSION_LIST.replacen(AO_BELOW, &list, 1);
        s += "\n";
        s += &parts::AMBIENT_OCCLUSION.replacen(
            AO_START,
            &format!("    ao_list(p, n);\n{AO_START}"),
            1,
        );
        s
    } else {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "// The scene's distance at q, h along the normal, or h where it is no nearer: the\n\
             // walk, each box no nearer than the best so far passed over, and no far box's\n\
             // distance taken for its instances' (`walk_node`'s `least`). The samples reach {},\n\
             // more than {LIST_MOST} of the instances' spacing: one list for them all would hold\n\
             // more than the walk evaluates.",
            float(reach as f32),
        );
        let _ = writeln!(
            s,
            "fn ao_below(q: vec3<f32>, h: f32) -> f32 {{\n    \
             return scene_nearest(q, {below}, 3.0e38).distance;\n}}\n"
        );
        s += parts::AMBIENT_OCCLUSION;
        s
    };
    s = s.replacen(AO_SAMPLE, "ao_below(p + n * h, h)", 1);
    s
}

/// Whether the samples reaching `reach` along the normal take one list
/// ([`LIST_MOST`] of the instances' spacing or less, or the spacing unknown). A millionth
/// more is let in: the reach comes from f32 settings (`4 * 0.3` is 1.2000000477).
fn lists(reach: f64, spacing: Option<f64>) -> bool {
    spacing.is_none_or(|s| reach <= LIST_MOST * s * (1.0 + 1e-6))
}

#[cfg(test)]
mod tests {
    use super::{lists, AO_BELOW, AO_SAMPLE, AO_START};
    use crate::parts;

    /// Ambient occlusion of a union read as data makes its list before the first sample and
    /// samples through it, bounded by a mixed union's other children: were the texts `emit`
    /// rewrites written differently, each sample would walk the hierarchy, or ignore the
    /// other children.
    #[test]
    fn the_texts_emit_rewrites_are_there() {
        assert_eq!(parts::AMBIENT_OCCLUSION.matches(AO_START).count(), 1);
        assert_eq!(parts::AMBIENT_OCCLUSION.matches(AO_SAMPLE).count(), 1);
        assert_eq!(parts::AMBIENT_OCCLUSION_LIST.matches(AO_BELOW).count(), 1);
        let start = parts::AMBIENT_OCCLUSION.find(AO_START).expect("the start");
        assert!(
            start
                < parts::AMBIENT_OCCLUSION
                    .find(AO_SAMPLE)
                    .expect("the sample")
        );
    }

    #[test]
    fn samples_within_the_spacing_take_the_list() {
        assert!(lists(0.25, Some(1.5)));
        assert!(lists(1.2, Some(1.5)));
        assert!(lists(f64::from(0.3f32) * 4.0, Some(1.5)));
        assert!(!lists(1.25, Some(1.5)));
        assert!(!lists(2.4, Some(1.5)));
        assert!(lists(100.0, None));
    }
}
