//! Validation of emitted WGSL with naga's front end and validator.

use naga::valid::{Capabilities, ValidationFlags, Validator};

/// Why a module is invalid: naga's report rendered against the source, and its first
/// problem in one line (for `sdfc check`'s one line per file).
#[derive(Clone, Debug)]
pub struct Invalid {
    pub report: String,
    /// 1-based line and column of the problem, where naga gives a span.
    pub at: Option<(u32, u32)>,
    pub message: String,
}

/// Parses and validates a WGSL module; the error is naga's report, rendered against the
/// source. `name` labels the source in the report.
pub fn validate(name: &str, wgsl: &str) -> Result<(), String> {
    validate_located(name, wgsl).map_err(|e| e.report)
}

/// [`validate`], with the first problem's position and message besides the report.
pub fn validate_located(name: &str, wgsl: &str) -> Result<(), Invalid> {
    let at = |l: Option<naga::SourceLocation>| l.map(|l| (l.line_number, l.line_position));
    let module = naga::front::wgsl::parse_str(wgsl).map_err(|e| Invalid {
        report: e.emit_to_string_with_path(wgsl, name),
        at: at(e.location(wgsl)),
        message: e.message().to_string(),
    })?;
    Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(&module)
        .map_err(|e| Invalid {
            report: e.emit_to_string_with_path(wgsl, name),
            at: at(e.location(wgsl)),
            message: e.as_inner().to_string(),
        })?;
    Ok(())
}
