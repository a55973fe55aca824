//! Dispatching only the tiles whose rays can meet the scene's bounds (`sdfc_wgsl::screen`,
//! the render crate's `tiles`): the frame must be the whole dispatch's to the bit (colour,
//! depth, normal, steps), wherever the scene sits on the image, with antialiasing,
//! reflections, shadows and ambient occlusion, relaxation, far from the origin, for an image
//! of no whole tiles, for a union read as data, under the horizon of a floor's half-space,
//! and from the interpreter, which dispatches the same way.

mod common;

use common::{compile, renderer};
use sdfc_render::{Frame, RenderOptions};

const SIZE: (u32, u32) = (64, 48);

fn frame(
    r: &sdfc_render::Renderer,
    c: &sdfc_wgsl::Compiled,
    (w, h): (u32, u32),
    all_pixels: bool,
    interpreted: bool,
) -> Frame {
    let opts = RenderOptions {
        aovs: true,
        all_pixels,
        ..RenderOptions::sized(w, h)
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
    same_both_ways(name, source, SIZE, false);
}

fn same_both_ways(name: &str, source: &str, (w, h): (u32, u32), interpreted: bool) {
    let Some(r) = renderer() else {
        return;
    };
    let c = compile(name, source);
    let rect = sdfc_wgsl::screen::screen_rect(c.program(), w, h).expect("a rectangle");
    let tiles_in = |a: u32, b: u32| b.div_ceil(8).saturating_sub(a / 8);
    let covered = tiles_in(rect[0], rect[2]) * tiles_in(rect[1], rect[3]);
    let all_tiles = w.div_ceil(8) * h.div_ceil(8);
    assert!(
        covered < all_tiles - 1,
        "{name}: the rectangle {rect:?} covers the image"
    );
    let some = frame(r, &c, (w, h), false, interpreted);
    let all = frame(r, &c, (w, h), true, interpreted);
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
    // The background's tiles are taken from the left of the rectangle where there is room,
    // else from its right, else above, else below: a sphere touching the left edge, then
    // one touching the right, then bars across the whole width (at the top, so the tiles
    // come from below; lower down, from above).
    for (name, scene) in [
        ("left", "sphere(1.2).translate([-5.2, 0, 0])"),
        ("right", "sphere(1.2).translate([5.2, 0, 0])"),
        ("top", "box([9, 0.4, 0.5]).translate([0, 3.9, 0])"),
        ("bottom", "box([9, 0.4, 0.5]).translate([0, -3.2, 0])"),
    ] {
        same_as_the_whole_dispatch(name, &format!("{CAMERA}scene = {scene};\n"));
    }
}

#[test]
fn an_image_of_no_whole_tiles_far_from_the_origin_with_relaxation() {
    // 61x45 (the last column and row of tiles lie partly outside the image), the scene 1e5
    // from the origin (camera-relative coordinates in the shader), relaxed steps.
    same_both_ways(
        "far",
        "camera { position: [100000, 1, 10], target: [100000, 0, 0], fov: 50deg }\n\
         render { relaxation: 1.6 }\n\
         scene = sphere(1).translate([100000, 0, 0]) | torus(1, 0.2).translate([100003, 0, 0]);\n",
        (61, 45),
        false,
    );
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
        SIZE,
        true,
    );
}

#[test]
fn below_a_floors_horizon_both_ways() {
    // A floor's half-space bounds the scene above (y <= 1.2): looking level from above it,
    // the sky's tiles are left out, with fog (a miss is the background however far the ray
    // went), shadows and a reflective floor.
    let source = "camera { position: [0, 2, 8], target: [0, 1.6, 0], fov: 50deg }\n\
                  material mirror { color: [0.6, 0.6, 0.6], reflectivity: 0.4 }\n\
                  render { shadows: soft(8), reflections: 1, fog: fog(0.05, [0.7, 0.78, 0.88]) }\n\
                  scene = plane([0, 1, 0], 0).material(mirror) | sphere(1).translate([0, 0.2, 0]);\n";
    same_both_ways("floor", source, SIZE, false);
    same_both_ways("floor interpreted", source, SIZE, true);
}
