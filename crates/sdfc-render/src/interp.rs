//! `render_interpreted`: a frame from the generic interpreted marcher, the scene uploaded
//! as bytecode. The interpreter's pipeline is the same for every scene, so it is compiled
//! once per [`Renderer`] and a new scene only costs an upload.

use crate::device::Renderer;
use crate::pipelines::Kind;
use crate::render::header;
use crate::{params, Frame, RenderError, RenderOptions};
use sdfc_ir::scene::RenderSettings;
use sdfc_ir::Program;
use sdfc_wgsl::interp::encode::{encode, Bytecode};
use sdfc_wgsl::interp::frame::frame_data_with;
use std::sync::atomic::Ordering;

/// The interpreter's WGSL running `unroll` instructions per trip of its loop (emitted and
/// validated once per process).
fn interpreter_wgsl(unroll: u32) -> Result<&'static str, RenderError> {
    sdfc_wgsl::interp::shader_unrolled(unroll).map_err(|f| match f {
        sdfc_wgsl::Failure::Internal { report, .. } => RenderError::Emit(report),
        // Neither happens here: the program was lowered, the options are fixed.
        f => RenderError::Emit(format!("while emitting the interpreter: {f}")),
    })
}

impl Renderer {
    /// Makes the interpreter ready to draw at once: builds its pipeline and draws one pixel
    /// with it, unless an interpreted frame has been drawn already. The pixel matters on
    /// lavapipe, which compiles a pipeline's machine code at its first dispatch (seconds for
    /// the interpreter, on the device's one queue thread), not when the pipeline is created.
    /// A live editor calls this (or [`Renderer::warm_interpreter_in_background`]) at
    /// start-up, so that its first interpreted frame need not wait.
    pub fn warm_interpreter(&self) -> Result<(), RenderError> {
        if self.interpreter_is_warm() {
            return Ok(());
        }
        let sphere = sdfc_wgsl::lower("scene = sphere(1);", &Default::default())
            .map_err(|_| RenderError::Emit("the warm-up scene does not compile".into()))?;
        self.render_interpreted(&sphere.stages.program, &RenderOptions::sized(1, 1))
            .map(|_| ())
    }

    /// As [`Renderer::warm_interpreter`], on a thread of its own, which may outlive the call
    /// (it holds a clone of the renderer); returns at once, and calls `done` on that thread
    /// when the interpreter is warm (or could not be made so). See
    /// [`Renderer::wait_for_background_work`].
    pub fn warm_interpreter_in_background(
        &self,
        done: impl FnOnce(Result<(), RenderError>) + Send + 'static,
    ) {
        let renderer = self.clone();
        let spawned = std::thread::Builder::new()
            .name("sdfc-interpreter".into())
            .spawn(move || done(renderer.warm_interpreter()));
        // Where no thread can start, `done` is dropped uncalled: a live render then goes on
        // waiting for the specialised pipeline alone.
        if let Ok(handle) = spawned {
            self.keep_in_background(handle);
        }
    }

    /// Whether an interpreted frame has been drawn on this device, so that the next one
    /// needs no pipeline build or machine-code compilation.
    pub fn interpreter_is_warm(&self) -> bool {
        self.interpreter_warm.load(Ordering::Relaxed)
    }

    /// Renders a compiled program with the interpreted marcher: the same picture as
    /// [`Renderer::render`] (up to float rounding), without a per-scene shader.
    pub fn render_interpreted(
        &self,
        program: &Program,
        opts: &RenderOptions,
    ) -> Result<Frame, RenderError> {
        self.check_health()?;
        let code = encode(program).map_err(RenderError::Interpreter)?;
        self.render_bytecode(program, &code, opts)
    }

    /// As [`Renderer::render_interpreted`], with the bytecode already encoded (by
    /// `sdfc_wgsl::interp::encode::encode` of the same program).
    pub fn render_bytecode(
        &self,
        program: &Program,
        code: &Bytecode,
        opts: &RenderOptions,
    ) -> Result<Frame, RenderError> {
        self.render_bytecode_with(program, &program.scene.render, code, opts)
    }

    /// As [`Renderer::render_bytecode`], with render settings `settings` in place of the
    /// scene's (the interpreter reads them at run time). lavapipe and llvmpipe end an
    /// invocation's loops after 65 535 trips in all; where that cut pixels' code short, the
    /// pipeline with two instructions per trip draws the frame again, and pixels still cut
    /// make it an error (the scene is too large for the interpreter there).
    pub(crate) fn render_bytecode_with(
        &self,
        program: &Program,
        settings: &RenderSettings,
        code: &Bytecode,
        opts: &RenderOptions,
    ) -> Result<Frame, RenderError> {
        let (mut frame, mut cut) = self.render_bytecode_cut(program, settings, code, opts, 1)?;
        if cut > 0 && self.adapter_description().software {
            let unroll = sdfc_wgsl::interp::CPU_UNROLL;
            (frame, cut) = self.render_bytecode_cut(program, settings, code, opts, unroll)?;
        }
        if cut > 0 {
            return Err(self.cut_short(cut, opts));
        }
        Ok(frame)
    }

    /// Why a frame with `cut` pixels cut short by the device's loop budget is refused.
    pub(crate) fn cut_short(&self, cut: usize, opts: &RenderOptions) -> RenderError {
        RenderError::Interpreter(sdfc_wgsl::interp::encode::EncodeError::TooLarge(format!(
            "on {} of {} pixels it needs more loop trips than {} allows one invocation \
             (lavapipe and llvmpipe: 65 535 in all)",
            cut,
            opts.width as usize * opts.height as usize,
            self.adapter_description().name
        )))
    }

    /// One interpreted frame by the pipeline running `unroll` instructions per trip, and
    /// how many of its pixels the device cut short (made opaque again).
    pub(crate) fn render_bytecode_cut(
        &self,
        program: &Program,
        settings: &RenderSettings,
        code: &Bytecode,
        opts: &RenderOptions,
        unroll: u32,
    ) -> Result<(Frame, usize), RenderError> {
        let params = params::values(program, &opts.params)?;
        params::check_time(opts.time)?;
        let (gx, gy) = self.check_size(opts.width, opts.height, opts.aovs)?;
        let data = frame_data_with(program, settings, code, header(opts), &params);
        let max = self.max_buffer_bytes();
        if data.code.len() as u64 > max || data.data.len() as u64 > max {
            return Err(RenderError::Interpreter(
                sdfc_wgsl::interp::encode::EncodeError::TooLarge(format!(
                    "its bytecode needs {} KiB in one buffer, and this device allows {} KiB",
                    data.code.len().max(data.data.len()) >> 10,
                    max >> 10
                )),
            ));
        }
        let pipeline = self.pipeline(Kind::Interpreted, interpreter_wgsl(unroll)?)?;
        let mut frame = self.dispatch(
            &pipeline.pipeline,
            &self.interp_bind_layout,
            &data.frame,
            &[
                ("sdfc bytecode", &data.code),
                ("sdfc scene data", &data.data),
            ],
            opts,
            (gx, gy),
        )?;
        self.interpreter_warm.store(true, Ordering::Relaxed);
        let cut = sdfc_wgsl::interp::cut_pixels(&mut frame.rgba);
        Ok((frame, cut))
    }
}
