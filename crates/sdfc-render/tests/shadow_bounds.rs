//! Shadow rays stop once they have left the scene's bounds for good (`bounds_outside`,
//! `shaders/shading/shadow_soft.wgsl` and `shadow_hard.wgsl`): the picture must be the one of
//! shadow rays that march on to the light, to the bit (outside the box the distance is at
//! least `OUTSIDE_FACTOR` times the distance to the box, so the samples left out could not
//! have narrowed the cone, and no surface lies there). The shader that marches on is
//! the same text with `bounds_outside` answering "inside" everywhere; the test fails if the
//! stop is taken too early (a penumbra or a shadow cut short) and checks that the scene's
//! shader has the stop at all. The interpreter stops by the same rule from its data.

mod common;

use common::{compile, compile_with, renderer};
use sdfc_render::{Frame, RenderOptions};

const SIZE: (u32, u32) = (64, 48);

/// Exact distances on a floor's half-space and in a bounded box, a smooth blend, an
/// intersection, an ellipsoid and a heightfield (bounds whose factor is known), under a high sun, a low sun
/// (its rays leave the floor's box at a grazing angle, where the rate test decides), a point
/// light and a light below the box's top (its rays never leave it), soft and hard.
fn scenes() -> Vec<(String, String)> {
    let shapes =
        "sphere(0.8).translate([0, 0.8, 0]) | box([0.5, 1, 0.5]).translate([1.8, 1, -0.5]) \
                  | torus(0.6, 0.2).translate([-1.8, 0.2, 0.3])";
    let lights = [
        (
            "high sun",
            "light directional { direction: [-0.4, -1, -0.3] }",
        ),
        (
            "low sun",
            "light directional { direction: [-1, -0.12, -0.2] }",
        ),
        ("point", "light point { position: [2, 3, 2], intensity: 8 }"),
        (
            "under the top",
            "light point { position: [-3, 0.5, 3], intensity: 8 }",
        ),
    ];
    let mut v = Vec::new();
    for (light_name, light) in lights {
        for shadows in ["soft(4)", "soft(16)", "hard"] {
            for (ground_name, scene) in [
                ("floor", format!("plane([0, 1, 0], 0) | {shapes}")),
                ("bounded", shapes.to_string()),
                // A smooth union (factor 1: its box grows by what the blend takes off) and a
                // heightfield (factor 1 / sqrt(1 + L^2)), bounds rather than distances.
                (
                    "blend",
                    format!("union({shapes}, box([2.5, 0.1, 1.5]), smooth: 0.4)"),
                ),
                // An intersection whose box is neither child's (factor 1 / sqrt(2)) and an
                // ellipsoid (min(r) / max(r)).
                (
                    "cut",
                    format!(
                        "plane([0, 1, 0], 0) | intersect(sphere(0.9), \
                         box([1.2, 1.2, 1.2]).translate([0.4, 0.4, 0])).translate([0, 0.9, 1.5]) \
                         | ellipsoid([0.8, 0.3, 0.5]).translate([-1, 0.3, 1.6]) | {shapes}"
                    ),
                ),
                (
                    "terrain",
                    format!(
                        "heightfield(|x, z| 0.3 * sin(2 * x) * cos(1.5 * z), lipschitz: 0.8) \
                         | {shapes}"
                    ),
                ),
            ] {
                v.push((
                    format!("{ground_name}, {light_name}, {shadows}"),
                    format!(
                        "camera {{ position: [1, 3, 7], target: [0, 0.5, 0], fov: 50deg }}\n\
                         {light}\n\
                         render {{ shadows: {shadows} }}\n\
                         scene = {scene};\n"
                    ),
                ));
            }
        }
    }
    v
}

