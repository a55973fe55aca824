//! A union emitted as data (`sdfc_wgsl::Options::instances`, `sdfc render --instances`, and
//! the interpreter's walk, `encode_as_data`): the same picture as the union emitted as code,
//! against the f64 reference as well, near the origin and 1e5 away from it (the
//! camera-relative frame); a mixed union (instances and other children) too.

mod common;

use common::against_reference::{frame_metrics, parted};
use common::{compile, compile_as_data, compile_with, renderer};
use sdfc_reference::metrics::Metrics;
use sdfc_render::{Frame, RenderOptions, Renderer};
use sdfc_wgsl::interp::encode_instances::encode_as_data;
use sdfc_wgsl::Options;

/// The generated grid of `n` shapes (spheres, turned boxes, turned tori, three materials)
/// seen from close by, every ray among the shapes, moved by `offset` with its camera.
fn close_grid(n: usize, offset: f64) -> String {
    let src = sdfc_tests::grid_scene(n);
    let far = "camera { position: [0, 20, 60], target: [0, 0, 0]";
    assert!(src.contains(far), "the generated grid's camera has changed");
    let close = src.replace(
        far,
        &format!(
            "camera {{ position: [{}, 4, 6], target: [{}, 1.5, -2]",
            offset - 1.0,
            offset - 2.0
        ),
    );
    close
        .replace("scene = union(", "scene = translate(union(")
        .replace("\n);\n", &format!("\n), [{offset}, 0, 0]);\n"))
}

const W: u32 = 64;
const H: u32 = 48;

