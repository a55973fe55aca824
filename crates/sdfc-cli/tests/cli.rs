//! End-to-end tests of the `sdfc` binary against the CLI contract (`shared/spec/cli.md`):
//! outputs, files written, exit statuses (0 ok, 1 a problem in the input, 2 usage or
//! environment), and never a panic or a backtrace. `render` and `bench` have their own tests in `render.rs`; the output streams in `streams.rs`.

mod common;

use common::{eval_lines, s, sdfc_in, TempDir};
use std::path::Path;

const SPEC_SECTION10: &str = "\
// The tutorials' sphere-and-box studies, with light, shadow and a floor.
material red   { color: [0.9, 0.2, 0.15], specular: 0.6, shininess: 48 }
material floor { color: [0.7, 0.7, 0.7], reflectivity: 0.2 }

camera { position: [0, 1.5, 5], target: [0, 0.5, 0], fov: 50deg }
light point { position: [4, 6, -3], color: [1, 0.95, 0.9], intensity: 1.2 }
render { shadows: soft(16), ao: ao(samples: 5), reflections: 1, background: [0.55, 0.7, 0.9] }

fn ribbed(r) = sphere(r).displace(|p| sin(30 * p.y) / 16, lipschitz: 2.875);

let blob = union(ribbed(1), box([1.4, 1.4, 1.4]).rotate_y(30deg), smooth: 0.3);

scene = blob.material(red).translate([0, 1, 0])
      | plane([0, 1, 0], 0).material(floor)
      | sphere(0.3).repeat([3, 0, 3]).translate([0, 0.3, -6]);
";

const SPHERE: &str = "scene = sphere(1);\n";
const PARAM_SPHERE: &str = "param r = 1;\nparam c = [0, 0, 0];\nscene = sphere(r).translate(c);\n";
const BROKEN: &str = "let r = 1;\nscene = spher(r);\n";

fn validate(wgsl: &str) {
    if let Err(report) = sdfc_wgsl::validate::validate("out.wgsl", wgsl) {
        panic!("the WGSL does not validate:\n{report}\n--- WGSL ---\n{wgsl}");
    }
}

// ---- compile ----

#[test]
fn compile_to_stdout_is_valid_wgsl() {
    let t = TempDir::new("compile-stdout");
    let scene = t.write("scene.sdf", SPEC_SECTION10);
    let run = sdfc_in(&t.0, &["compile", s(&scene)]).expect_code(0);
    validate(&run.stdout);
    assert!(run.stdout.contains("@compute"));
    assert!(run
        .stdout
        .contains("fn scene_distance(p: vec3<f32>) -> f32"));
    // Shadows, ao and reflections are all rendered: no diagnostic at all.
    assert!(run.stderr.is_empty(), "{}", run.describe());
}

#[test]
fn compile_with_output_file_writes_it() {
    let t = TempDir::new("compile-o");
    let scene = t.write("scene.sdf", SPHERE);
    let out = t.path("out.wgsl");
    let run = sdfc_in(&t.0, &["compile", s(&scene), "-o", s(&out)]).expect_code(0);
    assert!(run.stdout.is_empty(), "{}", run.describe());
    let written = std::fs::read_to_string(&out).expect("the output file is written");
    validate(&written);
    // The same text as on stdout.
    let to_stdout = sdfc_in(&t.0, &["compile", s(&scene)]).expect_code(0);
    assert_eq!(written, to_stdout.stdout);
    // The long form of the option too.
    let out2 = t.path("out2.wgsl");
    sdfc_in(&t.0, &["compile", s(&scene), "--output", s(&out2)]).expect_code(0);
    assert_eq!(std::fs::read_to_string(&out2).expect("written"), written);
}