/// The same shader with shadow rays that never stop at the bounds.
fn marching_on(name: &str, wgsl: &str) -> String {
    let start = wgsl
        .find("fn bounds_outside(p: vec3<f32>) -> vec3<f32> {\n")
        .unwrap_or_else(|| panic!("{name}: no bounds_outside"));
    let end = start + wgsl[start..].find("\n}\n").expect("its end");
    let body = &wgsl[start..end];
    assert!(
        body.contains("clamp(p, "),
        "{name}: the bounds are not tested: {body}"
    );
    format!(
        "{}fn bounds_outside(p: vec3<f32>) -> vec3<f32> {{\n    return vec3<f32>(0.0);{}",
        &wgsl[..start],
        &wgsl[end..]
    )
}

fn options() -> RenderOptions {
    RenderOptions {
        aovs: true,
        ..RenderOptions::sized(SIZE.0, SIZE.1)
    }
}

fn same_colours(name: &str, a: &Frame, b: &Frame) {
    let off = a.rgba.iter().zip(&b.rgba).filter(|(x, y)| x != y).count();
    assert_eq!(off, 0, "{name}: {off} channels differ from marching on");
}

#[test]
fn scenes_shade_as_if_shadow_rays_marched_on() {
    let Some(r) = renderer() else {
        return;
    };
    for (name, source) in scenes() {
        let c = compile(&name, &source);
        let stopping = r.render(&c, &options()).expect("render");
        let on = marching_on(&name, &c.wgsl);
        let full = r
            .render_wgsl(c.program(), &on, &options())
            .expect("render marching on");
        same_colours(&name, &stopping, &full);
    }
}

#[test]
fn a_union_read_as_data_too() {
    let Some(r) = renderer() else {
        return;
    };
    let mut union = String::from("union(");
    for i in 0..40 {
        let (x, z) = ((i % 8) as f32 * 0.9 - 3.2, (i / 8) as f32 * -0.9);
        union += &format!("sphere(0.35).translate([{x}, 0.35, {z}]), ");
    }
    union += ")";
    let source = format!(
        "camera {{ position: [0, 3, 5], target: [0, 0, -1.5], fov: 50deg }}\n\
         light directional {{ direction: [-1, -0.3, -0.2] }}\n\
         render {{ shadows: soft(8) }}\n\
         scene = plane([0, 1, 0], 0) | {union};\n"
    );
    let opts = sdfc_wgsl::Options {
        instances: sdfc_wgsl::Instances::Always,
        ..sdfc_wgsl::Options::default()
    };
    let c = compile_with("data", &source, &opts);
    assert!(!c.data.is_empty(), "the union is not read as data");
    let stopping = r.render(&c, &options()).expect("render");
    let on = marching_on("data", &c.wgsl);
    let full = r
        .render_wgsl_with_data(c.program(), &on, &c.data, &options())
        .expect("render marching on");
    same_colours("data", &stopping, &full);
}

/// The interpreter stops by the same rule: its pictures are the specialised shader's that
/// marches on, up to the float rounding the two marchers differ by (interpreted.rs: a unit or
/// two of 255 on a channel, and a few silhouette pixels that one marcher hits and the other
/// passes); a penumbra cut short moves tens of pixels by tens of units.
#[test]
fn the_interpreter_shades_as_if_shadow_rays_marched_on() {
    let Some(r) = renderer() else {
        return;
    };
    // Not the heightfield: there the two marchers differ by more than that on a few pixels
    // whether or not shadow rays stop (6 pixels at 64x48 under the high sun, the same 6
    // against the shader that stops as against the one that marches on).
    for (name, source) in scenes()
        .into_iter()
        .filter(|(n, _)| !n.starts_with("terrain"))
    {
        let c = compile(&name, &source);
        let on = marching_on(&name, &c.wgsl);
        let full = r
            .render_wgsl(c.program(), &on, &options())
            .expect("render marching on");
        let interpreted = r
            .render_interpreted(c.program(), &options())
            .expect("render interpreted");
        let off = |a: &[u8], b: &[u8]| a.iter().zip(b).any(|(x, y)| x.abs_diff(*y) > 6);
        let pixels = interpreted
            .rgba
            .chunks(4)
            .zip(full.rgba.chunks(4))
            .filter(|(a, b)| off(a, b))
            .count();
        assert!(
            pixels <= 4,
            "{name}: {pixels} pixels more than 6/255 off marching on"
        );
    }
}
