//! `render_interpreted`: a frame from the generic interpreted marcher, the scene uploaded
//! as bytecode. The interpreter's pipeline is the same for every scene, so it is compiled
//! once per [`Renderer`] and a new scene only costs an upload.

use crate::device::{Kind, Renderer};
use crate::render::header;
use crate::{params, Frame, RenderError, RenderOptions};
use sdfc_ir::Program;
use sdfc_wgsl::interp::encode::{encode, Bytecode};
use sdfc_wgsl::interp::frame::frame_data;

impl Renderer {
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
        let params = params::values(program, &opts.params)?;
        params::check_time(opts.time)?;
        let (gx, gy) = self.check_size(opts.width, opts.height, opts.aovs)?;
        let wgsl = sdfc_wgsl::interp::shader().map_err(|f| match f {
            sdfc_wgsl::Failure::Internal { report, .. } => RenderError::Emit(report),
            sdfc_wgsl::Failure::Diagnostics(d) => RenderError::Emit(format!(
                "{} diagnostic(s) while emitting the interpreter",
                d.len()
            )),
        })?;
        let data = frame_data(program, code, header(opts), &params);
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
        let pipeline = self.pipeline(Kind::Interpreted, wgsl)?;
        self.dispatch(
            &pipeline.pipeline,
            &self.interp_bind_layout,
            &data.uniform,
            &[
                ("sdfc bytecode", &data.code),
                ("sdfc scene data", &data.data),
            ],
            opts,
            (gx, gy),
        )
    }
}
