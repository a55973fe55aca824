//! The renderer's API: pipeline caching, errors instead of panics (rejected shaders, sizes,
//! params), and the float writers.

mod common;

use common::{compile, hits, renderer};
use sdfc_render::output::{self, npy_bytes};
use sdfc_render::{AovKind, Frame, RenderError, RenderOptions, Renderer};

const PARAM_SCENE: &str = "param r = 0.8;\nparam c = [0, 0, 0];\n\
                           scene = sphere(r).translate(c + [0.1 * time, 0, 0]);\n";

#[test]
fn pipelines_are_compiled_once_per_shader_text() {
    // A renderer of its own: the shared one is compiling other tests' shaders concurrently.
    if renderer().is_none() {
        return;
    }
    let r = Renderer::new().unwrap();
    let a = compile("a", PARAM_SCENE);
    let b = compile("b", "scene = box(1);");
    assert_eq!(r.pipeline_compilations(), 0);
    r.render(&a, &RenderOptions::sized(16, 16)).unwrap();
    assert_eq!(r.pipeline_compilations(), 1);
    // Another size, time, param values, AOVs: the same pipeline.
    r.render(
        &a,
        &RenderOptions {
            width: 24,
            height: 8,
            time: 2.0,
            params: vec![("r".into(), vec![0.5]), ("c".into(), vec![0.1, 0.2, 0.3])],
            aovs: true,
            all_pixels: false,
        },
    )
    .unwrap();
    assert_eq!(r.pipeline_compilations(), 1);
    // The same text compiled again (a new `Compiled`) hits the cache too.
    let a2 = compile("a2", PARAM_SCENE);
    r.render(&a2, &RenderOptions::sized(8, 8)).unwrap();
    assert_eq!(r.pipeline_compilations(), 1);
    r.render(&b, &RenderOptions::sized(8, 8)).unwrap();
    assert_eq!(r.pipeline_compilations(), 2);
    // The evaluation shader is a pipeline of its own, also cached.
    r.eval_gpu(a.program(), &[[0.0; 3]], 0.0, &[]).unwrap();
    r.eval_gpu(a.program(), &[[1.0; 3]], 1.0, &[("r".into(), vec![2.0])])
        .unwrap();
    assert_eq!(r.pipeline_compilations(), 3);
}

#[test]
fn a_rejected_shader_is_an_error_not_a_panic() {
    let Some(r) = renderer() else { return };
    let good = compile("good", "scene = sphere(1);");
    // Not WGSL at all.
    let e = r
        .render_wgsl(
            good.program(),
            "this is not wgsl",
            &RenderOptions::sized(8, 8),
        )
        .unwrap_err();
    eprintln!("rejected: {e}");
    assert!(matches!(e, RenderError::Shader(_)), "{e:?}");
    // Valid WGSL that does not follow the interface (a binding the layout lacks).
    let wrong = "@group(0) @binding(5) var<storage, read_write> x: array<u32>;\n\
                 @compute @workgroup_size(8, 8, 1)\n\
                 fn main(@builtin(global_invocation_id) g: vec3<u32>) { x[g.x] = 1u; }\n";
    let e = r
        .render_wgsl(good.program(), wrong, &RenderOptions::sized(8, 8))
        .unwrap_err();
    eprintln!("rejected: {e}");
    assert!(matches!(e, RenderError::Shader(_)), "{e:?}");
    // No entry point `main`.
    let e = r
        .render_wgsl(
            good.program(),
            "@compute @workgroup_size(1) fn other() {}\n",
            &RenderOptions::sized(8, 8),
        )
        .unwrap_err();
    eprintln!("rejected: {e}");
    assert!(matches!(e, RenderError::Shader(_)), "{e:?}");
    // The device still works afterwards.
    let frame = r.render(&good, &RenderOptions::sized(8, 8)).unwrap();
    assert_eq!(frame.rgba.len(), 8 * 8 * 4);
}

