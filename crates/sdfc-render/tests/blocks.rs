//! The blocks' pass of a union read as data (`shaders/instances_blocks.wgsl`): each camera
//! ray's list, made from its 4x4 block's candidates, draws the frame the walk of the whole
//! hierarchy draws, bit for bit (colour, depth, normal, steps), for cameras near the origin
//! and 1e5 from it, looking down and along the rows, with antialiasing and reflections
//! (whose rays walk), with and without AOVs (the slots' place in the buffer), at a size of
//! partial tiles with the scene off the image's first tiles; and the frame reads what the
//! pass wrote (with every block's count written as 0, the frame changes), in every case.

mod common;

use common::{compile_as_data, hits, renderer};
use sdfc_render::{Frame, RenderOptions, Renderer};

/// 12 x 9 = 108 of the frame's 8x8 tiles: enough for the renderer to run the pass (it skips
/// frames of fewer than 64 tiles), where the scene fills the view.
const W: u32 = 96;
const H: u32 = 72;

/// The generated grid of `n` shapes seen from `camera` (position, target), the whole scene
/// moved by `offset` along x with its camera, with `render` settings.
fn grid(n: usize, camera: ([f64; 3], [f64; 3]), offset: f64, render: &str) -> String {
    let src = sdfc_tests::grid_scene(n);
    let far = "camera { position: [0, 20, 60], target: [0, 0, 0]";
    assert!(src.contains(far), "the generated grid's camera has changed");
    let ((p, t), o) = (camera, offset);
    let camera = format!(
        "camera {{ position: [{}, {}, {}], target: [{}, {}, {}]",
        p[0] + o,
        p[1],
        p[2],
        t[0] + o,
        t[1],
        t[2]
    );
    format!(
        "{}render {{ {render} }}\n",
        src.replace(far, &camera)
            .replace("scene = union(", "scene = translate(union(")
            .replace("\n);\n", &format!("\n), [{o}, 0, 0]);\n"))
    )
}

fn data(name: &str, src: &str) -> sdfc_wgsl::Compiled {
    let c = compile_as_data(name, src);
    assert!(
        c.wgsl.contains("fn blocks_main("),
        "{name}: no blocks' pass"
    );
    c
}

/// The image: its size, and whether the AOVs are written (the blocks' slots come after them).
#[derive(Clone, Copy)]
struct Image {
    w: u32,
    h: u32,
    aovs: bool,
}

const WITH_AOVS: Image = Image {
    w: W,
    h: H,
    aovs: true,
};

fn frame(r: &Renderer, c: &sdfc_wgsl::Compiled, wgsl: &str, image: Image) -> Frame {
    let opts = RenderOptions {
        aovs: image.aovs,
        ..RenderOptions::sized(image.w, image.h)
    };
    r.render_wgsl_with_data(c.program(), wgsl, &c.data, &opts)
        .expect("renders")
}

/// The shader's text without its blocks' pass: the renderer finds no `blocks_main` and
/// leaves bit 1 of `frame.flags` clear, so every ray walks.
fn without_pass(wgsl: &str) -> String {
    wgsl.replace("fn blocks_main(", "fn blocks_unused(")
}

/// The shader's text with every block's count written as 0: camera rays that take their
/// block's candidates list nothing and miss.
fn emptied(wgsl: &str) -> String {
    let written = "    aov_out[slot].x = f32(count);";
    assert_eq!(wgsl.matches(written).count(), 1);
    wgsl.replace(written, "    aov_out[slot].x = 0.0;")
}

/// How many pixels of `a` and `b` differ in colour or in any AOV's bits.
fn differing(a: &Frame, b: &Frame) -> usize {
    let n = (a.width * a.height) as usize;
    (0..n)
        .filter(|&i| {
            let aovs_differ = match (a.aovs.as_ref(), b.aovs.as_ref()) {
                (Some(fa), Some(fb)) => {
                    fa.depth[i].to_bits() != fb.depth[i].to_bits()
                        || fa.steps[i] != fb.steps[i]
                        || (0..3).any(|k| fa.normal[i][k].to_bits() != fb.normal[i][k].to_bits())
                }
                _ => false,
            };
            a.rgba[4 * i..4 * i + 4] != b.rgba[4 * i..4 * i + 4] || aovs_differ
        })
        .count()
}

