//! `eval_gpu`: the scene distance at a list of points, through the emitted WGSL.

use crate::device::{Renderer, Scopes};
use crate::pipelines::Kind;
use crate::render::{read_bytes, readback, storage, upload};
use crate::{params, RenderError};
use sdfc_ir::Program;

/// The evaluation shader's workgroup size.
const GROUP: u64 = 64;
/// Bytes per point (a `vec4<f32>`).
const POINT_BYTES: u64 = 16;

impl Renderer {
    /// Evaluates the scene distance at each point on the device, with `params` overriding the
    /// defaults (as in [`crate::RenderOptions::params`]). Large point sets run in batches of at
    /// most 65 535 workgroups (and within the device's buffer limits).
    pub fn eval_gpu(
        &self,
        program: &Program,
        points: &[[f32; 3]],
        time: f32,
        params: &[(String, Vec<f32>)],
    ) -> Result<Vec<f32>, RenderError> {
        let _serial = self.serial.hold();
        let values = params::values(program, params)?;
        params::check_time(time)?;
        self.check_health()?;
        let wgsl = sdfc_wgsl::eval_shader::eval_shader(program).map_err(|f| match f {
            sdfc_wgsl::Failure::Internal { report, .. } => RenderError::Emit(report),
            // Neither happens here: the program was lowered, the options are fixed.
            f => RenderError::Emit(format!("while emitting the evaluation shader: {f}")),
        })?;
        let pipeline = self.pipeline(Kind::Eval, &wgsl)?;
        let max_groups = (self.limits.max_compute_workgroups_per_dimension as u64).min(65_535);
        let batch = (max_groups * GROUP)
            .min(self.max_buffer_bytes() / POINT_BYTES)
            .max(1) as usize;
        let mut out = Vec::with_capacity(points.len());
        for chunk in points.chunks(batch) {
            let scopes = Scopes::push(&self.device);
            let count = chunk.len() as u64;
            let frame = upload(
                self,
                "sdfc eval frame",
                &params::frame_bytes([chunk.len() as u32, time.to_bits(), 0, 0], &values),
                wgpu::BufferUsages::STORAGE,
            );
            let mut point_bytes = Vec::with_capacity(chunk.len() * POINT_BYTES as usize);
            for p in chunk {
                for c in [p[0], p[1], p[2], 0.0] {
                    point_bytes.extend_from_slice(&c.to_le_bytes());
                }
            }
            let input = upload(
                self,
                "sdfc eval points",
                &point_bytes,
                wgpu::BufferUsages::STORAGE,
            );
            let output = storage(&self.device, "sdfc eval out", 4 * count);
            let read = readback(&self.device, "sdfc eval read", 4 * count);
            let bind = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("sdfc eval bindings"),
                layout: &self.eval_bind_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: frame.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: input.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: output.as_entire_binding(),
                    },
                ],
            });
            let mut encoder = self
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("sdfc eval"),
                });
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("sdfc eval"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(&pipeline.pipeline);
                pass.set_bind_group(0, &bind, &[]);
                pass.dispatch_workgroups(count.div_ceil(GROUP) as u32, 1, 1);
            }
            encoder.copy_buffer_to_buffer(&output, 0, &read, 0, 4 * count);
            self.queue.submit([encoder.finish()]);
            let mapped = self.map_and_wait(&[&read]);
            self.finish(scopes.pop())?;
            mapped?;
            let bytes = read_bytes(&read)?;
            out.extend(
                bytes
                    .chunks_exact(4)
                    .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            );
        }
        Ok(out)
    }
}
