//! End-to-end tests of `sdfc render` and `sdfc eval --gpu` (CLI contract, `shared/spec/cli.md`).
//! They need a wgpu adapter (a GPU, or Mesa's software Vulkan): without one they are skipped
//! with a printed reason, except on CI (`CI=true`), where they fail.

mod common;

use common::{eval_lines, s, sdfc_env, sdfc_in, Run, TempDir};
use std::path::Path;
use std::sync::OnceLock;

const SPHERE: &str = "scene = sphere(1);\n";
const PARAM_SPHERE: &str = "param r = 1;\nparam c = [0, 0, 0];\nscene = sphere(r).translate(c);\n";
const MOVING: &str = "scene = sphere(1).translate([time, 0, 0]);\n";
const BROKEN: &str = "let r = 1;\nscene = spher(r);\n";

/// Whether `sdfc render` finds a device here. Without one: skip (printing why), or fail on CI.
fn have_device() -> bool {
    static AVAILABLE: OnceLock<Result<(), String>> = OnceLock::new();
    let r = AVAILABLE.get_or_init(|| {
        let t = TempDir::new("probe");
        let scene = t.write("s.sdf", SPHERE);
        let out = t.path("s.png");
        let run = sdfc_in(&t.0, &["render", s(&scene), "-o", s(&out), "--size", "8x8"]);
        match run.code {
            0 => Ok(()),
            _ if run.stderr.contains("no usable graphics adapter") => Err(run.stderr),
            _ => panic!("`sdfc render` of a sphere failed:\n{}", run.describe()),
        }
    });
    match r {
        Ok(()) => true,
        Err(e) if std::env::var("CI").is_ok_and(|v| v == "true" || v == "1") => {
            panic!("no wgpu adapter on CI (install mesa-vulkan-drivers): {e}")
        }
        Err(e) => {
            // Once, on the real stderr (libtest captures `eprintln!` of passing tests).
            static ONCE: std::sync::Once = std::sync::Once::new();
            ONCE.call_once(|| {
                use std::io::Write;
                let _ = writeln!(
                    std::io::stderr(),
                    "SKIPPED: render tests need a wgpu adapter, and this machine has none: {e}"
                );
            });
            false
        }
    }
}

/// Runs `sdfc render SCENE -o OUT` in `t` with each group of further options.
fn render_in(t: &TempDir, scene: &Path, out: &Path, options: &[&[&str]]) -> Run {
    let mut args = vec!["render", s(scene), "-o", s(out)];
    for group in options {
        args.extend(group.iter().copied());
    }
    sdfc_in(&t.0, &args)
}

/// The options of [`sphere_rendered_plainly`]'s render: a small odd size, a param set.
const SPHERE_OPTIONS: &[&str] = &["--size", "33x25", "--param", "r=1.5"];

/// A directory holding [`PARAM_SPHERE`] as `s.sdf` and its specialised render with
/// [`SPHERE_OPTIONS`] as `plain.png`: what the other ways of rendering are compared with.
fn sphere_rendered_plainly(name: &str) -> (TempDir, std::path::PathBuf, std::path::PathBuf) {
    let t = TempDir::new(name);
    let scene = t.write("s.sdf", PARAM_SPHERE);
    let plain = t.path("plain.png");
    render_in(&t, &scene, &plain, &[SPHERE_OPTIONS]).expect_code(0);
    (t, scene, plain)
}

fn read_png(path: &Path) -> image::RgbaImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
}

/// (shape, values) of a little-endian f4 `.npy` file.
fn read_npy(path: &Path) -> (Vec<usize>, Vec<f32>) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(&bytes[..6], b"\x93NUMPY", "not a .npy file");
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
    assert!(header.contains("'descr': '<f4'"), "{header}");
    let shape: Vec<usize> = header
        .split("'shape': (")
        .nth(1)
        .and_then(|t| t.split(')').next())
        .unwrap()
        .split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap())
        .collect();
    let data: Vec<f32> = bytes[10 + len..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    assert_eq!(shape.iter().product::<usize>(), data.len());
    (shape, data)
}

