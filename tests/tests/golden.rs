//! Golden tests over the scene corpus in `tests/scenes/`: for every scene, snapshots of the
//! lowered IR, the optimised IR and the emitted WGSL, plus checks that hold for every scene
//! (the WGSL validates, in full and library form; compiling is deterministic; no scene of the
//! corpus draws a warning).
//!
//! Snapshots live in `tests/tests/snapshots/golden__<scene>.<stage>.snap`. After an intended
//! change, read the diffs, then accept them with `INSTA_UPDATE=always cargo test -p sdfc-tests`.

use sdfc_syntax::diag::{self, Diagnostic};
use sdfc_wgsl::{Compiled, Failure, Options};
use std::path::{Path, PathBuf};

struct Scene {
    stem: String,
    path: PathBuf,
    source: String,
}

fn scenes() -> Vec<Scene> {
    sdfc_tests::read_corpus("scenes", 12)
        .into_iter()
        .map(|f| Scene {
            stem: f.stem,
            path: f.path,
            source: f.source,
        })
        .collect()
}

fn compile(name: &str, source: &str, opts: &Options) -> Compiled {
    match sdfc_wgsl::compile(source, opts) {
        Ok(c) => c,
        Err(Failure::Diagnostics(d)) => {
            panic!(
                "{name} does not compile:\n{}",
                diag::render(name, source, &d)
            )
        }
        Err(Failure::Internal { report, wgsl }) => {
            panic!("{name}: internal compiler error:\n{report}\n--- WGSL ---\n{wgsl}")
        }
        Err(f) => panic!("{name}: {f}"),
    }
}

/// The optimised IR as `sdfc compile --emit opt-ir` prints it.
fn opt_ir(c: &Compiled) -> String {
    sdfc_ir::dump::program_text(c.program())
}

/// The text of `fn NAME(...` up to its closing brace at the start of a line.
fn function_text<'a>(wgsl: &'a str, signature_start: &str) -> &'a str {
    let start = wgsl
        .find(signature_start)
        .unwrap_or_else(|| panic!("no `{signature_start}` in:\n{wgsl}"));
    let len = wgsl[start..]
        .find("\n}\n")
        .unwrap_or_else(|| panic!("`{signature_start}` is not closed"));
    &wgsl[start..start + len + 3]
}

fn settings_for(scene: &Scene) -> insta::Settings {
    let mut s = insta::Settings::clone_current();
    s.set_input_file(&scene.path);
    s.set_omit_expression(true);
    if let Some(first) = scene.source.lines().next() {
        s.set_description(first.trim_start_matches("//").trim());
    }
    s
}

#[test]
fn every_scene_documents_what_it_covers() {
    for scene in scenes() {
        assert!(
            scene.source.starts_with("// "),
            "{}: the first line should be a `//` comment saying what the scene covers",
            scene.path.display()
        );
    }
}

#[test]
fn lowered_ir_snapshots() {
    for scene in scenes() {
        let c = compile(&scene.stem, &scene.source, &Options::default());
        let text = sdfc_ir::dump::scene_text(&c.stages.lowered);
        settings_for(&scene).bind(|| {
            insta::assert_snapshot!(format!("{}.ir", scene.stem), text);
        });
    }
}

#[test]
fn optimised_ir_snapshots() {
    for scene in scenes() {
        let c = compile(&scene.stem, &scene.source, &Options::default());
        let text = opt_ir(&c);
        settings_for(&scene).bind(|| {
            insta::assert_snapshot!(format!("{}.opt-ir", scene.stem), text);
        });
    }
}

#[test]
fn wgsl_snapshots_validate() {
    for scene in scenes() {
        let c = compile(&scene.stem, &scene.source, &Options::default());
        if let Err(report) = sdfc_wgsl::validate::validate(&format!("{}.wgsl", scene.stem), &c.wgsl)
        {
            panic!("{}: emitted WGSL does not validate:\n{report}", scene.stem);
        }
        assert!(
            c.wgsl.contains("@compute"),
            "{}: no entry point",
            scene.stem
        );
        assert!(
            c.wgsl.contains("fn scene_distance(p: vec3<f32>) -> f32"),
            "{}: no scene_distance",
            scene.stem
        );
        settings_for(&scene).bind(|| {
            insta::assert_snapshot!(format!("{}.wgsl", scene.stem), c.wgsl);
        });
    }
}

