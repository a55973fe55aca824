//! The `.sdf` scene language front end: parsing (pest grammar in `grammar/sdf.pest`), the AST
//! with spans, diagnostics, and an AST dump for golden tests. No pest type is public.
//!
//! Limits the parser guarantees to later stages: a source is at most [`MAX_SOURCE_BYTES`],
//! brackets nest at most [`MAX_NESTING`] deep, lambdas nest at most [`MAX_NESTING`] deep, and
//! every expression tree is at most [`MAX_EXPR_DEPTH`] nodes deep, so recursive passes over the
//! AST need only a bounded stack.

pub mod ast;
pub mod diag;
pub mod pretty;
pub mod span;

mod lower;
mod parser;
mod scan;
mod syntax_error;

/// The largest source file accepted, in bytes.
pub const MAX_SOURCE_BYTES: usize = 1 << 20;

/// The deepest nesting of `( [ {` brackets accepted (and of lambdas inside lambdas).
pub const MAX_NESTING: usize = 128;

/// The deepest expression tree accepted: `a | b | c | ...` with more than this many operands,
/// or as many unary minus signs or chained method calls, is rejected with a diagnostic.
pub const MAX_EXPR_DEPTH: usize = 256;

/// Parses a whole `.sdf` file. On failure returns every diagnostic found (syntax errors are
/// reported for each item, resynchronising after each one). Never panics.
///
/// An empty or blank file parses to an empty [`ast::File`]; whether it has a `scene` is for the
/// later stages to check.
pub fn parse(source: &str) -> Result<ast::File, Vec<diag::Diagnostic>> {
    parser::parse(source)
}