/// One channel of an OpenEXR file: (width, height, values).
fn read_exr_channel(path: &Path, name: &str) -> (usize, usize, Vec<f32>) {
    let image = exr::prelude::read_first_flat_layer_from_file(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let layer = &image.layer_data;
    let channel = layer
        .channel_data
        .list
        .iter()
        .find(|c| c.name.to_string() == name)
        .unwrap_or_else(|| panic!("{}: no channel {name}", path.display()));
    let values = match &channel.sample_data {
        exr::prelude::FlatSamples::F32(v) => v.clone(),
        other => panic!("channel {name} is not f32: {other:?}"),
    };
    (layer.size.0, layer.size.1, values)
}

// ---- usage (no device needed) ----

#[test]
fn missing_output_is_a_usage_error() {
    let t = TempDir::new("no-o");
    let scene = t.write("s.sdf", SPHERE);
    let run = sdfc_in(&t.0, &["render", s(&scene)]).expect_code(2);
    assert!(run.stderr.contains("-o"), "{}", run.describe());
}

#[test]
fn bad_options_are_usage_errors() {
    let t = TempDir::new("usage");
    let scene = t.write("s.sdf", SPHERE);
    let png = t.path("o.png");
    for args in [
        vec!["--size", "64"],
        vec!["--size", "0x10"],
        vec!["--size", "axb"],
        vec!["--aov", "colour"],
        vec!["--param", "r"],
    ] {
        let mut all = vec!["render", s(&scene), "-o", s(&png)];
        all.extend(args.iter().copied());
        sdfc_in(&t.0, &all).expect_code(2);
    }
    // The output's extension must fit: PNG for colour, EXR/NPY for an AOV.
    let run = sdfc_in(&t.0, &["render", s(&scene), "-o", s(&t.path("o.jpg"))]).expect_code(2);
    assert!(run.stderr.contains(".png"), "{}", run.describe());
    let run = sdfc_in(
        &t.0,
        &["render", s(&scene), "-o", s(&png), "--aov", "depth"],
    )
    .expect_code(2);
    assert!(run.stderr.contains(".exr"), "{}", run.describe());
    assert!(!png.exists());
}

#[test]
fn interpreted_renders_the_same_picture() {
    if !have_device() {
        return;
    }
    let (t, scene, plain) = sphere_rendered_plainly("interp");
    let (interp, depth, size) = (t.path("interp.png"), t.path("depth.npy"), SPHERE_OPTIONS);
    render_in(&t, &scene, &interp, &[size, &["--interpreted"]]).expect_code(0);
    let (a, b) = (read_png(&plain), read_png(&interp));
    assert_eq!(a.dimensions(), (33, 25));
    assert_eq!(b.dimensions(), (33, 25));
    let diff: u64 = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(x, y)| x.abs_diff(*y) as u64)
        .sum();
    let mean = diff as f64 / a.as_raw().len() as f64;
    assert!(mean < 1.0, "mean colour difference {mean}/255");
    // The AOVs too: the camera axis meets the sphere of radius 1.5 at t = 3.5.
    render_in(
        &t,
        &scene,
        &depth,
        &[size, &["--interpreted", "--aov", "depth"]],
    )
    .expect_code(0);
    let (shape, d) = read_npy(&depth);
    assert_eq!(shape, vec![25, 33]);
    let centre = 12 * 33 + 16;
    assert!((d[centre] - 3.5).abs() < 1e-5, "{}", d[centre]);
    assert_eq!(d[0], f32::INFINITY, "a miss is inf");
}

#[test]
fn interpreted_reports_input_errors_as_the_specialised_path() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("interp_err");
    let scene = t.write("s.sdf", PARAM_SPHERE);
    let broken = t.write("b.sdf", BROKEN);
    let out = t.path("o.png");
    let run = sdfc_in(
        &t.0,
        &[
            "render",
            s(&scene),
            "-o",
            s(&out),
            "--interpreted",
            "--param",
            "nope=1",
        ],
    )
    .expect_code(1);
    assert!(run.stderr.contains("nope"), "{}", run.describe());
    let run = sdfc_in(
        &t.0,
        &["render", s(&broken), "-o", s(&out), "--interpreted"],
    )
    .expect_code(1);
    assert!(run.stderr.contains("sphere"), "{}", run.describe());
    // A scene beyond the interpreter's register file: an input error with the way out.
    // Terms used by a sum and then by a product: all live at once (see sdfc-wgsl's tests).
    let terms: Vec<String> = (0..72).map(|i| format!("sin(p.x * {}.5)", i + 1)).collect();
    let expr = format!("({}) + ({})", terms.join(" + "), terms.join(" * "));
    let big = t.write(
        "big.sdf",
        format!("scene = sdf(|p| length(p) - 1 + 0.001 * ({expr}), lipschitz: 2);\n"),
    );
    let run = sdfc_in(
        &t.0,
        &[
            "render",
            s(&big),
            "-o",
            s(&out),
            "--interpreted",
            "--size",
            "8x8",
        ],
    )
    .expect_code(1);
    assert!(
        run.stderr.contains("without --interpreted"),
        "{}",
        run.describe()
    );
    assert!(!run.stderr.contains("panicked"), "{}", run.describe());
}

#[test]
fn a_bad_backend_choice_is_an_environment_error() {
    let t = TempDir::new("backend");
    let scene = t.write("s.sdf", SPHERE);
    let run = sdfc_env(
        &t.0,
        &[
            "render",
            s(&scene),
            "-o",
            s(&t.path("o.png")),
            "--size",
            "8x8",
        ],
        &[("SDFC_BACKEND", "metal")],
    )
    .expect_code(2);
    assert!(run.stderr.contains("SDFC_BACKEND"), "{}", run.describe());
}

/// No adapter at all: Vulkan asked for, and the Vulkan loader pointed at a driver list that
/// does not exist. Exit status 2 with the reason, never a panic or a hang.
#[test]
fn no_adapter_is_an_environment_error() {
    let t = TempDir::new("no-adapter");
    let scene = t.write("s.sdf", SPHERE);
    let none = t.path("no-such-icd.json");
    let run = sdfc_env(
        &t.0,
        &[
            "render",
            s(&scene),
            "-o",
            s(&t.path("o.png")),
            "--size",
            "8x8",
        ],
        &[
            ("SDFC_BACKEND", "vulkan"),
            ("VK_ICD_FILENAMES", s(&none)),
            ("VK_DRIVER_FILES", s(&none)),
        ],
    )
    .expect_code(2);
    assert!(
        run.stderr.contains("no usable graphics adapter"),
        "{}",
        run.describe()
    );
    assert!(!t.path("o.png").exists());
}

