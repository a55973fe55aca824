//! Helpers shared by the render tests: one device per test binary, scene loading, goldens.
#![allow(dead_code)]

pub mod against_reference;
pub mod eval_check;

use sdfc_render::{Frame, Renderer};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The repository root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// True on CI (`CI=true`), where a missing adapter must fail the tests.
pub fn on_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true" || v == "1")
}

/// The shared device of this test binary, or `None` (with the reason printed) where the
/// machine has no adapter at all. On CI a missing adapter fails the test instead.
pub fn renderer() -> Option<&'static Renderer> {
    static R: OnceLock<Result<Renderer, String>> = OnceLock::new();
    let r = R.get_or_init(|| {
        let r = Renderer::new().map_err(|e| e.to_string());
        if let Ok(r) = &r {
            eprintln!("render tests on {}", r.adapter_description());
        }
        r
    });
    match r {
        Ok(r) => Some(r),
        Err(e) if on_ci() => panic!("no wgpu adapter on CI (install mesa-vulkan-drivers): {e}"),
        Err(e) => {
            skip_notice(e);
            None
        }
    }
}

/// Says once per test binary why the device tests are skipped, on the real stderr (libtest
/// captures `eprintln!` of passing tests).
fn skip_notice(reason: &str) {
    use std::io::Write;
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED: render tests need a wgpu adapter, and this machine has none: {reason}"
        );
    });
}

/// Compiles a scene, failing the test with the diagnostics if it does not compile.
pub fn compile(name: &str, source: &str) -> sdfc_wgsl::Compiled {
    compile_with(name, source, &sdfc_wgsl::Options::default())
}

/// [`compile`] with `opts`.
pub fn compile_with(name: &str, source: &str, opts: &sdfc_wgsl::Options) -> sdfc_wgsl::Compiled {
    match sdfc_wgsl::compile(source, opts) {
        Ok(c) => c,
        Err(sdfc_wgsl::Failure::Diagnostics(d)) => panic!(
            "{name} does not compile:\n{}",
            sdfc_syntax::diag::render_with(name, source, &d, false)
        ),
        Err(f) => panic!("{name}: {f}"),
    }
}

/// [`compile`] with its root union read as data at any size (`Instances::Always`), failing
/// the test where it is not.
pub fn compile_as_data(name: &str, source: &str) -> sdfc_wgsl::Compiled {
    let opts = sdfc_wgsl::Options {
        instances: sdfc_wgsl::Instances::Always,
        ..sdfc_wgsl::Options::default()
    };
    let c = compile_with(name, source, &opts);
    assert!(
        !c.data.is_empty(),
        "{name}: the union was not emitted as data"
    );
    c
}

/// How many pixels of a frame with AOVs hit a surface (a miss's depth is infinite).
pub fn hits(f: &Frame) -> usize {
    f.aovs
        .as_ref()
        .expect("a frame with AOVs")
        .depth
        .iter()
        .filter(|d| d.is_finite())
        .count()
}

/// Reads and compiles a scene file (path relative to the repository root).
pub fn compile_file(rel: &str) -> sdfc_wgsl::Compiled {
    let path = root().join(rel);
    let source =
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    compile(rel, &source)
}

/// A pixel of a golden image matches when every channel is within this many 8-bit steps.
/// The goldens come from lavapipe; another driver (or another Mesa/LLVM) computes `sin`,
/// `pow`, `exp` and fused multiply-adds to slightly different last bits, which moves a
/// colour by a rounding step or two after `pack4x8unorm`.
pub const CHANNEL_TOLERANCE: u8 = 3;
/// At most this fraction of pixels may be further off: a pixel whose ray grazes a silhouette
/// or a shadow edge can flip between hit and miss (lit and shadowed) on float rounding.
pub const OUTLIER_FRACTION: f64 = 0.01;
/// And the mean absolute difference over all channels must stay below this (8-bit steps):
/// driver noise averages well below one step, while a shift of the whole picture (a gamma or
/// light change) is a real change even when each pixel stays within the tolerance.
pub const MEAN_TOLERANCE: f64 = 1.0;

