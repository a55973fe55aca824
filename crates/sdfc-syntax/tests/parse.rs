//! Unit tests of the parser: precedence, literals, arguments, comments, spans, limits, and
//! that no input makes it panic.

use sdfc_syntax::ast::*;
use sdfc_syntax::diag::Diagnostic;
use sdfc_syntax::span::Span;
use sdfc_syntax::{parse, MAX_EXPR_DEPTH, MAX_NESTING, MAX_SOURCE_BYTES};

fn parse_ok(src: &str) -> File {
    match parse(src) {
        Ok(f) => f,
        Err(d) => panic!(
            "unexpected errors:\n{}",
            sdfc_syntax::diag::render("t.sdf", src, &d)
        ),
    }
}

fn parse_err(src: &str) -> Vec<Diagnostic> {
    match parse(src) {
        Ok(f) => panic!("expected an error, got {f:?}"),
        Err(d) => d,
    }
}

/// The value of `let x = EXPR;`.
fn expr(src: &str) -> Expr {
    let file = parse_ok(&format!("let x = {src};"));
    match file.items.into_iter().next().map(|i| i.kind) {
        Some(ItemKind::Let { value, .. }) => value,
        other => panic!("not a let: {other:?}"),
    }
}

fn num(src: &str) -> f32 {
    match expr(src).kind {
        ExprKind::Number(v) => v,
        other => panic!("not a number: {other:?}"),
    }
}

/// A compact S-expression without spans, for shape assertions.
fn sx(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Number(v) => format!("{v}"),
        ExprKind::Bool(b) => format!("{b}"),
        ExprKind::Name(n) => n.name.clone(),
        ExprKind::Vector(xs) => format!("[{}]", xs.iter().map(sx).collect::<Vec<_>>().join(" ")),
        ExprKind::Unary(UnaryOp::Neg, x) => format!("(neg {})", sx(x)),
        ExprKind::Binary(op, l, r) => format!("({} {} {})", op.symbol(), sx(l), sx(r)),
        ExprKind::Chain(op, xs) => format!(
            "({} {})",
            op.symbol(),
            xs.iter().map(sx).collect::<Vec<_>>().join(" ")
        ),
        ExprKind::Call {
            callee,
            args,
            method,
        } => {
            let mut s = format!("({}{}", if *method { "." } else { "" }, callee.name);
            for a in args {
                s.push(' ');
                if let Some(n) = &a.name {
                    s.push_str(&n.name);
                    s.push(':');
                }
                s.push_str(&sx(&a.value));
            }
            s.push(')');
            s
        }
        ExprKind::Swizzle(x, l) => format!("(.{} {})", l.name, sx(x)),
        ExprKind::Lambda { params, body } => {
            let ps: Vec<&str> = params.iter().map(|p| p.name.as_str()).collect();
            format!("(|{}| {})", ps.join(","), sx(body))
        }
    }
}

fn shape(src: &str) -> String {
    sx(&expr(src))
}

fn text(src: &str, span: Span) -> &str {
    &src[span.range()]
}

// ---------------------------------------------------------------------------------------------
// Precedence and associativity

#[test]
fn precedence_ladder() {
    assert_eq!(
        shape("a | b & c + d * -e.x"),
        "(| a (& b (+ c (* d (neg (.x e))))))"
    );
    assert_eq!(
        shape("-e.x * d + c & b | a"),
        "(| (& (+ (* (neg (.x e)) d) c) b) a)"
    );
    assert_eq!(shape("a < b + 1 & c"), "(& (< a (+ b 1)) c)");
    assert_eq!(shape("a == b | c != d"), "(| (== a b) (!= c d))");
}

#[test]
fn binary_operators_are_left_associative() {
    assert_eq!(shape("a - b - c"), "(- (- a b) c)");
    assert_eq!(shape("a / b * c % d"), "(% (* (/ a b) c) d)");
    assert_eq!(shape("a < b < c"), "(< (< a b) c)");
}

