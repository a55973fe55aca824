//! `sdfc compile`: a scene to validated WGSL, or a stage of the IR with `--emit`.

use crate::out::{say, say_part};
use crate::{read_source, report, Outcome};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// The scene file (.sdf)
    scene: PathBuf,
    /// Where to write the WGSL (stdout if absent)
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Only the scene functions, no entry point, for use in your own shaders
    #[arg(long)]
    lib: bool,
    /// With --lib: add a naga_oil `#define_import_path NAME` line
    #[arg(long, value_name = "NAME", requires = "lib", value_parser = import_path)]
    import_path: Option<String>,
    /// What to print: the WGSL, or a stage of the compiler for inspection
    #[arg(long, value_enum, default_value_t = Emit::Wgsl)]
    emit: Emit,
    /// Print to stderr the scene's Lipschitz bound and every shape node whose distance is
    /// not exact (line:column, exact/bound/neither, L)
    #[arg(long)]
    explain: bool,
    /// Emit large unions (16 or more bounded children) as a hierarchy of bounding boxes
    /// with early-outs; the same distances near the surface, a lower bound far from it. Off
    /// by default: on the software device measured so far it is slower (docs/performance.md)
    #[arg(long)]
    cull: bool,
    /// Read the scene's root union from a buffer, as `sdfc render --instances` does: the WGSL
    /// walks instances in a hierarchy of boxes (bound at group 0, binding 3, as
    /// `array<vec4<u32>>`) instead of holding each shape's code, and the buffer's bytes go to
    /// the --data file. A scene without such a union is compiled as usual, with a note.
    /// Without it the WGSL holds the whole scene, whatever its size (`sdfc render` reads
    /// unions of 100 or more shapes as data by itself)
    #[arg(long, requires = "data", conflicts_with_all = ["cull", "lib"])]
    instances: bool,
    /// With --instances: where to write the buffer (little-endian 32-bit words)
    #[arg(long, value_name = "OUT.bin", requires = "instances")]
    data: Option<PathBuf>,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum Emit {
    /// The validated WGSL module
    Wgsl,
    /// The parsed syntax tree
    Ast,
    /// The scene as lowered, before optimisation
    Ir,
    /// The optimised shapes and scalar functions
    OptIr,
}

/// The library's check of an import path, as a clap value parser.
fn import_path(s: &str) -> Result<String, String> {
    sdfc_wgsl::check_import_path(s).map(|()| s.to_string())
}

pub fn run(a: Args) -> Outcome {
    for (set, flag) in [(a.lib, "--lib"), (a.instances, "--instances")] {
        if set && !matches!(a.emit, Emit::Wgsl) {
            say!("sdfc: {flag} shapes the WGSL; it has no effect on --emit ast, ir or opt-ir");
            return Outcome::EnvError;
        }
    }
    let path = a.scene.display().to_string();
    let source = match read_source(&a.scene) {
        Ok(s) => s,
        Err(o) => return o,
    };
    let opts = sdfc_wgsl::Options {
        lib: a.lib,
        import_path: a.import_path.clone(),
        cull: a.cull,
        // The file must draw without a buffer unless one is written beside it.
        instances: if a.instances {
            sdfc_wgsl::Instances::Always
        } else {
            sdfc_wgsl::Instances::Never
        },
    };
    let text = if let Emit::Ast = a.emit {
        match sdfc_syntax::parse(&source) {
            Ok(f) => sdfc_syntax::pretty::dump(&f),
            Err(d) => return report::failure(&path, &source, &sdfc_wgsl::Failure::Diagnostics(d)),
        }
    } else {
        let compiled = match sdfc_wgsl::compile(&source, &opts) {
            Ok(c) => c,
            Err(f) => return report::failure(&path, &source, &f),
        };
        report::diagnostics(&path, &source, &compiled.warnings);
        if a.explain {
            let p = compiled.program();
            say_part!(
                "{}",
                sdfc_ir::analysis::explain(&p.scene, &p.analysis, &source)
            );
        }
        if let Some(out) = &a.data {
            if compiled.data.is_empty() {
                let instead = "it is compiled as code, and no data file is written";
                say!("{}", crate::render::instances_note(true, instead));
            } else if let Err(o) = write(out, &compiled.data) {
                return o;
            }
        }
        match a.emit {
            Emit::Wgsl => compiled.wgsl,
            Emit::Ir => sdfc_ir::dump::scene_text(&compiled.stages.lowered),
            _ => sdfc_ir::dump::program_text(compiled.program()),
        }
    };
    match &a.output {
        Some(out) => write(out, text.as_bytes()).err().unwrap_or(Outcome::Ok),
        None => crate::out::print_last(&text),
    }
}

/// Writes `bytes` to `out`, or says why not.
fn write(out: &Path, bytes: &[u8]) -> Result<(), Outcome> {
    std::fs::write(out, bytes).map_err(|e| {
        say!("sdfc: cannot write {}: {e}", out.display());
        Outcome::EnvError
    })
}
