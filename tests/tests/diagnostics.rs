//! Golden tests of what the user sees for broken scenes: every file in `tests/errors/` holds
//! one class of mistake. Each must fail to compile with diagnostics (never an internal error),
//! every diagnostic must have a message and a span inside the source, and the rendered text is
//! snapshotted in `tests/tests/snapshots/diagnostics__<name>.snap`.
//!
//! Each file starts with `// what is wrong` and `// expect: TEXT`, where TEXT must appear in
//! the rendered diagnostics (a check written by hand, independent of the snapshot). The one
//! exception is `empty.sdf`, which is empty on purpose.

use sdfc_syntax::diag::{self, Diagnostic};
use sdfc_wgsl::{Failure, Options};

struct Case {
    stem: String,
    source: String,
    expect: String,
}

fn cases() -> Vec<Case> {
    sdfc_tests::read_corpus("errors", 25)
        .into_iter()
        .map(|f| {
            let (path, source, stem) = (f.path, f.source, f.stem);
            let expect = match source.lines().find_map(|l| l.strip_prefix("// expect: ")) {
                Some(e) => e.to_string(),
                None if source.is_empty() => "the file has no `scene` item".to_string(),
                None => panic!("{}: no `// expect: ...` line", path.display()),
            };
            Case {
                stem,
                source,
                expect,
            }
        })
        .collect()
}

/// The diagnostics of a scene that must not compile.
fn diagnostics_of(name: &str, source: &str, opts: &Options) -> Vec<Diagnostic> {
    match sdfc_wgsl::compile(source, opts) {
        Ok(c) => panic!(
            "{name} compiled, but it should not (warnings: {:?})",
            c.warnings
        ),
        Err(Failure::Diagnostics(d)) => d,
        Err(f) => panic!("{name}: {f} (instead of a diagnostic)"),
    }
}

fn check_well_formed(name: &str, source: &str, diags: &[Diagnostic]) {
    assert!(
        diags.iter().any(|d| d.is_error()),
        "{name}: compilation failed without an error diagnostic: {diags:?}"
    );
    let len = source.len() as u64;
    for d in diags {
        assert!(
            !d.message.trim().is_empty(),
            "{name}: a diagnostic with an empty message: {d:?}"
        );
        assert!(
            !d.message.contains("internal"),
            "{name}: a user mistake reported as an internal error: {d:?}"
        );
        let spans = std::iter::once(d.span).chain(d.secondary.iter().map(|(s, _)| *s));
        for s in spans {
            let (start, end) = (u64::from(s.start), u64::from(s.end));
            assert!(
                start <= end && end <= len,
                "{name}: span {start}..{end} outside the source (length {len}): {d:?}"
            );
            assert!(
                source.is_char_boundary(start as usize) && source.is_char_boundary(end as usize),
                "{name}: span {start}..{end} splits a character: {d:?}"
            );
        }
        if let Some(h) = &d.hint {
            assert!(!h.trim().is_empty(), "{name}: an empty hint: {d:?}");
        }
    }
}

#[test]
fn every_error_file_is_rejected_with_well_formed_diagnostics() {
    for case in cases() {
        let file = format!("{}.sdf", case.stem);
        let diags = diagnostics_of(&file, &case.source, &Options::default());
        check_well_formed(&file, &case.source, &diags);
        // The library form sees the same scene, so the same mistakes.
        let lib = Options {
            lib: true,
            import_path: None,
            cull: false,
            instances: sdfc_wgsl::Instances::Never,
        };
        assert_eq!(
            diagnostics_of(&file, &case.source, &lib),
            diags,
            "{file}: the library form reports different diagnostics"
        );
    }
}

#[test]
fn rendered_diagnostics_name_the_mistake() {
    for case in cases() {
        let file = format!("{}.sdf", case.stem);
        let diags = diagnostics_of(&file, &case.source, &Options::default());
        let text = diag::render(&file, &case.source, &diags);
        assert!(
            text.contains(&case.expect),
            "{file}: the diagnostics do not mention `{}`:\n{text}",
            case.expect
        );
        // Every error is located: `(file:line:col)` in its headline.
        for d in diags.iter().filter(|d| d.is_error()) {
            let (line, col) = d.line_col(&case.source);
            let located = format!("({file}:{line}:{col})");
            assert!(
                text.contains(&located),
                "{file}: no `{located}` in:\n{text}"
            );
        }
    }
}

#[test]
fn rendered_diagnostics_snapshots() {
    for case in cases() {
        let file = format!("{}.sdf", case.stem);
        let diags = diagnostics_of(&file, &case.source, &Options::default());
        let text = diag::render(&file, &case.source, &diags);
        let mut settings = insta::Settings::clone_current();
        settings.set_input_file(sdfc_tests::root().join("errors").join(&file));
        settings.set_omit_expression(true);
        settings.set_description(case.source.clone());
        settings.bind(|| insta::assert_snapshot!(case.stem.clone(), text));
    }
}

#[test]
fn diagnostics_are_deterministic() {
    for case in cases() {
        let a = diagnostics_of(&case.stem, &case.source, &Options::default());
        let b = diagnostics_of(&case.stem, &case.source, &Options::default());
        assert_eq!(a, b, "{}: diagnostics differ between two runs", case.stem);
    }
}

/// A non-finite constant that reaches a shape transform (an offset or an angle) is reported
/// where it is written (this once panicked in the emitter).
#[test]
fn non_finite_transform_constants_are_diagnosed() {
    for source in [
        "scene = sphere(1).translate([1e30 * 1e30, 0, 0]);\n",
        "scene = sphere(1).translate([1 / 0, 0, 0]);\n",
        "scene = sphere(1).rotate_y(1 / 0);\n",
    ] {
        let diags = diagnostics_of(source.trim(), source, &Options::default());
        check_well_formed(source.trim(), source, &diags);
        let text = diag::render("scene.sdf", source, &diags);
        assert!(text.contains("not finite"), "{text}");
    }
}

/// Two scales that are each fine but whose product overflows f32 once the merge pass folds
/// them are reported at the scales, not at line 1, column 1.
#[test]
fn merged_scale_overflow_points_at_the_scales() {
    let source = "let s = sphere(1).scale(1e20);\nscene = s.scale(1e20);\n";
    let diags = diagnostics_of("merged_scale", source, &Options::default());
    check_well_formed("merged_scale", source, &diags);
    let first_scale = source.find("scale").unwrap_or_default() as u32;
    for d in diags.iter().filter(|d| d.is_error()) {
        assert!(
            d.span.end > first_scale,
            "the error points before the first `scale`:\n{}",
            diag::render("merged_scale.sdf", source, &diags)
        );
    }
}