/// `|` and `&` chains are one node each: a chain joins a parenthesised chain of the same
/// operator on its left (union and intersection are associative), not one on its right, nor
/// a chain of the other operator.
#[test]
fn shape_operator_chains_are_flat() {
    assert_eq!(shape("a | b | c"), "(| a b c)");
    assert_eq!(shape("a & b & c & d"), "(& a b c d)");
    assert_eq!(shape("(a | b) | c"), "(| a b c)");
    assert_eq!(shape("a | (b | c)"), "(| a (| b c))");
    assert_eq!(shape("(a & b) | c & d"), "(| (& a b) (& c d))");
    assert_eq!(shape("a - b - c | d"), "(| (- (- a b) c) d)");
}

/// A chain of `|` as long as a file allows parses: its length does not count towards the
/// depth limit, which still holds for its operands.
#[test]
fn long_shape_chains_parse() {
    let n = 20_000;
    let src = format!("scene = {};", vec!["sphere(1)"; n].join(" | "));
    let file = parse_ok(&src);
    let ItemKind::Scene { value: e } = &file.items[0].kind else {
        panic!("expected the scene")
    };
    let ExprKind::Chain(BinaryOp::Or, xs) = &e.kind else {
        panic!("expected a chain, got {e:?}")
    };
    assert_eq!(xs.len(), n);
    // The chain is one level: over an operand as deep as the limit allows it is refused,
    // at its `|`; over one a level less it parses.
    let deep = |minus: usize| format!("scene = a | {}b;", "-".repeat(minus));
    let d = parse(&deep(MAX_EXPR_DEPTH - 1)).expect_err("a chain past the limit");
    assert!(d[0].message.contains("nested too deeply"), "{d:?}");
    assert_eq!(d[0].span, Span::new(10, 11));
    parse_ok(&deep(MAX_EXPR_DEPTH - 2));
}

#[test]
fn unary_and_postfix() {
    assert_eq!(shape("--a"), "(neg (neg a))");
    assert_eq!(shape("a - -b"), "(- a (neg b))");
    assert_eq!(
        shape("-sphere(1).translate(v)"),
        "(neg (.translate (sphere 1) v))"
    );
    assert_eq!(shape("(a + b).xz"), "(.xz (+ a b))");
    assert_eq!(shape("v.x.y"), "(.y (.x v))");
}

#[test]
fn lambda_body_extends_as_far_as_possible() {
    assert_eq!(
        shape("f(|p| p.x + 1 | q, 2)"),
        "(f (|p| (| (+ (.x p) 1) q)) 2)"
    );
    assert_eq!(shape("f(|x, z| x * z)"), "(f (|x,z| (* x z)))");
    assert_eq!(shape("a | |p| p"), "(| a (|p| p))");
}

// ---------------------------------------------------------------------------------------------
// Literals

#[test]
fn number_forms() {
    assert_eq!(num("1"), 1.0);
    assert_eq!(num("1.5"), 1.5);
    assert_eq!(num(".5"), 0.5);
    assert_eq!(num("2."), 2.0);
    assert_eq!(num("1e-4"), 1e-4);
    assert_eq!(num("3.2E+2"), 320.0);
    assert_eq!(num("0.1"), 0.1f32);
    assert_eq!(num("007"), 7.0);
    assert_eq!(num("3.4028235e38"), f32::MAX);
    // Correctly rounded, not via f64 first: halfway cases in f32 would differ otherwise.
    assert_eq!(num("16777217"), 16777216.0);
}

#[test]
fn degrees_convert_in_f64_and_round_once() {
    let expect = |d: f64| (d * (std::f64::consts::PI / 180.0)) as f32;
    assert_eq!(num("30deg"), expect(30.0));
    assert_eq!(num("22.5deg"), expect(22.5));
    assert_eq!(num("1e2deg"), expect(100.0));
    assert_eq!(num(".5deg"), expect(0.5));
    assert_eq!(num("180deg"), std::f32::consts::PI);
    assert_eq!(expr("30deg").span, Span::new(8, 13));
}

