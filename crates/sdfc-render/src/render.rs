//! One frame: frame buffer, dispatch, readback.

use crate::device::{Renderer, Scopes};
use crate::pipelines::Kind;
use crate::{params, tiles, Aovs, Frame, RenderError, RenderOptions};
use sdfc_ir::Program;
use sdfc_wgsl::Compiled;
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Bytes per pixel of the colour buffer (one packed `u32`) and of the AOV buffer (two `vec4`).
const COLOR_BYTES: u64 = 4;
const AOV_BYTES: u64 = 32;
/// The blocks' pass (`shaders/instances_blocks.wgsl`): a block's side in pixels, the bytes of
/// its slot (`BLOCK_VEC4S` vec4s) and the bit of `frame.flags` that says the pass ran.
const BLOCK: u32 = 4;
const BLOCK_SLOT_BYTES: u64 = 5 * 16;
const BLOCKS_FLAG: u32 = 2;
/// The fewest 8x8 tiles a frame's dispatch covers for the blocks' pass to run: on lavapipe
/// the second dispatch costs about 0.1 ms whatever its size, and the 300-shape grid seen
/// from afar at 160x120 (a few dozen tiles) drew at 0.82x with it, at 320x240 1.15x
/// (docs/performance.md, "Each ray's list from its block's candidates").
const BLOCKS_MIN_TILES: u64 = 64;
/// The shader's workgroup size in x and y.
const GROUP: u32 = 8;

pub(crate) fn storage(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// A buffer holding `contents`. Written through the queue rather than mapped at creation:
/// wgpu's `create_buffer_init` panics when the device has been lost, this path reports an
/// error instead.
pub(crate) fn upload(
    r: &Renderer,
    label: &str,
    contents: &[u8],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let size = (contents.len() as u64).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
    let buffer = r.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(wgpu::COPY_BUFFER_ALIGNMENT),
        usage: usage | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut bytes = contents.to_vec();
    bytes.resize(size as usize, 0);
    r.queue.write_buffer(&buffer, 0, &bytes);
    buffer
}

pub(crate) fn readback(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Timestamp queries around a compute pass.
pub(crate) struct Timer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    pub(crate) read: wgpu::Buffer,
}

impl Timer {
    pub(crate) fn new(r: &Renderer) -> Option<Timer> {
        if !r.timestamps {
            return None;
        }
        let queries = r.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("sdfc timer"),
            ty: wgpu::QueryType::Timestamp,
            count: 2,
        });
        let resolve = r.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sdfc timer resolve"),
            size: 16,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let read = readback(&r.device, "sdfc timer read", 16);
        Some(Timer {
            queries,
            resolve,
            read,
        })
    }

    pub(crate) fn writes(&self) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        }
    }

    pub(crate) fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.queries, 0..2, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.read, 0, 16);
    }

    /// The pass's duration, once `read` is mapped.
    pub(crate) fn elapsed(&self, r: &Renderer) -> Option<Duration> {
        let view = self.read.get_mapped_range(..).ok()?;
        let begin = u64::from_le_bytes(view[0..8].try_into().ok()?);
        let end = u64::from_le_bytes(view[8..16].try_into().ok()?);
        drop(view);
        self.read.unmap();
        let ns = end.checked_sub(begin)? as f64 * r.queue.get_timestamp_period() as f64;
        (ns.is_finite() && ns >= 0.0).then(|| Duration::from_nanos(ns as u64))
    }
}

/// The bytes of the AOVs' buffer before any blocks' slots: the AOVs where they are written,
/// else 32 (a buffer may not be empty), where `block_base` in the shader starts the slots.
fn aov_bytes(opts: &RenderOptions) -> u64 {
    if opts.aovs {
        opts.width as u64 * opts.height as u64 * AOV_BYTES
    } else {
        32
    }
}

/// The bytes of the blocks' slots for an image (one slot a block of 4x4 pixels).
fn block_slots(opts: &RenderOptions) -> u64 {
    let across = opts.width.div_ceil(BLOCK) as u64;
    let down = opts.height.div_ceil(BLOCK) as u64;
    across * down * BLOCK_SLOT_BYTES
}

