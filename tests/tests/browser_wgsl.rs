//! Every kind of shader sdfc emits passes Tint, the WGSL compiler of Chrome, as well as naga
//! (which Firefox uses): the scene corpus and the examples in every form, under the render
//! settings that change the emitted code, with culling, the evaluation shader, the
//! interpreter, and random scenes. Tint runs through Dawn's Node.js binding
//! (`tests/browser/`, installed by `.ci/run`) twice, so no GPU is needed: on Dawn's null
//! backend at WebGPU's core feature level and default limits, and on Mesa's software OpenGL
//! ES at the compatibility level, where pipelines also pass Tint's back end and Mesa's GLSL
//! compiler.

use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use sdfc_ir::scene::{Ao, Epsilon, Fog, Normals, RenderSettings, Shadows};
use sdfc_ir::Program;
use sdfc_tests::random_scene::shape;
use sdfc_wgsl::{compile, emit_validated, eval_shader::eval_shader, interp, Failure, Options};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Set (by `.ci/run`) to make a missing Node.js or Dawn binding a failure, not a skip.
const REQUIRE: &str = "SDFC_REQUIRE_TINT";

/// How many random scenes are checked.
const RANDOM_SCENES: usize = 48;

fn browser_dir() -> PathBuf {
    sdfc_tests::root().join("browser")
}

/// Why Tint cannot run here, if it cannot.
fn unavailable() -> Option<String> {
    if !browser_dir().join("node_modules/webgpu").is_dir() {
        return Some(
            "Dawn's Node.js binding is not installed: run `npm ci --prefix tests/browser`".into(),
        );
    }
    match Command::new("node").arg("--version").output() {
        Ok(o) if o.status.success() => None,
        _ => Some("Node.js (`node`) is not on the PATH".into()),
    }
}

/// Checks that Tint can run, or says why the calling test is skipped (`false`); fails
/// where `SDFC_REQUIRE_TINT` is set.
fn tint_available(test: &str) -> bool {
    let Some(why) = unavailable() else {
        return true;
    };
    assert!(
        std::env::var_os(REQUIRE).is_none(),
        "{REQUIRE} is set, but {why}"
    );
    eprintln!("{test}: skipped, {why}");
    false
}

/// One file's verdict from `check_wgsl.mjs`.
struct Verdict {
    ok: bool,
    messages: String,
}

/// Where Dawn runs the shaders.
#[derive(Clone, Copy, Debug)]
enum Backend {
    /// No device: Tint's front end and WebGPU's validation, core feature level.
    Null,
    /// Mesa's llvmpipe through OpenGL ES, compatibility feature level.
    Gles,
}