#[test]
fn library_form_validates_and_matches_the_full_shader() {
    for scene in scenes() {
        let full = compile(&scene.stem, &scene.source, &Options::default());
        let lib_opts = Options {
            lib: true,
            import_path: None,
            cull: false,
            instances: sdfc_wgsl::Instances::Never,
        };
        let lib = compile(&scene.stem, &scene.source, &lib_opts);
        if let Err(report) =
            sdfc_wgsl::validate::validate(&format!("{}.lib.wgsl", scene.stem), &lib.wgsl)
        {
            panic!("{}: library WGSL does not validate:\n{report}", scene.stem);
        }
        for absent in ["@compute", "@group", "@binding", "fn main("] {
            assert!(
                !lib.wgsl.contains(absent),
                "{}: the library form contains `{absent}`",
                scene.stem
            );
        }
        for sig in [
            "fn scene_distance(p: vec3<f32>) -> f32",
            "fn scene_material(p: vec3<f32>) -> SceneMaterial",
        ] {
            assert_eq!(
                function_text(&lib.wgsl, sig),
                function_text(&full.wgsl, sig),
                "{}: `{sig}` differs between the library form and the full shader",
                scene.stem
            );
        }
        assert!(
            !lib.wgsl.starts_with("#define_import_path"),
            "{}: import path line without an import path",
            scene.stem
        );
    }
}

#[test]
fn library_form_with_import_path() {
    for scene in scenes() {
        let opts = Options {
            lib: true,
            import_path: Some("my::scene".into()),
            cull: false,
            instances: sdfc_wgsl::Instances::Never,
        };
        let with_path = compile(&scene.stem, &scene.source, &opts);
        let plain = compile(
            &scene.stem,
            &scene.source,
            &Options {
                lib: true,
                import_path: None,
                cull: false,
                instances: sdfc_wgsl::Instances::Never,
            },
        );
        let first = with_path.wgsl.lines().next().unwrap_or_default();
        assert_eq!(first, "#define_import_path my::scene", "{}", scene.stem);
        // The import line is not WGSL; what follows it is the plain library form.
        let rest = with_path
            .wgsl
            .strip_prefix("#define_import_path my::scene\n")
            .unwrap_or_default();
        assert_eq!(rest.trim_start(), plain.wgsl.trim_start(), "{}", scene.stem);
    }
}

/// An import path only means something in the library form; without `lib` it used to be
/// ignored silently, and is now the caller's mistake (as `sdfc compile` has always said).
#[test]
fn import_path_without_lib_is_refused() {
    let scene = &scenes()[0];
    let opts = Options {
        lib: false,
        import_path: Some("my::scene".into()),
        cull: false,
        instances: sdfc_wgsl::Instances::Never,
    };
    match sdfc_wgsl::compile(&scene.source, &opts) {
        Err(Failure::Usage(m)) => assert!(m.contains("library form"), "{m}"),
        other => panic!("{:?}", other.map(|c| c.wgsl.len())),
    }
}

#[test]
fn compiling_is_deterministic() {
    for scene in scenes() {
        let a = compile(&scene.stem, &scene.source, &Options::default());
        // The second compilation runs on another thread, after other work, to shake out any
        // dependence on hash seeds, addresses or thread-local state.
        let src = scene.source.clone();
        let b = std::thread::spawn(move || {
            let _warm_up = sdfc_wgsl::compile("scene = box(2) | sphere(3);", &Options::default());
            sdfc_wgsl::compile(&src, &Options::default())
        })
        .join()
        .expect("compiler thread")
        .unwrap_or_else(|_| panic!("{} failed to compile the second time", scene.stem));
        assert!(
            a.wgsl == b.wgsl,
            "{}: WGSL differs between two compilations",
            scene.stem
        );
        assert_eq!(
            opt_ir(&a),
            opt_ir(&b),
            "{}: optimised IR differs",
            scene.stem
        );
        assert_eq!(
            sdfc_ir::dump::scene_text(&a.stages.lowered),
            sdfc_ir::dump::scene_text(&b.stages.lowered),
            "{}: lowered IR differs",
            scene.stem
        );
        assert_eq!(a.warnings, b.warnings, "{}: warnings differ", scene.stem);
    }
}

