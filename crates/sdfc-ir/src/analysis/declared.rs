//! The sampling check of declared `lipschitz:` bounds: a warning, with the bound to use, where
//! a lambda's sampled slope exceeds what the scene declares.

use super::bounds::Aabb;
use super::gradient::{self, Comp};
use super::sample;
use super::{Analyser, DEFAULT_REGION, MAX_CHECKED};
use crate::graph::NodeId;
use crate::ops::Op;
use crate::scene::Scene;
use crate::value::Value;
use sdfc_syntax::diag::Diagnostic;
use sdfc_syntax::span::Span;

/// Relative slack for the declared-bound check (finite differences in f64 are far more
/// accurate than this; it keeps rounding from raising a warning).
const CHECK_SLACK: f64 = 1e-3;

/// A sampled slope above this is taken for a discontinuity.
const JUMP: f64 = 1e3;

/// A value rounded up to 3 significant digits, for hints.
fn round_up(x: f64) -> f64 {
    if x.is_nan() || x <= 0.0 || !x.is_finite() {
        return x;
    }
    // Scaled by an exact power of ten and back by dividing: multiplying by 0.01 (inexact)
    // printed 3.01 as 3.0100000000000002.
    let k = x.log10().floor() as i32 - 2;
    if k < 0 {
        let scale = 10f64.powi(-k);
        (x * scale).ceil() / scale
    } else {
        let scale = 10f64.powi(k);
        (x / scale).ceil() * scale
    }
}

impl Analyser<'_> {
    /// Value and gradient bounds of a lambda body over all of space (the segment from a
    /// point to the nearest surface may leave any bounded region).
    pub(super) fn body_bound(&mut self, body: NodeId, lambda: u32, params: u8) -> Vec<Comp> {
        let (lo, hi) = (f64::NEG_INFINITY, f64::INFINITY);
        let input = |op: Op, width: usize| match op {
            // `|p|`: the point; `|x, z|`: its x and z.
            Op::LambdaArg { lambda: l, index } if l == lambda && index < params => {
                Some(if params == 1 {
                    (0..width).map(|i| Comp::coord(i, lo, hi)).collect()
                } else {
                    vec![Comp::coord(2 * index as usize, lo, hi)]
                })
            }
            // Params and time vary at run time but not with the point.
            Op::Param(_) | Op::Time => Some(vec![Comp::fixed(lo, hi); width]),
            _ => None,
        };
        gradient::bound(&self.scene.values, body, &input)
    }

    /// Warns when sampling finds the point function's slope above its declared bound (for
    /// `displace`, the bound is that of the displaced distance: the child's distance plus
    /// the expression, and `child` is that child).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn check_declared(
        &mut self,
        body: NodeId,
        lambda: u32,
        params: u8,
        declared: f64,
        child: Option<crate::shape::ShapeId>,
        at: Span,
        region: &Aabb,
        name: &str,
    ) {
        if !self.check || self.checked >= MAX_CHECKED {
            return;
        }
        self.checked += 1;
        let region = Aabb {
            lo: region.lo.map(|x| x.max(-DEFAULT_REGION)),
            hi: region.hi.map(|x| x.min(DEFAULT_REGION)),
        };
        let params_now: Vec<Value<f64>> =
            self.scene.params.iter().map(|p| p.default.cast()).collect();
        let ev = sample::LambdaEval::new(&self.scene.values, body, lambda, params_now.clone());
        // The child's distance function, for `displace`.
        let child_fn = child.map(|c| {
            let sub = Scene {
                root: c,
                ..self.scene.clone()
            };
            crate::to_ssa::functions(&sub, false)
        });
        let f = |p: [f64; 3]| -> Vec<f64> {
            let args = if params == 1 {
                vec![Value::V3(p)]
            } else {
                vec![Value::F(p[0]), Value::F(p[2])]
            };
            let mut v = ev.eval(&args).comps();
            if let (Some(fs), Some(x)) = (&child_fn, v.first_mut()) {
                let inputs = crate::eval::Inputs {
                    point: p,
                    ray: [0.0; 3],
                    params: params_now.clone(),
                    time: 0.0,
                };
                let d = crate::eval::eval_func(&fs.distance, &fs.groups, &inputs);
                *x += d.first().and_then(|d| d.scalar()).unwrap_or(0.0);
            }
            v
        };
        let slope = sample::max_slope(&region, sample::SAMPLES, &f);
        if slope > declared * (1.0 + CHECK_SLACK) + 1e-9 {
            let what = match name {
                "displace" => {
                    format!("the displaced distance changes at up to {slope:.4} per unit")
                }
                "warp" => format!("the warp stretches space by up to {slope:.4}"),
                "heightfield" => format!("the terrain's slope reaches {slope:.4}"),
                _ => format!("the distance expression's slope reaches {slope:.4}"),
            };
            self.out.diagnostics.push(
                Diagnostic::warning(at, format!("the declared Lipschitz bound {} of `{name}` is too small: {what}", declared as f32))
                    .with_label("contradicted by sampling")
                    .with_hint(if slope > JUMP {
                        "the expression seems to jump (a `step`, `floor`, `fract` or `select` of the point?): no bound makes a discontinuous distance safe".to_string()
                    } else {
                        format!("use `lipschitz: {}` or more; a bound that is too small lets rays step through the surface", round_up(slope))
                    }),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hints print the rounded bound as a user would write it.
    #[test]
    fn hints_round_up_to_three_digits_and_print_short() {
        assert_eq!(round_up(3.0000001).to_string(), "3.01");
        assert_eq!(round_up(0.0123401).to_string(), "0.0124");
        assert_eq!(round_up(12345.6).to_string(), "12400");
        assert_eq!(round_up(2.5).to_string(), "2.5");
        for x in [0.3333, 1.7001, 7.77777, 123.4567, 9.999] {
            assert!(round_up(x) >= x, "{x}");
        }
    }
}