/// `--instances --data OUT.bin`: a union of many constant shapes is compiled to WGSL that
/// reads it from the buffer at binding 3, and the buffer's bytes are written, as the
/// library compiles them; a scene without such a union is compiled as code, with a note and
/// no data file; `--instances` needs `--data`, and does not go with `--lib` or `--cull`.
#[test]
fn compile_instances_writes_the_wgsl_and_its_data() {
    let t = TempDir::new("compile-instances");
    let grid_src = sdfc_tests::grid_scene(40);
    let grid = t.write("grid.sdf", &grid_src);
    let (out, data) = (t.path("grid.wgsl"), t.path("grid.bin"));
    let args = ["--instances", "--data", s(&data), "-o", s(&out)];
    let run = sdfc_in(&t.0, &[&["compile", s(&grid)][..], &args].concat()).expect_code(0);
    assert!(run.stderr.is_empty(), "{}", run.describe());
    let wgsl = std::fs::read_to_string(&out).expect("the WGSL is written");
    validate(&wgsl);
    assert!(wgsl.contains("@group(0) @binding(3) var<storage, read> scene_data"));
    let opts = sdfc_wgsl::Options {
        instances: sdfc_wgsl::Instances::Always,
        ..Default::default()
    };
    let library = sdfc_wgsl::compile(&grid_src, &opts).unwrap();
    assert_eq!(wgsl, library.wgsl);
    let bytes = std::fs::read(&data).expect("the data is written");
    assert!(!bytes.is_empty() && bytes.len() % 16 == 0);
    assert_eq!(bytes, library.data);

    let sphere = t.write("sphere.sdf", SPHERE);
    let none = t.path("sphere.bin");
    let run = sdfc_in(
        &t.0,
        &["compile", s(&sphere), "--instances", "--data", s(&none)],
    )
    .expect_code(0);
    validate(&run.stdout);
    assert!(
        run.stderr.contains("no data file is written"),
        "{}",
        run.describe()
    );
    assert!(!none.exists());

    for wrong in [
        &["--instances"][..],
        &["--instances", "--data", s(&data), "--lib"],
        &["--instances", "--data", s(&data), "--cull"],
        &["--instances", "--data", s(&data), "--emit", "ir"],
    ] {
        sdfc_in(&t.0, &[&["compile", s(&grid)][..], wrong].concat()).expect_code(2);
    }
}

#[test]
fn compile_lib_has_functions_and_no_entry_point() {
    let t = TempDir::new("compile-lib");
    let scene = t.write("scene.sdf", SPEC_SECTION10);
    let run = sdfc_in(&t.0, &["compile", s(&scene), "--lib"]).expect_code(0);
    validate(&run.stdout);
    assert!(!run.stdout.contains("@compute"), "{}", run.stdout);
    assert!(!run.stdout.contains("@group"), "{}", run.stdout);
    assert!(run
        .stdout
        .contains("fn scene_distance(p: vec3<f32>) -> f32"));
    assert!(run
        .stdout
        .contains("fn scene_material(p: vec3<f32>) -> SceneMaterial"));
    assert!(!run.stdout.contains("#define_import_path"));
}

#[test]
fn compile_lib_with_import_path() {
    let t = TempDir::new("compile-import");
    let scene = t.write("scene.sdf", PARAM_SPHERE);
    let run = sdfc_in(
        &t.0,
        &["compile", s(&scene), "--lib", "--import-path", "my::scene"],
    )
    .expect_code(0);
    assert_eq!(
        run.stdout.lines().next(),
        Some("#define_import_path my::scene")
    );
    assert!(!run.stdout.contains("@compute"));
    assert!(run
        .stdout
        .contains("fn scene_distance(p: vec3<f32>) -> f32"));
    // Without the import line the rest is the plain library form.
    let plain = sdfc_in(&t.0, &["compile", s(&scene), "--lib"]).expect_code(0);
    let rest = run
        .stdout
        .strip_prefix("#define_import_path my::scene\n")
        .unwrap_or_default();
    assert_eq!(rest.trim_start(), plain.stdout.trim_start());
    // `check` accepts the library file, import line and all.
    let lib_file = t.write("lib.wgsl", &run.stdout);
    let check = sdfc_in(&t.0, &["check", s(&lib_file)]).expect_code(0);
    assert!(check.stdout.starts_with("ok"), "{}", check.describe());
}

