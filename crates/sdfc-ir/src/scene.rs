//! A lowered scene: its shapes and value graph, and the resolved materials, lights,
//! camera, render settings and runtime parameters.

use crate::graph::Graph;
use crate::shape::{ShapeId, ShapeNode};
use crate::types::Ty;
use crate::value::Value;

/// A whole scene after lowering (and, later, after the shape-level passes).
#[derive(Clone, Debug)]
pub struct Scene {
    /// Numeric arguments of shapes and the bodies of lambdas.
    pub values: Graph,
    pub shapes: Vec<ShapeNode>,
    pub root: ShapeId,
    /// Material 0 is the default.
    pub materials: Vec<Material>,
    pub params: Vec<ParamDecl>,
    pub lights: Vec<Light>,
    pub camera: Camera,
    pub render: RenderSettings,
}

impl Scene {
    pub fn shape(&self, id: ShapeId) -> &ShapeNode {
        &self.shapes[id.index()]
    }

    /// Every param's value in f64: its default, or the override of that name (overrides of
    /// unknown names, and components that do not fit its type, are left to the caller's
    /// checks).
    pub fn param_values(&self, overrides: &[(String, Vec<f64>)]) -> Vec<Value<f64>> {
        let mut values: Vec<Value<f64>> = self.params.iter().map(|p| p.default.cast()).collect();
        for (name, comps) in overrides {
            if let Some(i) = self.params.iter().position(|p| &p.name == name) {
                values[i] = Value::from_comps(self.params[i].ty, comps);
            }
        }
        values
    }
}

/// A `param`: a runtime uniform with its default.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamDecl {
    pub name: String,
    pub ty: Ty,
    pub default: Value<f32>,
}

/// Phong material (spec section 6).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The user's name; anonymous colours from `color(s, c)` are named `color#N`.
    pub name: String,
    pub color: [f32; 3],
    pub ambient: f32,
    pub diffuse: f32,
    pub specular: f32,
    pub shininess: f32,
    pub reflectivity: f32,
}

impl Material {
    /// The shader's albedo vector: rgb colour, reflectivity.
    pub fn albedo(&self) -> [f32; 4] {
        let c = self.color;
        [c[0], c[1], c[2], self.reflectivity]
    }

    /// The shader's phong vector: ambient, diffuse, specular, shininess.
    pub fn phong(&self) -> [f32; 4] {
        [self.ambient, self.diffuse, self.specular, self.shininess]
    }
}

impl Default for Material {
    fn default() -> Material {
        Material {
            name: "default".into(),
            color: [0.8, 0.8, 0.8],
            ambient: 0.1,
            diffuse: 0.9,
            specular: 0.5,
            shininess: 32.0,
            reflectivity: 0.0,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub enum LightKind {
    Point {
        position: [f32; 3],
    },
    /// `direction` is the way the light travels, normalised.
    Directional {
        direction: [f32; 3],
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    pub kind: LightKind,
    pub color: [f32; 3],
    pub intensity: f32,
}

impl Light {
    /// The spec's default light: directional along `[-1, -1, -1]`, white, intensity 1.
    pub fn default_light() -> Light {
        let s = 1.0 / 3f64.sqrt();
        Light {
            kind: LightKind::Directional {
                direction: [-s as f32; 3],
            },
            color: [1.0; 3],
            intensity: 1.0,
        }
    }
}

/// The camera of spec section 8; `fov` is vertical, in radians.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub position: [f32; 3],
    pub target: [f32; 3],
    pub up: [f32; 3],
    pub fov: f32,
}

impl Default for Camera {
    fn default() -> Camera {
        Camera {
            position: [0.0, 0.0, 5.0],
            target: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            fov: 60f64.to_radians() as f32,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Epsilon {
    /// Scaled by the pixel's footprint at distance t.
    Pixel,
    Absolute(f32),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Normals {
    Central,
    Tetrahedron,
    Forward,
    Analytic,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shadows {
    None,
    Hard,
    Soft(f32),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ao {
    pub samples: u32,
    pub step: f32,
    pub strength: f32,
    pub falloff: f32,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fog {
    pub density: f32,
    pub color: [f32; 3],
}

/// Render settings of spec section 7, defaults filled in.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    pub max_steps: u32,
    pub max_distance: f32,
    pub epsilon: Epsilon,
    pub relaxation: f32,
    pub normals: Normals,
    pub shadows: Shadows,
    pub ao: Option<Ao>,
    pub reflections: u32,
    pub background: [f32; 3],
    pub fog: Option<Fog>,
    pub antialias: u32,
    pub gamma: f32,
}

impl Default for RenderSettings {
    fn default() -> RenderSettings {
        RenderSettings {
            max_steps: 256,
            max_distance: 100.0,
            epsilon: Epsilon::Pixel,
            relaxation: 1.0,
            normals: Normals::Tetrahedron,
            shadows: Shadows::None,
            ao: None,
            reflections: 0,
            background: [0.0; 3],
            fog: None,
            antialias: 1,
            gamma: 2.2,
        }
    }
}

/// Documented limits of render settings (spec section 9 asks for errors above them).
pub mod limits {
    pub const MAX_STEPS: u32 = 100_000;
    pub const MAX_REFLECTIONS: u32 = 16;
    pub const MAX_ANTIALIAS: u32 = 8;
    pub const MAX_AO_SAMPLES: u32 = 64;
    pub const MAX_PARAMS: usize = 256;
    pub const MAX_REPEAT_COUNT: u32 = 100_000;
    /// Nodes in the value graph after inlining (guards against exponential `fn` growth).
    pub const MAX_NODES: usize = 2_000_000;
    /// `fn` calls expanded while inlining. Hash-consing can keep the graph small while the
    /// expansion is exponential (`fn f1(x) = f0(x) + f0(x);` and so on: 26 levels are 67
    /// million calls for 27 nodes), so the work is bounded as well as the result.
    pub const MAX_INLINED_CALLS: u64 = 1_000_000;
    /// The largest magnitude of a constant shape or transform argument (a size, a position,
    /// a factor): three such multiplied stay below f32's 3.4e38.
    pub const MAX_MAGNITUDE: f32 = 1e12;
    /// Why param values are held to [`MAX_MAGNITUDE`] too (defaults and render overrides).
    pub const PARAM_MAGNITUDE_WHY: &str = "as a size or position a larger value makes \
        distances overflow f32 (a length squares it), and shapes vanish";

    /// A param override past [`MAX_MAGNITUDE`], refused in these words by the renderer and
    /// by `sdfc eval` (which evaluates on the CPU, without one).
    pub fn check_param_magnitude(name: &str, value: &[f64]) -> Result<(), String> {
        if value.iter().all(|c| c.abs() <= MAX_MAGNITUDE as f64) {
            return Ok(());
        }
        Err(format!(
            "param `{name}` must be at most {MAX_MAGNITUDE:e} in magnitude, found {value:?}: \
             {PARAM_MAGNITUDE_WHY}"
        ))
    }
    /// Shapes of the scene unfolded into a tree (a `let` shape counts once per use). A
    /// 1 MiB file of one flat union holds about 28 000 shapes (56 000 with a transform each).
    pub const MAX_SHAPE_INSTANCES: u64 = 100_000;
}