/// Compares a frame with `tests/images/NAME.png`. With `SDFC_UPDATE_GOLDEN=1` the golden is
/// (re)written instead; it is never written otherwise. On a mismatch the actual image and a
/// difference image are left in `target/golden-diff/` for inspection.
pub fn check_golden(name: &str, frame: &Frame) {
    let golden = root().join("tests/images").join(format!("{name}.png"));
    if std::env::var("SDFC_UPDATE_GOLDEN").is_ok_and(|v| v == "1") {
        std::fs::create_dir_all(golden.parent().unwrap()).unwrap();
        sdfc_render::output::write_png(&golden, frame).unwrap();
        eprintln!("updated golden {}", golden.display());
        return;
    }
    let expected = match image::open(&golden) {
        Ok(i) => i.to_rgba8(),
        Err(e) => panic!(
            "no golden image {} ({e}); create it with \
             SDFC_UPDATE_GOLDEN=1 cargo test -p sdfc-render --test golden, and look at it",
            golden.display()
        ),
    };
    assert_eq!(
        (expected.width(), expected.height()),
        (frame.width, frame.height),
        "{name}: the golden's size differs"
    );
    let exp = expected.as_raw();
    let mut outliers = 0usize;
    let mut sum = 0u64;
    let mut worst = 0u8;
    let mut diff = vec![0u8; exp.len()];
    for (i, (a, b)) in frame
        .rgba
        .chunks_exact(4)
        .zip(exp.chunks_exact(4))
        .enumerate()
    {
        let d = (0..4).map(|c| a[c].abs_diff(b[c])).max().unwrap();
        sum += (0..4).map(|c| a[c].abs_diff(b[c]) as u64).sum::<u64>();
        worst = worst.max(d);
        if d > CHANNEL_TOLERANCE {
            outliers += 1;
        }
        let v = d.saturating_mul(16);
        diff[4 * i..4 * i + 4].copy_from_slice(&[v, v, v, 255]);
    }
    let pixels = (frame.width * frame.height) as usize;
    let mean = sum as f64 / (4 * pixels) as f64;
    let fraction = outliers as f64 / pixels as f64;
    eprintln!(
        "{name}: {outliers} pixels beyond {CHANNEL_TOLERANCE}/255, mean difference \
         {mean:.3}/255, worst {worst}/255"
    );
    if fraction > OUTLIER_FRACTION || mean > MEAN_TOLERANCE {
        let dir = root().join("target/golden-diff");
        let _ = std::fs::create_dir_all(&dir);
        let actual = dir.join(format!("{name}.actual.png"));
        let _ = sdfc_render::output::write_png(&actual, frame);
        let diff_frame = Frame {
            rgba: diff,
            ..frame.clone()
        };
        let _ = sdfc_render::output::write_png(dir.join(format!("{name}.diff.png")), &diff_frame);
        panic!(
            "{name}: differs from {}: {outliers} of {pixels} pixels ({:.2}%) off by more than \
             {CHANNEL_TOLERANCE}/255 (allowed {:.1}%), mean difference {mean:.3}/255 (allowed \
             {MEAN_TOLERANCE}), worst {worst}/255; actual image in {}. If the change is \
             intended, regenerate with SDFC_UPDATE_GOLDEN=1.",
            golden.display(),
            100.0 * fraction,
            100.0 * OUTLIER_FRACTION,
            actual.display()
        );
    }
}

/// Checks the colour and AOVs of a frame for garbage: opaque pixels, more than a flat
/// colour, no NaN or infinity where there should be none, unit normals on hits, zero normals
/// and infinite depth on misses, whole positive step counts.
pub fn check_sane(name: &str, frame: &Frame, max_steps: u32) {
    assert!(
        frame.rgba.chunks_exact(4).any(|p| p[..3] != [0, 0, 0]),
        "{name}: the image is all black"
    );
    let mut colours: Vec<[u8; 3]> = frame
        .rgba
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    colours.sort_unstable();
    colours.dedup();
    assert!(
        colours.len() >= 16,
        "{name}: only {} distinct colours: a flat or garbage image",
        colours.len()
    );
    let hits = check_aovs(name, frame, max_steps);
    assert!(hits > 0, "{name}: no ray hits anything");
}

/// The checks of [`check_sane`] that hold for any scene, even one the camera does not see:
/// opaque pixels, and AOVs (when present) free of NaN, depths not negative, with unit normals on hits, zero
/// normals and infinite depth on misses, whole positive step counts. Returns the hit count.
pub fn check_aovs(name: &str, frame: &Frame, max_steps: u32) -> usize {
    assert!(
        frame.rgba.chunks_exact(4).all(|p| p[3] == 255),
        "{name}: alpha is not 1 everywhere"
    );
    let Some(aovs) = &frame.aovs else { return 0 };
    let n = (frame.width * frame.height) as usize;
    assert_eq!(aovs.depth.len(), n);
    assert_eq!(aovs.normal.len(), n);
    assert_eq!(aovs.steps.len(), n);
    let mut hits = 0;
    for i in 0..n {
        let (d, nrm, s) = (aovs.depth[i], aovs.normal[i], aovs.steps[i]);
        let at = format!(
            "{name}: pixel ({}, {})",
            i % frame.width as usize,
            i / frame.width as usize
        );
        assert!(!d.is_nan(), "{at}: depth is NaN");
        // A camera inside a shape sees its surface at depth 0.
        assert!(d >= 0.0, "{at}: depth {d} is negative");
        assert!(
            nrm.iter().all(|c| c.is_finite()),
            "{at}: normal {nrm:?} is not finite"
        );
        if d.is_finite() {
            hits += 1;
            let len = nrm.iter().map(|c| c * c).sum::<f32>().sqrt();
            assert!(
                (len - 1.0).abs() < 1e-3,
                "{at}: normal {nrm:?} is not unit length"
            );
        } else {
            assert_eq!(d, f32::INFINITY, "{at}: depth {d}");
            assert_eq!(nrm, [0.0; 3], "{at}: a miss with a normal");
        }
        // A ray that misses the scene's bounds takes no step (`ray_span`); a hit takes one.
        // The march's samples and those of refinements that pass by have a budget of
        // `max_steps` each (`march_spent`), and the refinement that ends the march takes up
        // to 20: at most 2 max_steps + 19.
        assert!(
            s.is_finite() && s >= 0.0 && s.fract() == 0.0 && s <= 2.0 * max_steps as f32 + 19.0,
            "{at}: step count {s}"
        );
        assert!(!d.is_finite() || s >= 1.0, "{at}: a hit in {s} steps");
    }
    hits
}