#[test]
fn image_sizes_are_checked_against_the_device() {
    let Some(r) = renderer() else { return };
    let c = compile("sphere", "scene = sphere(1);");
    for (w, h) in [(0, 10), (10, 0)] {
        let e = r.render(&c, &RenderOptions::sized(w, h)).unwrap_err();
        assert!(matches!(e, RenderError::ImageSize(_)), "{e:?}");
    }
    // Far beyond any buffer or dispatch limit: an error at once, no attempt.
    let e = r
        .render(&c, &RenderOptions::sized(1_000_000, 1_000_000))
        .unwrap_err();
    assert!(matches!(e, RenderError::ImageSize(_)), "{e:?}");
    assert!(e.to_string().contains("too large") || e.to_string().contains("MiB"));
    // A size whose AOV buffer (32 bytes a pixel) is beyond the limit.
    let side = ((r.max_buffer_bytes() / 32) as f64).sqrt() as u32 + 8;
    let e = r
        .render(
            &c,
            &RenderOptions {
                aovs: true,
                ..RenderOptions::sized(side, side)
            },
        )
        .unwrap_err();
    assert!(
        matches!(&e, RenderError::ImageSize(m) if m.contains("AOVs")),
        "{e:?}"
    );
}

#[test]
fn bad_params_and_time_are_input_errors() {
    let Some(r) = renderer() else { return };
    let c = compile("params", PARAM_SCENE);
    let bad: Vec<(RenderOptions, &str)> = vec![
        (
            RenderOptions {
                params: vec![("radius".into(), vec![1.0])],
                ..RenderOptions::sized(8, 8)
            },
            "no param `radius`",
        ),
        (
            RenderOptions {
                params: vec![("c".into(), vec![1.0, 2.0])],
                ..RenderOptions::sized(8, 8)
            },
            "takes 3",
        ),
        (
            RenderOptions {
                params: vec![("r".into(), vec![f32::NAN])],
                ..RenderOptions::sized(8, 8)
            },
            "finite",
        ),
        (
            RenderOptions {
                params: vec![("c".into(), vec![1e20, 0.0, 0.0])],
                ..RenderOptions::sized(8, 8)
            },
            "at most 1e12 in magnitude",
        ),
        (
            RenderOptions {
                time: f32::INFINITY,
                ..RenderOptions::sized(8, 8)
            },
            "time",
        ),
    ];
    for (opts, what) in bad {
        let e = r.render(&c, &opts).unwrap_err();
        assert!(e.is_input_error(), "{e:?}");
        assert!(
            e.to_string().contains(what),
            "`{e}` should mention `{what}`"
        );
        let e = r
            .eval_gpu(c.program(), &[[0.0; 3]], opts.time, &opts.params)
            .unwrap_err();
        assert!(e.is_input_error(), "{e:?}");
    }
}

#[test]
fn eval_gpu_of_no_points_is_empty() {
    let Some(r) = renderer() else { return };
    let c = compile("sphere", "scene = sphere(1);");
    assert!(r.eval_gpu(c.program(), &[], 0.0, &[]).unwrap().is_empty());
}

#[test]
fn aovs_of_a_sphere_seen_head_on() {
    let Some(r) = renderer() else { return };
    // Default camera at z = 5 looking at the origin; odd size so the centre pixel's ray is
    // the axis.
    let c = compile("sphere", "scene = sphere(1);");
    let frame = r
        .render(
            &c,
            &RenderOptions {
                aovs: true,
                ..RenderOptions::sized(33, 25)
            },
        )
        .unwrap();
    let aovs = frame.aovs.as_ref().unwrap();
    let centre = 12 * 33 + 16;
    assert!(
        (aovs.depth[centre] - 4.0).abs() < 1e-5,
        "{}",
        aovs.depth[centre]
    );
    let n = aovs.normal[centre];
    assert!(
        (n[2] - 1.0).abs() < 1e-4 && n[0].abs() < 1e-3 && n[1].abs() < 1e-3,
        "{n:?}"
    );
    assert_eq!(aovs.depth[0], f32::INFINITY);
    assert_eq!(aovs.normal[0], [0.0; 3]);
    assert!(aovs.steps[centre] >= 1.0);
    // The corner's ray misses the sphere's bounds: no step (`ray_span`).
    assert_eq!(aovs.steps[0], 0.0);
    assert!(aovs.mean_steps() > 0.0);
    // The colour without AOVs is the same picture.
    let plain = r.render(&c, &RenderOptions::sized(33, 25)).unwrap();
    assert!(plain.aovs.is_none());
    assert_eq!(plain.rgba, frame.rgba);
}

