//! `sdfc eval`: the scene distance at given points, from the f64 reference evaluator, or
//! with `--gpu` through the emitted WGSL on the wgpu device.

use crate::out::say;
use crate::render::{open_renderer, param_overrides, render_failure, to_f32};
use crate::{load_scene, read_source, Outcome};
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
    /// Time in seconds (negative too: `--time -1`)
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    time: f64,
}

pub fn run(a: Args) -> Outcome {
    // The device's time is an f32 even where the reference evaluates in f64.
    if let Err(o) = crate::render::check_time(a.time as f32) {
        return o;
    }
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
    let text = match read_source(&a.points) {
        Ok(t) => t,
        Err(o) => return o,
    };
    let points = match parse_points(&text, &a.points.display().to_string()) {
        Ok(p) => p,
        Err(o) => return o,
    };
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
        // The reference's evaluator: near a far camera, its camera-relative functions.
        let scene = sdfc_reference::scene::SceneEval::new(program, &params, a.time);
        for p in points {
            out += &format!("{:?}\n", scene.distance(p));
        }
    }
    crate::out::print_last(&out)
}

/// The points of a CSV file, one `x,y,z` a line; blank lines and lines starting with `#` are
/// skipped. A bad line is reported with its line and the column of the first bad field.
fn parse_points(text: &str, path: &str) -> Result<Vec<[f64; 3]>, Outcome> {
    let mut points = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut p = Vec::with_capacity(3);
        let (mut bad, mut fields) = (None, 0);
        let mut col = raw.len() - raw.trim_start().len() + 1;
        for field in line.split(',') {
            fields += 1;
            match field.trim().parse::<f64>() {
                Ok(v) => p.push(v),
                Err(_) if bad.is_none() => {
                    bad = Some(col + field.len() - field.trim_start().len());
                }
                Err(_) => {}
            }
            col += field.chars().count() + 1;
        }
        if bad.is_some() || fields != 3 {
            let (col, what) = match bad {
                Some(c) => (c, "a number"),
                None => (1, "three numbers"),
            };
            say!(
                "error: expected {what} in `x,y,z`, found `{line}` ({path}:{}:{col})\n  = hint: \
                 one point a line, three numbers separated by commas; a header or comment line \
                 starts with `#`",
                n + 1
            );
            return Err(Outcome::InputError);
        }
        points.push([p[0], p[1], p[2]]);
    }
    Ok(points)
}
