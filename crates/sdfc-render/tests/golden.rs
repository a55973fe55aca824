//! Golden images: the spec's section 10 scene and one scene per shading feature, rendered at
//! 64x48 and compared with `tests/images/*.png` (tolerance in `common::check_golden`:
//! each channel within 3/255, at most 1% of pixels further off, mean difference under
//! 1/255). Every frame is also checked for garbage colour and NaN/infinite AOVs.
//! Regenerate the goldens with `SDFC_UPDATE_GOLDEN=1 cargo test -p sdfc-render --test golden`.

mod common;

use common::{check_aovs, check_golden, check_sane, compile_file, renderer};
use sdfc_render::RenderOptions;

const W: u32 = 64;
const H: u32 = 48;

fn golden_with(name: &str, rel: &str, opts: RenderOptions) {
    let Some(r) = renderer() else { return };
    let compiled = compile_file(rel);
    let opts = RenderOptions {
        width: W,
        height: H,
        aovs: true,
        ..opts
    };
    let frame = r
        .render(&compiled, &opts)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    check_sane(name, &frame, compiled.program().scene.render.max_steps);
    check_golden(name, &frame);
}

fn golden(name: &str) {
    golden_with(
        name,
        &format!("crates/sdfc-render/tests/scenes/{name}.sdf"),
        RenderOptions::default(),
    );
}

#[test]
fn spec_section10() {
    golden_with(
        "spec_section10",
        "examples/spec_section10.sdf",
        RenderOptions::default(),
    );
}

#[test]
fn diffuse_lights() {
    golden("diffuse_lights");
}

#[test]
fn fog() {
    golden("fog");
}

#[test]
fn antialias() {
    golden("antialias");
}

#[test]
fn relaxation() {
    golden("relaxation");
}

#[test]
fn normals_central() {
    golden("normals_central");
}

#[test]
fn normals_analytic() {
    golden("normals_analytic");
}

#[test]
fn normals_forward() {
    golden("normals_forward");
}

#[test]
fn shadows_hard() {
    golden("shadows_hard");
}

#[test]
fn shadows_soft() {
    golden("shadows_soft");
}

#[test]
fn ambient_occlusion() {
    golden("ambient_occlusion");
}

#[test]
fn reflections() {
    golden("reflections");
}

const PARAMS_TIME: &str = "crates/sdfc-render/tests/scenes/params_time.sdf";

fn params_time_options() -> RenderOptions {
    RenderOptions {
        time: 0.9,
        params: vec![
            ("radius".into(), vec![0.8]),
            ("tint".into(), vec![1.0, 0.2, 0.3]),
            ("offset".into(), vec![-0.3, 0.3, 0.2]),
        ],
        ..RenderOptions::default()
    }
}

#[test]
fn params_time_defaults() {
    golden_with(
        "params_time_defaults",
        PARAMS_TIME,
        RenderOptions::default(),
    );
}

#[test]
fn params_time_overridden() {
    golden_with("params_time_overridden", PARAMS_TIME, params_time_options());
}

/// Params and time reach the shader: each of them alone changes the picture.
#[test]
fn params_and_time_change_the_picture() {
    let Some(r) = renderer() else { return };
    let compiled = compile_file(PARAMS_TIME);
    let render = |opts: RenderOptions| {
        r.render(
            &compiled,
            &RenderOptions {
                width: W,
                height: H,
                ..opts
            },
        )
        .unwrap()
        .rgba
    };
    let base = render(RenderOptions::default());
    let timed = render(RenderOptions {
        time: 0.9,
        ..RenderOptions::default()
    });
    assert_ne!(base, timed, "the time does not change the picture");
    for (name, value) in params_time_options().params {
        let changed = render(RenderOptions {
            params: vec![(name.clone(), value)],
            ..RenderOptions::default()
        });
        assert_ne!(base, changed, "param `{name}` does not change the picture");
    }
}

/// Every scene of the shared corpus (`tests/scenes`) renders, with no NaN in its AOVs and
/// unit normals on its hits (no goldens: the corpus tests the language, not pictures).
#[test]
fn every_corpus_scene_renders_without_nan() {
    let Some(r) = renderer() else { return };
    let scenes = sdfc_tests::corpus("scenes");
    assert!(!scenes.is_empty());
    for path in scenes {
        let name = path.display().to_string();
        let source = std::fs::read_to_string(&path).unwrap();
        let compiled = common::compile(&name, &source);
        let frame = r
            .render(
                &compiled,
                &RenderOptions {
                    width: 32,
                    height: 24,
                    time: 0.5,
                    aovs: true,
                    ..RenderOptions::default()
                },
            )
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        check_aovs(&name, &frame, compiled.program().scene.render.max_steps);
    }
}