fn temp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("sdfc-render-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Parses the `.npy` files `npy_bytes` writes: (shape, values).
fn parse_npy(bytes: &[u8]) -> (Vec<usize>, Vec<f32>) {
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    assert_eq!((10 + len) % 64, 0, "the header is not padded to 64 bytes");
    let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
    assert!(header.ends_with('\n'));
    assert!(header.contains("'descr': '<f4'"), "{header}");
    assert!(header.contains("'fortran_order': False"), "{header}");
    let shape_text = header
        .split("'shape': (")
        .nth(1)
        .unwrap()
        .split(')')
        .next()
        .unwrap();
    let shape: Vec<usize> = shape_text
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().unwrap())
        .collect();
    let data: Vec<f32> = bytes[10 + len..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    assert_eq!(shape.iter().product::<usize>(), data.len());
    (shape, data)
}

#[test]
fn npy_layout() {
    let (shape, data) = parse_npy(&npy_bytes(
        &[2, 3],
        &[1.0, 2.0, 3.0, 4.0, f32::INFINITY, -0.0],
    ));
    assert_eq!(shape, vec![2, 3]);
    assert_eq!(data[4], f32::INFINITY);
    assert_eq!(data[5].to_bits(), (-0.0f32).to_bits());
    let (shape, _) = parse_npy(&npy_bytes(&[4], &[0.0; 4]));
    assert_eq!(shape, vec![4]);
}

fn synthetic_frame() -> Frame {
    let (w, h) = (5u32, 3u32);
    let n = (w * h) as usize;
    let depth: Vec<f32> = (0..n)
        .map(|i| {
            if i.is_multiple_of(4) {
                f32::INFINITY
            } else {
                1.0 + i as f32 / 7.0
            }
        })
        .collect();
    let normal: Vec<[f32; 3]> = (0..n)
        .map(|i| {
            if i.is_multiple_of(4) {
                [0.0; 3]
            } else {
                let a = i as f32;
                [a.sin() * 0.6, a.cos() * 0.6, 0.8]
            }
        })
        .collect();
    Frame {
        width: w,
        height: h,
        rgba: vec![200; 4 * n],
        aovs: Some(sdfc_render::Aovs {
            depth,
            normal,
            steps: (0..n).map(|i| (i * 3 + 1) as f32).collect(),
        }),
        device_time: None,
        wall_time: Default::default(),
    }
}

#[test]
fn aovs_round_trip_bit_for_bit_through_npy_and_exr() {
    let frame = synthetic_frame();
    let (w, h) = (frame.width as usize, frame.height as usize);
    for kind in [AovKind::Depth, AovKind::Normal, AovKind::Steps] {
        let values = kind.values(&frame).unwrap();
        let npy = temp(&format!("{kind:?}.npy"));
        output::write_aov(&npy, &frame, kind).unwrap();
        let (shape, data) = parse_npy(&std::fs::read(&npy).unwrap());
        let expect_shape = if kind == AovKind::Normal {
            vec![h, w, 3]
        } else {
            vec![h, w]
        };
        assert_eq!(shape, expect_shape);
        assert_eq!(bits(&data), bits(&values), "{kind:?} through npy");

        let exr_path = temp(&format!("{kind:?}.exr"));
        output::write_aov(&exr_path, &frame, kind).unwrap();
        let image = exr::prelude::read_first_flat_layer_from_file(&exr_path).unwrap();
        let layer = &image.layer_data;
        assert_eq!((layer.size.0, layer.size.1), (w, h));
        let channel = |name: &str| -> Vec<f32> {
            let c = layer
                .channel_data
                .list
                .iter()
                .find(|c| c.name.to_string() == name)
                .unwrap_or_else(|| panic!("no channel {name}"));
            match &c.sample_data {
                exr::prelude::FlatSamples::F32(v) => v.clone(),
                other => panic!("channel {name} is not f32: {other:?}"),
            }
        };
        let read: Vec<f32> = match kind {
            AovKind::Depth => channel("Z"),
            AovKind::Steps => channel("Y"),
            AovKind::Normal => {
                let (r, g, b) = (channel("R"), channel("G"), channel("B"));
                (0..w * h).flat_map(|i| [r[i], g[i], b[i]]).collect()
            }
        };
        assert_eq!(bits(&read), bits(&values), "{kind:?} through exr");
    }
    // A frame without AOVs, and a file name that is not a float format.
    let plain = Frame {
        aovs: None,
        ..synthetic_frame()
    };
    assert_eq!(
        output::write_aov(temp("x.npy"), &plain, AovKind::Depth).unwrap_err(),
        RenderError::NoAovs
    );
    assert!(matches!(
        output::write_aov(temp("x.png"), &frame, AovKind::Depth).unwrap_err(),
        RenderError::Output { .. }
    ));
    // PNG: read back as written.
    let png = temp("c.png");
    output::write_png(&png, &frame).unwrap();
    let back = image::open(&png).unwrap().to_rgba8();
    assert_eq!(back.as_raw(), &frame.rgba);
    // An unwritable place is an error, not a panic.
    assert!(matches!(
        output::write_png(temp("no/such/dir/c.png"), &frame).unwrap_err(),
        RenderError::Output { .. }
    ));
}

/// The AOVs are the pixel centre's ray whatever the antialiasing: with an odd `antialias` the
/// centre is one of the samples (its colour sample is reused), with an even one it is marched
/// as an extra sample that adds no colour. Depth, normal and steps are the same bits as
/// without antialiasing, and asking for AOVs leaves the colour as it is.
#[test]
fn aovs_are_the_centre_ray_at_every_antialias_setting() {
    let Some(r) = renderer() else { return };
    let scene = |aa: u32| {
        format!(
            "render {{ antialias: {aa} }}\n\
             scene = union(sphere(1), box([0.6, 0.6, 0.6]).translate([1.2, 0.4, 0]));\n"
        )
    };
    let size = RenderOptions::sized(24, 18);
    let with_aovs = RenderOptions {
        aovs: true,
        ..size.clone()
    };
    let one = r.render(&compile("aa1", &scene(1)), &with_aovs).unwrap();
    let one = one.aovs.unwrap();
    assert!(one.depth.iter().any(|d| d.is_finite()));
    for aa in [2, 3] {
        let c = compile("aa", &scene(aa));
        let frame = r.render(&c, &with_aovs).unwrap();
        let aovs = frame.aovs.as_ref().unwrap();
        assert_eq!(bits(&aovs.depth), bits(&one.depth), "antialias {aa}");
        assert_eq!(bits(&aovs.steps), bits(&one.steps), "antialias {aa}");
        let normals = |a: &sdfc_render::Aovs| bits(&a.normal.concat());
        assert_eq!(normals(aovs), normals(&one), "antialias {aa}");
        let plain = r.render(&c, &size).unwrap();
        assert_eq!(plain.rgba, frame.rgba, "antialias {aa}");
    }
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|f| f.to_bits()).collect()
}

