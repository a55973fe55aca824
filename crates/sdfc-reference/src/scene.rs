//! The scene's distance and material functions evaluated in f64 by the IR evaluator.

use crate::vec::V3;
use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_ir::value::Value;
use sdfc_ir::Program;

/// A surface's material as `scene_material` returns it: albedo = (rgb, reflectivity),
/// phong = (ambient, diffuse, specular, shininess).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    pub albedo: [f64; 4],
    pub phong: [f64; 4],
}

/// The program's scene functions at fixed params and time.
pub struct SceneEval<'a> {
    program: &'a Program,
    params: Vec<Value<f64>>,
    time: f64,
}

impl<'a> SceneEval<'a> {
    /// `params` in declaration order; missing ones take the scene's defaults.
    pub fn new(program: &'a Program, params: &[Value<f64>], time: f64) -> SceneEval<'a> {
        let params = program
            .scene
            .params
            .iter()
            .enumerate()
            .map(|(i, d)| params.get(i).copied().unwrap_or_else(|| d.default.cast()))
            .collect();
        SceneEval {
            program,
            params,
            time,
        }
    }

    fn inputs(&self, p: V3) -> Inputs<f64> {
        Inputs {
            point: p,
            ray: [0.0; 3],
            params: self.params.clone(),
            time: self.time,
        }
    }

    /// The signed distance at `p`.
    pub fn distance(&self, p: V3) -> f64 {
        let r = eval_func(
            &self.program.distance,
            &self.program.groups,
            &self.inputs(p),
        );
        match r.first() {
            Some(Value::F(d)) => *d,
            _ => f64::NAN,
        }
    }

    /// The material at `p`.
    pub fn material(&self, p: V3) -> Material {
        let r = eval_func(
            &self.program.material,
            &self.program.groups,
            &self.inputs(p),
        );
        let v4 = |v: Option<&Value<f64>>| match v {
            Some(Value::V4(a)) => *a,
            _ => [0.0; 4],
        };
        Material {
            albedo: v4(r.first()),
            phong: v4(r.get(1)),
        }
    }
}