#[test]
fn dot_after_digits() {
    // `2.` is a number only when the dot is not followed by a letter, `_` or another dot.
    assert_eq!(shape("2.x"), "(.x 2)");
    assert_eq!(shape("2.abs()"), "(.abs 2)");
    assert_eq!(shape("1.5.x"), "(.x 1.5)");
    assert_eq!(shape("[2., 3.]"), "[2 3]");
    assert_eq!(shape("f(2.)"), "(f 2)");
    assert!(parse("let x = 2..5;").is_err());
    assert!(parse("let x = 1 .5;").is_err());
}

#[test]
fn bad_numbers() {
    let d = parse_err("let x = 1e39;");
    assert_eq!(d.len(), 1);
    assert_eq!(d[0].message, "number too large for a 32-bit float");
    assert_eq!(d[0].span, Span::new(8, 12));
    assert!(parse("let x = 1e40deg;").is_ok()); // 1.7e38
    let d = parse_err("let x = 1e41deg;");
    assert_eq!(d[0].message, "number too large for a 32-bit float");
    let d = parse_err("let x = 30rad;");
    assert_eq!(d[0].message, "unknown number suffix `rad`");
    assert_eq!(d[0].span, Span::new(10, 13));
    let d = parse_err("let x = 1e;");
    assert_eq!(d[0].message, "unknown number suffix `e`");
    // Underflow is not an error: it rounds to zero.
    assert_eq!(num("1e-50"), 0.0);
}

#[test]
fn booleans_and_vectors() {
    assert_eq!(shape("[true, false]"), "[true false]");
    assert_eq!(shape("[1]"), "[1]");
    assert_eq!(shape("[1, 2, 3, 4,]"), "[1 2 3 4]");
    assert!(parse("let x = [];").is_err());
    assert!(parse("let x = [,];").is_err());
    assert!(parse("let x = [1,,2];").is_err());
}

// ---------------------------------------------------------------------------------------------
// Calls, arguments, keywords

#[test]
fn named_arguments_keep_source_order() {
    assert_eq!(shape("f(a, smooth: 1, b, k: 2)"), "(f a smooth:1 b k:2)");
    assert_eq!(shape("s.f(x, k: 1)"), "(.f s x k:1)");
    assert_eq!(shape("f()"), "(f)");
    assert_eq!(shape("s.f()"), "(.f s)");
}

#[test]
fn method_call_puts_the_receiver_first() {
    let e = expr("sphere(1).translate([0, 1, 0])");
    let ExprKind::Call {
        callee,
        args,
        method,
    } = &e.kind
    else {
        panic!("not a call");
    };
    assert!(*method);
    assert_eq!(callee.name, "translate");
    assert_eq!(args.len(), 2);
    assert!(args.iter().all(|a| a.name.is_none()));
    assert_eq!(sx(&args[0].value), "(sphere 1)");
}

#[test]
fn trailing_commas() {
    assert_eq!(shape("f(1, 2,)"), "(f 1 2)");
    assert_eq!(shape("f(k: 1,)"), "(f k:1)");
    let file = parse_ok("fn f(a, b = 1,) = a; material m { color: [1, 1, 1], }");
    let ItemKind::Fn { params, .. } = &file.items[0].kind else {
        panic!()
    };
    assert_eq!(params.len(), 2);
    let ItemKind::Material { fields, .. } = &file.items[1].kind else {
        panic!()
    };
    assert_eq!(fields.len(), 1);
}

#[test]
fn empty_block_and_lone_comma() {
    parse_ok("camera {}");
    // `{,}` is not an empty block: a comma needs something before it.
    assert!(parse("render {,}").is_err());
    assert!(parse("fn f(,) = 1;").is_err());
    assert!(parse("let x = f(,);").is_err());
}

#[test]
fn keywords_where_words_are_allowed() {
    assert_eq!(shape("material(s, red)"), "(material s red)");
    assert_eq!(shape("s.material(red)"), "(.material s red)");
    assert_eq!(shape("f(light: 1, scene: 2)"), "(f light:1 scene:2)");
    let file = parse_ok("render { light: 1, let: 2 }");
    let ItemKind::Render { fields } = &file.items[0].kind else {
        panic!()
    };
    assert_eq!(fields[0].name.name, "light");
    assert_eq!(fields[1].name.name, "let");
}