#[test]
fn broken_scene_and_unknown_param_are_input_errors() {
    let t = TempDir::new("input");
    let broken = t.write("b.sdf", BROKEN);
    let out = t.path("o.png");
    let run = sdfc_in(&t.0, &["render", s(&broken), "-o", s(&out)]).expect_code(1);
    assert!(
        run.stderr.contains("unknown function `spher`"),
        "{}",
        run.describe()
    );
    assert!(run.stderr.contains("b.sdf:2:9"), "{}", run.describe());
    let scene = t.write("p.sdf", PARAM_SPHERE);
    let run = sdfc_in(
        &t.0,
        &["render", s(&scene), "-o", s(&out), "--param", "radius=2"],
    )
    .expect_code(1);
    assert!(run.stderr.contains("radius"), "{}", run.describe());
    sdfc_in(
        &t.0,
        &["render", s(&scene), "-o", s(&out), "--param", "c=1,2"],
    )
    .expect_code(1);
    assert!(!out.exists());
    sdfc_in(&t.0, &["render", s(&t.path("none.sdf")), "-o", s(&out)]).expect_code(2);
}

// ---- rendering ----

#[test]
fn render_writes_a_png_of_the_requested_size() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("png");
    let scene = t.write("s.sdf", SPHERE);
    let out = t.path("o.png");
    let run = sdfc_in(
        &t.0,
        &["render", s(&scene), "-o", s(&out), "--size", "40x30"],
    )
    .expect_code(0);
    assert!(run.stderr.contains("device:"), "{}", run.describe());
    let img = read_png(&out);
    assert_eq!((img.width(), img.height()), (40, 30));
    // The sphere in the middle, the black background in the corner.
    assert_ne!(img.get_pixel(20, 15).0[..3], [0, 0, 0]);
    assert_eq!(img.get_pixel(0, 0).0, [0, 0, 0, 255]);
    // The default size is 512x512.
    let out = t.path("default.png");
    sdfc_in(&t.0, &["render", s(&scene), "-o", s(&out)]).expect_code(0);
    let img = read_png(&out);
    assert_eq!((img.width(), img.height()), (512, 512));
}

#[test]
fn render_of_the_spec_scene() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("spec");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/spec_section10.sdf");
    let out = t.path("spec.png");
    sdfc_in(
        &t.0,
        &["render", s(&scene), "-o", s(&out), "--size", "48x32"],
    )
    .expect_code(0);
    assert_eq!(read_png(&out).dimensions(), (48, 32));
}

#[test]
fn params_and_time_change_the_picture() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("param");
    let scene = t.write("p.sdf", PARAM_SPHERE);
    let render = |name: &str, extra: &[&str]| {
        let out = t.path(name);
        let mut args = vec!["render", s(&scene), "-o", s(&out), "--size", "32x24"];
        args.extend_from_slice(extra);
        sdfc_in(&t.0, &args).expect_code(0);
        read_png(&out).into_raw()
    };
    let base = render("a.png", &[]);
    assert_eq!(
        base,
        render("b.png", &["--param", "r=1"]),
        "same value, same picture"
    );
    assert_ne!(base, render("c.png", &["--param", "r=0.5"]));
    assert_ne!(base, render("d.png", &["--param", "c=0.5,0,0"]));
    let moving = t.write("m.sdf", MOVING);
    let at = |time: &str| {
        let out = t.path(&format!("t{time}.png"));
        sdfc_in(
            &t.0,
            &[
                "render",
                s(&moving),
                "-o",
                s(&out),
                "--size",
                "32x24",
                "--time",
                time,
            ],
        )
        .expect_code(0);
        read_png(&out).into_raw()
    };
    assert_ne!(at("0"), at("0.5"));
}

#[test]
fn depth_aov_to_npy_and_exr() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("aov");
    let scene = t.write("s.sdf", SPHERE);
    // Odd size: the centre pixel's ray is the camera axis, which meets the sphere at t = 4.
    let (w, h) = (33usize, 25usize);
    let npy = t.path("depth.npy");
    let exr = t.path("depth.exr");
    for out in [&npy, &exr] {
        sdfc_in(
            &t.0,
            &[
                "render",
                s(&scene),
                "-o",
                s(out),
                "--size",
                "33x25",
                "--aov",
                "depth",
            ],
        )
        .expect_code(0);
    }
    let (shape, depth) = read_npy(&npy);
    assert_eq!(shape, vec![h, w]);
    let centre = (h / 2) * w + w / 2;
    assert!((depth[centre] - 4.0).abs() < 1e-5, "{}", depth[centre]);
    assert_eq!(depth[0], f32::INFINITY, "a miss is inf");
    assert!(depth.iter().all(|d| !d.is_nan()));
    let (ew, eh, exr_depth) = read_exr_channel(&exr, "Z");
    assert_eq!((ew, eh), (w, h));
    let bits = |v: &[f32]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
    assert_eq!(
        bits(&exr_depth),
        bits(&depth),
        "EXR and NPY hold the same floats"
    );
}