/// Threads sharing one renderer each get their own, complete results (one thread's poll may
/// run another's read-back callbacks).
#[test]
fn threads_share_one_renderer() {
    let Some(r) = renderer() else { return };
    let c = compile("params", PARAM_SCENE);
    let opts = |i: usize| RenderOptions {
        params: vec![("r".into(), vec![0.3 + 0.1 * i as f32])],
        aovs: i.is_multiple_of(2),
        ..RenderOptions::sized(24, 16)
    };
    let expected: Vec<Vec<u8>> = (0..8)
        .map(|i| r.render(&c, &opts(i)).unwrap().rgba)
        .collect();
    std::thread::scope(|s| {
        for (i, want) in expected.iter().enumerate() {
            let c = &c;
            s.spawn(move || {
                for _ in 0..12 {
                    let f = r.render(c, &opts(i)).unwrap();
                    assert_eq!(&f.rgba, want, "thread {i}");
                    let d = r
                        .eval_gpu(c.program(), &[[0.0; 3]], 0.0, &opts(i).params)
                        .unwrap();
                    assert!((d[0] + 0.3 + 0.1 * i as f32).abs() < 1e-6);
                }
            });
        }
    });
}

#[test]
fn frame_pixels_outside_the_image_are_none() {
    let f = synthetic_frame();
    assert_eq!(f.pixel(0, 0), Some([200; 4]));
    assert_eq!(f.pixel(4, 2), Some([200; 4]));
    // Column 5 of a 5-wide frame used to read row 1's first pixel; row 3 used to panic.
    assert_eq!(f.pixel(5, 0), None);
    assert_eq!(f.pixel(0, 3), None);
    assert_eq!(f.pixel(u32::MAX, u32::MAX), None);
    let mut short = synthetic_frame();
    short.rgba.truncate(8);
    assert_eq!(short.pixel(2, 0), None);
}

