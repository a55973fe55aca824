//! The interpreter's per-frame inputs, laid out as `shaders/interpreter/interface.wgsl`
//! declares them: the `Frame` buffer (image, time, camera, render settings, where things
//! sit in the data buffer) and the data buffer (lights, params, the scene's bounds,
//! constants, a union read as data).

use super::encode::Bytecode;
use crate::marcher::{camera_basis, root_bounds, shadow_slabs, span_slabs, Slab};
use sdfc_ir::rounding::f32_down;
use sdfc_ir::scene::{Epsilon, LightKind, Normals, RenderSettings, Shadows};
use sdfc_ir::types::Ty;
use sdfc_ir::Program;

/// Bytes of the `Frame` buffer.
pub const FRAME_BYTES: usize = 208;

/// `Frame.switches` bit: `epsilon: pixel` (else the absolute `Frame.epsilon`).
const SWITCH_EPSILON_PIXEL: u32 = 1;
/// `Frame.switches` bit: exponential fog.
const SWITCH_FOG: u32 = 2;
/// `Frame.switches` bit: the scene's distance is trusted (`distance_trusted()`).
const SWITCH_TRUSTED: u32 = 4;

/// Both buffers of one frame.
pub struct FrameData {
    /// The `Frame` buffer (read-only storage), [`FRAME_BYTES`] long.
    pub frame: Vec<u8>,
    /// The `data` storage buffer: `array<vec4<f32>>`.
    pub data: Vec<u8>,
    /// The `code` storage buffer: `array<vec4<u32>>`.
    pub code: Vec<u8>,
}

struct Writer(Vec<u8>);

