//! Property tests: mangled versions of the corpus scenes never crash the compiler. Whatever
//! the edit, `compile` returns WGSL or diagnostics (never `Failure::Internal`), and every
//! diagnostic is well formed. The seed is fixed so that runs are reproducible.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use sdfc_wgsl::{Failure, Options};

fn sources() -> &'static [String] {
    static SOURCES: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
    SOURCES.get_or_init(load)
}

fn load() -> Vec<String> {
    let mut v: Vec<String> = sdfc_tests::corpus("scenes")
        .into_iter()
        .chain(sdfc_tests::corpus("errors"))
        .map(|p| std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display())))
        .collect();
    v.retain(|s| !s.is_empty());
    assert!(v.len() >= 12, "corpus missing");
    v
}

/// Snippets that are plausible in a scene, inserted at random places.
const SNIPPETS: &[&str] = &[
    "(",
    ")",
    "[",
    "]",
    "{",
    "}",
    ",",
    ";",
    "|",
    "&",
    "-",
    "*",
    "/",
    "%",
    ".",
    ".x",
    ".zyx",
    "|p|",
    "0",
    "-1",
    "1e38",
    "2.",
    ".5",
    "30deg",
    "sphere(1)",
    "box(",
    "let",
    "fn",
    "scene =",
    "param",
    "material",
    "render",
    "camera",
    "light point",
    "smooth:",
    "time",
    "pi",
    "true",
    "select(",
    "sdf(|p| length(p) - 1)",
    "\n",
    " ",
    "/*",
    "*/",
    "//",
    "é",
    "\"",
];

#[derive(Debug, Clone)]
enum Edit {
    Delete { at: usize, len: usize },
    Insert { at: usize, snippet: usize },
    Duplicate { at: usize, len: usize },
    Truncate { at: usize },
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), 1usize..12).prop_map(|(at, len)| Edit::Delete { at, len }),
        (any::<usize>(), 0..SNIPPETS.len()).prop_map(|(at, snippet)| Edit::Insert { at, snippet }),
        (any::<usize>(), 1usize..40).prop_map(|(at, len)| Edit::Duplicate { at, len }),
        any::<usize>().prop_map(|at| Edit::Truncate { at }),
    ]
}

fn boundary(s: &str, at: usize) -> usize {
    let mut i = at % (s.len() + 1);
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

fn apply(src: &str, e: &Edit) -> String {
    match *e {
        Edit::Delete { at, len } => {
            let a = boundary(src, at);
            let b = boundary(src, (a + len).min(src.len()));
            format!("{}{}", &src[..a], &src[b..])
        }
        Edit::Insert { at, snippet } => {
            let a = boundary(src, at);
            format!("{}{}{}", &src[..a], SNIPPETS[snippet], &src[a..])
        }
        Edit::Duplicate { at, len } => {
            let a = boundary(src, at);
            let b = boundary(src, (a + len).min(src.len()));
            format!("{}{}", &src[..b], &src[a..])
        }
        Edit::Truncate { at } => src[..boundary(src, at)].to_string(),
    }
}

fn check(source: &str) -> Result<(), TestCaseError> {
    match sdfc_wgsl::compile(source, &Options::default()) {
        Ok(c) => {
            prop_assert!(c.warnings.iter().all(|d| !d.is_error()));
            prop_assert!(sdfc_wgsl::validate::validate("mangled.wgsl", &c.wgsl).is_ok());
        }
        Err(Failure::Diagnostics(diags)) => {
            prop_assert!(
                diags.iter().any(|d| d.is_error()),
                "failure without an error"
            );
            for d in &diags {
                prop_assert!(!d.message.trim().is_empty());
                // An internal error is a bug reported as a diagnostic (the parser's two
                // grammars disagreeing, a pair the tree builder did not expect, ill-typed IR).
                prop_assert!(!d.message.contains("internal"), "{d:?}\n{source}");
                prop_assert!(
                    d.span.start <= d.span.end && d.span.end as usize <= source.len(),
                    "{d:?}"
                );
            }
            // Rendering never panics either.
            let _ = sdfc_syntax::diag::render("mangled.sdf", source, &diags);
        }
        Err(f) => {
            return Err(TestCaseError::fail(format!(
                "{f}\n--- source ---\n{source}"
            )));
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(Config {
        cases: 512,
        rng_seed: RngSeed::Fixed(0x5dfc),
        failure_persistence: None,
        ..Config::default()
    })]

    #[test]
    fn mangled_scenes_never_crash_the_compiler(
        which in any::<usize>(),
        edits in proptest::collection::vec(edit(), 1..4),
    ) {
        let all = sources();
        let mut src = all[which % all.len()].clone();
        for e in &edits {
            src = apply(&src, e);
        }
        check(&src)?;
    }
}

/// Inputs the fuzzer (`fuzz/`, `cargo fuzz run compile`) once found to break the compiler:
/// each must now compile or be rejected with diagnostics, never fail internally.
#[test]
fn fuzzer_findings_stay_fixed() {
    let found = sdfc_tests::corpus("regressions");
    assert!(!found.is_empty(), "tests/regressions is empty");
    for path in found {
        let source =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        match sdfc_wgsl::compile(&source, &Options::default()) {
            Ok(_) | Err(Failure::Diagnostics(_)) => {}
            Err(f) => panic!("{}: {f}", path.display()),
        }
    }
}