#[test]
fn keywords_are_not_names() {
    for src in [
        "let let = 1;",
        "let scene = 1;",
        "param true = 1;",
        "fn f(render) = 1;",
        "let x = |fn| 1;",
        "let x = light;",
        "let x = material + 1;",
        "material camera {}",
    ] {
        assert!(parse(src).is_err(), "{src}");
    }
    // but a keyword may begin a longer name
    parse_ok("let lettuce = 1; let scenery = lettuce; let true_ = 1; let fnord = 2;");
}

#[test]
fn items() {
    let src = "let a = 1;\nfn f(x, y = 2) = x;\nparam p = [1, 2, 3];\nmaterial m { color: [1, 0, 0] }\n\
               light point { intensity: 1 }\ncamera { fov: 60deg }\nrender { max_steps: 64 }\nscene = sphere(1);";
    let file = parse_ok(src);
    let kinds: Vec<&str> = file
        .items
        .iter()
        .map(|i| match &i.kind {
            ItemKind::Let { .. } => "let",
            ItemKind::Fn { .. } => "fn",
            ItemKind::Param { .. } => "param",
            ItemKind::Material { .. } => "material",
            ItemKind::Light { .. } => "light",
            ItemKind::Camera { .. } => "camera",
            ItemKind::Render { .. } => "render",
            ItemKind::Scene { .. } => "scene",
        })
        .collect();
    assert_eq!(
        kinds,
        ["let", "fn", "param", "material", "light", "camera", "render", "scene"]
    );
    for item in &file.items {
        let t = text(src, item.span);
        assert!(t.ends_with(';') || t.ends_with('}'), "{t}");
    }
    let ItemKind::Fn { params, .. } = &file.items[1].kind else {
        panic!()
    };
    assert!(params[0].default.is_none());
    assert!(params[1].default.is_some());
    let ItemKind::Light { kind, .. } = &file.items[4].kind else {
        panic!()
    };
    assert_eq!(kind.name, "point");
}

// ---------------------------------------------------------------------------------------------
// Comments, whitespace, empty files

#[test]
fn comments() {
    let src = "/* a /* b */ let /* c */ a = // d\n 1 /**/;// e";
    let file = parse_ok(src);
    assert_eq!(file.items.len(), 1);
    assert_eq!(
        text(src, file.items[0].span),
        "let /* c */ a = // d\n 1 /**/;"
    );
    parse_ok("let a = 1; // comment at the end without a newline");
    parse_ok("let a = 1;/**/");
    parse_ok("let a = 4 //comment\n / 2;");
    assert_eq!(shape("a/*x*/-/*y*/b"), "(- a b)");
}

#[test]
fn block_comments_do_not_nest() {
    // The first `*/` ends the comment, so the second `*/` is a syntax error.
    assert!(parse("/* a /* b */ c */ let a = 1;").is_err());
    let d = parse_err("let a = 1; /* never closed");
    assert_eq!(d[0].message, "unterminated block comment");
    assert_eq!(d[0].span, Span::new(11, 13));
}

#[test]
fn empty_and_blank_files() {
    for src in [
        "",
        "   \n\t\r\n",
        "// only a comment",
        "/* block */",
        "\u{FEFF}",
    ] {
        assert_eq!(parse_ok(src).items.len(), 0, "{src:?}");
    }
    parse_ok("\u{FEFF}let a = 1;");
}

// ---------------------------------------------------------------------------------------------
// Spans