#[test]
fn normal_and_steps_aovs() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("aov2");
    let scene = t.write("s.sdf", SPHERE);
    let normal = t.path("n.npy");
    let steps = t.path("s.npy");
    let normal_exr = t.path("n.exr");
    for (out, kind) in [
        (&normal, "normal"),
        (&steps, "steps"),
        (&normal_exr, "normal"),
    ] {
        sdfc_in(
            &t.0,
            &[
                "render",
                s(&scene),
                "-o",
                s(out),
                "--size",
                "33x25",
                "--aov",
                kind,
            ],
        )
        .expect_code(0);
    }
    let (shape, n) = read_npy(&normal);
    assert_eq!(shape, vec![25, 33, 3]);
    let centre = 12 * 33 + 16;
    assert!(
        (n[3 * centre + 2] - 1.0).abs() < 1e-4,
        "{:?}",
        &n[3 * centre..3 * centre + 3]
    );
    assert_eq!(&n[..3], &[0.0, 0.0, 0.0], "a miss has a zero normal");
    let (_, _, z) = read_exr_channel(&normal_exr, "B");
    assert_eq!(z[centre].to_bits(), n[3 * centre + 2].to_bits());
    let (shape, st) = read_npy(&steps);
    assert_eq!(shape, vec![25, 33]);
    // Whole numbers; the centre's ray hits after at least one step (rays that miss the
    // scene's bounds take none).
    assert!(st.iter().all(|v| *v >= 0.0 && v.fract() == 0.0));
    assert!(st[centre] >= 1.0);
}

/// An output that cannot be written is refused before the device opens (the render used to
/// run in full first), for `render` and for `bench`'s pictures; needs no device.
#[test]
fn unwritable_output_is_an_environment_error_before_any_work() {
    let t = TempDir::new("unwritable");
    let scene = t.write("s.sdf", SPHERE);
    let missing = t.path("no/such/dir/o.png");
    let dir = t.path("a_dir.png");
    std::fs::create_dir(&dir).expect("a directory");
    let jpg = t.path("plot.jpg");
    for args in [
        vec!["render", s(&scene), "-o", s(&missing), "--size", "8x8"],
        vec!["render", s(&scene), "-o", s(&dir), "--size", "8x8"],
        vec!["bench", s(&scene), "--size", "8x8", "--plot", s(&missing)],
        vec!["bench", s(&scene), "--size", "8x8", "--heatmap", s(&dir)],
        vec!["bench", s(&scene), "--size", "8x8", "--plot", s(&jpg)],
    ] {
        let run = sdfc_in(&t.0, &args).expect_code(2);
        assert!(
            run.stderr.contains("cannot write") || run.stderr.contains("should end in .png"),
            "{args:?}: {}",
            run.describe()
        );
        assert!(
            !run.stderr.contains("device:"),
            "checked before the device opens: {}",
            run.describe()
        );
    }
    assert!(!jpg.exists());
}

/// On a machine without a desktop session (no `XDG_RUNTIME_DIR`), Mesa's device-select
/// layer made libwayland print "error: XDG_RUNTIME_DIR is invalid ..." twice on every device
/// run, as if it were sdfc's error; sdfc now switches the layer off there. (Where Mesa's layer
/// is not installed this passes without the fix too.)
#[test]
fn a_headless_machine_gets_no_wayland_noise() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("headless");
    let scene = t.write("s.sdf", SPHERE);
    let pts = t.write("p.csv", "2,0,0\n");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_sdfc"))
        .args(["eval", s(&scene), "--points", s(&pts), "--gpu"])
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("NODEVICE_SELECT")
        .output()
        .expect("sdfc runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("XDG_RUNTIME_DIR"), "{stderr}");
    assert!(stderr.contains("device:"), "{stderr}");
}

// ---- eval --gpu ----

#[test]
fn eval_gpu_agrees_with_the_reference() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("eval-gpu");
    let scene = t.write("p.sdf", PARAM_SPHERE);
    let pts = t.write(
        "pts.csv",
        "3,0,0\n0,0,0\n# comment\n\n1,1,1\n0.1,-2.5,0.7\n",
    );
    for extra in [vec![], vec!["--param", "r=0.5", "--param", "c=0.25,0,1"]] {
        let mut args = vec!["eval", s(&scene), "--points", s(&pts)];
        args.extend(extra.iter().copied());
        let cpu = eval_lines(&sdfc_in(&t.0, &args).expect_code(0));
        args.push("--gpu");
        let run = sdfc_in(&t.0, &args).expect_code(0);
        let gpu = eval_lines(&run);
        assert_eq!(gpu.len(), cpu.len(), "{}", run.describe());
        for (g, c) in gpu.iter().zip(&cpu) {
            assert!((g - c).abs() <= 1e-5 * c.abs() + 2e-6, "gpu {g} vs cpu {c}");
        }
        // Full f32 precision: each line reads back as the f32 it printed.
        for l in run.stdout.lines() {
            let v: f32 = l.parse().unwrap();
            assert_eq!(format!("{v:?}"), l);
        }
    }
    // The same errors as the CPU path.
    sdfc_in(
        &t.0,
        &[
            "eval",
            s(&scene),
            "--points",
            s(&pts),
            "--gpu",
            "--param",
            "q=1",
        ],
    )
    .expect_code(1);
}

