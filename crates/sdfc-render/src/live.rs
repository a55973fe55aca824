//! `render_live`: a first picture as soon as possible. While the scene's specialised shader is
//! emitted, validated and built into a pipeline on another thread, the interpreted marcher
//! (one fixed shader, already built for an earlier scene or cached by the driver) draws a
//! preview; then the specialised shader draws the final frame.

use crate::device::Renderer;
use crate::render::as_data;
use crate::{params, Aovs, Frame, RenderError, RenderOptions};
use sdfc_ir::Program;
use sdfc_wgsl::interp::encode::{encode, Bytecode};
use sdfc_wgsl::interp::encode_instances::encode_as_data;
use sdfc_wgsl::interp::frame::preview_settings;
use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

/// How often a live render asks whether it is superseded while it waits.
const POLL: Duration = Duration::from_millis(10);

/// The preview's default scale: a quarter of the width and height on a GPU, an eighth on a
/// CPU device.
const PREVIEW_SCALE: u32 = 4;
const SOFTWARE_PREVIEW_SCALE: u32 = 8;

/// Which shader drew a frame of [`Renderer::render_live`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Drawn {
    /// The interpreted marcher's preview.
    Interpreted,
    /// The scene's specialised shader: the final frame.
    Specialised,
}

/// How [`Renderer::render_live`] goes about it.
#[derive(Clone, Debug)]
pub struct LiveOptions {
    /// When the clock starts (when the scene file was read, say): the times of the
    /// [`LiveReport`] are measured from it.
    pub start: Instant,
    /// How long to wait for the specialised pipeline before the interpreter draws a preview:
    /// zero by default, since the preview is small (see `preview_scale`) and the first
    /// picture is what the live path is for. On a CPU device the preview is drawn only once
    /// the interpreter is warm. [`Duration::MAX`] never draws one.
    pub grace: Duration,
    /// The preview is drawn at `1 / preview_scale` of the width and height (rounded up) and
    /// enlarged to the full size, nearest pixel, so that it costs little next to the final
    /// frame. 1 draws it at full size. `None` chooses by device: 4 on a GPU, 8 on a CPU device
    /// (whose one queue runs the preview and the final frame one after the other, where the
    /// interpreter is 20 to 250 times slower than the specialised shader).
    pub preview_scale: Option<u32>,
    /// How the specialised shader is emitted (`cull`; `instances`, its union as data).
    pub emit: sdfc_wgsl::Options,
    /// The program the interpreter draws the preview from, where it is not the one
    /// specialised: the scene lowered with culling (`sdfc_wgsl::lower_live`), whose bytecode
    /// jumps over the parts of a large union a step does not need. `None`: the same program.
    pub preview: Option<Arc<Program>>,
}

impl Default for LiveOptions {
    /// The clock started now, no grace, the preview's scale chosen by device.
    fn default() -> LiveOptions {
        LiveOptions {
            start: Instant::now(),
            grace: Duration::ZERO,
            preview_scale: None,
            emit: sdfc_wgsl::Options::default(),
            preview: None,
        }
    }
}

impl LiveOptions {
    /// The preview's scale on `r`'s device: [`LiveOptions::preview_scale`] (at least 1), or
    /// the device's default.
    pub fn preview_scale_on(&self, r: &Renderer) -> u32 {
        self.preview_scale
            .unwrap_or(if r.adapter_description().software {
                SOFTWARE_PREVIEW_SCALE
            } else {
                PREVIEW_SCALE
            })
            .max(1)
    }
}

/// When each picture of a live render came, measured from [`LiveOptions::start`].
#[derive(Clone, Debug)]
pub struct LiveReport {
    /// The interpreted preview, when one was drawn: until its pixels were on the CPU.
    pub interpreted: Option<Duration>,
    /// Pixels of the preview (before it was enlarged) whose code the device's loop budget
    /// cut short, so that they show arbitrary colours: at most a tenth of them, else no
    /// preview is drawn (lavapipe and llvmpipe; never on a GPU).
    pub preview_cut: usize,
    /// Whether the preview's bytecode walked the scene's root union read as data
    /// (`encode_as_data`: a union of 16 or more constant shapes), not the union as code.
    pub preview_as_data: bool,
    /// Why no preview was drawn although the specialised pipeline was late: the scene is
    /// beyond the interpreter's limits, say.
    pub preview_skipped: Option<String>,
    /// Until the specialised shader started to be emitted (the scene was lowered before the
    /// call, and the device opened).
    pub build_started: Duration,
    /// Until the specialised pipeline was ready (WGSL emitted, validated, pipeline built).
    pub pipeline_ready: Duration,
    /// The specialised frame: until its pixels were on the CPU.
    pub specialised: Duration,
    /// The specialised shader's WGSL.
    pub wgsl: String,
}