#[test]
fn identity_transforms_emit_identical_wgsl() {
    let read = |name: &str| {
        let path = sdfc_tests::root().join("scenes").join(name);
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    };
    let (a_src, b_src) = (read("identity_a.sdf"), read("identity_b.sdf"));
    let code = |s: &str| -> String { s.lines().filter(|l| !l.starts_with("//")).collect() };
    assert_eq!(code(&a_src), "scene = sphere(1);");
    assert_eq!(
        code(&b_src),
        "scene = sphere(1).translate([0,0,0]).rotate_y(0).scale(1);"
    );
    for opts in [
        Options::default(),
        Options {
            lib: true,
            import_path: None,
            cull: false,
            instances: sdfc_wgsl::Instances::Never,
        },
    ] {
        let a = compile("identity_a", &a_src, &opts);
        let b = compile("identity_b", &b_src, &opts);
        assert!(
            a.wgsl == b.wgsl,
            "identity transforms change the WGSL (lib: {}):\n--- a ---\n{}\n--- b ---\n{}",
            opts.lib,
            a.wgsl,
            b.wgsl
        );
    }
}

fn rendered(scene: &Scene, diags: &[Diagnostic]) -> String {
    diag::render(&format!("{}.sdf", scene.stem), &scene.source, diags)
}

#[test]
fn no_scene_draws_a_warning() {
    for scene in scenes() {
        let c = compile(&scene.stem, &scene.source, &Options::default());
        assert!(
            c.warnings.is_empty(),
            "{}: unexpected diagnostics:\n{}",
            scene.stem,
            rendered(&scene, &c.warnings)
        );
    }
}

#[test]
fn scene_files_are_found_relative_to_the_crate() {
    let root = sdfc_tests::root();
    assert!(Path::new(&root).join("scenes").is_dir());
    assert!(Path::new(&root).join("errors").is_dir());
}

/// A culled union's WGSL (`--cull`): 64 spheres on an 8x8 grid split into 8 parts and those
/// into leaves, each guarded by its box against the best distance so far and handed that best
/// (`best: f32`), with the part's reach as a cut. Reviewed as text; naga validates it inside
/// `compile`.
#[test]
fn culled_union_wgsl() {
    let mut src = String::from("scene = union(\n");
    for i in 0..64 {
        src += &format!("    sphere(0.4).translate([{}, 0, {}]),\n", i % 8, i / 8);
    }
    src += ");\n";
    let opts = Options {
        cull: true,
        ..Options::default()
    };
    let c = compile("culled_union", &src, &opts);
    // From the first group function to the end of `scene_distance`.
    let start = c.wgsl.find("fn scene_group0(").expect("group functions");
    let dist = c.wgsl.find("fn scene_distance(").expect("scene_distance");
    let end = dist + c.wgsl[dist..].find("\n}\n").expect("its end") + 3;
    let funcs = &c.wgsl[start..end];
    assert!(
        funcs.contains("best: f32"),
        "no part takes the best distance"
    );
    insta::assert_snapshot!("culled_union.wgsl", funcs);
}

