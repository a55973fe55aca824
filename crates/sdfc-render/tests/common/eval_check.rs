//! The GPU-against-CPU distance check: `eval_gpu` (the emitted WGSL run on the device, f32)
//! against the f64 reference evaluator at given points.

use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_render::Renderer;

/// `n` deterministic points uniformly in the box `lo..hi`.
pub fn points(seed: u64, n: usize, lo: [f32; 3], hi: [f32; 3]) -> Vec<[f32; 3]> {
    let mut rng = sdfc_tests::SplitMix(seed);
    (0..n)
        .map(|_| {
            let mut p = [0.0f32; 3];
            for k in 0..3 {
                p[k] = lo[k] + (hi[k] - lo[k]) * rng.unit() as f32;
            }
            p
        })
        .collect()
}

/// How far apart the two sides may be: `|gpu - cpu| <= rel * |cpu| + abs`, on the points
/// whose reference value is at least `skip_near` from zero (0: every point).
#[derive(Clone, Copy)]
pub struct Tolerance {
    pub rel: f64,
    pub abs: f64,
    pub skip_near: f64,
}

/// The worst errors seen where every point passed.
pub struct Agreement {
    /// Worst relative error over points with |d| > 1e-3.
    pub worst_rel: f64,
    pub worst_abs: f64,
    /// Points compared (those not skipped by `skip_near`).
    pub compared: usize,
}

/// Evaluates `compiled` at `pts` on the device and in f64 on the CPU (with `time` and the
/// `params` overrides on both sides) and compares them; `Err` lists the first failures.
pub fn agree(
    r: &Renderer,
    compiled: &sdfc_wgsl::Compiled,
    pts: &[[f32; 3]],
    time: f32,
    params: &[(String, Vec<f32>)],
    tol: Tolerance,
) -> Result<Agreement, String> {
    let program = compiled.program();
    let gpu = r
        .eval_gpu(program, pts, time, params)
        .map_err(|e| format!("eval_gpu failed: {e}"))?;
    if gpu.len() != pts.len() {
        return Err(format!("{} values for {} points", gpu.len(), pts.len()));
    }
    let overrides: Vec<(String, Vec<f64>)> = params
        .iter()
        .map(|(n, v)| (n.clone(), v.iter().map(|&c| c as f64).collect()))
        .collect();
    let param_values = program.scene.param_values(&overrides);
    let mut worst_rel: f64 = 0.0;
    let mut worst_abs: f64 = 0.0;
    let mut failures = Vec::new();
    let mut compared = 0;
    for (p, &g) in pts.iter().zip(&gpu) {
        let inputs = Inputs {
            point: [p[0] as f64, p[1] as f64, p[2] as f64],
            ray: [0.0; 3],
            params: param_values.clone(),
            time: time as f64,
        };
        let c = eval_func(&program.distance, &program.groups, &inputs)[0]
            .scalar()
            .unwrap_or(f64::NAN);
        if c.abs() < tol.skip_near {
            continue;
        }
        compared += 1;
        let err = (g as f64 - c).abs();
        worst_abs = worst_abs.max(err);
        if c.abs() > 1e-3 {
            worst_rel = worst_rel.max(err / c.abs());
        }
        if err.is_nan() || err > tol.rel * c.abs() + tol.abs {
            failures.push((*p, g, c));
        }
    }
    if failures.is_empty() {
        Ok(Agreement {
            worst_rel,
            worst_abs,
            compared,
        })
    } else {
        Err(format!(
            "{} of {compared} points off by more than {:e} relative + {:e}; first (point, gpu, \
             cpu): {:?}",
            failures.len(),
            tol.rel,
            tol.abs,
            &failures[..failures.len().min(5)]
        ))
    }
}
