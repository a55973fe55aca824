//! Validation of emitted WGSL with naga's front end and validator.

use naga::valid::{Capabilities, ValidationFlags, Validator};

/// Parses and validates a WGSL module; the error is naga's report, rendered against the
/// source. `name` labels the source in the report.
pub fn validate(name: &str, wgsl: &str) -> Result<(), String> {
    let module =
        naga::front::wgsl::parse_str(wgsl).map_err(|e| e.emit_to_string_with_path(wgsl, name))?;
    Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(&module)
        .map_err(|e| e.emit_to_string_with_path(wgsl, name))?;
    Ok(())
}
