//! The parse driver: pre-checks, then pest one item at a time, resynchronising after each
//! syntax error so that one run reports every error it can find.

use crate::ast::File;
use crate::diag::Diagnostic;
use crate::lower::{self, Lower};
use crate::span::Span;
use crate::{scan, syntax_error};
use pest::Parser;

#[derive(pest_derive::Parser)]
#[grammar = "../../../grammar/sdf.pest"]
struct SdfParser;

/// After this many diagnostics the parser stops looking for more.
const MAX_DIAGNOSTICS: usize = 100;

/// pest's budget of rule calls for one item: a safety net. A PEG parser backtracks, and some
/// broken inputs (unclosed parentheses inside lambdas, nested a dozen deep) once made it take
/// exponential time: 2.8 kB files found by the fuzzer took minutes. The grammar no longer
/// backtracks like that (see `expr` in the grammar), but any future rule that does is still
/// stopped here instead of hanging. A valid item needs fewer
/// than 24 calls per byte (a 1 MiB flat union passes with 24 per byte of the file size limit,
/// fails with 16), so 32 leaves a margin and bounds a tangled item to about 1.5 s on the
/// development VM. Exceeding it is reported as a syntax error at the item.
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
        match SdfParser::parse(Rule::next_item, rest) {
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
            Err(error) if is_call_limit(&error) => {
                diags.push(
                    Diagnostic::error(
                        Span::new(pos, bound),
                        "this item is too tangled for the parser to make sense of",
                    )
                    .with_label("gave up parsing here")
                    .with_hint(
                        "look for unclosed `(` or `[` in this item; split long expressions \
                         with `let`",
                    ),
                );
                context = pos;
                pos = bound.max(pos + 1);
            }
            Err(error) => {
                let (err_pos, d) = syntax_error::diagnose(source, pos, context, &error);
                diags.push(d);
                context = pos;
                pos = scan::resync(source, pos, err_pos).max(pos + 1);
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
fn is_call_limit(error: &pest::error::Error<Rule>) -> bool {
    matches!(
        &error.variant,
        pest::error::ErrorVariant::CustomError { message } if message.contains("call limit")
    )
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

    /// The whole-file rule documents the same language the item-by-item driver parses.
    #[test]
    fn file_rule_matches_the_driver() {
        let corpus = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/corpus/");
        for name in ["constructs.sdf", "spec_section10.sdf"] {
            let src = std::fs::read_to_string(format!("{corpus}{name}")).unwrap();
            assert!(SdfParser::parse(Rule::file, &src).is_ok(), "{name}");
            assert!(parse(&src).is_ok(), "{name}");
        }
        for bad in ["let a = 1", "scene = ;", "material m { a: 1 };", "x"] {
            assert!(SdfParser::parse(Rule::file, bad).is_err(), "{bad}");
            assert!(parse(bad).is_err(), "{bad}");
        }
    }
}