/// The fallback a fresh machine has: software GL (llvmpipe) renders the same picture as the
/// default device, within the golden images' tolerance (3/255 per channel, at most 1% of
/// pixels beyond it).
#[test]
fn software_gl_renders_the_same_picture() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("gl");
    let scene = t.write("spec.sdf", SPEC_SCENE_FOR_GL);
    let (a, b) = (t.path("default.png"), t.path("gl.png"));
    sdfc_in(&t.0, &["render", s(&scene), "-o", s(&a), "--size", "64x48"]).expect_code(0);
    let run = sdfc_env(
        &t.0,
        &["render", s(&scene), "-o", s(&b), "--size", "64x48"],
        &[("SDFC_BACKEND", "gl")],
    );
    if run.code != 0 && std::env::var("CI").is_err() {
        eprintln!("SKIPPED: no software GL adapter here:\n{}", run.describe());
        return;
    }
    assert_eq!(run.code, 0, "{}", run.describe());
    assert!(run.stderr.contains("Gl"), "{}", run.describe());
    let (a, b) = (read_png(&a), read_png(&b));
    let off = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0.iter()).any(|(x, y)| x.abs_diff(*y) > 3))
        .count();
    assert!(
        off * 100 <= (64 * 48),
        "{off} pixels differ by more than 3/255"
    );
}

const SPEC_SCENE_FOR_GL: &str =
    "material red { color: [0.9, 0.2, 0.15], specular: 0.6, shininess: 48 }
camera { position: [0, 1.5, 5], target: [0, 0.5, 0], fov: 50deg }
light point { position: [4, 6, -3], intensity: 1.2 }
render { shadows: soft(16), ao: ao(), reflections: 1, background: [0.55, 0.7, 0.9] }
scene = union(sphere(1), box(1.4).rotate_y(30deg), smooth: 0.3).material(red).translate([0, 1, 0])
      | plane([0, 1, 0], 0);
";

// ---- comparison with the f64 reference ----

/// The value after `label` on a line of the plain comparison table.
fn table_value<'a>(stdout: &'a str, label: &str) -> &'a str {
    stdout
        .lines()
        .find(|l| l.trim_start().starts_with(label))
        .and_then(|l| l.trim_start()[label.len()..].split_whitespace().next())
        .unwrap_or_else(|| panic!("no `{label}` line in:\n{stdout}"))
}

#[test]
fn render_compare_prints_the_error_table_without_an_output_file() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("compare");
    let scene = t.write("s.sdf", SPHERE);
    let run = sdfc_in(&t.0, &["render", s(&scene), "--compare", "--size", "32x24"]).expect_code(0);
    assert_eq!(
        table_value(&run.stdout, "pixels"),
        "768",
        "{}",
        run.describe()
    );
    assert_eq!(table_value(&run.stdout, "NaN/Inf pixels in the AOVs"), "0");
    assert_eq!(
        table_value(&run.stdout, "hit/miss mismatches: interior"),
        "0"
    );
    // A unit sphere from the default camera: depth errors far below the surface threshold.
    let median: f64 = table_value(&run.stdout, "depth error, relative: median")
        .parse()
        .unwrap();
    assert!(median < 1e-4, "{}", run.stdout);
    // With -o the picture is written too; --markdown gives a header and one row.
    let out = t.path("o.png");
    let run = sdfc_in(
        &t.0,
        &[
            "render",
            s(&scene),
            "--compare",
            "--markdown",
            "--size",
            "16x12",
            "-o",
            s(&out),
        ],
    )
    .expect_code(0);
    assert_eq!(read_png(&out).width(), 16);
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert_eq!(lines.len(), 3, "{}", run.stdout);
    assert!(lines[0].starts_with("| scene | hits |"), "{}", run.stdout);
    assert!(lines[2].starts_with("| s | "), "{}", run.stdout);
}

#[test]
fn render_without_output_is_still_a_usage_error_without_compare() {
    let t = TempDir::new("compare-usage");
    let scene = t.write("s.sdf", SPHERE);
    sdfc_in(&t.0, &["render", s(&scene)]).expect_code(2);
    // --markdown only goes with --compare.
    sdfc_in(&t.0, &["render", s(&scene), "--markdown", "-o", "x.png"]).expect_code(2);
}