/// An import path that naga_oil cannot read (or a newline, which made the written module
/// invalid after it was validated) is a usage error, and nothing is written.
#[test]
fn compile_lib_refuses_a_malformed_import_path() {
    let t = TempDir::new("compile-import-bad");
    let scene = t.write("scene.sdf", SPHERE);
    for bad in ["a\nb", "a b", "", "my::", "::a", "1st", "a-b"] {
        let run =
            sdfc_in(&t.0, &["compile", s(&scene), "--lib", "--import-path", bad]).expect_code(2);
        assert!(run.stdout.is_empty(), "{bad:?}: {}", run.describe());
        assert!(
            run.stderr.contains("identifiers joined by `::`"),
            "{bad:?}: {}",
            run.describe()
        );
    }
    sdfc_in(
        &t.0,
        &["compile", s(&scene), "--lib", "--import-path", "_a::b2::C"],
    )
    .expect_code(0);
}

/// `--lib` shapes the WGSL only; with another `--emit` it would be silently ignored.
#[test]
fn compile_lib_with_another_emit_is_a_usage_error() {
    let t = TempDir::new("compile-lib-emit");
    let scene = t.write("scene.sdf", SPHERE);
    for emit in ["ast", "ir", "opt-ir"] {
        let run = sdfc_in(&t.0, &["compile", s(&scene), "--lib", "--emit", emit]).expect_code(2);
        assert!(run.stdout.is_empty(), "{emit}: {}", run.describe());
    }
}

/// The library form's header names only the globals the module declares.
#[test]
fn compile_lib_header_names_what_the_module_has() {
    let t = TempDir::new("compile-lib-header");
    for (src, names) in [
        (SPHERE, "the functions need no setup"),
        (PARAM_SPHERE, "set `scene_params` before calling"),
        (
            "scene = sphere(1 + time);\n",
            "set `scene_time` before calling",
        ),
        (
            "param r = 1;\nscene = sphere(r + time);\n",
            "set `scene_time` and `scene_params`",
        ),
    ] {
        let scene = t.write("scene.sdf", src);
        let run = sdfc_in(&t.0, &["compile", s(&scene), "--lib"]).expect_code(0);
        assert!(run.stdout.contains(names), "{src}: {}", run.describe());
        for global in ["scene_time", "scene_params"] {
            let declared = run.stdout.contains(&format!("var<private> {global}"));
            let named = run
                .stdout
                .lines()
                .nth(1)
                .unwrap_or_default()
                .contains(global);
            assert_eq!(declared, named, "{src} {global}: {}", run.describe());
        }
    }
}

#[test]
fn compile_explain_lists_the_non_exact_nodes() {
    let t = TempDir::new("explain");
    let scene = t.write(
        "scene.sdf",
        "scene = sphere(1)\n      | box([1, 3, 1]).twist(1.5).translate([3, 0, 0]);\n",
    );
    let run = sdfc_in(&t.0, &["compile", s(&scene), "--explain"]).expect_code(0);
    validate(&run.stdout);
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert!(
        lines
            .first()
            .is_some_and(|l| l.starts_with("scene: bound, L = 1")),
        "{}",
        run.describe()
    );
    // The twist, at its line and column, with the constant from the box's bounding radius
    // (L = t + sqrt(1 + t^2), t = 1.5 * sqrt(0.5) / 2).
    let t2 = 1.5 * 0.5f64.sqrt() / 2.0;
    let l = t2 + (1.0 + t2 * t2).sqrt();
    let want = format!("2:9: twist: bound, L = {l:.4}");
    assert!(
        lines.iter().any(|x| x.starts_with(&want)),
        "no `{want}` in:\n{}",
        run.stderr
    );
    // The sphere is exact: no line for it.
    assert!(!run.stderr.contains("sphere"), "{}", run.stderr);
    // An exact scene: one line, nothing else.
    let exact = t.write("exact.sdf", SPHERE);
    let run = sdfc_in(&t.0, &["compile", s(&exact), "--explain"]).expect_code(0);
    assert_eq!(run.stderr, "scene: exact, L = 1 (no bound-only node)\n");
    // Without --explain, nothing on stderr.
    let run = sdfc_in(&t.0, &["compile", s(&scene)]).expect_code(0);
    assert!(run.stderr.is_empty(), "{}", run.describe());
}

