//! The compiler's library API: errors that explain themselves without the source (placed
//! diagnostics, `Display`, `std::error::Error`), and options the caller gets wrong.

use sdfc_wgsl::{compile, Failure, Options};

#[test]
fn a_failure_says_where_each_mistake_is() {
    let source = "let r = 1;\nscene = sphre(r);\n";
    let f = compile(source, &Options::default()).unwrap_err();
    let Failure::Diagnostics(d) = &f else {
        panic!("{f:?}")
    };
    assert_eq!(d[0].place, Some((2, 9)));
    let text = f.to_string();
    assert!(text.starts_with("2:9: error: "), "{text}");
    assert!(text.contains("hint: "), "{text}");
    // `?` into a boxed error works, with the same words.
    let boxed: Box<dyn std::error::Error> = f.into();
    assert_eq!(boxed.to_string(), text);
}

#[test]
fn syntax_errors_and_warnings_are_placed_too() {
    let f = compile("scene = sphere(1)", &Options::default()).unwrap_err();
    let Failure::Diagnostics(d) = &f else {
        panic!("{f:?}")
    };
    assert!(d.iter().all(|d| d.place.is_some()), "{d:?}");
    let rendered = f.render("s.sdf", "scene = sphere(1)");
    assert!(rendered.contains("s.sdf:1:"), "{rendered}");
    // A warning of a scene that compiles: a declared bound that sampling contradicts.
    let source = "\nscene = sdf(|p| 3 * (length(p) - 1), lipschitz: 1);\n";
    let c = compile(source, &Options::default()).unwrap();
    assert_eq!(c.warnings.len(), 1);
    let w = c.warnings[0].to_string();
    assert!(w.starts_with("2:49: warning: "), "{w}");
    assert!(w.contains("use `lipschitz: 3.01` or more"), "{w}");
}

#[test]
fn a_bad_import_path_is_the_callers_mistake() {
    for bad in ["bad name!!\n@compute", "", "a::", "1a", "_", "a:b"] {
        let opts = Options {
            lib: true,
            import_path: Some(bad.into()),
            ..Options::default()
        };
        match compile("scene = sphere(1);", &opts) {
            Err(Failure::Usage(m)) => assert!(m.contains("joined by `::`"), "{m}"),
            other => panic!("{bad:?}: {:?}", other.map(|c| c.wgsl)),
        }
    }
    // Without `lib` an import path would be ignored: refused instead.
    let opts = Options {
        import_path: Some("my::scene".into()),
        ..Options::default()
    };
    assert!(matches!(
        compile("scene = sphere(1);", &opts),
        Err(Failure::Usage(_))
    ));
    let good = Options {
        lib: true,
        import_path: Some("_a::b2::C".into()),
        ..Options::default()
    };
    let c = compile("scene = sphere(1);", &good).unwrap();
    assert!(c.wgsl.starts_with("#define_import_path _a::b2::C\n"));
    assert!(c.is_library());
    assert!(!compile("scene = sphere(1);", &Options::default())
        .unwrap()
        .is_library());
}