/// `sdfc bench`: the sweep's table (the scene's settings, the plain-marcher baseline, one
/// change at a time), a Pareto front, the step heat map at the image size, and the plot of
/// time against error.
#[test]
fn bench_prints_the_sweep_and_writes_a_heat_map_and_a_plot() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("bench");
    let scene = t.write(
        "s.sdf",
        "render { max_steps: 128 }\nscene = sphere(1) | plane([0, 1, 0], 1);\n",
    );
    let heat = t.path("steps.png");
    let plot = t.path("plot.png");
    let run = sdfc_in(
        &t.0,
        &[
            "bench",
            s(&scene),
            "--size",
            "16x12",
            "--runs",
            "1",
            "--heatmap",
            s(&heat),
            "--plot",
            s(&plot),
        ],
    );
    assert_eq!(run.code, 0, "{}", run.describe());
    let rows: Vec<&str> = run.stdout.lines().skip(2).collect();
    let names = [
        "scene's settings",
        "plain marcher",
        "max_steps: 64",
        "max_steps: 256",
        "epsilon: 1e-3",
        "relaxation: 1.6",
        "normals: central",
    ];
    for name in names {
        assert!(
            rows.iter().any(|r| r.contains(name)),
            "no row for {name}:\n{}",
            run.stdout
        );
    }
    // max_steps: 128 is the scene's own setting: not repeated.
    assert!(!run.stdout.contains("max_steps: 128"), "{}", run.stdout);
    assert!(
        rows.iter().any(|r| r.starts_with("* ")),
        "no setting on the Pareto front:\n{}",
        run.stdout
    );
    // Every row has its ten columns, with a finite time.
    for r in &rows {
        let cols: Vec<&str> = r.split("  ").filter(|c| !c.trim().is_empty()).collect();
        assert_eq!(cols.len(), 10, "{r}");
        let ms: f64 = cols[1].trim().parse().expect("time in ms");
        assert!(ms.is_finite() && ms > 0.0, "{r}");
    }
    let img = read_png(&heat);
    assert_eq!(img.dimensions(), (16, 12));
    // The plot: its fixed size, a white background, and something drawn on it.
    let plot = read_png(&plot);
    assert_eq!(plot.dimensions(), (1024, 640));
    let white = plot
        .pixels()
        .filter(|p| p.0[..3] == [255, 255, 255])
        .count();
    let total = (1024 * 640) as usize;
    assert!(
        white > total / 2 && white < total,
        "{white} white pixels of {total}"
    );
}

#[test]
fn bench_of_a_broken_scene_is_an_input_error() {
    let t = TempDir::new("bench_broken");
    let scene = t.write("s.sdf", BROKEN);
    let run = sdfc_in(&t.0, &["bench", s(&scene), "--size", "8x8"]);
    assert_eq!(run.code, 1, "{}", run.describe());
    assert!(run.stderr.contains("s.sdf:2:9"), "{}", run.stderr);
}

/// `--cull` renders a large union through its bounding-box hierarchy: the same hits, and
/// depths to 1e-4 relative (the culled field is exact near the surface), as without it; so
/// does the interpreted marcher with `--cull` (its bytecode jumps over the skipped parts).
#[test]
fn cull_renders_the_same_depths() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("cull");
    let mut src =
        String::from("camera { position: [0, 3, 5], target: [0, 0, -2] }\nscene = union(\n");
    for i in 0..24 {
        let (x, z) = ((i % 6) as f64 - 2.5, (i / 6) as f64 * -1.5);
        src += &format!("    sphere(0.5).translate([{x}, 0, {z}]),\n");
    }
    src += ");\n";
    let scene = t.write("u.sdf", &src);
    let (plain, culled, interp) = (
        t.path("plain.npy"),
        t.path("culled.npy"),
        t.path("interp.npy"),
    );
    for (out, extra) in [
        (&plain, &[][..]),
        (&culled, &["--cull"][..]),
        (&interp, &["--cull", "--interpreted"][..]),
    ] {
        let mut args = vec![
            "render",
            s(&scene),
            "-o",
            s(out),
            "--aov",
            "depth",
            "--size",
            "32x24",
        ];
        args.extend(extra);
        sdfc_in(&t.0, &args).expect_code(0);
    }
    let (_, a) = read_npy(&plain);
    for (name, path) in [("culled", &culled), ("interpreted culled", &interp)] {
        let hits = sdfc_tests::assert_same_depths(&a, &read_npy(path).1, 1e-4, name);
        assert!(hits > 50, "only {hits} hits");
    }
}