#[test]
fn compile_warns_about_a_contradicted_lipschitz_bound() {
    let t = TempDir::new("lipschitz-warning");
    let scene = t.write(
        "scene.sdf",
        "scene = sphere(1).displace(|p| sin(30 * p.y) / 8, lipschitz: 2.875);\n",
    );
    // A warning, not an error: the WGSL is still written and the exit status is 0.
    let run = sdfc_in(&t.0, &["compile", s(&scene)]).expect_code(0);
    validate(&run.stdout);
    assert!(run.stderr.contains("warning"), "{}", run.describe());
    assert!(run.stderr.contains("scene.sdf:1:62"), "{}", run.describe());
    assert!(
        run.stderr
            .contains("declared Lipschitz bound 2.875 of `displace` is too small"),
        "{}",
        run.describe()
    );
    // The displaced distance's slope is at most 1 + 30/8 = 4.75, and sampling finds close to
    // that (a difference quotient never exceeds the true bound): the hint asks for a value
    // from 4.5 to 4.75.
    let hint = run
        .stderr
        .split("use `lipschitz: ")
        .nth(1)
        .and_then(|r| r.split('`').next())
        .and_then(|x| x.parse::<f64>().ok())
        .unwrap_or_else(|| panic!("no hint with a number: {}", run.describe()));
    assert!(
        (4.5..=4.75).contains(&hint),
        "hint {hint}: {}",
        run.describe()
    );
}

#[test]
fn import_path_without_lib_is_a_usage_error() {
    let t = TempDir::new("import-no-lib");
    let scene = t.write("scene.sdf", SPHERE);
    let run = sdfc_in(&t.0, &["compile", s(&scene), "--import-path", "my::scene"]).expect_code(2);
    assert!(run.stdout.is_empty(), "{}", run.describe());
    assert!(run.stderr.contains("--lib"), "{}", run.describe());
}

#[test]
fn compile_emit_stages() {
    let t = TempDir::new("emit");
    let scene = t.write("scene.sdf", SPEC_SECTION10);
    let ast = sdfc_in(&t.0, &["compile", s(&scene), "--emit", "ast"]).expect_code(0);
    assert!(ast.stdout.starts_with("(file"), "{}", ast.describe());
    assert!(ast.stdout.contains("ribbed"));
    let ir = sdfc_in(&t.0, &["compile", s(&scene), "--emit", "ir"]).expect_code(0);
    assert!(ir.stdout.contains("shapes\n"), "{}", ir.describe());
    assert!(ir.stdout.contains("displace"), "{}", ir.describe());
    assert!(ir.stdout.contains("material 1 (red)"), "{}", ir.describe());
    let opt = sdfc_in(&t.0, &["compile", s(&scene), "--emit", "opt-ir"]).expect_code(0);
    assert!(
        opt.stdout.contains("fn scene_distance ("),
        "{}",
        opt.describe()
    );
    assert!(
        opt.stdout.contains("fn scene_material ("),
        "{}",
        opt.describe()
    );
    let wgsl = sdfc_in(&t.0, &["compile", s(&scene), "--emit", "wgsl"]).expect_code(0);
    validate(&wgsl.stdout);
    // `--emit` with `-o` writes the stage to the file.
    let out = t.path("scene.ir");
    sdfc_in(&t.0, &["compile", s(&scene), "--emit", "ir", "-o", s(&out)]).expect_code(0);
    assert_eq!(std::fs::read_to_string(&out).expect("written"), ir.stdout);
    // An unknown stage is a usage error.
    sdfc_in(&t.0, &["compile", s(&scene), "--emit", "llvm"]).expect_code(2);
}

#[test]
fn emit_ast_of_a_syntax_error_is_an_input_error() {
    let t = TempDir::new("emit-ast-err");
    let scene = t.write("bad.sdf", "let r = 1\nscene = sphere(r);\n");
    let run = sdfc_in(&t.0, &["compile", s(&scene), "--emit", "ast"]).expect_code(1);
    assert!(run.stdout.is_empty(), "{}", run.describe());
    assert!(run.stderr.contains("error"), "{}", run.describe());
}

#[test]
fn compile_broken_scene_reports_a_located_diagnostic() {
    let t = TempDir::new("compile-broken");
    t.write("broken.sdf", BROKEN);
    let run = sdfc_in(&t.0, &["compile", "broken.sdf"]).expect_code(1);
    assert!(run.stdout.is_empty(), "{}", run.describe());
    insta::assert_snapshot!("compile_broken_stderr", run.stderr);
}

