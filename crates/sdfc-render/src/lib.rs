//! The sdfc renderer: runs the compute shaders that `sdfc-wgsl` emits on a wgpu device and
//! brings the pixels back. This is the only crate of the workspace that knows wgpu.
//!
//! ```no_run
//! use sdfc_render::{Renderer, RenderOptions};
//!
//! // A mistake in the scene is an error whose `Display` gives each line and column;
//! // `Failure::render` adds the source lines.
//! let compiled = sdfc_render::sdfc_wgsl::compile("scene = sphere(1);", &Default::default())?;
//! let renderer = Renderer::new()?;
//! eprintln!("rendering on {}", renderer.adapter_description());
//! let frame = renderer.render(&compiled, &RenderOptions::sized(64, 48))?;
//! sdfc_render::output::write_png("sphere.png", &frame)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! `sdfc_wgsl` (the compiler) is re-exported, so this crate is the one dependency an
//! embedder needs.
//!
//! Every call blocks the calling thread until the device has done its work and the results
//! are back ([`Renderer::new`], the renders, [`Renderer::eval_gpu`]); on an async runtime, call
//! them from a blocking task. A [`Renderer`] is a cheap clone of one shared device and may be
//! used from several threads at once.
//!
//! # The device
//!
//! [`Renderer::new`] opens one wgpu device, chosen in this order:
//!
//! 1. a hardware adapter (discrete, then integrated, then virtual GPU; Vulkan before GL);
//! 2. a software Vulkan adapter (Mesa's lavapipe, package `mesa-vulkan-drivers`);
//! 3. a software GL adapter (Mesa's llvmpipe).
//!
//! Adapters that cannot run compute shaders are skipped. The environment variable
//! `SDFC_BACKEND` narrows the choice: `vulkan` or `gl` (also `gles`, `opengl`) allows only
//! that backend; `auto` or unset allows both. [`Renderer::adapter_description`] says which
//! adapter was taken. wgpu's own variables (`WGPU_VALIDATION`, `WGPU_DEBUG`, ...) are honoured
//! for debugging.
//!
//! # What a render does
//!
//! The shader interface is the one documented in `sdfc_wgsl` (entry point `main`, 8x8
//! workgroups, the `Frame` buffer, packed RGBA8 colour, two `vec4` of AOVs per pixel). Compute
//! pipelines are cached by a hash of the WGSL text (and checked against the text itself), so
//! rendering the same scene again, at another size or time or with other param values, never
//! compiles it again ([`Renderer::pipeline_compilations`] counts the compilations). Every
//! device call runs inside wgpu error scopes: a shader the device rejects, a device that runs
//! out of memory or is lost, becomes a [`RenderError`], never a panic. Image sizes are checked
//! against the device's limits (buffer sizes, dispatch size) before anything is submitted.
//!
//! # The interpreted marcher
//!
//! [`Renderer::render_interpreted`] renders the same picture from one fixed shader that reads
//! the scene as bytecode (`sdfc_wgsl::interp`): the pipeline is compiled on the first call
//! and reused for every scene after it.
//!
//! # The live path
//!
//! [`Renderer::render_live`] shows a first picture before a slow driver has built the
//! scene's specialised pipeline: the pipeline is built on another thread, and if it is not
//! ready within a grace period (none by default), the interpreted marcher draws a small
//! preview (a quarter of the width and height on a GPU, an eighth on a CPU device, where the
//! interpreter is 20 to 250 times slower); then the specialised shader draws the final frame. On a CPU device the preview is drawn
//! only once the interpreter is warm ([`Renderer::warm_interpreter`]): lavapipe compiles it
//! at its first dispatch, on the device's one queue thread, and the final frame would wait. The pipeline cache builds each text
//! once and never blocks one pipeline's build on another's. [`LiveReport`] says when each
//! picture came. [`Renderer::render_live_until`] gives up as soon as the scene has changed
//! again (a live editor's next edit), leaving the build to finish into the cache.
//!
//! # Outputs
//!
//! [`output`] writes PNG (colour), OpenEXR (32-bit float, ZIP compression: lossless) and NumPy
//! `.npy` (little-endian `f4`, shape `(H, W)` for depth and steps, `(H, W, 3)` for normals).

