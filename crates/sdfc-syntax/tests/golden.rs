//! Golden tests of the parse stage: the AST dump of the corpus files in `tests/corpus/`.

use std::path::PathBuf;

fn corpus(name: &str) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/corpus")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn dump(name: &str) -> String {
    let source = corpus(name);
    match sdfc_syntax::parse(&source) {
        Ok(file) => sdfc_syntax::pretty::dump(&file),
        Err(d) => panic!("{}", sdfc_syntax::diag::render(name, &source, &d)),
    }
}

#[test]
fn constructs() {
    insta::assert_snapshot!("constructs", dump("constructs.sdf"));
}

#[test]
fn spec_section10() {
    insta::assert_snapshot!("spec_section10", dump("spec_section10.sdf"));
}