#[test]
fn compile_output_to_unwritable_place_is_an_environment_error() {
    let t = TempDir::new("compile-unwritable");
    let scene = t.write("scene.sdf", SPHERE);
    let out = t.path("no/such/dir/out.wgsl");
    let run = sdfc_in(&t.0, &["compile", s(&scene), "-o", s(&out)]).expect_code(2);
    assert!(run.stderr.contains("cannot write"), "{}", run.describe());
}

#[test]
fn unreadable_files_are_environment_errors() {
    let t = TempDir::new("unreadable");
    let missing = t.path("missing.sdf");
    let run = sdfc_in(&t.0, &["compile", s(&missing)]).expect_code(2);
    assert!(run.stderr.contains("missing.sdf"), "{}", run.describe());
    sdfc_in(&t.0, &["check", s(&missing)]).expect_code(2);
    let pts = t.write("pts.csv", "0,0,0\n");
    sdfc_in(&t.0, &["eval", s(&missing), "--points", s(&pts)]).expect_code(2);
    // A directory is not a readable scene either.
    sdfc_in(&t.0, &["compile", s(&t.0)]).expect_code(2);
}

#[test]
fn invalid_utf8_is_an_input_error() {
    let t = TempDir::new("utf8");
    let scene = t.write("latin1.sdf", b"// caf\xe9\nscene = sphere(1);\n");
    let run = sdfc_in(&t.0, &["compile", s(&scene)]).expect_code(1);
    assert!(run.stderr.contains("UTF-8"), "{}", run.describe());
    assert!(run.stderr.contains(":1:"), "{}", run.describe());
}

// ---- check ----

#[test]
fn check_accepts_the_spec_scene_and_valid_wgsl() {
    let t = TempDir::new("check-ok");
    let scene = t.write("spec.sdf", SPEC_SECTION10);
    let compiled = sdfc_in(&t.0, &["compile", s(&scene)]).expect_code(0);
    let wgsl = t.write("spec.wgsl", &compiled.stdout);
    let run = sdfc_in(&t.0, &["check", s(&scene), s(&wgsl)]).expect_code(0);
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert_eq!(lines.len(), 2, "{}", run.describe());
    assert!(
        lines[0].starts_with("ok") && lines[0].ends_with("spec.sdf"),
        "{}",
        run.describe()
    );
    assert!(
        lines[1].starts_with("ok") && lines[1].ends_with("spec.wgsl"),
        "{}",
        run.describe()
    );
}

#[test]
fn check_rejects_broken_wgsl() {
    let t = TempDir::new("check-bad-wgsl");
    let wgsl = t.write("bad.wgsl", "fn f() -> f32 { return 1u; }\n");
    let run = sdfc_in(&t.0, &["check", s(&wgsl)]).expect_code(1);
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert_eq!(lines.len(), 1, "{}", run.describe());
    assert!(
        lines[0].starts_with("error") && lines[0].contains("bad.wgsl"),
        "{}",
        run.describe()
    );
    assert!(
        !run.stderr.is_empty(),
        "naga's report goes to stderr:\n{}",
        run.describe()
    );
    // The line names the place and the problem.
    assert!(
        lines[0].contains("bad.wgsl:1:") && lines[0].contains("invalid WGSL: "),
        "{}",
        run.describe()
    );
    // A syntax error, too.
    let syntax = t.write("syntax.wgsl", "fn f( {\n");
    let run = sdfc_in(&t.0, &["check", s(&syntax)]).expect_code(1);
    assert!(run.stdout.contains("syntax.wgsl:1:"), "{}", run.describe());
    // The extension in upper case is a shader still, not a scene.
    let upper = t.write("UPPER.WGSL", "fn f() -> f32 { return 1.0; }\n");
    let run = sdfc_in(&t.0, &["check", s(&upper)]).expect_code(0);
    assert!(run.stdout.starts_with("ok"), "{}", run.describe());
}