impl LiveReport {
    /// Until the first picture, whichever shader drew it.
    pub fn first_pixel(&self) -> Duration {
        self.interpreted
            .map_or(self.specialised, |i| i.min(self.specialised))
    }
}

impl Renderer {
    /// Renders `program` twice over: the interpreted marcher draws a preview if the
    /// specialised pipeline is not ready within the grace period, then the specialised shader
    /// draws the final frame, which is returned. `on_frame` sees each frame as it comes (the
    /// preview at full size). Errors in the params, the time or the size come before any
    /// work; a preview the interpreter cannot draw is skipped, with the reason in the report.
    /// On a CPU device with no grace and the interpreter warm, the preview is drawn before
    /// the pipeline's build starts rather than beside it: they would share the cores.
    pub fn render_live(
        &self,
        program: &Program,
        opts: &RenderOptions,
        live: &LiveOptions,
        on_frame: impl FnMut(Drawn, &Frame),
    ) -> Result<(Frame, LiveReport), RenderError> {
        self.render_live_until(program, opts, live, || false, on_frame)?
            .ok_or_else(|| RenderError::Device("a live render gave up unasked".into()))
    }

    /// As [`Renderer::render_live`], giving up as soon as `superseded` says so (it is asked
    /// every few milliseconds while the pipeline builds, and before each frame): then
    /// `Ok(None)` comes back at once. A live editor passes "the scene has changed again". A
    /// pipeline build already begun goes on, on its own thread, into the cache, where a later
    /// render of the same scene finds it; one not yet begun is skipped.
    pub fn render_live_until(
        &self,
        program: &Program,
        opts: &RenderOptions,
        live: &LiveOptions,
        superseded: impl Fn() -> bool,
        mut on_frame: impl FnMut(Drawn, &Frame),
    ) -> Result<Option<(Frame, LiveReport)>, RenderError> {
        params::values(program, &opts.params)?;
        params::check_time(opts.time)?;
        self.check_size(opts.width, opts.height, opts.aovs)?;
        let (mut interpreted, mut preview_skipped) = (None, None);
        let mut preview_cut = 0;
        let mut preview_as_data = false;
        let previewed = live.preview.as_deref().unwrap_or(program);
        // On a CPU device the pipeline's builder and the preview share the cores: emitting,
        // validating and building a large scene's pipeline slowed the preview it is meant to
        // precede (docs/performance.md). Where the preview is due at once (no grace) and the
        // interpreter is warm, it is drawn here first, and the build starts after it.
        let preview_first = self.adapter_description().software
            && live.grace.is_zero()
            && self.interpreter_is_warm();
        if preview_first {
            if superseded() {
                return Ok(None);
            }
            let drawn = match self.interpreter_for(program, previewed) {
                Err(why) => Err(why),
                Ok((code, from)) => {
                    preview_as_data = !code.instances.is_empty();
                    self.draw_preview(from, &code, opts, live, &mut on_frame)?
                }
            };
            match drawn {
                Ok((at, cut)) => (interpreted, preview_cut) = (Some(at), cut),
                Err(why) => preview_skipped = Some(why),
            }
        }
        let build_started = live.start.elapsed();
        let (tx, rx) = mpsc::channel();
        // Set when this render gives up: the builder then skips the pipeline build if it
        // has not begun it (a burst of edits would otherwise build every version).
        let abandoned = Arc::new(AtomicBool::new(false));
        self.specialise_in_background(program, live, tx.clone(), abandoned.clone())?;
        // `None`: never (a grace of `Duration::MAX`, or the preview already drawn).
        let preview_at = Instant::now()
            .checked_add(live.grace)
            .filter(|_| !preview_first);
        // Only the builder holds a sender where no preview is to come, so that its end
        // without a word is seen.
        let mut tx = preview_at.map(|_| tx);
        let mut code = None;
        let (built, pipeline_ready) = loop {
            if superseded() {
                abandoned.store(true, Ordering::Relaxed);
                return Ok(None);
            }
            // The interpreter starts as soon as the grace is over, not a poll later.
            let now = Instant::now();
            if let Some(tx) = tx.take_if(|_| preview_at.is_some_and(|at| now >= at)) {
                match self.interpreter_for(program, previewed) {
                    Err(why) => preview_skipped = Some(why),
                    Ok(c) => {
                        code = Some(c);
                        // On a thread of its own (at once, if the interpreter is warm
                        // already): when the specialised pipeline is ready first, the final
                        // frame does not wait for it.
                        self.warm_interpreter_in_background(move |r| {
                            let _ = tx.send(Event::Interpreter(r));
                        });
                    }
                }
            }
            let wait = match (&tx, preview_at) {
                (Some(_), Some(at)) => at.saturating_duration_since(now).min(POLL),
                _ => POLL,
            };
            match rx.recv_timeout(wait) {
                Ok(Event::Specialised(built, at)) => {
                    if code.is_some() && interpreted.is_none() && preview_skipped.is_none() {
                        preview_skipped = Some(
                            "the specialised pipeline was ready before the interpreter".into(),
                        );
                    }
                    break (built, at);
                }
                Ok(Event::Interpreter(Ok(()))) => {
                    let Some((code, from)) = &code else { continue };
                    preview_as_data = !code.instances.is_empty();
                    if superseded() {
                        abandoned.store(true, Ordering::Relaxed);
                        return Ok(None);
                    }
                    match self.draw_preview(from, code, opts, live, &mut on_frame)? {
                        Ok((at, cut)) => (interpreted, preview_cut) = (Some(at), cut),
                        Err(why) => preview_skipped = Some(why),
                    }
                }
                Ok(Event::Interpreter(Err(e))) => {
                    preview_skipped = Some(format!("the interpreter could not be warmed: {e}"));
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => return Err(builder_died()),
            }
        };
        let (wgsl, data) = built?;
        if superseded() {
            return Ok(None);
        }
        let frame = self.render_text(program, &wgsl, as_data(&data), opts)?;
        let specialised = live.start.elapsed();
        on_frame(Drawn::Specialised, &frame);
        Ok(Some((
            frame,
            LiveReport {
                interpreted,
                preview_cut,
                preview_as_data: preview_as_data && interpreted.is_some(),
                preview_skipped,
                build_started,
                pipeline_ready,
                specialised,
                wgsl,
            },
        )))
    }

    /// Emits, validates and builds the specialised pipeline on a thread of its own, which
    /// owns a copy of the program and of the renderer (a superseded live render does not wait
    /// for it), and reports on `done`.
    fn specialise_in_background(
        &self,
        program: &Program,
        live: &LiveOptions,
        done: mpsc::Sender<Event>,
        abandoned: Arc<AtomicBool>,
    ) -> Result<(), RenderError> {
        let (renderer, program, emit, start) =
            (self.clone(), program.clone(), live.emit.clone(), live.start);
        let handle = std::thread::Builder::new()
            .name("sdfc-pipeline".into())
            .spawn(move || {
                // A panic here (a bug) becomes an error, never the caller's panic.
                let built = std::panic::catch_unwind(AssertUnwindSafe(|| {
                    renderer.specialise(&program, &emit, &abandoned)
                }))
                .unwrap_or_else(|_| {
                    Err(RenderError::Emit(
                        "building the specialised pipeline panicked".into(),
                    ))
                });
                let _ = done.send(Event::Specialised(built, start.elapsed()));
            })
            .map_err(|e| RenderError::Device(format!("cannot start a thread: {e}")))?;
        self.keep_in_background(handle);
        Ok(())
    }

    /// Emits and validates the specialised shader (with its union as data where `emit` asks
    /// for `instances`) and builds its pipeline (into the cache), unless the render was
    /// `abandoned` by then.
    fn specialise(
        &self,
        program: &Program,
        emit: &sdfc_wgsl::Options,
        abandoned: &AtomicBool,
    ) -> Result<(String, Vec<u8>), RenderError> {
        let emit = sdfc_wgsl::Options {
            lib: false,
            import_path: None,
            ..emit.clone()
        };
        // On the compiler's stack, which deep scenes need, as `sdfc_wgsl::compile` runs.
        let emitted =
            sdfc_wgsl::on_compiler_stack(|| sdfc_wgsl::emit_validated_with_data(program, &emit));
        let (wgsl, data) = emitted.map_err(|f| match f {
            sdfc_wgsl::Failure::Internal { report, wgsl } if wgsl.is_empty() => {
                RenderError::Emit(report)
            }
            sdfc_wgsl::Failure::Internal { report, wgsl } => RenderError::Emit(format!(
                "the WGSL emitted for the scene is invalid (a bug in sdfc):\n{report}\n\
                 --- emitted WGSL ---\n{wgsl}"
            )),
            // Neither happens here: the program was lowered, the options are fixed.
            f => RenderError::Emit(format!("while emitting the scene: {f}")),
        })?;
        if abandoned.load(Ordering::Relaxed) {
            return Ok((wgsl, data));
        }
        // One pixel: lavapipe compiles machine code at a pipeline's first dispatch, and this
        // way that happens here, before the pipeline is called ready.
        self.render_text(program, &wgsl, as_data(&data), &RenderOptions::sized(1, 1))?;
        Ok((wgsl, data))
    }

    /// The scene's bytecode, or why the interpreter does not draw a preview: the scene is
    /// beyond its limits, or this is a CPU device where it is not yet warm. There its first
    /// frame compiles it on the device's one queue thread, for seconds (20 s on lavapipe
    /// without Mesa's disk cache), and the specialised frame would wait behind it.
    ///
    /// A root union of instances is encoded as data (`encode_as_data`, from `program`): the
    /// walk's bytecode does not grow with the shapes, and costs what the shapes near each
    /// ray cost. Any other scene is encoded from `previewed`. Returns the program the
    /// bytecode was encoded from.
    fn interpreter_for<'a>(
        &self,
        program: &'a Program,
        previewed: &'a Program,
    ) -> Result<(Bytecode, &'a Program), String> {
        let code = match encode_as_data(program) {
            Some(Ok(code)) => (code, program),
            _ => (encode(previewed).map_err(|e| e.to_string())?, previewed),
        };
        if self.adapter_description().software && !self.interpreter_is_warm() {
            return Err(if self.serial.gl {
                // `sdfc render --live --watch` does not warm it there (`serial.rs`).
                "on a CPU device the interpreter draws previews only once it is warm, and on \
                 the GL backend, whose one context serves one thread at a time, it is not \
                 warmed for previews"
                    .into()
            } else {
                "on a CPU device the interpreter draws previews only once it is warm \
                 (`Renderer::warm_interpreter`; `sdfc render --live --watch` warms it after \
                 its first frame)"
                    .into()
            });
        }
        Ok(code)
    }