/// Writes the shaders to a fresh folder and runs Tint over all of them at once; returns each
/// file name's verdict.
fn run_tint(
    label: &str,
    backend: Backend,
    shaders: &BTreeMap<String, String>,
) -> BTreeMap<String, Verdict> {
    let dir = std::env::temp_dir().join(format!(
        "sdfc-tint-{label}-{backend:?}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temporary folder");
    for (name, wgsl) in shaders {
        std::fs::write(dir.join(name), wgsl).expect("write a shader");
    }
    let mut node = Command::new("node");
    node.arg(browser_dir().join("check_wgsl.mjs"));
    if let Backend::Gles = backend {
        node.arg("--gles");
    }
    let out = node.arg(&dir).output().expect("run node");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        matches!(out.status.code(), Some(0 | 1)),
        "check_wgsl.mjs ({backend:?}) did not run: {}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let verdicts: BTreeMap<String, Verdict> = stdout
        .lines()
        .filter_map(parse_line)
        .map(|(file, v)| (file_name(&file), v))
        .collect();
    assert_eq!(
        verdicts.len(),
        shaders.len(),
        "Tint ({backend:?}) reported on {} of {} files:\n{stdout}",
        verdicts.len(),
        shaders.len()
    );
    verdicts
}

fn file_name(path: &str) -> String {
    Path::new(path)
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Reads `{"file":"...","ok":true|false,"messages":[...]}` without a JSON dependency: the
/// file names are ours (no quotes), and the messages are kept as raw text for the report.
fn parse_line(line: &str) -> Option<(String, Verdict)> {
    let rest = line.strip_prefix("{\"file\":\"")?;
    let (file, rest) = rest.split_once('"')?;
    let ok = if rest.starts_with(",\"ok\":true") {
        true
    } else if rest.starts_with(",\"ok\":false") {
        false
    } else {
        return None;
    };
    let messages = rest
        .split_once("\"messages\":")
        .map(|(_, m)| m.trim_end_matches('}').replace("\\n", "\n"))
        .unwrap_or_default();
    Some((file.to_string(), Verdict { ok, messages }))
}

fn emitted(what: &str, r: Result<String, Failure>) -> String {
    match r {
        Ok(w) => w,
        Err(Failure::Internal { report, .. }) => panic!("{what}: naga rejected it:\n{report}"),
        Err(f) => panic!("{what}: {f}"),
    }
}

/// Render settings that switch on, in turn, every part of the shader the settings choose:
/// the plain marcher of the tutorials, and everything at once with each normal method.
fn setting_variants(base: &RenderSettings) -> Vec<(&'static str, RenderSettings)> {
    let plain = RenderSettings {
        epsilon: Epsilon::Absolute(1e-3),
        relaxation: 1.0,
        normals: Normals::Central,
        shadows: Shadows::None,
        ao: None,
        reflections: 0,
        fog: None,
        antialias: 1,
        ..base.clone()
    };
    let rich = |normals, shadows| RenderSettings {
        relaxation: 1.6,
        normals,
        shadows,
        ao: Some(Ao {
            samples: 5,
            step: 0.1,
            strength: 1.0,
            falloff: 0.8,
        }),
        reflections: 2,
        fog: Some(Fog {
            density: 0.05,
            color: [0.5, 0.6, 0.7],
        }),
        antialias: 2,
        ..base.clone()
    };
    vec![
        ("plain", plain),
        (
            "rich_tetrahedron",
            rich(Normals::Tetrahedron, Shadows::Soft(16.0)),
        ),
        ("rich_forward", rich(Normals::Forward, Shadows::Hard)),
        ("rich_analytic", rich(Normals::Analytic, Shadows::Soft(4.0))),
    ]
}

/// Every form of one scene's shader: as compiled, as a library, culled, under each setting
/// variant, and its evaluation shader. Identical texts are kept once. A scene the
/// compiler rejects (a stress test of a diagnostic) has no shader to check.
fn forms(stem: &str, source: &str, out: &mut BTreeMap<String, String>) {
    let c = match compile(source, &Options::default()) {
        Ok(c) => c,
        Err(Failure::Diagnostics(_)) => return,
        Err(e) => panic!("{stem}: {e:?}"),
    };
    let mut add = |name: String, wgsl: String| {
        if !out.values().any(|w| *w == wgsl) {
            out.insert(name, wgsl);
        }
    };
    add(format!("{stem}.wgsl"), c.wgsl.clone());
    for (form, opts) in [
        (
            "lib",
            Options {
                lib: true,
                ..Options::default()
            },
        ),
        (
            "cull",
            Options {
                cull: true,
                ..Options::default()
            },
        ),
        // The same text as the plain form unless the root is a union of instances: by
        // default one of `AUTO_INSTANCES` or more is data, and asked for, from 16.
        (
            "code",
            Options {
                instances: sdfc_wgsl::Instances::Never,
                ..Options::default()
            },
        ),
        (
            "instances",
            Options {
                instances: sdfc_wgsl::Instances::Always,
                ..Options::default()
            },
        ),
    ] {
        let what = format!("{stem}.{form}");
        add(
            format!("{what}.wgsl"),
            emitted(&what, compile(source, &opts).map(|c| c.wgsl)),
        );
    }
    let program: &Program = c.program();
    for (name, render) in setting_variants(&program.scene.render) {
        let mut variant = program.clone();
        variant.scene.render = render;
        let what = format!("{stem}.{name}");
        add(
            format!("{what}.wgsl"),
            emitted(&what, emit_validated(&variant, &Options::default())),
        );
    }
    let what = format!("{stem}.eval");
    add(format!("{what}.wgsl"), emitted(&what, eval_shader(program)));
}

/// The scenes of the compiling corpus folders (`tests/corpus` is the parser's, with
/// mistakes) and the examples, by a name unique across folders.
fn scene_files() -> Vec<(String, String)> {
    let mut v = Vec::new();
    for folder in ["scenes", "stress", "../examples"] {
        let tag = folder.trim_start_matches("../");
        for f in sdfc_tests::read_corpus(folder, 1) {
            v.push((format!("{tag}_{}", f.stem), f.source));
        }
    }
    v
}

/// `count` random valid scenes, the same every run.
fn random_scenes(count: usize) -> Vec<String> {
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &[0x5d; 32]),
    );
    (0..count)
        .map(|_| {
            let tree = shape().new_tree(&mut runner).expect("a random scene");
            format!("scene = {};\n", tree.current())
        })
        .collect()
}

/// Runs Tint over the shaders on both backends and asserts that every one passed on both.
fn assert_all_pass(label: &str, shaders: &BTreeMap<String, String>) {
    let mut failed = Vec::new();
    for backend in [Backend::Null, Backend::Gles] {
        for (name, v) in run_tint(label, backend, shaders) {
            if !v.ok {
                failed.push(format!("--- {name} ({backend:?}): {}", v.messages));
            }
        }
    }
    assert!(
        failed.is_empty(),
        "Tint rejected {} of {} shaders (on two backends) that naga accepted:\n{}",
        failed.len(),
        shaders.len(),
        failed.join("\n")
    );
}

