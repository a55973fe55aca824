//! `render_interpreted`: a frame from the generic interpreted marcher, the scene uploaded
//! as bytecode. The interpreter's pipeline is the same for every scene, so it is compiled
//! once per [`Renderer`] and a new scene only costs an upload.

use crate::device::Renderer;
use crate::pipelines::Kind;
use crate::tiles;
use crate::{params, Frame, RenderError, RenderOptions};
use sdfc_ir::scene::RenderSettings;
use sdfc_ir::shape::{CombineOp, ShapeKind};
use sdfc_ir::to_ssa::CULL_MIN;
use sdfc_ir::Program;
use sdfc_wgsl::instances::plan_interpreted;
use sdfc_wgsl::interp::encode::{encode, Bytecode};
use sdfc_wgsl::interp::encode_instances::encode_as_data;
use sdfc_wgsl::interp::frame::frame_data_with;
use sdfc_wgsl::interp::Variant;
use std::sync::atomic::Ordering;

/// The WGSL of the interpreter's `variant` running `unroll` instructions per trip of its
/// loop (emitted and validated once per process).
fn interpreter_wgsl(unroll: u32, variant: Variant) -> Result<&'static str, RenderError> {
    sdfc_wgsl::interp::shader_variant(unroll, variant).map_err(|f| match f {
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
    ///
    /// Both variants are warmed: the one every scene runs on, and the one that walks a
    /// union read as data (the live path previews such a union with it).
    pub fn warm_interpreter(&self) -> Result<(), RenderError> {
        if self.interpreter_is_warm() {
            return Ok(());
        }
        let failed = |_| RenderError::Emit("the warm-up scene does not compile".into());
        let one = RenderOptions::sized(1, 1);
        if !self.variant_is_warm(Variant::Code) {
            let sphere =
                sdfc_wgsl::lower("scene = sphere(1);", &Default::default()).map_err(failed)?;
            self.render_interpreted(&sphere.stages.program, &one)?;
        }
        if !self.variant_is_warm(Variant::Walk) {
            // The smallest union read as data: 16 spheres in a row.
            let spheres: Vec<String> = (0..sdfc_ir::instances::MIN_CHILDREN)
                .map(|i| format!("sphere(0.4).translate([{i}, 0, 0])"))
                .collect();
            let src = format!("scene = union({});", spheres.join(", "));
            let row = sdfc_wgsl::lower(&src, &Default::default()).map_err(failed)?;
            let program = &row.stages.program;
            let code = encode_as_data(program)
                .ok_or_else(|| RenderError::Emit("the warm-up union is not read as data".into()))?
                .map_err(RenderError::Interpreter)?;
            self.render_bytecode(program, &code, &one)?;
        }
        Ok(())
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

    /// Whether both variants of the interpreter (`Variant`: the one every scene runs on,
    /// and the one that walks a union read as data) have drawn a frame on this device, so
    /// that the next interpreted frame needs no pipeline build or machine-code compilation.
    pub fn interpreter_is_warm(&self) -> bool {
        self.variant_is_warm(Variant::Code) && self.variant_is_warm(Variant::Walk)
    }

    /// Whether the interpreter's `variant` has drawn a frame on this device.
    fn variant_is_warm(&self, variant: Variant) -> bool {
        self.interpreter_warm[variant.index()].load(Ordering::Relaxed)
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
    /// make it an error (the scene is too large for the interpreter there). On such a
    /// device a frame of 768 pixels or more is probed first (16 pixels wide, [`probe`]).
    pub(crate) fn render_bytecode_with(
        &self,
        program: &Program,
        settings: &RenderSettings,
        code: &Bytecode,
        opts: &RenderOptions,
    ) -> Result<Frame, RenderError> {
        let software = self.adapter_description().software;
        let mut unroll = 1;
        // A frame cut short is drawn twice before it is refused: 72 s of lavapipe's time for
        // the 5 000-shape union at 160x120. A probe of the same view at a few pixels, whose
        // rays take no more steps than the frame's (its pixels' footprints are larger), finds
        // such a scene in a fraction of that (6 s). It runs the one-instruction pipeline
        // first, as the frame does: the other takes longer to build.
        if let Some(probe) = probe(opts).filter(|_| software) {
            let (_, cut) = self.render_bytecode_cut(program, settings, code, &probe, 1)?;
            if cut > 0 {
                unroll = sdfc_wgsl::interp::CPU_UNROLL;
                let (_, cut) = self.render_bytecode_cut(program, settings, code, &probe, unroll)?;
                if cut > 0 {
                    return Err(self.cut_short(cut, &probe, program, code, true));
                }
            }
        }
        let (mut frame, mut cut) =
            self.render_bytecode_cut(program, settings, code, opts, unroll)?;
        if cut > 0 && software && unroll == 1 {
            unroll = sdfc_wgsl::interp::CPU_UNROLL;
            (frame, cut) = self.render_bytecode_cut(program, settings, code, opts, unroll)?;
        }
        if cut > 0 {
            return Err(self.cut_short(cut, opts, program, code, false));
        }
        Ok(frame)
    }

    /// Why a frame of `code` with `cut` pixels cut short by the device's loop budget is
    /// refused; with `probe`, `opts` are the probe's.
    pub(crate) fn cut_short(
        &self,
        cut: usize,
        opts: &RenderOptions,
        program: &Program,
        code: &Bytecode,
        probe: bool,
    ) -> RenderError {
        let pixels = opts.width as usize * opts.height as usize;
        let of = if probe {
            format!(
                "{pixels} pixels of a {}x{} probe of the view",
                opts.width, opts.height
            )
        } else {
            format!("{pixels} pixels")
        };
        // A union of instances read as data costs what the shapes near each ray cost, and
        // its bytecode does not grow with them (the 5 000-shape union, refused as code, is
        // drawn so); culling makes the bytecode jump over the parts far from each ray.
        let cull = if code.instances.is_empty() && plan_interpreted(program).is_some() {
            "; with `--instances` the interpreter walks the union's shapes as data, which \
             costs what the shapes near each ray cost"
        } else if !program.culls() && has_cullable_union(program) {
            "; with `--cull` the bytecode jumps over the parts of large unions far from each \
             ray, which may bring it within the budget"
        } else {
            ""
        };
        RenderError::Interpreter(sdfc_wgsl::interp::encode::EncodeError::TooLarge(format!(
            "on {cut} of {of} it needs more loop trips than {} allows one invocation \
             (lavapipe and llvmpipe: 65 535 in all){cull}",
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
        // Held from the build to the end of the frame, the pipeline's last use (on GL).
        let _serial = self.serial.hold();
        let params = params::values(program, &opts.params)?;
        params::check_time(opts.time)?;
        let (gx, gy) = self.check_size(opts.width, opts.height, opts.aovs)?;
        // Only the tiles whose rays can meet the scene's bounds, as the specialised shader
        // (the interpreter's entry point is the render shader's, which reads its first tile:
        // `sdfc_wgsl::screen`'s tests check both).
        let plan = tiles::Dispatch::plan(program, true, opts, (gx, gy));
        let data = frame_data_with(program, settings, code, plan.header, &params);
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
        let variant = Variant::of(code);
        let pipeline = self.pipeline(Kind::Interpreted, interpreter_wgsl(unroll, variant)?)?;
        let passes = crate::render::Passes {
            march: &pipeline.pipeline,
            blocks: None,
        };
        let mut frame = self.dispatch(
            passes,
            &self.interp_bind_layout,
            &data.frame,
            &[
                ("sdfc bytecode", &data.code),
                ("sdfc scene data", &data.data),
            ],
            opts,
            plan.groups,
        )?;
        plan.finish(&mut frame);
        self.interpreter_warm[variant.index()].store(true, Ordering::Relaxed);
        let cut = sdfc_wgsl::interp::cut_pixels(&mut frame.rgba);
        Ok((frame, cut))
    }
}

/// The probe of a frame: the same view 16 pixels wide, where the frame has at least four
/// times its pixels (a smaller frame is its own probe), without AOVs.
fn probe(opts: &RenderOptions) -> Option<RenderOptions> {
    const WIDTH: u32 = 16;
    let height =
        ((WIDTH as f64 * opts.height as f64 / opts.width.max(1) as f64).round() as u32).max(1);
    let big = opts.width as u64 * opts.height as u64 >= 4 * WIDTH as u64 * height as u64;
    big.then(|| RenderOptions {
        width: WIDTH,
        height,
        aovs: false,
        ..opts.clone()
    })
}

/// Whether the scene has a hard union large enough for `--cull` to split
/// ([`CULL_MIN`] children or more).
fn has_cullable_union(program: &Program) -> bool {
    program.scene.shapes.iter().any(|s| {
        matches!(
            &s.kind,
            ShapeKind::Combine { op: CombineOp::Union, smooth: None, children }
                if children.len() >= CULL_MIN
        )
    })
}