    /// Draws the preview and hands it to `on_frame`: when it was drawn and how many of its
    /// pixels were cut short, or why it was not drawn. A lost device ends the render;
    /// anything else (the bytecode beyond the device's buffers, say) only costs the preview.
    fn draw_preview(
        &self,
        previewed: &Program,
        code: &Bytecode,
        opts: &RenderOptions,
        live: &LiveOptions,
        on_frame: &mut impl FnMut(Drawn, &Frame),
    ) -> Result<Result<(Duration, usize), String>, RenderError> {
        match self.preview(previewed, code, opts, live) {
            Ok((frame, cut)) => {
                let at = live.start.elapsed();
                on_frame(Drawn::Interpreted, &frame);
                Ok(Ok((at, cut)))
            }
            Err(e @ RenderError::DeviceLost(_)) => Err(e),
            Err(e) => Ok(Err(e.to_string())),
        }
    }

    /// The interpreted frame at `1 / preview_scale` of the size, enlarged back to it, in
    /// direct light only (`preview_settings`: no shadows, ambient occlusion, reflections or
    /// antialiasing, which multiply the distance evaluations per pixel).
    fn preview(
        &self,
        program: &Program,
        code: &Bytecode,
        opts: &RenderOptions,
        live: &LiveOptions,
    ) -> Result<(Frame, usize), RenderError> {
        let scale = live.preview_scale_on(self);
        let small = RenderOptions {
            width: opts.width.div_ceil(scale),
            height: opts.height.div_ceil(scale),
            ..opts.clone()
        };
        let settings = preview_settings(&program.scene.render);
        let (frame, cut) = self.render_bytecode_cut(program, &settings, code, &small, 1)?;
        // Pixels the device's loop budget cut short (lavapipe) show arbitrary colours: a
        // preview with a few is still a preview (the final frame replaces it); one with
        // more than a tenth of them is not, and the second pipeline that would draw it
        // again would hold the final frame up.
        if cut * 10 > frame.rgba.len() / 4 {
            return Err(self.cut_short(cut, &small, program, code, false));
        }
        Ok((enlarge(&frame, opts.width, opts.height, scale), cut))
    }
}