/// A frame's compute passes: the march over the image, and before it the pass that makes
/// each block of pixels' candidates for a union read as data, where it runs.
pub(crate) struct Passes<'a> {
    pub(crate) march: &'a wgpu::ComputePipeline,
    pub(crate) blocks: Option<&'a wgpu::ComputePipeline>,
}

/// The data a shader reads at binding 3, if it reads any (`sdfc_wgsl::Compiled::data`).
pub(crate) fn as_data(data: &[u8]) -> Option<&[u8]> {
    (!data.is_empty()).then_some(data)
}

impl Renderer {
    /// Renders a compiled scene (the whole shader: not the library form), with its union's
    /// data where it was emitted as data (`sdfc_wgsl::Options::instances`). Blocks until the
    /// pixels are back on the CPU.
    pub fn render(&self, scene: &Compiled, opts: &RenderOptions) -> Result<Frame, RenderError> {
        if scene.is_library() {
            return Err(RenderError::LibraryForm);
        }
        self.render_text(scene.program(), &scene.wgsl, as_data(&scene.data), opts)
    }

    /// Renders `wgsl`, a full shader emitted for `program` (the program gives the params'
    /// layout and defaults) that reads no data.
    pub fn render_wgsl(
        &self,
        program: &Program,
        wgsl: &str,
        opts: &RenderOptions,
    ) -> Result<Frame, RenderError> {
        self.render_text(program, wgsl, None, opts)
    }

    /// Renders `wgsl` as [`Renderer::render_wgsl`] does, with `data` bound as read-only
    /// storage at binding 3 where it is not empty, as [`Renderer::render`] binds a scene's:
    /// what `sdfc_wgsl::emit_validated_with_data` returns for a program whose settings were
    /// changed (`sdfc bench`), or an experiment's shader that reads its scene from a buffer
    /// (`scripts/bvh-experiment.py`, the `compare_shader` example).
    pub fn render_wgsl_with_data(
        &self,
        program: &Program,
        wgsl: &str,
        data: &[u8],
        opts: &RenderOptions,
    ) -> Result<Frame, RenderError> {
        self.render_text(program, wgsl, as_data(data), opts)
    }

    /// [`Renderer::render_wgsl`], with `data` at binding 3 where there is some.
    pub(crate) fn render_text(
        &self,
        program: &Program,
        wgsl: &str,
        data: Option<&[u8]>,
        opts: &RenderOptions,
    ) -> Result<Frame, RenderError> {
        // Held from the build to the end of the frame, the pipeline's last use (on GL).
        let _serial = self.serial.hold();
        let params = params::values(program, &opts.params)?;
        params::check_time(opts.time)?;
        // A lost device fails at once, before a pipeline is built on it.
        self.check_health()?;
        let (gx, gy) = self.check_size(opts.width, opts.height, opts.aovs)?;
        let (kind, layout, inputs) = match data {
            None => (Kind::Render, &self.render_bind_layout, vec![]),
            Some(data) => {
                if data.len() as u64 > self.max_buffer_bytes() {
                    return Err(RenderError::Device(format!(
                        "the scene's data needs {} KiB in one buffer, and this device allows {} KiB",
                        data.len() >> 10,
                        self.max_buffer_bytes() >> 10
                    )));
                }
                (
                    Kind::RenderData,
                    &self.data_bind_layout,
                    vec![("sdfc scene data", data)],
                )
            }
        };
        let pipeline = self.pipeline(kind, wgsl)?;
        // Only the tiles whose rays can meet the scene's bounds, where that is known.
        let plan = tiles::Dispatch::plan(program, pipeline.tiled, opts, (gx, gy));
        // The blocks' pass where the frame is large enough to pay for a second dispatch.
        let (tx, ty) = plan.groups;
        // And where its slots fit in the AOVs' buffer (else every ray walks, as before).
        let blocks = pipeline.blocks.as_ref().filter(|_| {
            tx as u64 * ty as u64 >= BLOCKS_MIN_TILES
                && aov_bytes(opts) + block_slots(opts) <= self.max_buffer_bytes()
        });
        let mut header = plan.header;
        if blocks.is_some() {
            // Bit 1: the blocks' candidates are made before the frame.
            header[3] |= BLOCKS_FLAG;
        }
        let frame = params::frame_bytes(header, &params);
        let passes = Passes {
            march: &pipeline.pipeline,
            blocks,
        };
        let mut out = self.dispatch(passes, layout, &frame, &inputs, opts, plan.groups)?;
        plan.finish(&mut out);
        Ok(out)
    }