#[test]
fn check_rejects_a_broken_scene_with_one_line_per_file() {
    let t = TempDir::new("check-bad-sdf");
    t.write("good.sdf", SPHERE);
    t.write("broken.sdf", BROKEN);
    t.write("also_good.sdf", PARAM_SPHERE);
    let run = sdfc_in(&t.0, &["check", "good.sdf", "broken.sdf", "also_good.sdf"]).expect_code(1);
    // stdout: exactly one line per file, in order; diagnostics go to stderr.
    insta::assert_snapshot!("check_mixed_stdout", run.stdout);
    assert!(run.stderr.contains("broken.sdf:2:9"), "{}", run.describe());
    assert!(
        run.stderr.contains("did you mean `sphere`?"),
        "{}",
        run.describe()
    );
}

#[test]
fn check_reports_every_kind_of_failure_with_the_worst_status() {
    let t = TempDir::new("check-worst");
    let good = t.write("good.sdf", SPHERE);
    let broken = t.write("broken.sdf", BROKEN);
    let missing = t.path("missing.sdf");
    // An unreadable file outranks an input error: exit 2, still one line per file.
    let run = sdfc_in(&t.0, &["check", s(&good), s(&broken), s(&missing)]).expect_code(2);
    assert_eq!(run.stdout.lines().count(), 3, "{}", run.describe());
}

#[test]
fn check_without_files_is_a_usage_error() {
    let t = TempDir::new("check-none");
    sdfc_in(&t.0, &["check"]).expect_code(2);
}

// ---- eval ----

#[test]
fn eval_prints_exact_distances() {
    let t = TempDir::new("eval");
    let scene = t.write("sphere.sdf", SPHERE);
    let pts = t.write(
        "pts.csv",
        "3,0,0\n0,0,0\n# a comment line\n\n0, 2 ,0\n1e0,0,0\n0,0,-0.25\n-4,3,0\n",
    );
    let run = sdfc_in(&t.0, &["eval", s(&scene), "--points", s(&pts)]).expect_code(0);
    assert_eq!(
        eval_lines(&run),
        vec![2.0, -1.0, 1.0, 0.0, -0.75, 4.0],
        "{}",
        run.describe()
    );
    // Full precision: a value that is not short in decimal keeps all its digits.
    let pts2 = t.write("pts2.csv", "1,1,1\n");
    let run = sdfc_in(&t.0, &["eval", s(&scene), "--points", s(&pts2)]).expect_code(0);
    assert_eq!(
        eval_lines(&run),
        vec![3f64.sqrt() - 1.0],
        "{}",
        run.describe()
    );
}

#[test]
fn eval_with_param_overrides() {
    let t = TempDir::new("eval-param");
    let scene = t.write("sphere.sdf", PARAM_SPHERE);
    let pts = t.write("pts.csv", "3,0,0\n0,0,0\n");
    let run = sdfc_in(&t.0, &["eval", s(&scene), "--points", s(&pts)]).expect_code(0);
    assert_eq!(eval_lines(&run), vec![2.0, -1.0]);
    let run = sdfc_in(
        &t.0,
        &["eval", s(&scene), "--points", s(&pts), "--param", "r=2"],
    )
    .expect_code(0);
    assert_eq!(eval_lines(&run), vec![1.0, -2.0], "{}", run.describe());
    let run = sdfc_in(
        &t.0,
        &[
            "eval",
            s(&scene),
            "--points",
            s(&pts),
            "--param",
            "r=2",
            "--param",
            "c=3,0,0",
        ],
    )
    .expect_code(0);
    assert_eq!(eval_lines(&run), vec![-2.0, 1.0], "{}", run.describe());
    // Mistakes in the overrides.
    let run = sdfc_in(
        &t.0,
        &[
            "eval",
            s(&scene),
            "--points",
            s(&pts),
            "--param",
            "radius=2",
        ],
    )
    .expect_code(1);
    assert!(run.stderr.contains("radius"), "{}", run.describe());
    sdfc_in(
        &t.0,
        &["eval", s(&scene), "--points", s(&pts), "--param", "c=1,2"],
    )
    .expect_code(1);
    sdfc_in(
        &t.0,
        &["eval", s(&scene), "--points", s(&pts), "--param", "r=big"],
    )
    .expect_code(1);
    // Past the magnitude limit, as the renderer refuses it (here with no renderer).
    let run = sdfc_in(
        &t.0,
        &["eval", s(&scene), "--points", s(&pts), "--param", "r=1e20"],
    )
    .expect_code(1);
    assert!(
        run.stderr.contains("must be at most 1e12 in magnitude"),
        "{}",
        run.describe()
    );
}

