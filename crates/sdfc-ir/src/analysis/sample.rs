//! Measured slopes of point functions: f64 evaluation of a lambda body, and the largest
//! difference quotient found at deterministic sample points. A difference quotient
//! `|f(a) - f(b)| / |a - b|` never exceeds a true Lipschitz constant, so one above a
//! declared bound proves the declaration wrong (up to rounding).

use super::bounds::Aabb;
use crate::eval::{apply, zero_of};
use crate::graph::{Graph, NodeId};
use crate::ops::Op;
use crate::value::Value;

/// How many points the declared-bound check samples.
pub const SAMPLES: usize = 2048;

/// A lambda body ready for repeated f64 evaluation.
pub struct LambdaEval<'g> {
    g: &'g Graph,
    lambda: u32,
    /// The nodes the body needs, in order, with their arguments as positions in this list.
    order: Vec<(NodeId, Vec<usize>)>,
    params: Vec<Value<f64>>,
}

impl<'g> LambdaEval<'g> {
    /// `params` are the values of the scene's params (their defaults).
    pub fn new(g: &'g Graph, root: NodeId, lambda: u32, params: Vec<Value<f64>>) -> Self {
        let mut need = vec![false; root.index() + 1];
        need[root.index()] = true;
        for i in (0..=root.index()).rev() {
            if need[i] {
                for a in g.node(NodeId(i as u32)).args() {
                    need[a.index()] = true;
                }
            }
        }
        let mut pos = vec![0usize; root.index() + 1];
        let mut order = Vec::new();
        for i in (0..=root.index()).filter(|i| need[*i]) {
            pos[i] = order.len();
            let id = NodeId(i as u32);
            let args = g.node(id).args().iter().map(|a| pos[a.index()]).collect();
            order.push((id, args));
        }
        LambdaEval {
            g,
            lambda,
            order,
            params,
        }
    }

    /// The body's value with the lambda's parameters set to `args`.
    pub fn eval(&self, args: &[Value<f64>]) -> Value<f64> {
        let mut vals: Vec<Value<f64>> = Vec::with_capacity(self.order.len());
        let mut a: Vec<Value<f64>> = Vec::with_capacity(4);
        for (id, arg_pos) in &self.order {
            let node = self.g.node(*id);
            let v = match node.op {
                Op::LambdaArg { lambda, index } if lambda == self.lambda => args
                    .get(index as usize)
                    .copied()
                    .unwrap_or_else(|| zero_of(node.ty)),
                Op::Param(k) => self
                    .params
                    .get(k as usize)
                    .copied()
                    .unwrap_or_else(|| zero_of(node.ty)),
                op if op.is_input() => zero_of(node.ty),
                op => {
                    a.clear();
                    a.extend(arg_pos.iter().map(|k| vals[*k]));
                    apply(op, node.ty, &a)
                }
            };
            vals.push(v);
        }
        vals.last().copied().unwrap_or(Value::F(0.0))
    }
}

/// Deterministic, evenly spread points of `region` (an additive recurrence on the plastic
/// number's powers, a low-discrepancy sequence).
pub fn points(region: &Aabb, n: usize) -> impl Iterator<Item = [f64; 3]> + '_ {
    let phi: f64 = 1.220_744_084_605_759_5;
    let a = [1.0 / phi, 1.0 / (phi * phi), 1.0 / (phi * phi * phi)];
    (0..n).map(move |k| {
        [0, 1, 2].map(|i| {
            let t = (0.5 + a[i] * k as f64).fract();
            region.lo[i] + t * (region.hi[i] - region.lo[i])
        })
    })
}

/// The largest difference quotient of `f` (values with any number of components) found at
/// the sample points of `region`, each taken along the direction in which `f` changes
/// fastest there (estimated by central differences).
pub fn max_slope(region: &Aabb, n: usize, f: &dyn Fn([f64; 3]) -> Vec<f64>) -> f64 {
    let extent = (0..3)
        .map(|i| region.hi[i] - region.lo[i])
        .fold(0.0, f64::max);
    let h = 1e-6 * extent.max(1.0);
    let mut best: f64 = 0.0;
    for p in points(region, n) {
        let at = |d: [f64; 3], s: f64| f([0, 1, 2].map(|i| p[i] + s * d[i]));
        // Jacobian columns by central differences.
        let cols: Vec<Vec<f64>> = (0..3)
            .map(|j| {
                let mut e = [0.0; 3];
                e[j] = 1.0;
                let (a, b) = (at(e, h), at(e, -h));
                a.iter().zip(&b).map(|(x, y)| (x - y) / (2.0 * h)).collect()
            })
            .collect();
        // The top right-singular vector of J, by power iteration on J^T J.
        let jtj = |v: [f64; 3]| -> [f64; 3] {
            let m = cols[0].len();
            let jv: Vec<f64> = (0..m)
                .map(|r| (0..3).map(|c| cols[c][r] * v[c]).sum())
                .collect();
            [0, 1, 2].map(|c| (0..m).map(|r| cols[c][r] * jv[r]).sum())
        };
        let mut u = [0.577, 0.578, 0.579];
        for _ in 0..30 {
            let w = jtj(u);
            let l = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
            if l.is_nan() || l <= 0.0 || !l.is_finite() {
                break;
            }
            u = w.map(|x| x / l);
        }
        let (a, b) = (at(u, h), at(u, -h));
        let q = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).powi(2))
            .sum::<f64>()
            .sqrt()
            / (2.0 * h);
        if q.is_finite() {
            best = best.max(q);
        }
    }
    best
}
