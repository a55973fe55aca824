//! The scene's distance and material functions evaluated in f64 by the IR evaluator.

use crate::vec::V3;
use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_ir::value::Value;
use sdfc_ir::{Program, SceneFunctions};

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
/// coordinates (`Program::relative`), and a point nearer the camera than the origin is
/// evaluated with those, at `p - origin` (exact in f64). Both have f32 constants, whose
/// rounding grows with their distance from their own origin: a box turned and then moved to
/// 1e5 has its offset `-R T` 0.0076 off in the world functions and exact to 1e-7 in the
/// relative ones, and a box turned at the origin seen from 1e5 is exact in the world
/// functions and 2.4e-4 off in the relative ones. So each point takes the frame whose
/// origin is nearer.
pub struct SceneEval<'a> {
    world: SceneFunctions<'a>,
    relative: Option<SceneFunctions<'a>>,
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
            world: program.world(),
            relative: program.relative.is_some().then(|| program.marched()),
            params,
            time,
        }
    }

    /// The frame for `p` (the one whose origin is nearer, by the largest coordinate) and
    /// the inputs at `p` in it.
    fn at(&self, p: V3) -> (&SceneFunctions<'a>, Inputs<f64>) {
        let far = |o: [f32; 3]| {
            (0..3)
                .map(|k| (p[k] - o[k] as f64).abs())
                .fold(0.0, f64::max)
        };
        let frame = match &self.relative {
            Some(r) if far(r.origin) < far([0.0; 3]) => r,
            _ => &self.world,
        };
        let inputs = Inputs {
            point: std::array::from_fn(|k| p[k] - frame.origin[k] as f64),
            ray: [0.0; 3],
            params: self.params.clone(),
            time: self.time,
        };
        (frame, inputs)
    }

    /// The signed distance at `p`.
    pub fn distance(&self, p: V3) -> f64 {
        let (frame, inputs) = self.at(p);
        let r = eval_func(frame.distance, frame.groups, &inputs);
        match r.first() {
            Some(Value::F(d)) => *d,
            _ => f64::NAN,
        }
    }

    /// The material at `p`.
    pub fn material(&self, p: V3) -> Material {
        let (frame, inputs) = self.at(p);
        let r = eval_func(frame.material, frame.groups, &inputs);
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
