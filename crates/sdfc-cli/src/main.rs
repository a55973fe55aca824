//! `sdfc`: compile, check, evaluate and render signed-distance scenes (see `shared/spec/cli.md`).
//! Exit status: 0 success, 1 a problem in the user's input, 2 usage or environment.

mod bench;
mod check;
mod compare;
mod compile;
mod eval;
mod live;
mod out;
mod plot;
mod render;
mod report;
mod slow_note;
mod watch;

use clap::{Parser, Subcommand};
use out::say;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "sdfc",
    version,
    about = "Compiles signed-distance-function scenes to specialised WGSL"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Compile a scene to validated WGSL (stdout without -o)
    Compile(compile::Args),
    /// Compile and validate .sdf files, validate .wgsl files; one line per file
    Check(check::Args),
    /// Print the scene distance at each x,y,z line of a CSV file (f64 reference evaluator,
    /// or the emitted WGSL on the device with --gpu)
    Eval(eval::Args),
    /// Render a scene to a PNG (or a float AOV to EXR/NPY) on the GPU or software Vulkan
    Render(render::Args),
    /// Run time against error: render under a sweep of settings and compare each with the
    /// f64 reference; marks the Pareto front
    Bench(bench::Args),
}

/// The outcome of a command, mapped to the exit statuses of the CLI contract.
pub enum Outcome {
    Ok,
    /// A problem in the user's input (diagnostics already printed).
    InputError,
    /// Usage or environment problem (message already printed).
    EnvError,
}

fn main() -> ExitCode {
    // SAFETY: the first statement of `main`, before any thread starts, so no other thread
    // can read or write the environment while it may set a variable.
    unsafe { sdfc_render::quiet_headless_vulkan() };
    // A bug must never show a Rust backtrace to a user: report it in one line instead.
    std::panic::set_hook(Box::new(|info| {
        say!("sdfc: internal error: {info}");
        say!("This is a bug in sdfc; please report it with the input that caused it.");
    }));
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
        }
    };
    let outcome = std::panic::catch_unwind(|| match cli.command {
        Command::Compile(a) => compile::run(a),
        Command::Check(a) => check::run(a),
        Command::Eval(a) => eval::run(a),
        Command::Render(a) => render::run(a),
        Command::Bench(a) => bench::run(a),
    });
    match outcome {
        Ok(Outcome::Ok) => ExitCode::SUCCESS,
        Ok(Outcome::InputError) => ExitCode::from(1),
        Ok(Outcome::EnvError) | Err(_) => ExitCode::from(2),
    }
}

/// Reads a scene file; an unreadable file or invalid UTF-8 is reported here.
pub fn read_source(path: &PathBuf) -> Result<String, Outcome> {
    match std::fs::read(path) {
        Ok(bytes) => match String::from_utf8(bytes) {
            Ok(s) => Ok(s),
            Err(e) => {
                let offset = e.utf8_error().valid_up_to();
                let text = String::from_utf8_lossy(e.as_bytes()).into_owned();
                let (line, col) = sdfc_syntax::diag::line_col(&text, offset);
                say!(
                    "error: {} is not valid UTF-8 ({}:{line}:{col})\n  = hint: save the file as UTF-8",
                    path.display(),
                    path.display()
                );
                Err(Outcome::InputError)
            }
        },
        Err(e) => {
            say!("sdfc: cannot read {}: {e}", path.display());
            Err(Outcome::EnvError)
        }
    }
}

/// Reads and compiles a scene file, printing its warnings; on failure the diagnostics are
/// printed and the outcome to exit with comes back.
pub fn load_scene(
    path: &PathBuf,
    opts: &sdfc_wgsl::Options,
) -> Result<sdfc_wgsl::Compiled, Outcome> {
    let name = path.display().to_string();
    let source = read_source(path)?;
    match sdfc_wgsl::compile(&source, opts) {
        Ok(c) => {
            report::diagnostics(&name, &source, &c.warnings);
            Ok(c)
        }
        Err(f) => Err(report::failure(&name, &source, &f)),
    }
}

/// Reads, parses and lowers a scene file without emitting its WGSL (the live path), printing
/// its warnings; on failure the diagnostics are printed and the outcome comes back.
pub fn load_lowered(
    path: &PathBuf,
    opts: &sdfc_wgsl::Options,
) -> Result<sdfc_wgsl::Lowered, Outcome> {
    lower_source(path, &read_source(path)?, opts)
}

/// Parses and lowers the text of a scene file, as [`load_lowered`], for the live path: with
/// the culled program the interpreted preview draws (`sdfc_wgsl::lower_live`).
pub fn lower_source(
    path: &Path,
    source: &str,
    opts: &sdfc_wgsl::Options,
) -> Result<sdfc_wgsl::Lowered, Outcome> {
    let name = path.display().to_string();
    match sdfc_wgsl::lower_live(source, opts) {
        Ok(l) => {
            report::diagnostics(&name, source, &l.warnings);
            Ok(l)
        }
        Err(f) => Err(report::failure(&name, source, &f)),
    }
}
