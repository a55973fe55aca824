//! Turns a pest failure into a [`Diagnostic`] that says in words what was expected and what was
//! found, with a hint where an obvious one exists. No pest rule name reaches the user.

use crate::diag::{nearest, Diagnostic};
use crate::grammar::report::Rule;
use crate::scan;
use crate::span::Span;
use pest::error::{ErrorVariant, InputLocation};

/// One thing the parser could have accepted, in the order messages list them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Expected {
    Item,
    Name,
    ParamName,
    Field,
    Arg,
    Expr,
    Member,
    Token(&'static str),
    /// An operator or `.`: something that would continue the expression so far. Only mentioned
    /// when nothing else was possible.
    Operator,
    EndOfFile,
}

impl Expected {
    /// Sort key: what a message lists first. Separators come before closing brackets.
    fn rank(self) -> (u8, u8) {
        match self {
            Expected::Item => (0, 0),
            Expected::Name => (1, 0),
            Expected::ParamName => (2, 0),
            Expected::Field => (3, 0),
            Expected::Arg => (4, 0),
            Expected::Expr => (5, 0),
            Expected::Member => (6, 0),
            Expected::Token(t) => {
                let order = [";", "=", ":", ",", "|", "(", "[", "{", ")", "]", "}"];
                (
                    7,
                    order.iter().position(|o| *o == t).unwrap_or(order.len()) as u8,
                )
            }
            Expected::Operator => (8, 0),
            Expected::EndOfFile => (9, 0),
        }
    }

    fn words(self) -> String {
        match self {
            Expected::Item => {
                "an item (`let`, `fn`, `param`, `material`, `light`, `camera`, `render` or `scene`)"
                    .to_string()
            }
            Expected::Name => "a name".to_string(),
            Expected::ParamName => "a parameter name".to_string(),
            Expected::Field => "a field (`name: value`)".to_string(),
            Expected::Arg => "an argument".to_string(),
            Expected::Expr => "an expression".to_string(),
            Expected::Member => "a method or swizzle name".to_string(),
            Expected::Token(t) => format!("`{t}`"),
            Expected::Operator => "an operator".to_string(),
            Expected::EndOfFile => "end of file".to_string(),
        }
    }
}

fn expected_of(rule: Rule) -> Expected {
    use Expected::*;
    match rule {
        Rule::kw_let
        | Rule::kw_fn
        | Rule::kw_param
        | Rule::kw_material
        | Rule::kw_light
        | Rule::kw_camera
        | Rule::kw_render
        | Rule::kw_scene
        | Rule::next_item
        | Rule::file
        | Rule::let_item
        | Rule::fn_item
        | Rule::param_item
        | Rule::material_item
        | Rule::light_item
        | Rule::camera_item
        | Rule::render_item
        | Rule::scene_item
        | Rule::item => Item,
        Rule::ident => Name,
        Rule::param_name | Rule::fn_param => ParamName,
        Rule::field | Rule::field_name => Field,
        Rule::arg | Rule::arg_name => Arg,
        Rule::member => Member,
        Rule::semi => Token(";"),
        Rule::assign => Token("="),
        Rule::colon => Token(":"),
        Rule::comma => Token(","),
        Rule::bar => Token("|"),
        Rule::lparen => Token("("),
        Rule::rparen => Token(")"),
        Rule::lbracket => Token("["),
        Rule::rbracket => Token("]"),
        Rule::lbrace => Token("{"),
        Rule::rbrace => Token("}"),
        Rule::dot
        | Rule::postfix
        | Rule::op_or
        | Rule::op_and
        | Rule::op_le
        | Rule::op_lt
        | Rule::op_ge
        | Rule::op_gt
        | Rule::op_eq
        | Rule::op_ne
        | Rule::op_add
        | Rule::op_sub
        | Rule::op_mul
        | Rule::op_div
        | Rule::op_rem
        | Rule::infix
        | Rule::infix_start => Operator,
        Rule::block => Token("{"),
        Rule::args => Arg,
        // Silent lexical rules: never reported by pest.
        Rule::WHITESPACE
        | Rule::COMMENT
        | Rule::ident_start
        | Rule::ident_char
        | Rule::word_chars
        | Rule::keyword => Operator,
        Rule::EOI => EndOfFile,
        Rule::expr
        | Rule::term
        | Rule::neg
        | Rule::number
        | Rule::num_body
        | Rule::boolean
        | Rule::call
        | Rule::callee
        | Rule::vector
        | Rule::lambda
        | Rule::name
        | Rule::paren
        | Rule::primary => Expr,
    }
}

