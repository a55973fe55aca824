//! A CPU reference renderer in f64 over the IR, and error metrics of a GPU frame against it.
//!
//! The reference renders a [`Program`] with the semantics of the WGSL that sdfc-wgsl emits
//! (camera rays of spec section 8, Phong shading with the scene's lights, hard or soft
//! shadows, ambient occlusion, reflections, fog, background, antialiasing and gamma), but
//! evaluates the scene functions in f64 with the IR evaluator and marches far more precisely:
//! sphere tracing down to a threshold of 1e-9 relative to t, then bisection of the bracketed
//! surface to about 1e-13 relative, normals from central differences with a step of 1e-8
//! times the point's magnitude (on the ray's side of a surface of zero thickness). Rows render on all cores with `std::thread::scope`.
//!
//! No I/O, no GPU: [`metrics`] takes plain slices, so callers glue it to any renderer.

pub mod camera;
pub mod march;
pub mod metrics;
pub mod scene;
pub mod shade;
pub mod vec;

use camera::Camera;
use march::march;
use scene::SceneEval;
use sdfc_ir::value::Value;
use sdfc_ir::Program;
use shade::{normal, Shader};
use vec::{add, mul};

/// What to render.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    pub width: u32,
    pub height: u32,
    /// The language's `time`.
    pub time: f64,
    /// Param values in declaration order; missing ones take the scene's defaults.
    pub params: Vec<Value<f64>>,
    /// Worker threads (0: as many as the machine has).
    pub threads: usize,
}

impl Options {
    pub fn sized(width: u32, height: u32) -> Options {
        Options {
            width,
            height,
            time: 0.0,
            params: Vec::new(),
            threads: 0,
        }
    }
}

/// One pixel of the reference: the AOVs of the ray through its centre, and its colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pixel {
    pub hit: bool,
    /// t along the centre ray; infinite on a miss.
    pub depth: f64,
    /// World-space unit normal at the hit; zero on a miss.
    pub normal: [f64; 3],
    /// Linear colour averaged over the antialiasing samples, before clamping and gamma.
    pub linear: [f64; 3],
    /// The colour as the GPU writes it: clamped, gamma applied, RGBA8 (`pack4x8unorm`).
    pub rgba: [u8; 4],
    /// Distance evaluations of the centre ray's march, bisection included.
    pub steps: u32,
}

/// A reference image, row-major with the top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Pixel>,
}

impl Image {
    pub fn pixel(&self, x: u32, y: u32) -> &Pixel {
        &self.pixels[y as usize * self.width as usize + x as usize]
    }
}

/// `pack4x8unorm` of one channel: round(clamp(v, 0, 1) * 255).
pub fn unorm8(v: f64) -> u8 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    (v * 255.0 + 0.5).floor() as u8
}

/// Renders the reference image.
pub fn render(program: &Program, opts: &Options) -> Image {
    let scene = SceneEval::new(program, &opts.params, opts.time);
    let shader = Shader {
        scene: &scene,
        desc: &program.scene,
    };
    let (w, h) = (opts.width.max(1), opts.height.max(1));
    let threads = if opts.threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        opts.threads
    };
    let rows: Vec<Vec<Pixel>> = {
        let next = std::sync::atomic::AtomicU32::new(0);
        let results = std::sync::Mutex::new(vec![Vec::new(); h as usize]);
        std::thread::scope(|s| {
            for _ in 0..threads.min(h as usize) {
                s.spawn(|| loop {
                    let y = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    if y >= h {
                        break;
                    }
                    let row: Vec<Pixel> = (0..w).map(|x| pixel(&shader, x, y, w, h)).collect();
                    if let Ok(mut r) = results.lock() {
                        r[y as usize] = row;
                    }
                });
            }
        });
        results.into_inner().unwrap_or_default()
    };
    Image {
        width: w,
        height: h,
        pixels: rows.into_iter().flatten().collect(),
    }
}

fn pixel(shader: &Shader, x: u32, y: u32, w: u32, h: u32) -> Pixel {
    let settings = &shader.desc.render;
    let cam = Camera::of(&shader.desc.camera);
    let (fw, fh) = (w as f64, h as f64);
    let max_distance = settings.max_distance as f64;
    let n = settings.antialias.max(1);
    let mut color = [0.0; 3];
    for sy in 0..n {
        for sx in 0..n {
            let ox = (sx as f64 + 0.5) / n as f64;
            let oy = (sy as f64 + 0.5) / n as f64;
            let rd = cam.ray(x as f64 + ox, y as f64 + oy, fw, fh);
            let hit = march(shader.scene, cam.position, rd, max_distance);
            color = add(color, shader.radiance(cam.position, rd, hit));
        }
    }
    let linear = mul(color, 1.0 / (n * n) as f64);
    let inv_gamma = 1.0 / settings.gamma as f64;
    let enc = |c: f64| unorm8(c.clamp(0.0, 1.0).powf(inv_gamma));
    let rgba = [enc(linear[0]), enc(linear[1]), enc(linear[2]), 255];
    let rd = cam.ray(x as f64 + 0.5, y as f64 + 0.5, fw, fh);
    let hit = march(shader.scene, cam.position, rd, max_distance);
    let (depth, nrm) = if hit.hit {
        (
            hit.t,
            normal(shader.scene, add(cam.position, mul(rd, hit.t)), rd),
        )
    } else {
        (f64::INFINITY, [0.0; 3])
    };
    Pixel {
        hit: hit.hit,
        depth,
        normal: nrm,
        linear,
        rgba,
        steps: hit.steps,
    }
}