/// Which shader draws a frame.
enum Form<'a> {
    Specialised(&'a sdfc_wgsl::Compiled),
    /// The interpreter, the union's walk as bytecode (`encode_as_data`).
    Interpreted(&'a sdfc_ir::Program),
}

/// A frame with AOVs and its metrics against `reference`.
fn against(r: &Renderer, form: Form, reference: &sdfc_reference::Image) -> (Frame, Metrics) {
    let opts = RenderOptions {
        aovs: true,
        ..RenderOptions::sized(W, H)
    };
    let frame = match form {
        Form::Specialised(c) => r.render(c, &opts),
        Form::Interpreted(p) => {
            let code = encode_as_data(p).expect("a union of instances").unwrap();
            r.render_bytecode(p, &code, &opts)
        }
    };
    let frame = frame.expect("renders");
    let m = frame_metrics(&frame, reference);
    (frame, m)
}

/// The data form (the specialised shader's, then the interpreter's) against the code form
/// and all against the f64 reference, at 64x48: the same hits and depths, and no larger
/// error than the code's.
fn check(name: &str, src: &str) {
    check_allowing(name, src, 2);
}

/// [`check`], with `edges` pixels where the two forms may take different surfaces (hit and
/// miss, or depths apart) with the data form's farther from the reference's: the marcher's
/// path decides at a grazing edge, and the two forms' paths differ where their bounds do.
/// The data form's error against the reference must still be no larger than the code's.
fn check_allowing(name: &str, src: &str, edges: usize) {
    check_colours(name, src, edges, 3 * 8);
}

/// [`check_allowing`], with at most `channels` colour channels more than 2 levels apart
/// from the code's.
fn check_colours(name: &str, src: &str, edges: usize, channels: usize) {
    let Some(r) = renderer() else { return };
    // The union as code at any size (by default one of `AUTO_INSTANCES` or more is data).
    let code = compile_with(
        name,
        src,
        &Options {
            instances: sdfc_wgsl::Instances::Never,
            ..Options::default()
        },
    );
    let reference = sdfc_reference::render(code.program(), &sdfc_reference::Options::sized(W, H));
    let data = compile_as_data(name, src);
    let (code_frame, c) = against(r, Form::Specialised(&code), &reference);
    let (data_frame, d) = against(r, Form::Specialised(&data), &reference);
    check_against(
        name,
        (&data_frame, &d),
        (&code_frame, &c),
        &reference,
        (edges, channels),
    );
    if data.wgsl.contains("fn rest_distance(") {
        // A mixed union: the interpreter walks only unions of instances alone.
        assert!(encode_as_data(code.program()).is_none(), "{name}");
        return;
    }
    let interpreted = against(r, Form::Interpreted(code.program()), &reference);
    let name = format!("{name}, interpreted");
    check_against(
        &name,
        (&interpreted.0, &interpreted.1),
        (&code_frame, &c),
        &reference,
        (edges, channels),
    );
}

/// The data form's frame and metrics `d` against the code form's `c`, with `edges` pixels
/// and `channels` colour channels allowed to part.
fn check_against(
    name: &str,
    (data_frame, d): (&Frame, &Metrics),
    (code_frame, c): (&Frame, &Metrics),
    reference: &sdfc_reference::Image,
    (edges, channels): (usize, usize),
) {
    eprintln!(
        "{name}: hits {}/{} and {}/{}, mismatches {}+{} and {}+{}, depth p99.9 {:.2e} and {:.2e}, \
         normal median {:.3} and {:.3} deg, PSNR {:.1} and {:.1} dB, steps {:.1} and {:.1}",
        d.both_hit,
        d.reference_hits,
        c.both_hit,
        c.reference_hits,
        d.mismatch_interior,
        d.mismatch_silhouette,
        c.mismatch_interior,
        c.mismatch_silhouette,
        d.depth_p999,
        c.depth_p999,
        d.normal_median_deg,
        c.normal_median_deg,
        d.psnr_db,
        c.psnr_db,
        d.mean_steps_gpu,
        c.mean_steps_gpu
    );
    let colours = data_frame
        .rgba
        .iter()
        .zip(&code_frame.rgba)
        .filter(|(a, b)| a.abs_diff(**b) > 2)
        .count();
    eprintln!("{name}: {colours} channels differ from the code's");
    assert!(
        d.reference_hits > (W * H / 3) as usize,
        "{name}: the grid fills the view"
    );
    assert_eq!(d.nonfinite, 0);
    assert_eq!(
        d.mismatch_interior, 0,
        "{name}: interior hit/miss mismatches"
    );
    assert!(
        d.mismatch_silhouette <= c.mismatch_silhouette + 2,
        "{name}: silhouettes"
    );
    assert!(
        d.depth_median <= 1e-6,
        "{name}: depth median {:e}",
        d.depth_median
    );
    assert!(d.normal_median_deg <= 0.1, "{name}: normals");
    // No farther from the reference than the code.
    assert!(d.psnr_db >= c.psnr_db - 0.5, "{name}: colour error");
    assert!(
        d.depth_p999 <= 1.5 * c.depth_p999 + 1e-6,
        "{name}: depth p99.9 {:e} against {:e}",
        d.depth_p999,
        c.depth_p999
    );
    // The two shaders' own pictures: where their hits or depths part (the marcher's path
    // decides at a grazing edge, and the two forms' paths differ where their bounds do), the
    // data form's pixel is no farther from the reference's than the code's, but on `edges`
    // pixels.
    let (da, ca) = (
        data_frame.aovs.as_ref().unwrap(),
        code_frame.aovs.as_ref().unwrap(),
    );
    let (parted, worse) = parted(&da.depth, &ca.depth, reference);
    eprintln!(
        "{name}: {parted} pixels part from the code's, {worse} of them farther from the reference"
    );
    assert!(
        worse <= edges,
        "{name}: {worse} of {parted} pixels that part from the code's are farther from the reference"
    );
    assert!(colours <= channels, "{name}: {colours} channels differ");
}

#[test]
fn a_grid_of_120_shapes_as_data_draws_as_code_does() {
    check("grid_120", &close_grid(120, 0.0));
}

#[test]
fn a_grid_far_from_the_origin_as_data_draws_as_code_does() {
    check("grid_120 at 1e5", &close_grid(120, 1e5));
}

/// The grid with a floor and a shell among its shapes: a mixed union, whose other children
/// stay code (`rest_distance`), marched first alone (`march_rest`), near the origin and 1e5
/// from it.
fn mixed_grid(offset: f64) -> String {
    let src = close_grid(120, offset);
    let head = "scene = translate(union(\n";
    assert!(src.contains(head));
    src.replace(
        head,
        &format!(
            "{head}    plane([0, 1, 0], 0.8).material(green),\n    \
             sphere(0.6).onion(0.05).translate([-2, 2.5, 1]),\n"
        ),
    )
}

#[test]
fn a_mixed_union_as_data_draws_as_code_does() {
    for (name, offset) in [("mixed grid_120", 0.0), ("mixed grid_120 at 1e5", 1e5)] {
        let src = mixed_grid(offset);
        let c = compile_as_data(name, &src);
        assert!(c.wgsl.contains("fn rest_distance("), "{name}: not mixed");
        check(name, &src);
    }
}

/// The mixed grid under every shading feature the ray lists meet: the relaxed marcher,
/// reflections (a march, and a list, per bounce), hard shadows (a list per shadow ray) and
/// ambient occlusion (a list per shaded point). Soft shadows:
/// `shadow_rays_through_the_lists`; ambient occlusion further:
/// `ambient_occlusion_through_its_list`.
#[test]
fn a_mixed_union_as_data_draws_with_every_shading_feature() {
    let src = mixed_grid(0.0).replace(
        "scene = translate(",
        "render { relaxation: 1.6, reflections: 2, shadows: hard, \
         ao: ao(samples: 4, step: 0.08, strength: 1.0, falloff: 0.7) }\nscene = translate(",
    );
    let c = compile_as_data("shaded", &src);
    assert!(c.wgsl.contains("fn rest_distance(") && c.wgsl.contains("fn march_rest("));
    // Four edges: the relaxed marcher's path (docs/performance.md, "Relaxation") parts the
    // two forms on 3 pixels at 64x48, one of them farther from the reference in the data
    // form, whose picture is nearer it (PSNR 37.8 against 36.3 dB, the same hits).
    check_allowing("mixed grid_120, shaded", &src, 4);
}

/// The grid with a Menger sponge among its shapes, in front of some and behind others: the
/// other child is dear, so its march alone refines in its stepping loop, and the
/// instances' marches stop at its hit. With central normals, whose samples go through the
/// ray's list and the other child at the march's end (`normal_nearest`), where the
/// tetrahedron's take what the march hit alone.
#[test]
fn a_mixed_union_with_a_fractal_and_central_normals() {
    let head = "scene = translate(union(\n";
    let src = close_grid(120, 0.0).replace(
        head,
        &format!("render {{ normals: central }}\n{head}    menger(3).scale(2.5).translate([-2.2, 1.6, -0.6]),\n"),
    );
    assert!(src.contains("menger(3)"));
    let c = compile_as_data("fractal", &src);
    assert!(c.wgsl.contains("fn march_rest(") && !c.wgsl.contains("fn refine("));
    check("mixed grid_120 with a sponge", &src);
}

/// A block of spheres 4 wide, 4 high and 40 deep, seen along its depth from just in front:
/// rays between the rows pass more boxes than a ray's list holds (`RAY_LIST`, 32), so their
/// lists fill: the march of instances alone lists them again from the first node left out
/// (`ray_resume`); the interpreter walks the whole hierarchy at every step.
#[test]
fn rays_past_more_instances_than_a_list_holds() {
    let mut src = String::from(
        "camera { position: [1.7, 1.6, 3], target: [1.4, 1.4, -40], fov: 60deg }\nscene = union(\n",
    );
    for i in 0..640 {
        let (x, y, z) = (i % 4, (i / 4) % 4, i / 16);
        src += &format!("    sphere(0.3).translate([{x}, {y}, -{z}]),\n");
    }
    src += ");\n";
    // Rays along the rows graze sphere after sphere: at 64x48 the union's march over the
    // lists parted from the code on 9 such pixels (the walk on 2), 3 of them farther from the
    // reference (false hits of both, at other depths). Each instance marched alone parts on
    // 1, no farther from the reference, and the interpreter on 1 too.
    check_allowing("a block of 640 spheres", &src, 2);
}

/// 48 spheres about one point, each moved by a few hundredths: every ray through the crowd
/// meets more padded boxes within a margin of one t than a list holds (`RAY_LIST`, 32). The
/// march of instances alone lists it again from the first node left out (`ray_resume`),
/// each of the 48 marched alone with its own budget of steps (with one for the ray, 15
/// silhouette pixels ran out and missed). Listing again at the cut instead cannot take a
/// ray through such a crowd (docs/performance.md, stop 35). The interpreter walks the whole
/// hierarchy at every step.
#[test]
fn a_crowd_of_more_instances_than_a_list_holds() {
    check("a crowd of 48 spheres", &crowd(""));
}

/// The same crowd with central differences for normals: their samples at the march's end
/// go through the ray's list (`ray_nearest`), and the march of instances alone lists a ray
/// through the crowd twice (`ray_resume`), so the last list does not hold the instances of
/// the first; those samples then walk, and the normals match the code's.
#[test]
fn a_crowd_with_central_normals() {
    check(
        "a crowd of 48 spheres, central normals",
        &crowd("render { normals: central }\n"),
    );
}

/// Shadow rays through a union read as data list the instances their padded boxes hold
/// (`shaders/shading/shadow_instances.wgsl`) and march each alone: hard and soft, on the
/// grid, on the mixed grid (the other children's shadow first, `shadow_rest`), and through
/// the crowd, where a shadow ray's list fills and it lists again from the first node left
/// out; and with a point light among the shapes (each stretch ends at the light) beside a
/// directional one. The soft shadow's samples are each instance's own, not the union's, so
/// its penumbras may part from the code's by a few levels; the check bounds how many
/// channels and that the data form is no farther from the reference. (With the point
/// light and `soft(8)`, 89 channels parted, PSNR against the reference 49.2 dB against the
/// code's 49.4: the penumbras' sampling, which hard shadows do not have.)
#[test]
fn shadow_rays_through_the_lists() {
    let grid = close_grid(120, 0.0);
    let head = "scene = translate(";
    assert!(grid.contains(head));
    let mixed = mixed_grid(0.0);
    let point = grid.replacen(
        head,
        "light point { position: [-1.5, 3.2, -1.0], color: [1, 1, 1], intensity: 1.5 }\n\
         light directional { direction: [0.3, -1, -0.4], color: [0.6, 0.6, 0.7], intensity: 0.6 }\n\
         scene = translate(",
        1,
    );
    for (name, src, render) in [
        ("grid_120, hard shadows", &grid, "shadows: hard"),
        (
            "grid_120, two lights, one among the shapes, hard shadows",
            &point,
            "shadows: hard",
        ),
        ("grid_120, soft shadows", &grid, "shadows: soft(16)"),
        ("mixed grid_120, soft shadows", &mixed, "shadows: soft(8)"),
    ] {
        let src = src.replacen(head, &format!("render {{ {render} }}\n{head}"), 1);
        let c = compile_as_data(name, &src);
        assert!(
            c.wgsl
                .contains("ray_start(ro, rd, 0.0, tmax, 0.0, SHADOW_REACH, start);"),
            "{name}: the shadow rays' lists"
        );
        assert_eq!(
            c.wgsl.contains("fn shadow_rest("),
            name.starts_with("mixed"),
            "{name}"
        );
        check(name, &src);
    }
    for render in ["shadows: hard", "shadows: soft(16)"] {
        check(
            &format!("a crowd of 48 spheres, {render}"),
            &crowd(&format!("render {{ {render} }}\n")),
        );
    }
    // soft(2): no padding of a list pays (`SOFT_MOST` in sdfc-wgsl's shadows.rs), so each
    // step walks the hierarchy, and takes a far box's distance for its instances' only where
    // that cannot lower the light. With the box's distance wherever the point was beyond its
    // reach, the penumbrae darkened: 1371 channels parted from the code at 160x120 on the
    // 300-shape grid on a floor, PSNR against the reference 44.2 dB against 45.4.
    for (name, src) in [
        ("grid_120, soft(2) through the walk", &grid),
        ("mixed grid_120, soft(2) through the walk", &mixed),
    ] {
        let src = src.replacen(head, &format!("render {{ shadows: soft(2) }}\n{head}"), 1);
        let c = compile_as_data(name, &src);
        assert!(
            c.wgsl.contains("light * t / SHADOW_K).distance, t)")
                && !c.wgsl.contains("SHADOW_REACH"),
            "{name}: the walk"
        );
        check(name, &src);
    }
}

/// Ambient occlusion of a union read as data: samples that reach no farther than 0.8 of the
/// instances' spacing go through one list along the normal
/// (`shaders/shading/ambient_occlusion_list.wgsl`), higher ones through the walk
/// (`occlusion.rs` in sdfc-wgsl). Through the list on the mixed grid (the other children
/// bound each sample first), and on a cluster of small spheres on a slab, whose lists fill,
/// so that samples past the cut walk (without that walk 645 channels parted); through the
/// walk on the grid. Colours keep to the code's, but on two pixels' worth of channels (on
/// the cluster one pixel where the code's march takes another surface than the data's and
/// the reference's). The walk at every sample that both replaced took a far box's distance
/// for its instances' (a bound, where ambient occlusion needs the distance up to the
/// sample's height): it parted from the code on 23 channels on the mixed grid here with
/// `ao(samples: 8, step: 0.3)`, on 54 at 160x120 on the 300-shape grid on a floor, and the
/// interpreter's walk on 55 on the grid here (`occlusion_distance`).
#[test]
fn ambient_occlusion_through_its_list() {
    let head = "scene = translate(";
    // 48 small spheres in a lattice 0.12 apart on a slab: every sample near them has more
    // boxes within its reach than a list holds. A row of spheres 2 apart, far behind the
    // camera, sets the spacing (the median of neighbours').
    let mut cluster = String::from(
        "render { ao: ao(samples: 6, step: 0.1) }\n\
         camera { position: [0.9, 0.8, 1.1], target: [0, 0.05, 0], fov: 50deg }\n\
         scene = union(\n    box([1.5, 0.1, 1.5]).translate([0, -0.1, 0]),\n",
    );
    for i in 0..48 {
        let (x, y, z) = (i % 4, (i / 4) % 3, i / 12);
        let at = |k: usize| 0.12 * k as f64 - 0.18;
        cluster += &format!(
            "    sphere(0.06).translate([{:.2}, {:.2}, {:.2}]),\n",
            at(x),
            0.06 + 0.12 * y as f64,
            at(z)
        );
    }
    for i in 0..100 {
        cluster += &format!("    sphere(0.3).translate([{}, 0, 30]),\n", 2 * i - 100);
    }
    cluster += ");\n";
    for (name, src, listed) in [
        (
            "mixed grid_120, ambient occlusion through the list",
            mixed_grid(0.0).replacen(
                head,
                &format!("render {{ ao: ao(samples: 4, step: 0.25) }}\n{head}"),
                1,
            ),
            true,
        ),
        (
            "grid_120, ambient occlusion through the walk",
            close_grid(120, 0.0).replacen(
                head,
                &format!("render {{ ao: ao(samples: 8, step: 0.3, strength: 1.5) }}\n{head}"),
                1,
            ),
            false,
        ),
        (
            "a cluster of 48 spheres on a slab, ambient occlusion",
            cluster,
            true,
        ),
    ] {
        let c = compile_as_data(name, &src);
        let start = c
            .wgsl
            .find("fn ambient_occlusion(")
            .expect("ambient occlusion");
        let end = start + c.wgsl[start..].find("\n}\n").expect("its end");
        let ao = &c.wgsl[start..end];
        assert!(ao.contains("ao_below(p + n * h, h)"), "{name}");
        assert_eq!(
            ao.contains("    ao_list(p, n);\n"),
            listed,
            "{name}: the list"
        );
        assert_eq!(
            c.wgsl
                .contains("return scene_nearest(q, h, 3.0e38).distance;"),
            !listed,
            "{name}: the walk"
        );
        check_colours(name, &src, 2, 6);
    }
}

/// The crowd of 48 spheres, after `head` (render settings).
fn crowd(head: &str) -> String {
    let mut src = format!(
        "{head}camera {{ position: [0.3, 0.4, 1.6], target: [0, 0, 0], fov: 50deg }}\nscene = union(\n"
    );
    for i in 0..48 {
        let k = i as f64;
        let (x, y, z) = (
            0.03 * k.sin(),
            0.03 * (1.7 * k).cos(),
            0.03 * (2.3 * k).sin(),
        );
        let r = 0.5 + 0.01 * (i % 5) as f64;
        src += &format!("    sphere({r}).translate([{x:.4}, {y:.4}, {z:.4}]),\n");
    }
    src + "    box([0.3, 0.3, 0.3]).translate([1.2, -0.4, -0.5]),\n);\n"
}

/// The 300-shape grid from `compare_shader`'s close camera: at 64x48 one ray came within the
/// threshold of a torus, `refine`'s secant step took it to just in front of a box behind,
/// over that box's corner, and the pass that followed was taken from the last sample: a hole
/// (pixel 17, 2) where the code and the reference hit. Refinement now goes on from the start
/// of such a gap (`shaders/hit.wgsl`, `gap`).
#[test]
fn the_300_shape_grid_from_close_by_has_no_holes() {
    let src = sdfc_tests::grid_scene_close(300);
    check("grid_300 close", &src);
}

/// The same grid marched with relaxation: each instance's relaxed steps stop at the end of
/// its stretch, or at the nearest hit so far where that is nearer (`march_start`'s span in
/// `shaders/march_instances.wgsl`); a step past it could leave the instance's nearer surface
/// between two samples.
#[test]
fn the_300_shape_grid_relaxed() {
    let src = sdfc_tests::grid_scene_close(300) + "render { relaxation: 1.6 }\n";
    check("grid_300 close, relaxed", &src);
}

/// The option changes nothing where the root is not a union of instances.
#[test]
fn a_scene_without_such_a_union_is_code() {
    let opts = Options {
        instances: sdfc_wgsl::Instances::Always,
        ..Options::default()
    };
    let src = "scene = sphere(1) | box([1, 1, 1]).translate([2, 0, 0]);";
    let c = sdfc_wgsl::compile(src, &opts).unwrap();
    assert!(c.data.is_empty());
    assert_eq!(c.wgsl, compile("plain", src).wgsl);
    let Some(r) = renderer() else { return };
    r.render(&c, &RenderOptions::sized(8, 8)).unwrap();
}