#[test]
fn expression_spans() {
    let src = "let x = a + b * c;";
    let e = expr("a + b * c");
    assert_eq!(text(src, e.span), "a + b * c");
    let ExprKind::Binary(_, l, r) = &e.kind else {
        panic!()
    };
    assert_eq!(text(src, l.span), "a");
    assert_eq!(text(src, r.span), "b * c");

    let src = "let x = sphere(1) .translate( [0, 1, 0] ) ;";
    let e = expr("sphere(1) .translate( [0, 1, 0] ) ");
    assert_eq!(text(src, e.span), "sphere(1) .translate( [0, 1, 0] )");
    let ExprKind::Call { callee, args, .. } = &e.kind else {
        panic!()
    };
    assert_eq!(text(src, callee.span), "translate");
    assert_eq!(text(src, args[0].value.span), "sphere(1)");
    assert_eq!(text(src, args[1].value.span), "[0, 1, 0]");

    let src = "let x = - v.xz  + ( 1 ) ;";
    let e = expr("- v.xz  + ( 1 ) ");
    assert_eq!(text(src, e.span), "- v.xz  + ( 1 )");
    let ExprKind::Binary(_, l, r) = &e.kind else {
        panic!()
    };
    assert_eq!(text(src, l.span), "- v.xz");
    assert_eq!(text(src, r.span), "( 1 )");
    let ExprKind::Unary(_, sw) = &l.kind else {
        panic!()
    };
    assert_eq!(text(src, sw.span), "v.xz");

    let src = "let x = f(|p| p.x  , k: 1);";
    let e = expr("f(|p| p.x  , k: 1)");
    let ExprKind::Call { args, .. } = &e.kind else {
        panic!()
    };
    assert_eq!(text(src, args[0].value.span), "|p| p.x");
    assert_eq!(text(src, args[1].name.as_ref().unwrap().span), "k");
    assert_eq!(text(src, args[1].value.span), "1");
}