impl Writer {
    fn u(&mut self, x: u32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn f(&mut self, x: f32) {
        self.u(x.to_bits());
    }
    fn v3f(&mut self, v: [f32; 3], w: f32) {
        for c in v {
            self.f(c);
        }
        self.f(w);
    }
}

/// The frame's buffers. `header` is `[width, height, time bits, flags]` as in the render
/// shader's `Frame`; `params` holds each param's value in declaration order (float params
/// are splatted here, as the interpreter keeps every scalar).
pub fn frame_data(
    program: &Program,
    code: &Bytecode,
    header: [u32; 4],
    params: &[[f32; 4]],
) -> FrameData {
    frame_data_with(program, &program.scene.render, code, header, params)
}

/// The render settings of a quick preview: the scene's, less what costs many distance
/// evaluations per pixel beyond the primary ray (shadow rays, ambient occlusion,
/// reflections, antialiasing). The preview of the live path uses them: a first picture of
/// the shapes and their colours in direct light.
pub fn preview_settings(r: &RenderSettings) -> RenderSettings {
    RenderSettings {
        shadows: Shadows::None,
        ao: None,
        reflections: 0,
        antialias: 1,
        ..r.clone()
    }
}

/// As [`frame_data`], with render settings `r` in place of the scene's.
pub fn frame_data_with(
    program: &Program,
    r: &RenderSettings,
    code: &Bytecode,
    header: [u32; 4],
    params: &[[f32; 4]],
) -> FrameData {
    let scene = &program.scene;
    let (forward, right, up, tan_half) = camera_basis(scene);
    // Camera-relative coordinates where the bytecode has them (`encode`): the camera at
    // the origin, the lights and the bounds moved with it.
    let marched = program.marched();
    let (lights, origin) = (marched.lights, marched.origin);
    let camera: [f32; 3] = std::array::from_fn(|k| scene.camera.position[k] - origin[k]);

    // Data buffer: lights (2 entries each), params, constants.
    let mut data: Vec<[f32; 4]> = Vec::new();
    let lights_at = data.len() as u32;
    for light in lights {
        let (v, kind) = match light.kind {
            LightKind::Directional { direction } => (direction.map(|x| -x), 0.0),
            LightKind::Point { position } => (position, 1.0),
        };
        data.push([v[0], v[1], v[2], kind]);
        let c = light.color.map(|c| c * light.intensity);
        data.push([c[0], c[1], c[2], 0.0]);
    }
    let params_at = data.len() as u32;
    for (i, v) in params.iter().enumerate() {
        let float = scene.params.get(i).is_some_and(|d| d.ty == Ty::F32);
        data.push(if float { [v[0]; 4] } else { *v });
    }
    // The scene's slabs as the specialised shader's `ray_span` has them: low corner with the
    // mask of finite ends in w (bit k: axis k's low end, bit k + 3: its high end), high corner
    // with the outside factor in w; then the shadow rays' box (the same ends).
    let bounds_at = data.len() as u32;
    let slabs = span_slabs(root_bounds(program), origin);
    let mask = slabs.iter().enumerate().fold(0u32, |m, (k, s)| {
        m | u32::from(s.lo.is_some()) << k | u32::from(s.hi.is_some()) << (k + 3)
    });
    // The factor by which the distance outside the box is at least the distance to it
    // (`OUTSIDE_FACTOR` of the specialised shader).
    let factor = f32_down(
        program
            .analysis
            .outside_factor(&program.scene)
            .clamp(0.0, 1.0),
    );
    // The box shadow rays stop at (`shadow_slabs`: the same finite ends, a little wider, and
    // around the hierarchy's root box where the union is read as data).
    let data_root = match code.instances.as_slice() {
        [c, h, ..] => Some((
            [0, 1, 2].map(|k| f32::from_bits(c[k])),
            [0, 1, 2].map(|k| f32::from_bits(h[k])),
        )),
        _ => None,
    };
    let shadow = shadow_slabs(root_bounds(program), origin, data_root);
    data.push(corner(&slabs, |s| s.lo, mask as f32));
    data.push(corner(&slabs, |s| s.hi, factor));
    data.push(corner(&shadow, |s| s.lo, 0.0));
    data.push(corner(&shadow, |s| s.hi, 0.0));
    let consts_at = data.len() as u32;
    data.extend_from_slice(&code.consts);
    // The shader reads constant 0 for every register operand too (and discards it): it
    // must exist.
    if code.consts.is_empty() {
        data.push([0.0; 4]);
    }
    // A union read as data comes last, its words as they are (floats by their bits).
    let instances_at = data.len() as u32;

    let mut w = Writer(Vec::with_capacity(FRAME_BYTES));
    for h in header {
        w.u(h);
    }
    w.v3f(camera, tan_half);
    w.v3f(forward, r.max_distance);
    w.v3f(right, (1.0 / r.gamma as f64) as f32);
    w.v3f(up, r.relaxation.max(1.0));
    let epsilon = match r.epsilon {
        Epsilon::Pixel => 0.0,
        Epsilon::Absolute(e) => e,
    };
    w.v3f(r.background, epsilon);
    let (fog_color, fog_density) = r.fog.map_or(([0.0; 3], 0.0), |f| (f.color, f.density));
    w.v3f(fog_color, fog_density);
    w.u(r.max_steps);
    w.u(r.antialias);
    w.u(match r.normals {
        // The interpreter has no gradient code: analytic normals fall back to the
        // tetrahedron there (docs/language.md).
        Normals::Tetrahedron | Normals::Analytic => 0,
        Normals::Central => 1,
        Normals::Forward => 2,
    });
    let (shadows, shadow_k) = match r.shadows {
        Shadows::None => (0, 0.0),
        Shadows::Hard => (1, 0.0),
        Shadows::Soft(k) => (2, k),
    };
    w.u(shadows);
    w.f(shadow_k);
    let ao = r.ao.unwrap_or(sdfc_ir::scene::Ao {
        samples: 0,
        step: 0.0,
        strength: 0.0,
        falloff: 0.0,
    });
    w.u(if r.ao.is_some() { ao.samples } else { 0 });
    w.f(ao.step);
    w.f(ao.strength);
    w.f(ao.falloff);
    w.u(r.reflections);
    w.u(lights.len() as u32);
    let mut switches = 0;
    if r.epsilon == Epsilon::Pixel {
        switches |= SWITCH_EPSILON_PIXEL;
    }
    if r.fog.is_some() {
        switches |= SWITCH_FOG;
    }
    if program.analysis.distance_trusted(&program.scene) {
        switches |= SWITCH_TRUSTED;
    }
    w.u(switches);
    w.u(code.distance[0]);
    w.u(code.distance[1]);
    w.u(code.material[0]);
    w.u(code.material[1]);
    w.u(lights_at);
    w.u(params_at);
    w.u(consts_at);
    w.u(bounds_at);
    w.u(instances_at);
    w.f(f32_down(program.analysis.feature));
    w.u(code.distance_ray[0]);
    w.u(code.distance_ray[1]);
    // The struct's size is a multiple of its alignment (16, its vec3s'): padded, never cut.
    debug_assert!(w.0.len() <= FRAME_BYTES && FRAME_BYTES - w.0.len() < 16);
    w.0.resize(FRAME_BYTES, 0);

    let data_bytes = data
        .iter()
        .flatten()
        .map(|x| x.to_bits())
        .chain(code.instances.iter().flatten().copied())
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let code_bytes = code
        .code
        .iter()
        .flatten()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    FrameData {
        frame: w.0,
        data: data_bytes,
        code: code_bytes,
    }
}

/// One corner of a box as the interpreter's data holds it: each axis's `end` (0 where it is
/// open: the mask says which are finite), and `w`.
fn corner(slabs: &[Slab; 3], end: impl Fn(&Slab) -> Option<f32>, w: f32) -> [f32; 4] {
    let v = slabs.map(|s| end(&s).unwrap_or(0.0));
    [v[0], v[1], v[2], w]
}