#[test]
fn a_frame_whose_fields_disagree_is_not_written() {
    let mut f = synthetic_frame();
    f.width = 10;
    let path = temp("mismatch.png");
    let e = output::write_png(&path, &f).unwrap_err();
    assert!(
        matches!(&e, RenderError::Output { message, .. } if message.contains("do not match")),
        "{e}"
    );
    assert!(!path.exists());
    // The frame as rendered is written.
    output::write_png(&path, &synthetic_frame()).unwrap();
    assert!(std::fs::metadata(&path).unwrap().len() > 0);
}

#[test]
fn the_library_form_is_refused_before_any_work() {
    let Some(r) = renderer() else { return };
    let lib = sdfc_render::sdfc_wgsl::compile(
        "scene = sphere(1);",
        &sdfc_render::sdfc_wgsl::Options {
            lib: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(lib.is_library());
    let before = r.pipeline_compilations();
    let e = r.render(&lib, &RenderOptions::sized(8, 8)).unwrap_err();
    assert_eq!(e, RenderError::LibraryForm);
    assert!(e.is_input_error());
    assert!(e.to_string().contains("without `lib`"), "{e}");
    assert_eq!(r.pipeline_compilations(), before);
}

#[test]
fn forgotten_scene_pipelines_are_built_again() {
    if renderer().is_none() {
        return;
    }
    let r = Renderer::new().unwrap();
    let a = compile("forget", "scene = sphere(1);");
    r.render(&a, &RenderOptions::sized(8, 8)).unwrap();
    r.render(&a, &RenderOptions::sized(8, 8)).unwrap();
    assert_eq!(r.pipeline_compilations(), 1);
    r.forget_scene_pipelines();
    r.render(&a, &RenderOptions::sized(8, 8)).unwrap();
    assert_eq!(r.pipeline_compilations(), 2);
}

/// The experiments' hook (`render_wgsl_with_data`, used by `compare_shader` for
/// `scripts/bvh-experiment.py`): the bytes given are what the shader reads at binding 3.
#[test]
fn a_shader_reads_the_data_given_at_binding_3() {
    let Some(r) = renderer() else { return };
    let opts = RenderOptions {
        aovs: true,
        ..RenderOptions::sized(32, 24)
    };
    let own = |radius: f32| {
        let c = compile("sphere", &format!("scene = sphere({radius:?});"));
        r.render(&c, &opts).unwrap()
    };
    let base = compile("sphere", "scene = sphere(1.0);");
    // The sphere's radius read from the data instead of written in the code.
    let from_data = base
        .wgsl
        .replace(
            "let d0 = sd_sphere(p, 1.0);",
            "let d0 = sd_sphere(p, bitcast<f32>(scene_data[0]));",
        )
        .replace(
            "fn scene_distance(",
            "@group(0) @binding(3) var<storage, read> scene_data: array<u32>;\n\nfn scene_distance(",
        );
    assert_ne!(
        from_data, base.wgsl,
        "the sphere's shader has changed: update the test"
    );
    for radius in [1.0f32, 0.5] {
        let frame = r
            .render_wgsl_with_data(base.program(), &from_data, &radius.to_le_bytes(), &opts)
            .unwrap();
        let expected = own(radius);
        assert!(hits(&frame) > 0);
        assert_eq!(hits(&frame), hits(&expected), "radius {radius}");
        assert_eq!(frame.rgba, expected.rgba, "radius {radius}");
    }
}