#[test]
fn live_writes_the_specialised_picture_and_says_when() {
    if !have_device() {
        return;
    }
    let (t, scene, plain) = sphere_rendered_plainly("live");
    let (live, depth, size) = (t.path("live.png"), t.path("depth.npy"), SPHERE_OPTIONS);
    // No grace: the interpreter's preview is drawn if it is ready before the scene's
    // pipeline (on a CPU device, only once warm, which a one-off render never is); either
    // way the file ends as the specialised picture.
    let live_options: &[&str] = &["--live", "--grace", "0", "--preview-scale", "4"];
    let run = render_in(&t, &scene, &live, &[size, live_options]).expect_code(0);
    assert!(
        run.stderr.contains("final frame (specialised) after"),
        "{}",
        run.describe()
    );
    assert!(
        run.stderr.contains("preview (interpreted, 9x7 enlarged)")
            || run
                .stderr
                .contains("no preview: the specialised pipeline was ready before")
            || run
                .stderr
                .contains("no preview: on a CPU device the interpreter draws"),
        "{}",
        run.describe()
    );
    assert_eq!(read_png(&live), read_png(&plain));
    // No file is left beside the output.
    let left: Vec<_> = std::fs::read_dir(&t.0)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("sdfc-live"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    // An AOV, with the grace left to the device: the camera axis meets the sphere at 3.5.
    render_in(&t, &scene, &depth, &[size, &["--live", "--aov", "depth"]]).expect_code(0);
    let (shape, d) = read_npy(&depth);
    assert_eq!(shape, vec![25, 33]);
    assert!((d[12 * 33 + 16] - 3.5).abs() < 1e-5, "{}", d[12 * 33 + 16]);
}

#[test]
fn live_reports_mistakes_as_render_does() {
    let t = TempDir::new("live-errors");
    let broken = t.write("b.sdf", BROKEN);
    let scene = t.write("s.sdf", SPHERE);
    let out = t.path("o.png");
    let run = sdfc_in(&t.0, &["render", s(&broken), "-o", s(&out), "--live"]).expect_code(1);
    assert!(run.stderr.contains("b.sdf:2:9"), "{}", run.describe());
    assert!(!run.stderr.contains("device:"), "{}", run.describe());
    for args in [
        vec!["--live", "--interpreted"],
        vec!["--grace", "10"],
        vec!["--live", "--preview-scale", "0"],
        vec!["--live", "--compare"],
        vec!["--watch"],
    ] {
        let mut all = vec!["render", s(&scene), "-o", s(&out)];
        all.extend(args.iter().copied());
        sdfc_in(&t.0, &all).expect_code(2);
    }
    assert!(!out.exists());
    if have_device() {
        let run = sdfc_in(
            &t.0,
            &[
                "render",
                s(&scene),
                "-o",
                s(&out),
                "--live",
                "--param",
                "r=1",
            ],
        )
        .expect_code(1);
        assert!(run.stderr.contains("no param `r`"), "{}", run.describe());
        // An output that cannot be written: an environment error naming it, nothing left.
        let missing = t.path("missing").join("o.png");
        let run = render_in(&t, &scene, &missing, &[&["--live", "--size", "8x8"]]).expect_code(2);
        assert!(run.stderr.contains("o.png"), "{}", run.describe());
        assert!(!run.stderr.contains(".sdfc-live"), "{}", run.describe());
    }
}

/// A `sdfc` process killed when dropped (a watching one never ends by itself).
struct Watcher(std::process::Child);

impl Drop for Watcher {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Waits until `done` holds of the log's text, failing after two minutes (a cold pipeline
/// build on a CPU device can take tens of seconds).
fn wait_for(log: &Path, what: &str, done: impl Fn(&str) -> bool) -> String {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    loop {
        let text = std::fs::read_to_string(log).unwrap_or_default();
        if done(&text) {
            return text;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "timed out waiting for {what}; stderr so far:\n{text}"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}

#[test]
fn watch_renders_each_change_and_keeps_the_picture_through_a_mistake() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("watch");
    let scene = t.write("s.sdf", SPHERE);
    let out = t.path("w.png");
    let log = t.path("stderr.txt");
    let size = ["--size", "24x16"];
    let plain = |name: &str, text: &str| {
        let src = t.write(&format!("{name}.sdf"), text);
        let png = t.path(&format!("{name}.png"));
        render_in(&t, &src, &png, &[&size]).expect_code(0);
        read_png(&png)
    };
    let (sphere, cube) = (
        plain("sphere", SPHERE),
        plain("cube", "scene = box(0.8);\n"),
    );
    assert_ne!(sphere, cube);

    let child = std::process::Command::new(env!("CARGO_BIN_EXE_sdfc"))
        .args([
            "render",
            s(&scene),
            "-o",
            s(&out),
            "--live",
            "--watch",
            "--grace",
            "0",
            "--preview-scale",
            "4",
        ])
        .args(size)
        .env("NO_COLOR", "1")
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    let _watcher = Watcher(child);
    // Edits replace the file whole (as editors that save atomically do): a poll between a
    // truncation and a write would render an empty scene.
    let edit = |text: &str| {
        let next = t.write("next.sdf.tmp", text);
        std::fs::rename(next, &scene).unwrap();
    };
    let frames = |n: usize| move |t: &str| t.matches("final frame (specialised)").count() >= n;
    wait_for(&log, "the first picture", frames(1));
    assert_eq!(read_png(&out), sphere);

    // Once the interpreter is warm, an edit is previewed (no grace) before its frame: the
    // warm interpreter is ready in microseconds, the scene's pipeline in milliseconds.
    wait_for(&log, "the interpreter", |t| {
        t.contains("the interpreter is warm")
    });
    let before = std::fs::read_to_string(&log).unwrap().len();
    edit("scene = box(0.8);\n");
    let text = wait_for(&log, "the edited picture", frames(2));
    assert_eq!(read_png(&out), cube);
    assert!(
        text[before..].contains("preview (interpreted, 6x4 enlarged)"),
        "{text}"
    );

    // A mistake: reported with its position, the last picture kept, the watch going on.
    edit(BROKEN);
    let text = wait_for(&log, "the diagnostic", |t| t.contains("s.sdf: 1 error"));
    assert!(text.contains("s.sdf:2:9"), "{text}");
    assert_eq!(read_png(&out), cube);
    edit(SPHERE);
    let text = wait_for(&log, "the fixed picture", frames(3));
    assert_eq!(read_png(&out), sphere);
    assert_eq!(text.matches("s.sdf: 1 error").count(), 1, "{text}");

    // An edit while a large scene's frame is still building: the frame may be given up for
    // the new version or finished first, but the file ends as the new version's picture.
    edit(&sdfc_tests::grid_scene(300));
    std::thread::sleep(std::time::Duration::from_millis(30));
    edit("scene = box(0.8);\n");
    let text = wait_for(&log, "the picture after a superseding edit", |t| {
        t.matches("final frame (specialised)").count() >= 4 && read_png(&out) == cube
    });
    assert!(!text.contains("panicked"), "{text}");
}

/// A render that outlasts a few seconds says why it may take long and what to do instead
/// (`SDFC_NOTE_AFTER_MS=0`: at once); the interpreted marcher, which builds no pipeline for the
/// scene, does not.
#[test]
fn a_slow_render_says_why_and_what_to_do_instead() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("slow-note");
    let scene = t.write("s.sdf", SPHERE);
    let out = t.path("s.png");
    let at_once = [("SDFC_NOTE_AFTER_MS", "0")];
    let args = ["render", s(&scene), "-o", s(&out), "--size", "8x8"];
    let run = sdfc_env(&t.0, &args, &at_once).expect_code(0);
    for part in ["still rendering", "pipeline", "--live", "--interpreted"] {
        assert!(
            run.stderr.contains(part),
            "no `{part}`:\n{}",
            run.describe()
        );
    }
    let interpreted = [&args[..], &["--interpreted"]].concat();
    let run = sdfc_env(&t.0, &interpreted, &at_once).expect_code(0);
    assert!(
        !run.stderr.contains("still rendering"),
        "{}",
        run.describe()
    );
}

/// `--instances`: a union of many constant shapes read from data draws the picture the code
/// draws, in the specialised shader and in the interpreter (`--interpreted`); a scene
/// without such a union is rendered as code, with a note saying why; it does not go with
/// `--cull` or `--no-instances`, which draws the same picture from code. By default a union
/// of `AUTO_INSTANCES` shapes is read as data, with a note.
#[test]
fn instances_render_the_same_picture_or_say_why_not() {
    if !have_device() {
        return;
    }
    let t = TempDir::new("instances");
    let grid = t.write("grid.sdf", sdfc_tests::grid_scene(40));
    let (code, data) = (t.path("code.png"), t.path("data.png"));
    let size: &[&str] = &["--size", "48x36"];
    render_in(&t, &grid, &code, &[size]).expect_code(0);
    let run = render_in(&t, &grid, &data, &[size, &["--instances"]]).expect_code(0);
    assert!(!run.stderr.contains("note"), "{}", run.describe());
    // Channels of the code's picture more than 2 off in `other`'s.
    let a = read_png(&code);
    let off = |other: &Path| {
        let b = read_png(other);
        let pairs = a.as_raw().iter().zip(b.as_raw());
        pairs.filter(|(x, y)| x.abs_diff(**y) > 2).count()
    };
    assert!(off(&data) <= 8, "{} channels differ", off(&data));
    let walked = t.path("walked.png");
    let both = ["--instances", "--interpreted"];
    let run = render_in(&t, &grid, &walked, &[size, &both]).expect_code(0);
    assert!(!run.stderr.contains("note"), "{}", run.describe());
    assert!(
        off(&walked) <= 8,
        "interpreted: {} channels differ",
        off(&walked)
    );
    // A single sphere: code, and a note, in either marcher.
    let scene = t.write("s.sdf", SPHERE);
    for extra in [&["--instances"][..], &both] {
        let run = render_in(&t, &scene, &t.path("s.png"), &[size, extra]).expect_code(0);
        assert!(
            run.stderr.contains("--instances: the scene's root is not"),
            "{}",
            run.describe()
        );
    }
    render_in(&t, &grid, &data, &[&["--instances", "--cull"]]).expect_code(2);
    render_in(&t, &grid, &data, &[&["--instances", "--no-instances"]]).expect_code(2);
    // `--no-instances`: the interpreter runs the union as code (by default it reads any
    // union of instances as data), to the same picture.
    let as_code = t.path("as_code.png");
    let never = ["--no-instances", "--interpreted"];
    render_in(&t, &grid, &as_code, &[size, &never]).expect_code(0);
    assert!(
        off(&as_code) <= 8,
        "as code: {} channels differ",
        off(&as_code)
    );
    // By default, a union of AUTO_INSTANCES shapes is read as data, and the user is told.
    let big = t.write("big.sdf", sdfc_tests::grid_scene(sdfc_wgsl::AUTO_INSTANCES));
    let run = render_in(&t, &big, &t.path("big.png"), &[&["--size", "16x12"]]).expect_code(0);
    assert!(
        run.stderr.contains("so they are read as data"),
        "{}",
        run.describe()
    );
    // As many about one point (a crowd): code, and the user is told why.
    let mut crowd = String::from("scene = union(\n");
    for i in 0..sdfc_wgsl::AUTO_INSTANCES {
        let k = i as f64;
        let (x, y) = (0.03 * k.sin(), 0.03 * (1.7 * k).cos());
        crowd += &format!("    sphere(0.5).translate([{x:.4}, {y:.4}, 0]),\n");
    }
    let crowd = t.write("crowd.sdf", crowd + ");\n");
    let run = render_in(&t, &crowd, &t.path("crowd.png"), &[&["--size", "16x12"]]).expect_code(0);
    assert!(
        run.stderr.contains("so they stay code") && !run.stderr.contains("read as data,"),
        "{}",
        run.describe()
    );
}
