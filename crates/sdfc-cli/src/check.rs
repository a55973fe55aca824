//! `sdfc check`: compiles each `.sdf` and validates each `.wgsl`; one line per file.

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
    let note = |o: Outcome, worst: &mut Outcome| {
        *worst = match (&*worst, o) {
            (Outcome::EnvError, _) | (_, Outcome::EnvError) => Outcome::EnvError,
            (Outcome::InputError, _) | (_, Outcome::InputError) => Outcome::InputError,
            _ => Outcome::Ok,
        }
    };
    for file in &a.files {
        let path = file.display().to_string();
        let source = match read_source(file) {
            Ok(s) => s,
            Err(o) => {
                println!("error {path}: unreadable");
                note(o, &mut worst);
                continue;
            }
        };
        let is_wgsl = file.extension().is_some_and(|e| e == "wgsl");
        if is_wgsl {
            match sdfc_wgsl::validate::validate(&path, &strip_import_path(&source)) {
                Ok(()) => println!("ok    {path}"),
                Err(r) => {
                    eprintln!("{r}");
                    println!("error {path}: invalid WGSL");
                    note(Outcome::InputError, &mut worst);
                }
            }
            continue;
        }
        match sdfc_wgsl::compile(&source, &sdfc_wgsl::Options::default()) {
            Ok(c) => {
                report::diagnostics(&path, &source, &c.warnings);
                println!("ok    {path}");
            }
            Err(f) => {
                let line = report::first_error(&source, &f);
                let o = report::failure(&path, &source, &f);
                println!("error {path}{line}");
                note(o, &mut worst);
            }
        }
    }
    worst
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
