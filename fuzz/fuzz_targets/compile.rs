//! Fuzz target: any bytes, as a scene, must compile to validated WGSL or to diagnostics with
//! in-bounds spans, never panic and never produce invalid WGSL (an internal error).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(source) = std::str::from_utf8(data) else { return };
    match sdfc_wgsl::compile_here(source, &sdfc_wgsl::Options::default()) {
        Ok(_) => {}
        Err(sdfc_wgsl::Failure::Diagnostics(diags)) => {
            assert!(!diags.is_empty());
            for d in &diags {
                assert!(d.span.start <= d.span.end && d.span.end as usize <= source.len());
            }
        }
        Err(sdfc_wgsl::Failure::Internal { report, wgsl }) => {
            panic!("internal error: {report}\n{wgsl}");
        }
    }
});