/// A union emitted as data (`--instances`): 20 shapes of two kinds (spheres of two radii,
/// boxes) under moves, turns and scales, in three materials. The shader's scene part (the
/// kinds' functions and their switch, the materials' lookup and the walk) is reviewed as
/// text; naga validates it inside `compile`. The data holds 39 nodes of two vec4 and 20
/// records: a sphere's three vec4 (quaternion; centre and scale; kind, material, radius), a
/// box's four (its size runs into the fourth).
#[test]
fn instances_union_wgsl() {
    let mut src = String::from(
        "material red { color: [0.9, 0.2, 0.1] }\nmaterial blue { color: [0.1, 0.2, 0.9], specular: 0.3 }\nscene = union(\n",
    );
    for i in 0..20 {
        let shape = match i % 4 {
            0 => "sphere(0.4)".to_string(),
            1 => "sphere(0.3).material(blue)".to_string(),
            _ => format!(
                "box([0.5, 0.3, 0.4]).rotate_y({}deg).scale(1.5).material(red)",
                10 * i
            ),
        };
        src += &format!("    {shape}.translate([{}, 0, {}]),\n", i % 5, i / 5);
    }
    src += ");\n";
    let opts = Options {
        instances: sdfc_wgsl::Instances::Always,
        ..Options::default()
    };
    let c = compile("instances_union", &src, &opts);
    assert_eq!(
        c.data.len(),
        32 * 39 + 10 * 48 + 10 * 64,
        "nodes and records"
    );
    let start = c
        .wgsl
        .find("fn instance_shape0(")
        .expect("template functions");
    let start = c.wgsl[..start].rfind("\n\n").expect("its comment") + 2;
    let mat = c.wgsl.find("fn scene_material(").expect("scene_material");
    let end = mat + c.wgsl[mat..].find("\n}\n").expect("its end") + 3;
    insta::assert_snapshot!("instances_union.wgsl", &c.wgsl[start..end]);
    // Each march lists the instances its ray passes first (`shaders/instances_rays.wgsl`),
    // then marches them one by one, each alone, in one loop with the refinement
    // (`shaders/march_instances.wgsl`), listing again where a full list left nodes out; the
    // tetrahedron normal samples the instance the march hit, alone, which is also the
    // material's (`end_leaf`).
    assert!(c
        .wgsl
        .contains("ray_start(ro, rd, span.x, best, pixel, 0.0, start);"));
    assert_eq!(
        c.wgsl
            .matches("instance_distance(ro + rd * t, leaf)")
            .count(),
        1
    );
    assert!(!c.wgsl.contains("fn march_rest("));
    assert!(c.wgsl.contains("let leaf = ray_end_leaf;"));
    assert!(!c.wgsl.contains("normal_nearest(end)"));
    assert!(c.wgsl.contains("normal_sample(p + k[i] * h, leaf)"));
    assert!(c
        .wgsl
        .contains("select(0.0, instance_distance(p, max(leaf, 1u)), leaf != 0u)"));
    assert!(c.wgsl.contains("return ray_end_leaf;"));
    // Without the option, the same scene is code.
    let code = compile("instances_union", &src, &Options::default());
    assert!(code.data.is_empty() && !code.wgsl.contains("scene_data"));
    // With a floor whose height is a param, and a shell: a mixed union, those two emitted
    // as code beside the walk (`rest_distance`, `rest_material`), the param read from the
    // frame. The other children's functions and the scene functions are reviewed as text.
    let mixed = src.replace(
        "scene = union(\n",
        "param floor = 1;\nscene = union(\n    plane([0, 1, 0], floor),\n    sphere(0.5).onion(0.05),\n",
    );
    let c = compile("instances_mixed", &mixed, &opts);
    assert_eq!(
        c.data.len(),
        32 * 39 + 10 * 48 + 10 * 64,
        "the same instances"
    );
    assert!(c.wgsl.contains("scene_params = frame.params;"));
    // The other children are marched first, alone (`march_rest`, a plane's and a shell's
    // cheap distance: refined in a loop of its own, the plane's distance along the ray),
    // then the listed instances one by one up to their hit; the tetrahedron normal samples
    // what the march hit.
    assert!(c.wgsl.contains("let rest = march_rest(ro, rd, pixel);"));
    assert!(c
        .wgsl
        .contains("ray_start(ro, rd, span.x, best, pixel, 0.0, start);"));
    assert_eq!(
        c.wgsl.matches("rest_distance_ray(ro + rd * t, rd)").count(),
        2
    );
    assert_eq!(
        c.wgsl
            .matches("instance_distance(ro + rd * t, leaf)")
            .count(),
        1
    );
    assert!(c.wgsl.contains("let leaf = ray_end_leaf;"));
    assert!(c
        .wgsl
        .contains("select(rest_distance(p), instance_distance(p, max(leaf, 1u)), leaf != 0u)"));
    let cut = |from: &str, to: &str| {
        let start = c.wgsl.find(from).expect(from);
        let start = c.wgsl[..start].rfind("\n\n").expect("its comment") + 2;
        let last = c.wgsl.find(to).expect(to);
        let end = last + c.wgsl[last..].find("\n}\n").expect("its end") + 3;
        c.wgsl[start..end].to_string()
    };
    let text = cut("fn rest_distance(", "fn rest_material(")
        + "\n"
        + &cut("fn scene_distance(", "fn scene_material(")
        + "\n"
        + &cut("fn normal_sample(", "fn normal_sample(");
    insta::assert_snapshot!("instances_mixed.wgsl", text);
}