fn check(name: &str, src: &str) {
    check_at(name, src, WITH_AOVS);
}

/// The frame with the pass is the walk's, bit for bit, and changes where the pass's counts
/// are emptied (so the pass ran and the frame read it).
fn check_at(name: &str, src: &str, image: Image) {
    let Some(r) = renderer() else { return };
    let c = data(name, src);
    let with = frame(r, &c, &c.wgsl, image);
    let without = frame(r, &c, &without_pass(&c.wgsl), image);
    if image.aovs {
        let (hits, n) = (hits(&with), (image.w * image.h) as usize);
        assert!(
            hits > n / 4 && hits < n,
            "{name}: the grid fills too little or all of the view ({hits} hits)"
        );
    }
    assert_eq!(
        differing(&with, &without),
        0,
        "{name}: the blocks' lists changed the frame"
    );
    let empty = frame(r, &c, &emptied(&c.wgsl), image);
    assert!(
        differing(&with, &empty) > 0,
        "{name}: the pass did not run, or the frame did not read it"
    );
}

#[test]
fn close_by_the_same_frame_as_the_walk() {
    check(
        "close by",
        &grid(120, ([-1.0, 4.0, 6.0], [-2.0, 1.5, -2.0]), 0.0, ""),
    );
}

#[test]
fn close_by_far_from_the_origin_the_same_frame_as_the_walk() {
    check(
        "1e5 out",
        &grid(120, ([-1.0, 4.0, 6.0], [-2.0, 1.5, -2.0]), 1e5, ""),
    );
}

#[test]
fn looking_down_with_antialiasing_the_same_frame_as_the_walk() {
    let src = grid(
        300,
        ([-2.0, 14.0, 2.0], [-2.5, 0.0, -3.0]),
        0.0,
        "antialias: 2",
    );
    check("down, antialiased", &src);
}

#[test]
fn along_the_rows_with_reflections_the_same_frame_as_the_walk() {
    // Rays along a row pass more boxes than a block's slot holds (its rays walk), and the
    // blue tori's reflections march rays that walk.
    let src = grid(
        300,
        ([-12.0, 0.5, 0.3], [3.0, 0.2, -0.2]),
        0.0,
        "reflections: 1",
    );
    check("along the rows", &src);
}

/// The frame reads the pass's candidates: with every block's count written as 0 the camera
/// rays list nothing and miss, where the walk hits.
#[test]
fn the_frame_reads_the_candidates() {
    let Some(r) = renderer() else { return };
    let src = grid(120, ([-1.0, 4.0, 6.0], [-2.0, 1.5, -2.0]), 0.0, "");
    let c = data("emptied", &src);
    assert!(hits(&frame(r, &c, &c.wgsl, WITH_AOVS)) > (W * H) as usize / 4);
    assert_eq!(hits(&frame(r, &c, &emptied(&c.wgsl), WITH_AOVS)), 0);
}

/// No AOVs (the slots right after the buffer's 32 bytes), an image of partial tiles and
/// blocks (101x77), and the grid in the image's lower right, off its first tiles: the tiles
/// dispatched, and the blocks' pass's, start past the first (`frame.flags`).
#[test]
fn without_aovs_at_an_odd_size_off_the_first_tiles_the_same_frame_as_the_walk() {
    let src = grid(120, ([-9.0, 9.0, 9.0], [-4.0, 4.0, -2.0]), 0.0, "");
    let odd = Image {
        w: 101,
        h: 77,
        aovs: false,
    };
    check_at("odd size, no AOVs", &src, odd);
    let Some(r) = renderer() else { return };
    let c = data("odd size", &src);
    let f = frame(r, &c, &c.wgsl, Image { aovs: true, ..odd });
    let depth = &f.aovs.as_ref().unwrap().depth;
    let corner = (0..16).all(|y| (0..16).all(|x| depth[y * 101 + x].is_infinite()));
    assert!(corner, "the grid reaches the image's first tiles");
}
