//! Golden tests of rendered syntax diagnostics: what the user sees for common mistakes.

use sdfc_syntax::{diag, parse, MAX_NESTING, MAX_SOURCE_BYTES};

fn render(source: &str) -> String {
    match parse(source) {
        Ok(_) => panic!("expected errors for:\n{source}"),
        Err(d) => diag::render("scene.sdf", source, &d),
    }
}

#[test]
fn missing_semicolon() {
    insta::assert_snapshot!(render("let r = 1\nscene = sphere(r);\n"));
}

#[test]
fn missing_semicolon_same_line() {
    insta::assert_snapshot!(render("let r = 1 2;\nscene = sphere(r);\n"));
}

#[test]
fn unclosed_paren() {
    insta::assert_snapshot!(render(
        "let blob = sphere(1)\n    .translate([0, 1, 0]\nscene = blob;\n"
    ));
}

#[test]
fn unclosed_paren_at_end_of_file() {
    insta::assert_snapshot!(render("scene = union(sphere(1), box(1)"));
}

#[test]
fn bad_number_suffix() {
    insta::assert_snapshot!(render("scene = sphere(1).rotate_y(30rad);\n"));
}

#[test]
fn exponent_without_digits() {
    insta::assert_snapshot!(render("let tiny = 1e;\n"));
}

#[test]
fn number_too_large() {
    insta::assert_snapshot!(render("let big = 1e39;\nlet also = [1, 4e38];\n"));
}

#[test]
fn stray_token() {
    insta::assert_snapshot!(render("let a = 1;\n)\nscene = sphere(a);\n"));
}

#[test]
fn keyword_as_name() {
    insta::assert_snapshot!(render("fn fn(r) = sphere(r);\n"));
}

#[test]
fn keyword_in_expression() {
    insta::assert_snapshot!(render("scene = sphere(1) | light;\n"));
}

#[test]
fn misspelt_item_keyword() {
    insta::assert_snapshot!(render("materal red { color: [1, 0, 0] }\n"));
}

#[test]
fn semicolon_after_block() {
    insta::assert_snapshot!(render("camera { fov: 50deg };\n"));
}

#[test]
fn missing_comma_between_fields() {
    insta::assert_snapshot!(render(
        "light point {\n    position: [4, 6, -3]\n    intensity: 1.2\n}\n"
    ));
}

#[test]
fn empty_lambda_params() {
    insta::assert_snapshot!(render("scene = sdf(|| 1);\n"));
}

#[test]
fn unterminated_block_comment() {
    insta::assert_snapshot!(render("scene = sphere(1); /* the end\n"));
}

#[test]
fn deep_nesting() {
    let depth = MAX_NESTING + 1;
    let source = format!("scene = {}1{};\n", "(".repeat(depth), ")".repeat(depth));
    insta::assert_snapshot!(render(&source));
}

#[test]
fn too_large_file() {
    let line = "let a = 1;\n";
    let source = line.repeat(MAX_SOURCE_BYTES / line.len() + 1);
    assert!(source.len() > MAX_SOURCE_BYTES);
    insta::assert_snapshot!(render(&source));
}

#[test]
fn multiple_errors() {
    insta::assert_snapshot!(render(
        "let a = 1\n\
         let b = (2 + ;\n\
         material m { color: [1, 2, 3] specular: 1 }\n\
         fn f(x y) = x;\n\
         scene = sphere(a) |;\n\
         let c = 1e40;\n"
    ));
}

/// A stray control character (here from a corrupted paste) is named by its code point: quoted,
/// it would show as nothing.
#[test]
fn control_character() {
    insta::assert_snapshot!(render("let a = 1;\nscene = sphere(\u{12}a);\n"));
}

/// Every span on sources with long lines (several-byte characters, CRLF, no final line
/// break), with a second label elsewhere: rendered without a panic, its header at the
/// source's line and column, and no line shown whole.
#[test]
fn long_lines_are_cut_and_keep_the_source_columns() {
    use sdfc_syntax::diag::Diagnostic;
    use sdfc_syntax::span::Span;
    let sources = [
        format!("let a = 1;\n{}\nscene = a;\n", "x".repeat(200)),
        format!("{}\r\n{}", "é".repeat(200), "ab".repeat(200)),
        "€x".repeat(200),
    ];
    for src in &sources {
        let middle = Span::new(src.len() / 2, src.len() / 2 + 1);
        for start in (0..=src.len()).step_by(7) {
            for len in [0, 1, 5, 90, 400] {
                let span = Span::new(start, (start + len).min(src.len()));
                let d = Diagnostic::error(span, "message")
                    .with_label("here")
                    .with_secondary(middle, "and there");
                let (line, col) = d.line_col(src);
                let text = diag::render("f.sdf", src, std::slice::from_ref(&d));
                assert!(
                    text.contains(&format!("┌─ f.sdf:{line}:{col}\n")),
                    "{start}+{len}:\n{text}"
                );
                assert!(
                    text.lines().all(|l| l.len() < 600),
                    "{start}+{len}:\n{text}"
                );
            }
        }
    }
    // The last source's 800 bytes, a label on its first `€`: 40 bytes past the label's end
    // are shown, to a character's end, and the rest is cut.
    let d = Diagnostic::error(Span::new(0, 3), "message").with_label("here");
    let text = diag::render("f.sdf", &sources[2], &[d]);
    assert!(
        text.contains(&format!("1 │ {}€...\n", "€x".repeat(10))),
        "{text}"
    );
}