/// A token quoted for a message; an invisible character (a control character or a stray NUL,
/// common in pasted or corrupted files) is named by its code point, since quoting it would
/// show nothing.
fn describe_token(token: &str) -> String {
    match token.chars().find(|c| c.is_control()) {
        Some(c) => format!("the control character U+{:04X}", u32::from(c)),
        None => format!("`{token}`"),
    }
}

/// The diagnostic for a pest failure while parsing the text that starts at `offset`.
/// `context` is an earlier token boundary (the start of the previous item) from which the
/// source can be scanned for hints.
pub(crate) fn diagnose(
    source: &str,
    offset: usize,
    context: usize,
    error: &pest::error::Error<Rule>,
) -> (usize, Diagnostic) {
    let local = match error.location {
        InputLocation::Pos(p) => p,
        InputLocation::Span((s, _)) => s,
    };
    let pos = (offset + local).min(source.len());
    let (found_span, found) = match scan::token_at(source, pos) {
        Some((span, text)) => (span, Some(text)),
        None => (Span::new(pos, pos), None),
    };
    let found_words = match found {
        Some(t) => describe_token(t),
        None => "end of file".to_string(),
    };

    let positives = match &error.variant {
        ErrorVariant::ParsingError { positives, .. } => positives,
        ErrorVariant::CustomError { .. } => {
            // pest's own stack or call budget ran out: only very deep input gets here.
            let d = Diagnostic::error(found_span, "this expression is nested too deeply to parse")
                .with_label("nested too deeply")
                .with_hint("split the expression into smaller pieces with `let`");
            return (pos, d);
        }
    };

    let mut expected: Vec<Expected> = positives.iter().map(|&r| expected_of(r)).collect();
    expected.sort_by_key(|e| e.rank());
    expected.dedup();
    if expected.len() > 1 {
        expected.retain(|e| *e != Expected::Operator);
    }
    if expected.contains(&Expected::Item) {
        expected.retain(|e| *e != Expected::EndOfFile);
    }
    // An expression may start with a lambda's `|`, which pest reports as a token of its own.
    if expected.contains(&Expected::Expr) {
        expected.retain(|e| *e != Expected::Token("|"));
    }
    if expected.contains(&Expected::Arg) {
        expected.retain(|e| *e != Expected::Expr);
    }

    // `scene = light + 1`: a keyword where a name belongs is read as the start of a call (a
    // callee may be any word), so pest's furthest failure is the missing `(` after it.
    if expected == [Expected::Token("(")] {
        if let Some(d) = keyword_as_name(source, offset, pos) {
            return (pos, d);
        }
    }

    let message = if expected.is_empty() {
        format!("unexpected {found_words}")
    } else if expected == [Expected::Token(";")] {
        format!("expected `;` after the item, found {found_words}")
    } else {
        format!("expected {}, found {found_words}", join_or(&expected))
    };
    let label = match found {
        Some(_) => "unexpected token".to_string(),
        None => "the file ends here".to_string(),
    };
    let mut d = Diagnostic::error(found_span, message).with_label(label);
    if let Some(hint) = hint(source, offset, context, pos, found, &expected, &mut d) {
        d = d.with_hint(hint);
    }
    (pos, d)
}