    /// Runs a render-interface pipeline over the image and reads the results back: the
    /// frame buffer at binding 0 (read-only storage), colour and AOVs at 1 and 2, `inputs`
    /// (read-only storage) from binding 3 on. `blocks`, the pass that makes each block of
    /// 4x4 pixels' candidates for a union read as data (`shaders/instances_blocks.wgsl`), runs
    /// first over the same tiles, its slots after the AOVs in the buffer at binding 2.
    pub(crate) fn dispatch(
        &self,
        passes: Passes,
        layout: &wgpu::BindGroupLayout,
        frame_bytes: &[u8],
        inputs: &[(&str, &[u8])],
        opts: &RenderOptions,
        (gx, gy): (u32, u32),
    ) -> Result<Frame, RenderError> {
        let Passes { march, blocks } = passes;
        // A lost device fails at once, before any work is recorded on it.
        self.check_health()?;
        let pixels = opts.width as u64 * opts.height as u64;
        let color_size = pixels * COLOR_BYTES;
        let aov_size = aov_bytes(opts);
        // `render_text` runs the blocks' pass only where its slots fit beside the AOVs.
        let slots = blocks.map_or(0, |_| block_slots(opts));

        let scopes = Scopes::push(&self.device);
        let frame = upload(self, "sdfc frame", frame_bytes, wgpu::BufferUsages::STORAGE);
        let input_buffers: Vec<wgpu::Buffer> = inputs
            .iter()
            .map(|(label, bytes)| upload(self, label, bytes, wgpu::BufferUsages::STORAGE))
            .collect();
        let color = storage(&self.device, "sdfc colour", color_size);
        let aov = storage(&self.device, "sdfc aovs", aov_size + slots);
        let color_read = readback(&self.device, "sdfc colour read", color_size);
        let aov_read = opts
            .aovs
            .then(|| readback(&self.device, "sdfc aovs read", aov_size));
        let timer = Timer::new(self);
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: 0,
                resource: frame.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: color.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: aov.as_entire_binding(),
            },
        ];
        for (i, b) in input_buffers.iter().enumerate() {
            entries.push(wgpu::BindGroupEntry {
                binding: 3 + i as u32,
                resource: b.as_entire_binding(),
            });
        }
        let bind = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sdfc frame bindings"),
            layout,
            entries: &entries,
        });
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("sdfc render"),
            });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("sdfc march"),
                timestamp_writes: timer.as_ref().map(|t| t.writes()),
            });
            pass.set_bind_group(0, &bind, &[]);
            if let Some(blocks) = blocks {
                // One invocation a block, 8x8 blocks a workgroup: 4x4 of the frame's tiles.
                pass.set_pipeline(blocks);
                pass.dispatch_workgroups(gx.div_ceil(4), gy.div_ceil(4), 1);
            }
            pass.set_pipeline(march);
            pass.dispatch_workgroups(gx, gy, 1);
        }
        encoder.copy_buffer_to_buffer(&color, 0, &color_read, 0, color_size);
        if let Some(read) = &aov_read {
            encoder.copy_buffer_to_buffer(&aov, 0, read, 0, aov_size);
        }
        if let Some(t) = &timer {
            t.resolve(&mut encoder);
        }
        let start = Instant::now();
        self.queue.submit([encoder.finish()]);
        let mut to_map = vec![&color_read];
        to_map.extend(aov_read.as_ref());
        to_map.extend(timer.as_ref().map(|t| &t.read));
        let mapped = self.map_and_wait(&to_map);
        let wall_time = start.elapsed();
        self.finish(scopes.pop())?;
        mapped?;

        let rgba = read_bytes(&color_read)?;
        let aovs = match &aov_read {
            Some(read) => Some(decode_aovs(&read_bytes(read)?)),
            None => None,
        };
        let device_time = timer.as_ref().and_then(|t| t.elapsed(self));
        Ok(Frame {
            width: opts.width,
            height: opts.height,
            rgba,
            aovs,
            device_time,
            wall_time,
        })
    }

    /// Checks an image size against the device's limits; returns the dispatch size.
    pub(crate) fn check_size(
        &self,
        width: u32,
        height: u32,
        aovs: bool,
    ) -> Result<(u32, u32), RenderError> {
        if width == 0 || height == 0 {
            return Err(RenderError::ImageSize(format!(
                "the image size {width}x{height} is empty"
            )));
        }
        let (gx, gy) = (width.div_ceil(GROUP), height.div_ceil(GROUP));
        let max_groups = self.limits.max_compute_workgroups_per_dimension;
        if gx > max_groups || gy > max_groups {
            return Err(RenderError::ImageSize(format!(
                "a {width}x{height} image is too large for this device: it allows at most \
                 {} pixels on a side",
                max_groups as u64 * GROUP as u64
            )));
        }
        let max = self.max_buffer_bytes();
        let per_pixel = if aovs { AOV_BYTES } else { COLOR_BYTES };
        let pixels = width as u64 * height as u64;
        if pixels * per_pixel > max {
            let side = ((max / per_pixel) as f64).sqrt() as u64;
            return Err(RenderError::ImageSize(format!(
                "a {width}x{height} image{} needs {} MiB in one buffer, and this device allows \
                 at most {} MiB (about {side}x{side} pixels)",
                if aovs { " with AOVs" } else { "" },
                (pixels * per_pixel).div_ceil(1 << 20),
                max >> 20
            )));
        }
        Ok((gx, gy))
    }

    /// Maps each buffer for reading and waits until all are mapped (or failed).
    ///
    /// With threads sharing the device, another thread's poll may be the one that runs our
    /// callbacks, a moment after our own poll returns: so wait for the callbacks themselves,
    /// polling again now and then, until each has reported.
    pub(crate) fn map_and_wait(&self, buffers: &[&wgpu::Buffer]) -> Result<(), RenderError> {
        let (tx, rx) = mpsc::channel();
        for (i, b) in buffers.iter().enumerate() {
            let tx = tx.clone();
            b.map_async(wgpu::MapMode::Read, .., move |r| {
                let _ = tx.send((i, r));
            });
        }
        drop(tx);
        let mut done = 0;
        while done < buffers.len() {
            self.device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| RenderError::Device(format!("waiting for the device: {e}")))?;
            match rx.recv_timeout(Duration::from_millis(50)) {
                Ok((i, r)) => {
                    r.map_err(|e| RenderError::Device(format!("reading back buffer {i}: {e}")))?;
                    done += 1;
                }
                Err(mpsc::RecvTimeoutError::Timeout) => self.check_health()?,
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    self.check_health()?;
                    return Err(RenderError::Device(
                        "the device dropped a read-back without finishing it".into(),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// The contents of a mapped buffer; unmaps it.
pub(crate) fn read_bytes(buffer: &wgpu::Buffer) -> Result<Vec<u8>, RenderError> {
    let view = buffer
        .get_mapped_range(..)
        .map_err(|e| RenderError::Device(format!("reading back a buffer: {e}")))?;
    let bytes = view.to_vec();
    drop(view);
    buffer.unmap();
    Ok(bytes)
}

/// The frame header both render interfaces start with: size, time, flags (bit 0: AOVs).
pub(crate) fn header(opts: &RenderOptions) -> [u32; 4] {
    [
        opts.width,
        opts.height,
        opts.time.to_bits(),
        u32::from(opts.aovs),
    ]
}

/// `(normal, depth), (steps, 0, 0, 0)` per pixel; depth -1 means a miss.
fn decode_aovs(bytes: &[u8]) -> Aovs {
    let f = |b: &[u8]| f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    let n = bytes.len() / AOV_BYTES as usize;
    let mut aovs = Aovs {
        depth: Vec::with_capacity(n),
        normal: Vec::with_capacity(n),
        steps: Vec::with_capacity(n),
    };
    for px in bytes.chunks_exact(AOV_BYTES as usize) {
        let d = f(&px[12..16]);
        if d < 0.0 {
            aovs.depth.push(f32::INFINITY);
            aovs.normal.push([0.0; 3]);
        } else {
            aovs.depth.push(d);
            aovs.normal
                .push([f(&px[0..4]), f(&px[4..8]), f(&px[8..12])]);
        }
        aovs.steps.push(f(&px[16..20]));
    }
    aovs
}