#[test]
fn eval_with_time() {
    let t = TempDir::new("eval-time");
    let scene = t.write("moving.sdf", "scene = sphere(1).translate([time, 0, 0]);\n");
    let pts = t.write("pts.csv", "3,0,0\n");
    let run = sdfc_in(&t.0, &["eval", s(&scene), "--points", s(&pts)]).expect_code(0);
    assert_eq!(eval_lines(&run), vec![2.0]);
    let run = sdfc_in(
        &t.0,
        &["eval", s(&scene), "--points", s(&pts), "--time", "2"],
    )
    .expect_code(0);
    assert_eq!(eval_lines(&run), vec![0.0], "{}", run.describe());
    // A negative time as its own argument (clap took `-1` for a flag before).
    let run = sdfc_in(
        &t.0,
        &["eval", s(&scene), "--points", s(&pts), "--time", "-1"],
    )
    .expect_code(0);
    assert_eq!(eval_lines(&run), vec![3.0], "{}", run.describe());
}

#[test]
fn eval_bad_csv_line_is_an_input_error() {
    let t = TempDir::new("eval-bad-csv");
    let scene = t.write("sphere.sdf", SPHERE);
    for (i, bad) in ["3,0,0\n1,2\n", "3,0,0\nx,y,z\n", "3,0,0\n1,2,3,4\n"]
        .iter()
        .enumerate()
    {
        let pts = t.write(&format!("bad{i}.csv"), bad);
        let run = sdfc_in(&t.0, &["eval", s(&scene), "--points", s(&pts)]).expect_code(1);
        assert!(
            run.stderr.contains(&format!("bad{i}.csv:2:")),
            "{}",
            run.describe()
        );
        assert!(run.stderr.contains("hint: "), "{}", run.describe());
    }
    // The column is the first field that is not a number.
    let pts = t.write("field.csv", "1, 2, zz\n");
    let run = sdfc_in(&t.0, &["eval", s(&scene), "--points", s(&pts)]).expect_code(1);
    assert!(run.stderr.contains("field.csv:1:7)"), "{}", run.describe());
    // Invalid UTF-8 is a mistake in the input, placed like a scene's.
    let pts = t.write("utf8.csv", b"0,0,0\n1,\xff,0\n");
    let run = sdfc_in(&t.0, &["eval", s(&scene), "--points", s(&pts)]).expect_code(1);
    assert!(run.stderr.contains("utf8.csv:2:3"), "{}", run.describe());
}

/// A time that is not finite is refused before anything is evaluated, as by `render`: the
/// reference evaluator printed NaN for every point.
#[test]
fn eval_refuses_a_time_that_is_not_finite() {
    let t = TempDir::new("eval-time");
    let scene = t.write("sphere.sdf", "scene = sphere(1 + time);\n");
    let pts = t.write("pts.csv", "0,0,0\n");
    for time in ["inf", "NaN", "-inf"] {
        let run = sdfc_in(
            &t.0,
            &["eval", s(&scene), "--points", s(&pts), "--time", time],
        )
        .expect_code(2);
        assert!(run.stdout.is_empty(), "{time}: {}", run.describe());
    }
}

#[test]
fn eval_of_a_broken_scene_is_an_input_error() {
    let t = TempDir::new("eval-broken");
    let scene = t.write("broken.sdf", BROKEN);
    let pts = t.write("pts.csv", "0,0,0\n");
    let run = sdfc_in(&t.0, &["eval", s(&scene), "--points", s(&pts)]).expect_code(1);
    assert!(run.stdout.is_empty(), "{}", run.describe());
    assert!(
        run.stderr.contains("unknown function `spher`"),
        "{}",
        run.describe()
    );
}

#[test]
fn eval_missing_points_file_is_an_environment_error() {
    let t = TempDir::new("eval-no-points");
    let scene = t.write("sphere.sdf", SPHERE);
    sdfc_in(
        &t.0,
        &["eval", s(&scene), "--points", s(&t.path("none.csv"))],
    )
    .expect_code(2);
    // `--points` is required.
    sdfc_in(&t.0, &["eval", s(&scene)]).expect_code(2);
}

// ---- general ----

