//! `sdfc check`: compiles each `.sdf` and validates each `.wgsl`; one line per file.

use crate::out::say;
use crate::{read_source, report, Outcome};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Scene (.sdf) and shader (.wgsl) files
    #[arg(required = true)]
    files: Vec<PathBuf>,
}

pub fn run(a: Args) -> Outcome {
    let mut worst = Outcome::Ok;
    for file in &a.files {
        let (line, o) = check_one(file);
        if let Err(stop) = crate::out::print(&format!("{line}\n")) {
            return stop;
        }
        worst = match (worst, o) {
            (Outcome::EnvError, _) | (_, Outcome::EnvError) => Outcome::EnvError,
            (Outcome::InputError, _) | (_, Outcome::InputError) => Outcome::InputError,
            _ => Outcome::Ok,
        };
    }
    worst
}

/// Checks one file: its line for stdout (`ok    PATH` or `error PATH:LINE:COL: message`) and
/// its outcome; diagnostics go to stderr.
fn check_one(file: &PathBuf) -> (String, Outcome) {
    let path = file.display().to_string();
    let source = match read_source(file) {
        Ok(s) => s,
        Err(Outcome::InputError) => {
            return (
                format!("error {path}: not valid UTF-8"),
                Outcome::InputError,
            )
        }
        Err(o) => return (format!("error {path}: unreadable"), o),
    };
    // `.WGSL` is a shader too, as `render` takes `.PNG` for a picture.
    let is_wgsl = file
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("wgsl"));
    if is_wgsl {
        return match sdfc_wgsl::validate::validate_located(&path, &strip_import_path(&source)) {
            Ok(()) => (format!("ok    {path}"), Outcome::Ok),
            Err(e) => {
                say!("{}", e.report);
                let at = e.at.map(|(l, c)| format!(":{l}:{c}")).unwrap_or_default();
                (
                    format!("error {path}{at}: invalid WGSL: {}", e.message),
                    Outcome::InputError,
                )
            }
        };
    }
    match sdfc_wgsl::compile(&source, &sdfc_wgsl::Options::default()) {
        Ok(c) => {
            report::diagnostics(&path, &source, &c.warnings);
            (format!("ok    {path}"), Outcome::Ok)
        }
        Err(f) => {
            let line = report::first_error(&source, &f);
            let o = report::failure(&path, &source, &f);
            (format!("error {path}{line}"), o)
        }
    }
}

/// naga_oil's `#define_import_path` line is not WGSL: blank it (keeping line numbers).
fn strip_import_path(source: &str) -> String {
    source
        .lines()
        .map(|l| {
            if l.trim_start().starts_with("#define_import_path") {
                ""
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}