/// A keyword, not at the start of its item, right before `pos`, reported as a misused name.
fn keyword_as_name(source: &str, offset: usize, pos: usize) -> Option<Diagnostic> {
    let end = scan::prev_token_end(source, offset, pos)?;
    let (start, word) = scan::word_before(source, end);
    let first = scan::first_token(source, offset)?;
    if start <= first || !scan::KEYWORDS.contains(&word) {
        return None;
    }
    Some(
        Diagnostic::error(
            Span::new(start, end),
            format!("expected an expression, found the keyword `{word}`"),
        )
        .with_label("a keyword, not a name")
        .with_hint(format!(
            "`{word}` is a keyword and cannot be used as a name; choose another name"
        )),
    )
}

fn join_or(expected: &[Expected]) -> String {
    let words: Vec<String> = expected.iter().map(|e| e.words()).collect();
    match words.split_last() {
        None => String::new(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
    }
}

fn hint(
    source: &str,
    offset: usize,
    context: usize,
    pos: usize,
    found: Option<&str>,
    expected: &[Expected],
    d: &mut Diagnostic,
) -> Option<String> {
    let wants = |e: Expected| expected.contains(&e);
    let found_keyword = found.filter(|t| scan::KEYWORDS.contains(t));
    let found_item_keyword = found.filter(|t| scan::ITEM_KEYWORDS.contains(t));

    // A keyword where a name was wanted: `let fn = ...`, `scene = light + 1`.
    if let Some(k) = found_keyword {
        if wants(Expected::Name) || wants(Expected::ParamName) || wants(Expected::Expr) {
            return Some(format!(
                "`{k}` is a keyword and cannot be used as a name; choose another name"
            ));
        }
    }

    // An unclosed bracket: a closer was expected, and the text ran out or moved on.
    let closer = expected.iter().find_map(|e| match e {
        Expected::Token(t @ (")" | "]" | "}")) => Some(*t),
        _ => None,
    });
    let moved_on = match found {
        None => true,
        Some(t) => matches!(t, ";" | ")" | "]" | "}") || found_item_keyword.is_some(),
    };
    if let (Some(closer), true) = (closer, moved_on) {
        if let Some((at, open)) = scan::unclosed_bracket(source, offset, pos) {
            let open = char::from(open);
            let (line, col) = crate::diag::line_col(source, at);
            d.secondary.push((
                Span::new(at, at + 1),
                format!("this `{open}` is never closed"),
            ));
            return Some(format!(
                "add `{closer}` to close the `{open}` at line {line}, column {col}"
            ));
        }
    }

    // A missing `;` at the end of the previous line.
    if wants(Expected::Token(";")) {
        if let Some(end) = scan::prev_token_end(source, offset, pos) {
            let (prev_line, _) = crate::diag::line_col(source, end);
            let (line, _) = crate::diag::line_col(source, pos);
            if prev_line < line {
                return Some(format!(
                    "the item probably lacks its `;`: add one at the end of line {prev_line}"
                ));
            }
        }
        return None;
    }

    if wants(Expected::Item) {
        if found == Some(";")
            && scan::prev_token_end(source, context, pos)
                .is_some_and(|end| source.as_bytes().get(end - 1) == Some(&b'}'))
        {
            return Some(
                "`material`, `light`, `camera` and `render` blocks do not end with `;`; remove it"
                    .to_string(),
            );
        }
        if let Some(word) = found.filter(|t| t.bytes().next().is_some_and(scan::is_ident_start)) {
            if let Some(k) = nearest(word, scan::ITEM_KEYWORDS) {
                return Some(format!("did you mean `{k}`?"));
            }
            return Some(format!(
                "every item starts with a keyword, for example `let {word} = ...;`"
            ));
        }
        return None;
    }

    // `||`: a lambda without parameters.
    if wants(Expected::ParamName) && matches!(found, Some("|" | "||")) {
        return Some("a lambda takes one or two parameters, as in `|p| length(p) - 1`".into());
    }

    // `[1, 2 3]`, `f(a b)`, `{ a: 1 b: 2 }`: a missing separator.
    if wants(Expected::Token(",")) && found.is_some() {
        return Some("a `,` is probably missing before this".into());
    }
    None
}
