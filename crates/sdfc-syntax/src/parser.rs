//! The parse driver: pre-checks, then pest one item at a time (the tree parser; the report
//! parser again for an item with a syntax error), resynchronising after each syntax error so
//! that one run reports every error it can find.

use crate::ast::File;
use crate::diag::Diagnostic;
use crate::grammar::report::{self, ReportParser};
use crate::grammar::tree::{Rule, TreeParser};
use crate::lower::{self, Lower};
use crate::span::Span;
use crate::{scan, syntax_error, MAX_DIAGNOSTICS};
use pest::{Parser, RuleType};

/// pest's budget of rule calls for one item: a safety net. A PEG parser backtracks, and some
/// broken inputs (unclosed parentheses inside lambdas, nested a dozen deep) once made it take
/// exponential time: 2.8 kB files found by the fuzzer took minutes. The grammar no longer
/// backtracks like that (see `expr` in the grammar), but any future rule that does is still
/// stopped here instead of hanging. A 1 MiB flat union of spheres passes with 24 calls per
/// byte of the file size limit and fails with 16; a chain `1+1+...` needs more than 32, and
/// is refused. 32 bounds a tangled item to about 1.5 s on the development VM, twice that
/// where the tree parser finds a syntax error and the report parser, parsing the item again
/// for its message, runs out. The tree parser never needs more calls than the report parser
/// (a test below), so where it runs out the report parser would too, and "too tangled" is
/// said without asking it; an item near the limit that the report parser alone (the grammar
/// before the split) gave up on now parses. Exceeding it is reported as a syntax error at
/// the item.
pub const CALL_LIMIT: usize = 32 * crate::MAX_SOURCE_BYTES;

pub(crate) fn parse(source: &str) -> Result<File, Vec<Diagnostic>> {
    scan::precheck(source).map_err(|d| vec![d])?;
    // Process-wide in pest, and the same value for every parse, so threads cannot disagree.
    pest::set_call_limit(std::num::NonZeroUsize::new(CALL_LIMIT));
    let pratt = lower::pratt();
    let mut items = Vec::new();
    let mut diags: Vec<Diagnostic> = Vec::new();
    // A byte-order mark is not part of the text.
    let mut pos = if source.starts_with('\u{FEFF}') { 3 } else { 0 };
    // The start of the previous item, from which hints may scan the source.
    let mut context = pos;
    while pos <= source.len() {
        if diags.len() >= MAX_DIAGNOSTICS {
            diags.push(Diagnostic::error(
                Span::new(pos, pos),
                format!("too many errors; stopping after {MAX_DIAGNOSTICS}"),
            ));
            break;
        }
        // pest sees the text only up to where this item must end at the latest (a valid item
        // never runs past its first `;` outside braces, the `}` closing its block, or a line
        // that starts another item). This keeps the cost of each syntax error proportional to
        // the item, not to the rest of the file: pest's error scans its whole input.
        let bound = scan::resync(source, pos, pos);
        let Some(rest) = source.get(pos..bound) else {
            diags.push(internal(pos, "resumed inside a character"));
            break;
        };
        match TreeParser::parse(Rule::next_item, rest) {
            Ok(mut pairs) => {
                let Some(item) = pairs.next().and_then(|p| p.into_inner().next()) else {
                    diags.push(internal(pos, "empty parse"));
                    break;
                };
                if item.as_rule() == Rule::EOI {
                    break;
                }
                let end = item.as_span().end();
                let lower = Lower::new(pos, &pratt);
                // On `Err(Stop)` the reasons are already in `lower.diags`.
                if let Ok(item) = lower.item(item) {
                    items.push(item);
                }
                diags.append(&mut lower.diags.borrow_mut());
                context = pos;
                pos += end.max(1);
            }
            Err(tree_error) => {
                // The tree parser's pairs cannot name the punctuation that was expected: the
                // report parser parses the item again for the message (a broken item only).
                // Where the tree parser ran out of calls, so would it (it needs as many or
                // more), and the item is too tangled either way.
                let report = match is_call_limit(&tree_error) {
                    true => Err(None),
                    false => ReportParser::parse(report::Rule::next_item, rest).map_err(Some),
                };
                match report {
                    Err(Some(error)) if !is_call_limit(&error) => {
                        let (err_pos, d) = syntax_error::diagnose(source, pos, context, &error);
                        diags.push(d);
                        context = pos;
                        pos = scan::resync(source, pos, err_pos).max(pos + 1);
                    }
                    Err(_) => {
                        diags.push(tangled(pos, bound));
                        context = pos;
                        pos = bound.max(pos + 1);
                    }
                    Ok(_) => {
                        diags.push(internal(pos, "the tree and report parsers disagree"));
                        break;
                    }
                }
            }
        }
    }
    if diags.is_empty() {
        Ok(File { items })
    } else {
        Err(diags)
    }
}

