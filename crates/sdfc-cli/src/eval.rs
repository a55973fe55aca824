//! `sdfc eval`: the scene distance at given points, from the f64 reference evaluator.

use crate::{read_source, report, Outcome};
use sdfc_ir::eval::{eval_graph, Inputs};
use sdfc_ir::value::Value;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The scene file (.sdf)
    scene: PathBuf,
    /// A CSV file with one `x,y,z` point per line
    #[arg(long)]
    points: PathBuf,
    /// Evaluate through the emitted WGSL on the GPU (needs the renderer)
    #[arg(long)]
    gpu: bool,
    /// Override a param: NAME=VALUE, or NAME=x,y,z for vectors
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Time in seconds
    #[arg(long, default_value_t = 0.0)]
    time: f64,
}

pub fn run(a: Args) -> Outcome {
    if a.gpu {
        eprintln!("sdfc: `eval --gpu` needs the wgpu renderer, which this build of sdfc does not include yet");
        return Outcome::EnvError;
    }
    let path = a.scene.display().to_string();
    let source = match read_source(&a.scene) {
        Ok(s) => s,
        Err(o) => return o,
    };
    let compiled = match sdfc_wgsl::compile(&source, &sdfc_wgsl::Options::default()) {
        Ok(c) => c,
        Err(f) => return report::failure(&path, &source, &f),
    };
    let program = compiled.program();
    let mut params: Vec<Value<f64>> = program
        .scene
        .params
        .iter()
        .map(|p| p.default.cast())
        .collect();
    for spec in &a.params {
        let Some((name, value)) = spec.split_once('=') else {
            eprintln!("sdfc: --param takes NAME=VALUE, found `{spec}`");
            return Outcome::EnvError;
        };
        let Some(i) = program.scene.params.iter().position(|p| p.name == name) else {
            eprintln!("sdfc: the scene has no param `{name}`");
            return Outcome::InputError;
        };
        let comps: Result<Vec<f64>, _> =
            value.split(',').map(|c| c.trim().parse::<f64>()).collect();
        match comps {
            Ok(c) if c.len() == program.scene.params[i].ty.width() => {
                params[i] = Value::from_comps(program.scene.params[i].ty, &c);
            }
            _ => {
                eprintln!(
                    "sdfc: --param {name} needs {} number(s), found `{value}`",
                    program.scene.params[i].ty.width()
                );
                return Outcome::InputError;
            }
        }
    }
    let text = match std::fs::read_to_string(&a.points) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("sdfc: cannot read {}: {e}", a.points.display());
            return Outcome::EnvError;
        }
    };
    let pts_path = a.points.display().to_string();
    let mut out = String::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let comps: Vec<Result<f64, _>> = line.split(',').map(|c| c.trim().parse::<f64>()).collect();
        if comps.len() != 3 || comps.iter().any(|c| c.is_err()) {
            eprintln!(
                "error: expected `x,y,z` ({pts_path}:{}:1), found `{line}`",
                n + 1
            );
            return Outcome::InputError;
        }
        let p: Vec<f64> = comps.into_iter().flatten().collect();
        let inputs = Inputs {
            point: [p[0], p[1], p[2]],
            params: params.clone(),
            time: a.time,
        };
        let d = eval_graph(&program.distance.graph, &program.distance.results, &inputs);
        out += &format!("{:?}\n", d[0].scalar().unwrap_or(f64::NAN));
    }
    print!("{out}");
    Outcome::Ok
}