#[test]
fn every_emitted_shader_passes_tint() {
    if !tint_available("every_emitted_shader_passes_tint") {
        return;
    }
    let mut shaders = BTreeMap::new();
    for (stem, source) in scene_files() {
        forms(&stem, &source, &mut shaders);
    }
    forms("grid_300", &sdfc_tests::grid_scene(300), &mut shaders);
    // A mixed union: a floor whose height is a param beside the grid's instances, emitted as
    // code beside the walk in the instances form (`rest_distance`).
    let floor = sdfc_tests::grid_scene(300).replacen(
        "scene = union(\n",
        "param floor = 0.8;\nscene = union(\n    plane([0, 1, 0], floor),\n",
        1,
    );
    forms("grid_300_floor", &floor, &mut shaders);
    for unroll in [1, interp::CPU_UNROLL] {
        for (name, variant) in [
            ("", interp::Variant::Code),
            ("_walk", interp::Variant::Walk),
        ] {
            let wgsl = emitted(
                "interpreter",
                interp::shader_variant(unroll, variant).map(str::to_string),
            );
            shaders.insert(format!("interpreter{name}_unroll{unroll}.wgsl"), wgsl);
        }
    }
    assert!(shaders.len() > 200, "only {} shaders", shaders.len());
    assert_all_pass("all", &shaders);
}

#[test]
fn random_scenes_pass_tint() {
    if !tint_available("random_scenes_pass_tint") {
        return;
    }
    let mut shaders = BTreeMap::new();
    for (i, source) in random_scenes(RANDOM_SCENES).iter().enumerate() {
        let c = compile(source, &Options::default())
            .unwrap_or_else(|e| panic!("random scene {i}:\n{source}\n{e:?}"));
        shaders.insert(format!("random_{i:02}.wgsl"), c.wgsl);
    }
    assert_all_pass("random", &shaders);
}

/// The check itself can fail, and names the file: Tint rejects a name WGSL reserves (as naga
/// does), a workgroup wider than WebGPU's default limits and `*` mixed with `^` unbracketed
/// (both of which naga accepts; the second was in the noise helper until this check).
#[test]
fn tint_rejects_what_a_browser_rejects() {
    if !tint_available("tint_rejects_what_a_browser_rejects") {
        return;
    }
    let main = |body: &str| format!("@compute @workgroup_size(8, 8) fn main() {{ {body} }}\n");
    let mut shaders = BTreeMap::new();
    shaders.insert("fine.wgsl".to_string(), main("let h = (1u * 3u) ^ 5u;"));
    shaders.insert("reserved.wgsl".to_string(), main("let filter = 1.0;"));
    shaders.insert("mixed.wgsl".to_string(), main("let h = 1u * 3u ^ 5u;"));
    shaders.insert(
        "too_wide.wgsl".to_string(),
        "@compute @workgroup_size(1024) fn main() {}\n".to_string(),
    );
    let verdicts = run_tint("negative", Backend::Null, &shaders);
    assert!(
        verdicts["fine.wgsl"].ok,
        "{}",
        verdicts["fine.wgsl"].messages
    );
    for (name, says) in [
        ("reserved.wgsl", "reserved"),
        ("mixed.wgsl", "parenthesis"),
        ("too_wide.wgsl", "1024"),
    ] {
        let v = &verdicts[name];
        assert!(!v.ok, "{name} passed");
        assert!(v.messages.contains(says), "{name}: {}", v.messages);
    }
    // naga accepts the last two, so this check adds to the validation every shader gets.
    for name in ["mixed.wgsl", "too_wide.wgsl"] {
        assert!(
            sdfc_wgsl::validate::validate(name, &shaders[name]).is_ok(),
            "naga now rejects {name}"
        );
    }
}

/// The OpenGL ES pass runs at the compatibility feature level, which is narrower: a storage
/// texture of format `rg32float` is core WebGPU, and not available there.
#[test]
fn the_gles_pass_applies_the_compatibility_level() {
    if !tint_available("the_gles_pass_applies_the_compatibility_level") {
        return;
    }
    let wgsl = "@group(0) @binding(0) var t: texture_storage_2d<rg32float, write>;\n\
                @compute @workgroup_size(8, 8) fn main() {\n\
                \x20   textureStore(t, vec2<i32>(0), vec4<f32>(1.0));\n\
                }\n";
    let shaders = BTreeMap::from([("rg32float.wgsl".to_string(), wgsl.to_string())]);
    let core = run_tint("level", Backend::Null, &shaders);
    assert!(
        core["rg32float.wgsl"].ok,
        "{}",
        core["rg32float.wgsl"].messages
    );
    let compat = run_tint("level", Backend::Gles, &shaders);
    let v = &compat["rg32float.wgsl"];
    assert!(!v.ok, "the OpenGL ES pass passed it");
    assert!(v.messages.contains("RG32Float"), "{}", v.messages);
}
