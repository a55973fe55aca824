//! Printing diagnostics and internal errors on stderr.

use crate::out::{say, say_part};
use sdfc_syntax::diag::{self, Diagnostic};
use sdfc_wgsl::Failure;
use std::io::IsTerminal;

pub fn diagnostics(path: &str, source: &str, diags: &[Diagnostic]) {
    if diags.is_empty() {
        return;
    }
    let color = std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none();
    say_part!("{}", diag::render_with(path, source, diags, color));
}

/// Prints a failure; returns the outcome it maps to.
pub fn failure(path: &str, source: &str, f: &Failure) -> crate::Outcome {
    match f {
        Failure::Diagnostics(d) => {
            diagnostics(path, source, d);
            let n = d.iter().filter(|d| d.is_error()).count();
            say!("sdfc: {path}: {n} error{}", if n == 1 { "" } else { "s" });
            crate::Outcome::InputError
        }
        Failure::Internal { report, wgsl } => {
            say!("sdfc: internal compiler error: the WGSL emitted for {path} is invalid.");
            say!("This is a bug in sdfc, not in the scene; please report it with the scene.");
            say!("{report}");
            if !wgsl.is_empty() {
                say!("--- emitted WGSL ---\n{wgsl}");
            }
            crate::Outcome::EnvError
        }
        Failure::Usage(message) => {
            say!("sdfc: {message}");
            crate::Outcome::EnvError
        }
    }
}

/// The first error's message with its position (`:line:col: message`), for one-line summaries.
pub fn first_error(source: &str, f: &Failure) -> String {
    match f {
        Failure::Diagnostics(d) => d
            .iter()
            .find(|d| d.is_error())
            .map(|d| {
                let (l, c) = d.line_col(source);
                format!(":{l}:{c}: {}", d.message)
            })
            .unwrap_or_else(|| ": error".into()),
        Failure::Internal { .. } => ": internal compiler error (invalid WGSL emitted)".into(),
        Failure::Usage(message) => format!(": {message}"),
    }
}