/// Whether pest gave up because the item used up [`CALL_LIMIT`].
fn is_call_limit<R: RuleType>(error: &pest::error::Error<R>) -> bool {
    matches!(
        &error.variant,
        pest::error::ErrorVariant::CustomError { message } if message.contains("call limit")
    )
}

/// The item from `pos` to `bound` used up [`CALL_LIMIT`].
fn tangled(pos: usize, bound: usize) -> Diagnostic {
    Diagnostic::error(
        Span::new(pos, bound),
        "this item is too tangled for the parser to make sense of",
    )
    .with_label("gave up parsing here")
    .with_hint("look for unclosed `(` or `[` in this item; split long expressions with `let`")
}

fn internal(pos: usize, what: &str) -> Diagnostic {
    Diagnostic::error(
        Span::new(pos, pos),
        format!("internal parser error: {what}"),
    )
    .with_hint("this is a bug in sdfc; please report it with the input")
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Mutex, MutexGuard};

    /// pest's call limit is process-wide: the tests that parse take turns, since one of them
    /// sets small limits.
    fn pest_turn() -> MutexGuard<'static, ()> {
        static PEST: Mutex<()> = Mutex::new(());
        PEST.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Every scene and error file of the repository.
    fn sources() -> Vec<(String, String)> {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../");
        let mut out = Vec::new();
        for dir in ["tests/corpus", "tests/errors", "tests/scenes", "examples"] {
            let mut paths: Vec<_> = std::fs::read_dir(format!("{root}{dir}"))
                .unwrap()
                .map(|e| e.unwrap().path())
                .filter(|p| p.extension().is_some_and(|x| x == "sdf"))
                .collect();
            paths.sort();
            for p in paths {
                out.push((
                    p.display().to_string(),
                    std::fs::read_to_string(&p).unwrap(),
                ));
            }
        }
        assert!(out.len() > 80, "the scene files have moved");
        out
    }

    /// A text to parse: as one file (`whole`, the `file` rule) or its first item
    /// (`next_item`), and where it came from.
    struct Text {
        text: String,
        whole: bool,
        from: String,
    }

    /// Mostly broken texts: an item from every seventh character of every scene and error
    /// file, and whole files with one character taken out, doubled, or changed into
    /// punctuation.
    fn texts() -> Vec<Text> {
        let mut out = Vec::new();
        for (name, src) in sources() {
            let starts = (0..src.len())
                .step_by(7)
                .filter(|&i| src.is_char_boundary(i));
            for i in starts {
                out.push(Text {
                    text: src[i..].to_string(),
                    whole: false,
                    from: format!("{name} from byte {i}"),
                });
            }
            let cuts = (0..src.len())
                .step_by(13)
                .filter(|&i| src.is_char_boundary(i));
            for i in cuts {
                let Some(c) = src[i..].chars().next() else {
                    continue;
                };
                let j = i + c.len_utf8();
                for with in [
                    String::new(),
                    format!("{c}{c}"),
                    ")".into(),
                    ",".into(),
                    "-".into(),
                ] {
                    out.push(Text {
                        text: format!("{}{with}{}", &src[..i], &src[j..]),
                        whole: true,
                        from: format!("{name}, byte {i} replaced by {with:?}"),
                    });
                }
            }
        }
        // Items of negated terms, where the tree parser's calls come nearest the report's.
        for k in [1, 3, 10, 30, 100, 300] {
            for neg in ["-1", "-x.y", "- -[1, -2].z", "-f(-1, a: -2)"] {
                out.push(Text {
                    text: format!("let v = f({});", vec![neg; k].join(", ")),
                    whole: false,
                    from: format!("{k} arguments `{neg}`"),
                });
                out.push(Text {
                    text: format!("let v = {};", vec![neg; k].join(" * ")),
                    whole: false,
                    from: format!("{k} factors `{neg}`"),
                });
            }
        }
        out
    }

    /// What a parser made of a text: where it ends, a syntax error, or `None` where it ran
    /// out of calls.
    type Outcome = Option<Result<usize, ()>>;

    /// The [`Outcome`] of one parse.
    fn outcome<R: RuleType>(
        result: Result<pest::iterators::Pairs<'_, R>, pest::error::Error<R>>,
    ) -> Outcome {
        match result {
            Ok(pairs) => Some(Ok(pairs.last().map_or(0, |p| p.as_span().end()))),
            Err(e) if is_call_limit(&e) => None,
            Err(_) => Some(Err(())),
        }
    }

    /// Both parsers' outcomes for `t`.
    fn both(t: &Text) -> (Outcome, Outcome) {
        let (tree, rep) = match t.whole {
            true => (Rule::file, report::Rule::file),
            false => (Rule::next_item, report::Rule::next_item),
        };
        (
            outcome(TreeParser::parse(tree, &t.text)),
            outcome(ReportParser::parse(rep, &t.text)),
        )
    }

    /// The tree parser and the report parser accept the same texts and end an item at the
    /// same place: the driver builds the tree from one and reports errors from the other,
    /// which is right only if their companions' rules match alike. It fails if a
    /// companion's `]` also takes `)`, or its term one postfix form instead of many.
    #[test]
    fn the_tree_and_report_parsers_accept_the_same_texts() {
        let _turn = pest_turn();
        pest::set_call_limit(std::num::NonZeroUsize::new(CALL_LIMIT));
        let (mut compared, mut rejected) = (0, 0);
        for t in texts() {
            if let (Some(tree), Some(rep)) = both(&t) {
                assert_eq!(tree, rep, "{}", t.from);
                compared += 1;
                rejected += usize::from(tree.is_err());
            }
        }
        // Both kinds of outcome were compared, many times.
        assert!(
            compared > 10_000 && rejected > compared / 4,
            "{compared}, {rejected}"
        );
    }

    /// The tree parser runs out of pest's calls ([`CALL_LIMIT`]) only where the report parser
    /// does too: the driver reports "too tangled" from the first without asking the second,
    /// which is what the report parser (the grammar as it was before the split) would have
    /// said. The same texts under small budgets, which most of them exceed. It fails with a
    /// guard (`&"-" ~ neg_term`) before the tree parser's negated terms, whose sequence and
    /// lookahead cost more calls than the report parser's `neg*`.
    #[test]
    fn the_tree_parser_needs_no_more_calls_than_the_report_parser() {
        let _turn = pest_turn();
        let (mut both_out, mut report_only) = (0, 0);
        let texts = texts();
        for limit in [64, 256, 1024, 4096, 16384] {
            pest::set_call_limit(std::num::NonZeroUsize::new(limit));
            for t in &texts {
                match both(t) {
                    (None, None) => both_out += 1,
                    (None, Some(_)) => {
                        pest::set_call_limit(std::num::NonZeroUsize::new(CALL_LIMIT));
                        panic!("{}: only the tree parser ran out of {limit} calls", t.from);
                    }
                    (Some(_), None) => report_only += 1,
                    (Some(_), Some(_)) => {}
                }
            }
        }
        pest::set_call_limit(std::num::NonZeroUsize::new(CALL_LIMIT));
        // The budgets were reached by both, and by the report parser alone (it needs more).
        assert!(
            both_out > 10_000 && report_only > 500,
            "{both_out}, {report_only}"
        );
    }

    /// The whole-file rule documents the same language the item-by-item driver parses.
    #[test]
    fn file_rule_matches_the_driver() {
        let _turn = pest_turn();
        let corpus = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/corpus/");
        for name in ["constructs.sdf", "spec_section10.sdf"] {
            let src = std::fs::read_to_string(format!("{corpus}{name}")).unwrap();
            assert!(TreeParser::parse(Rule::file, &src).is_ok(), "{name}");
            assert!(
                ReportParser::parse(report::Rule::file, &src).is_ok(),
                "{name}"
            );
            assert!(parse(&src).is_ok(), "{name}");
        }
        for bad in ["let a = 1", "scene = ;", "material m { a: 1 };", "x"] {
            assert!(TreeParser::parse(Rule::file, bad).is_err(), "{bad}");
            assert!(
                ReportParser::parse(report::Rule::file, bad).is_err(),
                "{bad}"
            );
            assert!(parse(bad).is_err(), "{bad}");
        }
    }
}
