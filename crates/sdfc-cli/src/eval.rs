//! `sdfc eval`: the scene distance at given points, from the f64 reference evaluator, or
//! with `--gpu` through the emitted WGSL on the wgpu device.

use crate::render::{open_renderer, param_overrides, render_failure, to_f32};
use crate::{load_scene, Outcome};
use sdfc_ir::eval::{eval_func, Inputs};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The scene file (.sdf)
    scene: PathBuf,
    /// A CSV file with one `x,y,z` point per line
    #[arg(long)]
    points: PathBuf,
    /// Evaluate through the emitted WGSL on the wgpu device (f32) instead of the f64 reference
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
    let compiled = match load_scene(&a.scene, &sdfc_wgsl::Options::default()) {
        Ok(c) => c,
        Err(o) => return o,
    };
    let program = compiled.program();
    let overrides = match param_overrides(program, &a.params) {
        Ok(p) => p,
        Err(o) => return o,
    };
    let params = program.scene.param_values(&overrides);
    let text = match std::fs::read_to_string(&a.points) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("sdfc: cannot read {}: {e}", a.points.display());
            return Outcome::EnvError;
        }
    };
    let pts_path = a.points.display().to_string();
    let mut points = Vec::new();
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
        points.push([p[0], p[1], p[2]]);
    }
    let mut out = String::new();
    if a.gpu {
        let renderer = match open_renderer() {
            Ok(r) => r,
            Err(o) => return o,
        };
        let pts: Vec<[f32; 3]> = points
            .iter()
            .map(|p| [p[0] as f32, p[1] as f32, p[2] as f32])
            .collect();
        let values = match renderer.eval_gpu(program, &pts, a.time as f32, &to_f32(&overrides)) {
            Ok(v) => v,
            Err(e) => return render_failure(&e),
        };
        for d in values {
            out += &format!("{d:?}\n");
        }
    } else {
        for p in points {
            let inputs = Inputs {
                point: p,
                ray: [0.0; 3],
                params: params.clone(),
                time: a.time,
            };
            let d = eval_func(&program.distance, &program.groups, &inputs);
            out += &format!("{:?}\n", d[0].scalar().unwrap_or(f64::NAN));
        }
    }
    print!("{out}");
    Outcome::Ok
}
