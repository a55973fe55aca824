//! The `.sdf` scene language front end: parsing (pest grammar in `grammar/`), the AST
//! with spans, diagnostics, and an AST dump for golden tests. No pest type is public.
//!
//! Limits the parser guarantees to later stages: a source is at most [`MAX_SOURCE_BYTES`],
//! brackets and lambdas together nest at most [`MAX_NESTING`] deep, and every expression tree
//! is at most [`MAX_EXPR_DEPTH`] nodes deep, so recursive passes over the AST (and its `Drop`)
//! need only a bounded stack.

pub mod ast;
pub mod diag;
mod elide;
pub mod pretty;
pub mod span;

mod grammar;
mod lower;
mod parser;
mod scan;
mod syntax_error;

/// The largest source file accepted, in bytes.
pub const MAX_SOURCE_BYTES: usize = 1 << 20;

/// The deepest nesting of `( [ {` brackets accepted; a lambda whose body is still open counts
/// as one level too. Checked by a cheap scan before parsing, so deep input cannot exhaust the
/// parser's stack.
pub const MAX_NESTING: usize = 128;

/// The deepest expression tree accepted: more than this many unary minus signs, chained
/// method calls, arithmetic operators or nested calls in a row are rejected with a diagnostic.
/// A chain of `|` or `&`, however long, is one level (`ast::ExprKind::Chain`); its operands
/// count as usual.
pub const MAX_EXPR_DEPTH: usize = 256;

/// After this many diagnostics the parser stops looking for more, and the compiler's later
/// stages report no more (one last diagnostic says so).
pub const MAX_DIAGNOSTICS: usize = 100;

/// Parses a whole `.sdf` file. On failure returns every diagnostic found (syntax errors are
/// reported for each item, resynchronising after each one). Never panics.
///
/// An empty or blank file parses to an empty [`ast::File`]; whether it has a `scene` is for the
/// later stages to check.
pub fn parse(source: &str) -> Result<ast::File, Vec<diag::Diagnostic>> {
    // The parser recurses once per nesting level, and at MAX_NESTING an unoptimised build needs
    // up to about 2 MiB of stack, as much as a whole test thread has. So it runs on its own
    // thread with a stack that is ample whatever the caller's is (the memory is only reserved,
    // not used).
    std::thread::scope(|scope| {
        let spawned = std::thread::Builder::new()
            .name("sdfc-parse".to_string())
            .stack_size(PARSER_STACK_BYTES)
            .spawn_scoped(scope, || parser::parse(source));
        match spawned {
            Ok(handle) => handle.join().unwrap_or_else(|_| {
                Err(vec![diag::Diagnostic::error(
                    span::Span::new(0, 0),
                    "internal parser error: the parser panicked",
                )
                .with_hint(
                    "this is a bug in sdfc; please report it with the input",
                )])
            }),
            // No thread to be had: parse on this one.
            Err(_) => parser::parse(source),
        }
    })
}

/// The stack of the parser's thread.
const PARSER_STACK_BYTES: usize = 16 << 20;