#[test]
fn usage_errors_exit_2_and_help_exits_0() {
    let t = TempDir::new("usage");
    sdfc_in(&t.0, &[]).expect_code(2);
    sdfc_in(&t.0, &["frobnicate"]).expect_code(2);
    sdfc_in(&t.0, &["compile"]).expect_code(2);
    sdfc_in(&t.0, &["compile", "a.sdf", "--no-such-flag"]).expect_code(2);
    let help = sdfc_in(&t.0, &["--help"]).expect_code(0);
    assert!(help.stdout.contains("compile"), "{}", help.describe());
    let version = sdfc_in(&t.0, &["--version"]).expect_code(0);
    assert!(
        version.stdout.starts_with("sdfc "),
        "{}",
        version.describe()
    );
}

/// The contract (shared/spec/cli.md): "`--size` defaults to 512x512", for every command that
/// takes it (drawing at that size takes minutes on a CPU, so the help is read instead).
#[test]
fn every_size_option_defaults_to_512x512() {
    let t = TempDir::new("sizes");
    for command in ["render", "bench"] {
        let help = sdfc_in(&t.0, &[command, "--help"]).expect_code(0);
        // The option's entry, from its line to the next option's, in one line: clap may wrap
        // the help text (and the default with it) at the terminal's width.
        let mut lines = help
            .stdout
            .lines()
            .skip_while(|l| !l.trim_start().starts_with("--size"));
        let first = lines
            .next()
            .unwrap_or_else(|| panic!("{command} has no --size: {}", help.describe()));
        let rest = lines.take_while(|l| !l.trim_start().starts_with('-'));
        let entry = std::iter::once(first)
            .chain(rest)
            .flat_map(str::split_whitespace)
            .collect::<Vec<_>>()
            .join(" ");
        assert!(entry.contains("[default: 512x512]"), "{command}: {entry}");
    }
}

#[test]
fn compile_every_scene_of_the_corpus() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(&scenes).expect("tests/scenes") {
        let path = entry.expect("dir entry").path();
        if path.extension().is_none_or(|e| e != "sdf") {
            continue;
        }
        n += 1;
        let run = sdfc_in(&scenes, &["compile", s(&path)]).expect_code(0);
        validate(&run.stdout);
        let lib = sdfc_in(&scenes, &["compile", s(&path), "--lib"]).expect_code(0);
        validate(&lib.stdout);
    }
    assert!(n >= 12, "found only {n} scenes in {}", scenes.display());
}

#[test]
fn every_broken_scene_fails_cleanly() {
    let errors = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/errors");
    let mut n = 0;
    for entry in std::fs::read_dir(&errors).expect("tests/errors") {
        let path = entry.expect("dir entry").path();
        if path.extension().is_none_or(|e| e != "sdf") {
            continue;
        }
        n += 1;
        let run = sdfc_in(&errors, &["compile", s(&path)]).expect_code(1);
        assert!(
            run.stdout.is_empty(),
            "{}: {}",
            path.display(),
            run.describe()
        );
        assert!(
            run.stderr.contains("error"),
            "{}: {}",
            path.display(),
            run.describe()
        );
        let check = sdfc_in(&errors, &["check", s(&path)]).expect_code(1);
        assert_eq!(
            check.stdout.lines().count(),
            1,
            "{}: {}",
            path.display(),
            check.describe()
        );
    }
    assert!(
        n >= 25,
        "found only {n} broken scenes in {}",
        errors.display()
    );
}

/// A non-finite constant in a translate offset or rotation angle is an input error (exit 1
/// with a diagnostic), not an internal one.
#[test]
fn non_finite_transform_constant_is_an_input_error() {
    let t = TempDir::new("non-finite");
    for (i, src) in [
        "scene = sphere(1).translate([1e30 * 1e30, 0, 0]);\n",
        "scene = sphere(1).translate([1 / 0, 0, 0]);\n",
        "scene = sphere(1).rotate_y(1 / 0);\n",
    ]
    .iter()
    .enumerate()
    {
        let scene = t.write(&format!("inf{i}.sdf"), src);
        let run = sdfc_in(&t.0, &["compile", s(&scene)]).expect_code(1);
        assert!(run.stderr.contains("not finite"), "{}", run.describe());
    }
}
