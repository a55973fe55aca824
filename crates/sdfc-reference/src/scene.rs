//! The scene's distance and material functions evaluated in f64 by the IR evaluator.

use crate::vec::V3;
use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_ir::func::Func;
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
///
/// For a camera far from the origin the program also has the functions in camera-relative
/// coordinates (`Program::relative`), and those are evaluated, at `p - origin` (exact in
/// f64): the world functions' constants are f32, and an offset composed at compile time
/// near 1e5 (a turned shape moved there: `-R T`) is rounded to 0.008 in them, where the
/// relative functions' small offsets were computed in f64 and rounded once.
pub struct SceneEval<'a> {
    distance: &'a Func,
    material: &'a Func,
    groups: &'a [Func],
    origin: [f64; 3],
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
        let (distance, material, groups, origin) = match &program.relative {
            Some(r) => (
                &r.distance,
                &r.material,
                &r.groups[..],
                r.origin.map(|c| c as f64),
            ),
            None => (
                &program.distance,
                &program.material,
                &program.groups[..],
                [0.0; 3],
            ),
        };
        SceneEval {
            distance,
            material,
            groups,
            origin,
            params,
            time,
        }
    }

    fn inputs(&self, p: V3) -> Inputs<f64> {
        Inputs {
            point: std::array::from_fn(|k| p[k] - self.origin[k]),
            ray: [0.0; 3],
            params: self.params.clone(),
            time: self.time,
        }
    }

    /// The signed distance at `p`.
    pub fn distance(&self, p: V3) -> f64 {
        let r = eval_func(self.distance, self.groups, &self.inputs(p));
        match r.first() {
            Some(Value::F(d)) => *d,
            _ => f64::NAN,
        }
    }

    /// The material at `p`.
    pub fn material(&self, p: V3) -> Material {
        let r = eval_func(self.material, self.groups, &self.inputs(p));
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
