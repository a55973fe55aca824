//! Dispatching only the tiles whose rays can meet the scene's bounds (`sdfc_wgsl::screen`,
//! the render crate's `tiles`): the frame must be the whole dispatch's to the bit (colour,
//! depth, normal, steps), wherever the scene sits on the image, with antialiasing,
//! reflections, shadows and ambient occlusion, for a union read as data, and from the
//! interpreter, which dispatches the same way.

mod common;

use common::{compile, renderer};
use sdfc_render::{Frame, RenderOptions};

const W: u32 = 64;
const H: u32 = 48;

fn frame(
    r: &sdfc_render::Renderer,
    c: &sdfc_wgsl::Compiled,
    all_pixels: bool,
    interpreted: bool,
) -> Frame {
    let opts = RenderOptions {
        aovs: true,
        all_pixels,
        ..RenderOptions::sized(W, H)
    };
    if interpreted {
        r.render_interpreted(c.program(), &opts).expect("render")
    } else {
        r.render(c, &opts).expect("render")
    }
}

/// Renders `source` both ways and checks the frames are the same, and that the scene's
/// rectangle on the image leaves tiles out (so the test draws what it means to).
fn same_as_the_whole_dispatch(name: &str, source: &str) {
    same_both_ways(name, source, false);
}

fn same_both_ways(name: &str, source: &str, interpreted: bool) {
    let Some(r) = renderer() else {
        return;
    };
    let c = compile(name, source);
    let rect = sdfc_wgsl::screen::screen_rect(c.program(), W, H).expect("a rectangle");
    let tiles_in = |a: u32, b: u32| b.div_ceil(8).saturating_sub(a / 8);
    let covered = tiles_in(rect[0], rect[2]) * tiles_in(rect[1], rect[3]);
    assert!(
        covered < 8 * 6 - 1,
        "{name}: the rectangle {rect:?} covers the image"
    );
    let some = frame(r, &c, false, interpreted);
    let all = frame(r, &c, true, interpreted);
    assert_eq!(some.rgba, all.rgba, "{name}: colours differ");
    let (a, b) = (some.aovs.expect("AOVs"), all.aovs.expect("AOVs"));
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.depth), bits(&b.depth), "{name}: depths differ");
    assert_eq!(bits(&a.steps), bits(&b.steps), "{name}: steps differ");
    assert_eq!(a.normal, b.normal, "{name}: normals differ");
    // The scene is on the image: some pixels hit.
    assert!(a.depth.iter().any(|d| d.is_finite()), "{name}: nothing hit");
}

const CAMERA: &str = "camera { position: [0, 1, 10], target: [0, 0, 0], fov: 50deg }\n";

#[test]
fn a_shape_in_the_middle() {
    same_as_the_whole_dispatch(
        "middle",
        &format!(
            "{CAMERA}render {{ antialias: 2, shadows: soft(8), ao: ao(), background: [0.3, 0.5, 0.7] }}\n\
             scene = sphere(1) | box([0.5, 0.5, 0.5]).translate([1.2, 0, 0]);\n"
        ),
    );
}

#[test]
fn a_shape_at_each_edge() {
    // Touching the left edge, the background's tile is on the right, and so on.
    for (name, at) in [
        ("left", "[-5.2, 0, 0]"),
        ("right", "[5.2, 0, 0]"),
        ("top", "[0, 3.9, 0]"),
        ("bottom", "[0, -4.4, 0]"),
    ] {
        same_as_the_whole_dispatch(
            name,
            &format!("{CAMERA}scene = sphere(1.2).translate({at});\n"),
        );
    }
}

#[test]
fn reflections_between_shapes() {
    same_as_the_whole_dispatch(
        "reflections",
        &format!(
            "{CAMERA}material mirror {{ color: [0.8, 0.8, 0.8], reflectivity: 0.6 }}\n\
             render {{ reflections: 2, fog: fog(0.05, [0.6, 0.7, 0.8]) }}\n\
             scene = sphere(1).material(mirror) | sphere(0.6).translate([1.5, 0.2, 0.5]);\n"
        ),
    );
}

#[test]
fn a_union_read_as_data() {
    // The suite's 300-shape grid, read as data by default, from its own camera (the grid
    // covers a few tiles).
    same_as_the_whole_dispatch("grid", &sdfc_tests::grid_scene(300));
}

#[test]
fn the_interpreter_too() {
    same_both_ways(
        "interpreted",
        &format!(
            "{CAMERA}render {{ shadows: soft(8) }}\n\
             scene = sphere(1).translate([-3, 0, 0]) | torus(0.8, 0.2).translate([2, 1, 0]);\n"
        ),
        true,
    );
}
