//! A union of many shapes in three materials, whose material the WGSL picks by index
//! (`sdfc_wgsl::material_index`), renders with the f64 reference's colours: 64x48 from a
//! camera near the grid, so each shape covers many pixels. Bound: no pixel both call a hit
//! differs by more than 8/255 in any channel away from silhouettes (a wrong material is
//! tens to hundreds off), and the mean colour difference is under 1/255.

mod common;

use common::against_reference::{render_against_reference, Compared};
use common::{compile_with, renderer};
use sdfc_reference::metrics::is_silhouette;

const W: u32 = 64;
const H: u32 = 48;

#[test]
fn a_150_shape_union_picks_its_materials_by_index() {
    let name = "grid_scene(150)";
    let Some(r) = renderer() else { return };
    let source = sdfc_tests::grid_scene(150).replace(
        "camera { position: [0, 20, 60], target: [0, 0, 0], fov: 50deg }",
        "camera { position: [-5, 5, 6], target: [-4, 1.5, -3], fov: 60deg }",
    );
    // The union as code: by default a union this large is read as data
    // (`sdfc_wgsl::AUTO_INSTANCES`), whose materials come from its records instead.
    let code = sdfc_wgsl::Options {
        instances: sdfc_wgsl::Instances::Never,
        ..sdfc_wgsl::Options::default()
    };
    let compiled = compile_with(name, &source, &code);
    assert!(
        compiled.wgsl.contains("let k0 = select("),
        "{name}: the material is no longer picked by index; pick a scene where it is"
    );
    let Compared {
        frame,
        reference,
        metrics: m,
    } = render_against_reference(r, name, &compiled, W, H);
    let mut worst = 0u8;
    let mut hits = 0;
    for y in 0..H {
        for x in 0..W {
            let rp = reference.pixel(x, y);
            let i = ((y * W + x) * 4) as usize;
            let gpu_hit = frame.aovs.as_ref().unwrap().depth[(y * W + x) as usize].is_finite();
            if !rp.hit || !gpu_hit || is_silhouette(&reference, x, y) {
                continue;
            }
            hits += 1;
            for c in 0..3 {
                worst = worst.max(frame.rgba[i + c].abs_diff(rp.rgba[c]));
            }
        }
    }
    eprintln!(
        "{name}: {hits} interior hit pixels, worst channel difference {worst}/255, mean colour difference {:.3}/255",
        m.colour_mae
    );
    assert!(hits > 300, "{name}: only {hits} interior hit pixels");
    assert!(worst <= 8, "{name}: a pixel's colour is {worst}/255 off");
    assert!(
        m.colour_mae < 1.0,
        "{name}: mean colour difference {}",
        m.colour_mae
    );
}