/// Every span in the corpus covers exactly its node's text: no surrounding blanks, names
/// spell their names, and composite nodes start and end where their parts do.
#[test]
fn corpus_spans_are_exact() {
    for name in ["constructs.sdf", "spec_section10.sdf"] {
        let path = format!("{}/../../tests/corpus/{name}", env!("CARGO_MANIFEST_DIR"));
        let src = std::fs::read_to_string(path).unwrap();
        let file = parse_ok(&src);
        for item in &file.items {
            let t = text(&src, item.span);
            assert_eq!(t.trim(), t);
            let mut exprs = Vec::new();
            let mut idents = Vec::new();
            match &item.kind {
                ItemKind::Let { name, value }
                | ItemKind::Param {
                    name,
                    default: value,
                } => {
                    idents.push(name);
                    exprs.push(value);
                }
                ItemKind::Fn { name, params, body } => {
                    idents.push(name);
                    for p in params {
                        idents.push(&p.name);
                        exprs.extend(&p.default);
                    }
                    exprs.push(body);
                }
                ItemKind::Material { name: n, fields } | ItemKind::Light { kind: n, fields } => {
                    idents.push(n);
                    for f in fields {
                        idents.push(&f.name);
                        exprs.push(&f.value);
                    }
                }
                ItemKind::Camera { fields } | ItemKind::Render { fields } => {
                    for f in fields {
                        idents.push(&f.name);
                        exprs.push(&f.value);
                    }
                }
                ItemKind::Scene { value } => exprs.push(value),
            }
            while let Some(e) = exprs.pop() {
                let t = text(&src, e.span);
                assert_eq!(t.trim(), t, "{t:?}");
                assert!(item.span.start <= e.span.start && e.span.end <= item.span.end);
                let parens = t.starts_with('(') && t.ends_with(')');
                match &e.kind {
                    ExprKind::Name(n) => {
                        idents.push(n);
                        assert!(parens || t == n.name);
                    }
                    ExprKind::Number(_) => {
                        assert!(t.as_bytes()[0].is_ascii_digit() || t.starts_with('.'))
                    }
                    ExprKind::Bool(b) => assert_eq!(t, b.to_string()),
                    ExprKind::Vector(xs) => {
                        assert!(t.starts_with('[') && t.ends_with(']'));
                        exprs.extend(xs);
                    }
                    ExprKind::Unary(_, x) => {
                        assert!(t.starts_with('-') || parens);
                        assert_eq!(e.span.end, x.span.end);
                        exprs.push(x);
                    }
                    ExprKind::Binary(op, l, r) => {
                        if !parens {
                            assert_eq!(e.span, l.span.to(r.span));
                        }
                        let between = &src[l.span.end as usize..r.span.start as usize];
                        assert!(between.contains(op.symbol()), "{between:?}");
                        exprs.push(l);
                        exprs.push(r);
                    }
                    ExprKind::Chain(op, xs) => {
                        // A parenthesised chain on the left joined it, parentheses and all.
                        let (first, last) = (&xs[0], &xs[xs.len() - 1]);
                        assert!(e.span.start <= first.span.start);
                        if !parens {
                            assert_eq!(e.span.end, last.span.end);
                        }
                        for pair in xs.windows(2) {
                            let between =
                                &src[pair[0].span.end as usize..pair[1].span.start as usize];
                            assert!(between.contains(op.symbol()), "{between:?}");
                        }
                        exprs.extend(xs);
                    }
                    ExprKind::Call {
                        callee,
                        args,
                        method,
                    } => {
                        idents.push(callee);
                        assert!(t.ends_with(')'));
                        if *method && !parens {
                            assert_eq!(e.span.start, args[0].value.span.start);
                        } else if !parens {
                            assert_eq!(e.span.start, callee.span.start);
                        }
                        for a in args {
                            idents.extend(&a.name);
                            exprs.push(&a.value);
                        }
                    }
                    ExprKind::Swizzle(x, l) => {
                        idents.push(l);
                        assert!(parens || e.span.end == l.span.end);
                        exprs.push(x);
                    }
                    ExprKind::Lambda { params, body } => {
                        assert!(t.starts_with('|') || parens);
                        assert_eq!(e.span.end, body.span.end);
                        idents.extend(params);
                        exprs.push(body);
                    }
                }
            }
            for id in idents {
                assert_eq!(text(&src, id.span), id.name);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Error recovery

#[test]
fn reports_every_item_error() {
    let src = "let a = 1\nlet b = (2 + ;\nmaterial m { color: 1 specular: 1 }\nscene = |;\nlet ok = 1;\nlet c = 1e40;";
    let d = parse_err(src);
    let lines: Vec<usize> = d.iter().map(|d| d.line_col(src).0).collect();
    assert_eq!(lines, [2, 2, 3, 4, 6], "{d:#?}");
    for rule_name in ["_item", "kw_", "term", "lparen", "semi", "EOI", "num_"] {
        assert!(d.iter().all(|d| !d.message.contains(rule_name)), "{d:#?}");
    }
}

#[test]
fn recovers_after_an_unclosed_bracket_at_the_next_item_line() {
    let src = "let a = f(1,\nlet b = [1, 2;\nscene = a b;\n";
    let d = parse_err(src);
    let lines: Vec<usize> = d.iter().map(|d| d.line_col(src).0).collect();
    assert_eq!(lines, [2, 2, 3], "{d:#?}");
}

#[test]
fn messages_say_what_was_expected_in_words() {
    let cases = [
        ("let a = 1\nscene = a;", "expected `;` after the item, found `scene`"),
        ("let = 1;", "expected a name, found `=`"),
        ("let a 1;", "expected `=`, found `1`"),
        ("let a = ;", "expected an expression, found `;`"),
        ("material m { 1 }", "expected a field (`name: value`) or `}`, found `1`"),
        ("material m { a 1 }", "expected `:`, found `1`"),
        ("scene = f(1", "expected `,` or `)`, found end of file"),
        ("scene = [1 2];", "expected `,` or `]`, found `2`"),
        ("scene = x.;", "expected a method or swizzle name, found `;`"),
        ("fn f(1) = 1;", "expected a parameter name or `)`, found `1`"),
        ("scene = |p 1;", "expected `,` or `|`, found `1`"),
        ("camera = {}", "expected `{`, found `=`"),
        (
            "x = 1;",
            "expected an item (`let`, `fn`, `param`, `material`, `light`, `camera`, `render` or `scene`), found `x`",
        ),
    ];
    for (src, message) in cases {
        let d = parse_err(src);
        assert_eq!(d[0].message, message, "{src}");
    }
}

// ---------------------------------------------------------------------------------------------
// Limits: nothing deep or large may overflow the stack or panic

/// Runs `f` on a thread with a small stack (256 KiB): the parser must not depend on the
/// caller's stack.
fn small_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new()
        .stack_size(256 * 1024)
        .spawn(f)
        .unwrap()
        .join()
        .unwrap()
}

#[test]
fn nesting_at_the_limit_parses_whatever_the_callers_stack() {
    small_stack(|| {
        let n = MAX_NESTING;
        for src in [
            format!("scene = {}1{};", "(".repeat(n), ")".repeat(n)),
            format!("scene = {}1{};", "f(".repeat(n), ")".repeat(n)),
            format!("scene = {}1{};", "x.f(".repeat(n), ")".repeat(n)),
            format!("scene = {}1{};", "[".repeat(n), "]".repeat(n)),
            format!("scene = f({}1);", "|p| ".repeat(n - 1)),
            format!(
                "scene = {}1{};",
                "f(k: -(".repeat(n / 2),
                "))".repeat(n / 2)
            ),
        ] {
            assert_eq!(parse_ok(&src).items.len(), 1);
        }
    });
}

#[test]
fn nesting_past_the_limit_is_one_diagnostic() {
    let n = MAX_NESTING + 1;
    let src = format!("scene = {}1{};", "[".repeat(n), "]".repeat(n));
    let d = parse_err(&src);
    assert_eq!(d.len(), 1);
    assert_eq!(d[0].span, Span::new(8 + n - 1, 8 + n));
    // and a mixture of kinds counts together, ignoring comments
    let src = format!("scene = {}1;", "([{".repeat(50));
    assert_eq!(parse_err(&src).len(), 1);
    let src = format!(
        "scene = 1; /* {} */ // {}",
        "(".repeat(500),
        "[".repeat(500)
    );
    parse_ok(&src);
}

#[test]
fn deep_input_never_overflows_the_stack() {
    small_stack(|| {
        let cases = [
            format!("scene = {}1;", "-".repeat(50_000)),
            format!("scene = {}a;", "a-".repeat(50_000)),
            format!("scene = {}a;", "|a|".repeat(50_000)),
            format!("scene = {}a;", "|a| ".repeat(200)),
            format!("scene = x{};", ".f()".repeat(20_000)),
            format!("scene = x{};", ".x".repeat(20_000)),
            format!("scene = {}", "(".repeat(1_000_000)),
        ];
        for src in &cases {
            assert!(src.len() <= MAX_SOURCE_BYTES);
            let d = parse_err(src);
            assert!(!d.is_empty() && d.len() <= 2, "{:?}", d);
        }
        // A chain of `|` is one node: as long as a file allows, it parses (and drops) on
        // the same stack.
        parse_ok(&format!("scene = {}a;", "a|".repeat(50_000)));
    });
}

#[test]
fn long_but_shallow_input_is_fine() {
    let n = MAX_EXPR_DEPTH - 1;
    parse_ok(&format!("scene = a{};", " + a".repeat(n)));
    parse_ok(&format!("scene = {}1;", "-".repeat(n)));
    parse_ok(&format!("scene = [{}1];", "1, ".repeat(30_000)));
    parse_ok(&format!("scene = union({}a);", "a, ".repeat(30_000)));
    parse_ok(&"let a = 1;\n".repeat(5_000));
    // Arithmetic chains nest (`shape_operator_chains_are_flat` for `|` and `&`).
    assert!(parse(&format!("scene = a{};", " + a".repeat(n + 1))).is_err());
}

/// Past the depth limit the hint says how to write what nested: cuts as one `subtract` of a
/// union, a chain of calls split with `let`.
#[test]
fn too_deep_hints_name_the_flat_form() {
    let hint = |src: String| parse_err(&src)[0].hint.clone().unwrap_or_default();
    let cuts = format!(
        "scene = box(10){};",
        " - sphere(1)".repeat(MAX_EXPR_DEPTH + 1)
    );
    assert!(hint(cuts).contains("subtract(a, union(b, c, ...))"));
    let moves = format!(
        "scene = box(1){};",
        ".translate([1, 0, 0])".repeat(MAX_EXPR_DEPTH)
    );
    assert!(hint(moves).contains("chain of calls"));
}

#[test]
fn too_large_file_is_one_diagnostic_at_the_end() {
    let src = " ".repeat(MAX_SOURCE_BYTES + 1);
    let d = parse_err(&src);
    assert_eq!(d.len(), 1);
    assert_eq!(d[0].message, "file is larger than the 1 MiB limit");
    assert_eq!(d[0].span, Span::new(src.len(), src.len()));
    // exactly at the limit is fine
    parse_ok(&" ".repeat(MAX_SOURCE_BYTES));
}

#[test]
fn many_errors_stop_after_a_hundred() {
    let d = parse_err(&";".repeat(100_000));
    assert_eq!(d.len(), 101);
    assert!(d[100].message.starts_with("too many errors"));
}

/// A tiny deterministic generator, so the fuzz tests need no extra dependency.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 33) as usize
    }
}

#[test]
fn no_panic_on_any_prefix_of_the_corpus() {
    let path = format!(
        "{}/../../tests/corpus/spec_section10.sdf",
        env!("CARGO_MANIFEST_DIR")
    );
    let src = std::fs::read_to_string(path).unwrap();
    for end in (0..=src.len()).filter(|&i| src.is_char_boundary(i)) {
        let prefix = &src[..end];
        if let Err(d) = parse(prefix) {
            assert!(!d.is_empty());
            let _ = sdfc_syntax::diag::render("p.sdf", prefix, &d);
        }
    }
}

#[test]
fn no_panic_on_token_soup() {
    let tokens = [
        "let", "fn", "param", "material", "light", "camera", "render", "scene", "true", "false",
        "x", "p", "sphere", "=", "==", ";", ",", ":", ".", "..", "(", ")", "[", "]", "{", "}", "|",
        "||", "&", "+", "-", "*", "/", "%", "<", "<=", "!=", "!", "1", ".5", "2.", "1e-4", "1e",
        "30deg", "9e99", " ", "\n", "//c\n", "/*", "*/", "é", "\u{FEFF}", "\0", "#", "\"",
    ];
    let mut rng = Lcg(0x5df_c0de);
    for _ in 0..3000 {
        let n = rng.next() % 40;
        let src: String = (0..n).map(|_| tokens[rng.next() % tokens.len()]).collect();
        if let Err(d) = parse(&src) {
            assert!(!d.is_empty());
            for diag in &d {
                assert!(diag.span.start <= diag.span.end);
                assert!(diag.span.end as usize <= src.len(), "{src:?}: {diag:?}");
                assert!(!diag.message.contains("internal"), "{src:?}: {diag:?}");
            }
            let _ = sdfc_syntax::diag::render("soup.sdf", &src, &d);
        }
    }
}

#[test]
fn no_panic_on_mutated_corpus() {
    let path = format!(
        "{}/../../tests/corpus/spec_section10.sdf",
        env!("CARGO_MANIFEST_DIR")
    );
    let src = std::fs::read_to_string(path).unwrap();
    let bytes = src.as_bytes();
    let mut rng = Lcg(42);
    let alphabet = b"()[]{}|&;,.:=-+*/%<>!0123456789eE_azAZ \n\t";
    for _ in 0..400 {
        let mut m = bytes.to_vec();
        for _ in 0..1 + rng.next() % 4 {
            let i = rng.next() % m.len();
            match rng.next() % 3 {
                0 => m[i] = alphabet[rng.next() % alphabet.len()],
                1 => {
                    m.remove(i);
                }
                _ => m.insert(i, alphabet[rng.next() % alphabet.len()]),
            }
        }
        let s = String::from_utf8_lossy(&m);
        if let Err(d) = parse(&s) {
            assert!(!d.is_empty());
            assert!(
                d.iter().all(|d| !d.message.contains("internal")),
                "{s}: {d:?}"
            );
        }
    }
}