#![warn(missing_docs)]

mod device;
mod error;
mod eval;
mod interp;
mod live;
pub mod output;
mod params;
mod pipelines;
mod render;
mod serial;
mod tiles;

pub use device::{quiet_headless_vulkan, AdapterDescription, Renderer};
pub use error::RenderError;
pub use live::{Drawn, LiveOptions, LiveReport};
pub use output::AovKind;
/// The compiler, so that this crate is the one dependency an embedder needs.
pub use sdfc_wgsl;

use std::time::Duration;

/// How to render a frame.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels (at least 1).
    pub width: u32,
    /// Image height in pixels (at least 1).
    pub height: u32,
    /// Scene time in seconds (the language's `time`).
    pub time: f32,
    /// Param values by name, overriding the scene's defaults: one number for a float param,
    /// two or three for vectors. Unknown names and wrong sizes are errors.
    pub params: Vec<(String, Vec<f32>)>,
    /// Also bring back depth, world normal and march steps of each pixel's centre ray.
    pub aovs: bool,
    /// Run the shader for every pixel. By default a frame of a scene with finite bounds
    /// runs it only on the 8x8 tiles whose rays can meet them (`sdfc_wgsl::screen`) and gives
    /// the other pixels the background of one that was run, the same picture bit for bit;
    /// this is for comparisons and measurements of that.
    pub all_pixels: bool,
}

impl RenderOptions {
    /// `width x height`, time 0, default params, no AOVs.
    pub fn sized(width: u32, height: u32) -> RenderOptions {
        RenderOptions {
            width,
            height,
            ..RenderOptions::default()
        }
    }
}

impl Default for RenderOptions {
    /// 512 x 512 (the CLI's default), time 0, default params, no AOVs.
    fn default() -> RenderOptions {
        RenderOptions {
            width: 512,
            height: 512,
            time: 0.0,
            params: Vec::new(),
            aovs: false,
            all_pixels: false,
        }
    }
}

/// A rendered image.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// RGBA8, gamma applied, row-major with the top row first, `4 * width * height` bytes.
    pub rgba: Vec<u8>,
    /// The arbitrary output variables, when [`RenderOptions::aovs`] asked for them.
    pub aovs: Option<Aovs>,
    /// Time the device spent in the compute pass, from timestamp queries where the device
    /// has them.
    pub device_time: Option<Duration>,
    /// Time from submitting the work to having the results back on the CPU.
    pub wall_time: Duration,
}

impl Frame {
    /// The RGBA value of pixel column `x`, row `y` (row 0 at the top); `None` outside the
    /// image (or where `rgba` is shorter than the size says).
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = (y as usize)
            .checked_mul(self.width as usize)?
            .checked_add(x as usize)?
            .checked_mul(4)?;
        self.rgba.get(i..i.checked_add(4)?)?.try_into().ok()
    }

    /// `4 * width * height`, the length `rgba` should have; `None` if it overflows.
    pub(crate) fn byte_len(&self) -> Option<usize> {
        (self.width as usize)
            .checked_mul(self.height as usize)?
            .checked_mul(4)
    }
}

/// Per-pixel float outputs, for the ray through each pixel's centre; row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Aovs {
    /// Distance t along the ray from the camera to the hit (spec section 8); `f32::INFINITY`
    /// where the ray misses.
    pub depth: Vec<f32>,
    /// World-space unit normal at the hit; zero where the ray misses.
    pub normal: Vec<[f32; 3]>,
    /// Number of distance evaluations the primary march took (including the refinement
    /// steps after the hit).
    pub steps: Vec<f32>,
}

impl Aovs {
    /// Mean march steps per pixel.
    pub fn mean_steps(&self) -> f64 {
        if self.steps.is_empty() {
            return 0.0;
        }
        self.steps.iter().map(|&s| s as f64).sum::<f64>() / self.steps.len() as f64
    }
}
