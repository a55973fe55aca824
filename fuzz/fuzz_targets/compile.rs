//! Fuzz target: any bytes, as a scene, must compile to validated WGSL or to diagnostics with
//! in-bounds spans, never panic and never produce invalid WGSL (an internal error). A scene
//! that compiles is compiled again as a culled library (`--cull --lib`), the other emission
//! paths, which must validate too.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sdfc_wgsl::{compile_here, Failure, Options};

fuzz_target!(|data: &[u8]| {
    let Ok(source) = std::str::from_utf8(data) else {
        return;
    };
    match compile_here(source, &Options::default()) {
        Ok(_) => {
            let culled_lib = Options {
                lib: true,
                cull: true,
                ..Options::default()
            };
            if let Err(Failure::Internal { report, wgsl }) = compile_here(source, &culled_lib) {
                panic!("internal error (--cull --lib): {report}\n{wgsl}");
            }
        }
        Err(Failure::Diagnostics(diags)) => {
            assert!(!diags.is_empty());
            for d in &diags {
                assert!(d.span.start <= d.span.end && d.span.end as usize <= source.len());
            }
        }
        Err(Failure::Internal { report, wgsl }) => {
            panic!("internal error: {report}\n{wgsl}");
        }
        Err(f @ Failure::Usage(_)) => panic!("the default options refused: {f}"),
    }
});
