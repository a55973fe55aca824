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

/// How far apart the two sides may be: `|gpu - cpu| <= rel * |cpu| + abs + spread * s(p)`,
/// on the points whose reference value is at least `skip_near` from zero (0: every point).
/// `s(p)` is the conditioning of the value at p: the most the f64 value changes when one
/// coordinate of p moves by one f32 ulp, the least error f32 inputs can carry. It matters
/// for chaotic estimates (the mandelbulb) only; `spread` 0 leaves it out.
#[derive(Clone, Copy)]
pub struct Tolerance {
    pub rel: f64,
    pub abs: f64,
    pub skip_near: f64,
    pub spread: f64,
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
    let cpu = |p: [f32; 3]| {
        let inputs = Inputs {
            point: p.map(|c| c as f64),
            ray: [0.0; 3],
            params: param_values.clone(),
            time: time as f64,
        };
        eval_func(&program.distance, &program.groups, &inputs)[0]
            .scalar()
            .unwrap_or(f64::NAN)
    };
    for (p, &g) in pts.iter().zip(&gpu) {
        let c = cpu(*p);
        if c.abs() < tol.skip_near {
            continue;
        }
        compared += 1;
        let err = (g as f64 - c).abs();
        worst_abs = worst_abs.max(err);
        if c.abs() > 1e-3 {
            worst_rel = worst_rel.max(err / c.abs());
        }
        let spread = if tol.spread > 0.0 {
            tol.spread * ulp_spread(p, c, &cpu)
        } else {
            0.0
        };
        if err.is_nan() || err > tol.rel * c.abs() + tol.abs + spread {
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
            "{} of {compared} points off by more than {:e} relative + {:e} (+ {} times the \
             conditioning); first (point, gpu, cpu): {:?}",
            failures.len(),
            tol.rel,
            tol.abs,
            tol.spread,
            &failures[..failures.len().min(5)]
        ))
    }
}

/// The most `f` (whose value at p is `c`) changes when one coordinate of p moves by one f32
/// ulp either way.
fn ulp_spread(p: &[f32; 3], c: f64, f: &impl Fn([f32; 3]) -> f64) -> f64 {
    let mut worst: f64 = 0.0;
    for k in 0..3 {
        for next in [f32::next_up, f32::next_down] {
            let mut q = *p;
            q[k] = next(q[k]);
            worst = worst.max((f(q) - c).abs());
        }
    }
    worst
}