/// What the threads of a live render report.
enum Event {
    /// The specialised shader's WGSL (its pipeline in the cache) or why not, and when.
    Specialised(Result<(String, Vec<u8>), RenderError>, Duration),
    /// The interpreter's pipeline is in the cache, or why not.
    Interpreter(Result<(), RenderError>),
}

fn builder_died() -> RenderError {
    RenderError::Device("the thread building the specialised pipeline stopped".into())
}

/// `frame` enlarged `scale` times, nearest pixel, and cropped to `width x height`: each
/// pixel of the result is the one of `frame` it lies in.
pub(crate) fn enlarge(frame: &Frame, width: u32, height: u32, scale: u32) -> Frame {
    let src = |x: u32, y: u32| (y / scale) as usize * frame.width as usize + (x / scale) as usize;
    let n = width as usize * height as usize;
    let mut rgba = Vec::with_capacity(4 * n);
    let mut index = Vec::with_capacity(n);
    for y in 0..height {
        for x in 0..width {
            let i = src(x, y);
            rgba.extend_from_slice(&frame.rgba[4 * i..4 * i + 4]);
            index.push(i);
        }
    }
    let aovs = frame.aovs.as_ref().map(|a| Aovs {
        depth: index.iter().map(|&i| a.depth[i]).collect(),
        normal: index.iter().map(|&i| a.normal[i]).collect(),
        steps: index.iter().map(|&i| a.steps[i]).collect(),
    });
    Frame {
        width,
        height,
        rgba,
        aovs,
        device_time: frame.device_time,
        wall_time: frame.wall_time,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enlarging_repeats_each_pixel_and_crops() {
        // A 2x2 frame, pixels numbered 0..4 in red, enlarged 3 times into 5x4.
        let frame = Frame {
            width: 2,
            height: 2,
            rgba: (0..4u8).flat_map(|i| [i, 0, 0, 255]).collect(),
            aovs: Some(Aovs {
                depth: vec![1.0, 2.0, 3.0, f32::INFINITY],
                normal: vec![[1.0, 0.0, 0.0]; 4],
                steps: vec![10.0, 20.0, 30.0, 40.0],
            }),
            device_time: None,
            wall_time: Duration::ZERO,
        };
        let big = enlarge(&frame, 5, 4, 3);
        assert_eq!((big.width, big.height), (5, 4));
        let reds: Vec<u8> = (0..4)
            .flat_map(|y| (0..5).map(move |x| (x, y)))
            .map(|(x, y)| big.pixel(x, y).unwrap()[0])
            .collect();
        assert_eq!(
            reds,
            [0, 0, 0, 1, 1, 0, 0, 0, 1, 1, 0, 0, 0, 1, 1, 2, 2, 2, 3, 3]
        );
        let aovs = big.aovs.unwrap();
        assert_eq!(aovs.depth[19], f32::INFINITY);
        assert_eq!(aovs.steps[15], 30.0);
        assert_eq!(aovs.depth.len(), 20);
    }
}
