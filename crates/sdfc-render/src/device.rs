//! Opening the device, catching its errors, and the pipeline cache.

use crate::pipelines::{CachedPipeline, Kind, Pipelines};
use crate::serial::Serial;
use crate::RenderError;
use std::fmt;
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};

/// Which adapter a [`Renderer`] runs on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AdapterDescription {
    /// The adapter's name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// `Vulkan`, `Gl`, ...
    pub backend: String,
    /// `DiscreteGpu`, `IntegratedGpu`, `VirtualGpu`, `Cpu` or `Other`.
    pub device_type: String,
    /// Driver name and version, where the backend reports them.
    pub driver: String,
    /// True for a CPU (software) adapter.
    pub software: bool,
}

impl fmt::Display for AdapterDescription {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({}, {}", self.name, self.backend, self.device_type)?;
        if !self.driver.is_empty() {
            write!(f, ", {}", self.driver)?;
        }
        f.write_str(")")
    }
}

/// Errors nobody's error scope caught, and device loss, as reported by wgpu's callbacks.
#[derive(Default)]
pub(crate) struct ErrorSink {
    uncaptured: Mutex<Vec<String>>,
    lost: Mutex<Option<String>>,
    /// Set while the renderer is dropped, when wgpu reports the device `Destroyed` as a
    /// matter of course; a `Destroyed` at any other time is a loss like any other.
    dropping: std::sync::atomic::AtomicBool,
}

/// A wgpu device ready to render compiled scenes and evaluate them at points.
///
/// `Renderer` is `Send + Sync`: threads may share one (each call pushes its own error scopes).
/// A clone is cheap and works on the same device, with the same pipeline cache; the device
/// is closed when the last clone (or background build) is dropped.
#[derive(Clone)]
pub struct Renderer(Arc<Shared>);

/// What the clones of a [`Renderer`] share. Public only in name (this module is private, and
/// every field is the crate's), so that `Renderer` can deref to it.
#[doc(hidden)]
pub struct Shared {
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    pub(crate) limits: wgpu::Limits,
    pub(crate) timestamps: bool,
    description: AdapterDescription,
    pub(crate) render_bind_layout: wgpu::BindGroupLayout,
    pub(crate) eval_bind_layout: wgpu::BindGroupLayout,
    pub(crate) interp_bind_layout: wgpu::BindGroupLayout,
    /// [`Kind::RenderData`]'s.
    pub(crate) data_bind_layout: wgpu::BindGroupLayout,
    pub(crate) pipelines: Pipelines,
    /// Whether an interpreted frame has been drawn by each of the interpreter's variants
    /// (`Variant::Code`, `Variant::Walk`): its pipeline is then ready to run at once (see
    /// [`Renderer::warm_interpreter`]).
    pub(crate) interpreter_warm: [std::sync::atomic::AtomicBool; 2],
    /// Threads working on the device in the background (the interpreter's warm-up), for
    /// [`Renderer::wait_for_background_work`].
    pub(crate) background: Mutex<Vec<std::thread::JoinHandle<()>>>,
    sink: Arc<ErrorSink>,
    /// Whether work on this device waits for other threads' (a GL device; `serial.rs`).
    pub(crate) serial: Serial,
}

/// Mesa's device-select layer, an implicit Vulkan layer, connects to the Wayland display to
/// learn the desktop's GPU; on a machine without a session (no `XDG_RUNTIME_DIR`: CI, SSH,
/// containers) libwayland then prints "error: XDG_RUNTIME_DIR is invalid or not set in the
/// environment." twice on every run, which reads as the program's own error. The renderer
/// ranks the adapters itself (see the crate's "The device"), so the layer adds nothing: this
/// switches it off (`NODEVICE_SELECT=1`) where there is no session and the user has not
/// chosen (nor asked the layer for a device: `MESA_VK_DEVICE_SELECT`, `DRI_PRIME`).
///
/// # Safety
///
/// It sets an environment variable, which is undefined behaviour on most platforms while
/// another thread may read or write the environment (`std::env::set_var`). Call it first
/// thing in `main`, before any thread starts.
pub unsafe fn quiet_headless_vulkan() {
    let set = |v: &str| std::env::var_os(v).is_some();
    if ![
        "XDG_RUNTIME_DIR",
        "NODEVICE_SELECT",
        "MESA_VK_DEVICE_SELECT",
        "DRI_PRIME",
    ]
    .into_iter()
    .any(set)
    {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}

/// The backends `SDFC_BACKEND` allows.
fn backends_from_env() -> Result<wgpu::Backends, RenderError> {
    match std::env::var("SDFC_BACKEND") {
        Err(_) => Ok(wgpu::Backends::VULKAN | wgpu::Backends::GL),
        Ok(v) => match v.trim().to_ascii_lowercase().as_str() {
            "" | "auto" => Ok(wgpu::Backends::VULKAN | wgpu::Backends::GL),
            "vulkan" | "vk" => Ok(wgpu::Backends::VULKAN),
            "gl" | "gles" | "opengl" => Ok(wgpu::Backends::GL),
            _ => Err(RenderError::BadBackend(v)),
        },
    }
}

/// Lower is better: hardware first, then software Vulkan, then software GL.
fn rank(info: &wgpu::AdapterInfo) -> (u8, u8) {
    let vulkan = info.backend == wgpu::Backend::Vulkan;
    let kind = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu if vulkan => 3,
        wgpu::DeviceType::Other if vulkan => 4,
        wgpu::DeviceType::Cpu => 5,
        wgpu::DeviceType::Other => 6,
    };
    (kind, if vulkan { 0 } else { 1 })
}

fn describe(info: &wgpu::AdapterInfo) -> AdapterDescription {
    let driver = [info.driver.trim(), info.driver_info.trim()]
        .into_iter()
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join(" ");
    AdapterDescription {
        name: info.name.clone(),
        backend: format!("{:?}", info.backend),
        device_type: format!("{:?}", info.device_type),
        driver,
        software: info.device_type == wgpu::DeviceType::Cpu,
    }
}

fn buffer_entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// The bindings: the frame, storage (read-only where `read_only_input`), read-write storage,
/// and `extra_inputs` more read-only storage buffers. The frame is read-only storage, not a
/// uniform: lavapipe compiles a shader again at each new value of a uniform its branches
/// read (docs/performance.md).
fn layouts(
    device: &wgpu::Device,
    read_only_input: bool,
    extra_inputs: u32,
) -> (wgpu::BindGroupLayout, wgpu::PipelineLayout) {
    let mut entries = vec![
        buffer_entry(0, wgpu::BufferBindingType::Storage { read_only: true }),
        buffer_entry(
            1,
            wgpu::BufferBindingType::Storage {
                read_only: read_only_input,
            },
        ),
        buffer_entry(2, wgpu::BufferBindingType::Storage { read_only: false }),
    ];
    for i in 0..extra_inputs {
        entries.push(buffer_entry(
            3 + i,
            wgpu::BufferBindingType::Storage { read_only: true },
        ));
    }
    let bind = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("sdfc bindings"),
        entries: &entries,
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("sdfc layout"),
        bind_group_layouts: &[Some(&bind)],
        immediate_size: 0,
    });
    (bind, layout)
}

/// The error scopes around a piece of device work, popped innermost first.
pub(crate) struct Scopes(Vec<wgpu::ErrorScopeGuard>);

impl Scopes {
    pub(crate) fn push(device: &wgpu::Device) -> Scopes {
        Scopes(vec![
            device.push_error_scope(wgpu::ErrorFilter::Validation),
            device.push_error_scope(wgpu::ErrorFilter::OutOfMemory),
            device.push_error_scope(wgpu::ErrorFilter::Internal),
        ])
    }

    /// The errors the scopes caught, one message each.
    pub(crate) fn pop(mut self) -> Vec<String> {
        let mut errors = Vec::new();
        while let Some(scope) = self.0.pop() {
            if let Some(e) = pollster::block_on(scope.pop()) {
                errors.push(error_text(&e));
            }
        }
        errors
    }
}

/// A wgpu error with its chain of sources (the useful part is often in a source).
fn error_text(e: &wgpu::Error) -> String {
    use std::error::Error;
    let mut s = e.to_string();
    let mut source = e.source();
    while let Some(inner) = source {
        let t = inner.to_string();
        if !s.contains(&t) {
            s += ": ";
            s += &t;
        }
        source = inner.source();
    }
    s
}

/// Fails if `device` was lost or reported errors nobody's scope caught.
pub(crate) fn health(device: &wgpu::Device, sink: &ErrorSink) -> Result<(), RenderError> {
    // Let wgpu run its callbacks, the device-lost one among them, before looking.
    let _ = device.poll(wgpu::PollType::Poll);
    if let Some(l) = sink.lost.lock().ok().and_then(|l| l.clone()) {
        return Err(RenderError::DeviceLost(l));
    }
    let errors: Vec<String> = sink
        .uncaptured
        .lock()
        .map(|mut v| std::mem::take(&mut *v))
        .unwrap_or_default();
    if errors.is_empty() {
        Ok(())
    } else {
        Err(RenderError::Device(errors.join("; ")))
    }
}

impl Renderer {
    /// Opens the best device available (see the crate documentation for the order and
    /// `SDFC_BACKEND`).
    pub fn new() -> Result<Renderer, RenderError> {
        let backends = backends_from_env()?;
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends,
            flags: wgpu::InstanceFlags::empty().with_env(),
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let mut adapters = pollster::block_on(instance.enumerate_adapters(backends));
        adapters.sort_by_key(|a| rank(&a.get_info()));
        let mut tried = Vec::new();
        for adapter in adapters {
            let info = adapter.get_info();
            let compute = adapter
                .get_downlevel_capabilities()
                .flags
                .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS);
            if !compute {
                tried.push(format!(
                    "{} ({:?}): no compute shaders",
                    info.name, info.backend
                ));
                continue;
            }
            match Renderer::open(&adapter, &info) {
                Ok(r) => return Ok(r),
                Err(e) => tried.push(format!("{} ({:?}): {e}", info.name, info.backend)),
            }
        }
        let allowed = if backends == wgpu::Backends::GL {
            "GL (SDFC_BACKEND=gl)"
        } else if backends == wgpu::Backends::VULKAN {
            "Vulkan (SDFC_BACKEND=vulkan)"
        } else {
            "Vulkan and GL"
        };
        let mut msg = format!("none found among {allowed} adapters");
        if tried.is_empty() {
            msg += "; on a machine without a GPU install Mesa's software Vulkan \
                    (Debian/Ubuntu: apt-get install mesa-vulkan-drivers)";
        } else {
            msg += &format!(" ({})", tried.join("; "));
        }
        Err(RenderError::NoAdapter(msg))
    }

    fn open(adapter: &wgpu::Adapter, info: &wgpu::AdapterInfo) -> Result<Renderer, RenderError> {
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut required_features = if timestamps {
            wgpu::Features::TIMESTAMP_QUERY
        } else {
            wgpu::Features::empty()
        };
        // Subgroup operations where the device has them: sdfc's shaders use none, but the
        // coherent walk of `scripts/bvh-experiment.py --subgroup` does (docs/performance.md,
        // "Large unions as data").
        required_features |= adapter.features() & wgpu::Features::SUBGROUP;
        let limits = adapter.limits();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("sdfc"),
            required_features,
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| RenderError::Device(format!("cannot open the device: {e}")))?;
        let sink = Arc::new(ErrorSink::default());
        {
            let sink = sink.clone();
            device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
                if let Ok(mut v) = sink.uncaptured.lock() {
                    v.push(error_text(&e));
                }
            }));
        }
        {
            let sink = sink.clone();
            device.set_device_lost_callback(move |reason, message| {
                let dropping = sink.dropping.load(Ordering::Relaxed);
                if reason != wgpu::DeviceLostReason::Destroyed || !dropping {
                    if let Ok(mut l) = sink.lost.lock() {
                        // wgpu's message may be empty (a destroyed device): no dangling colon.
                        *l = Some(if message.trim().is_empty() {
                            format!("{reason:?}")
                        } else {
                            format!("{reason:?}: {message}")
                        });
                    }
                }
            });
        }
        let scopes = Scopes::push(&device);
        let (render_bind_layout, render_layout) = layouts(&device, false, 0);
        let (eval_bind_layout, eval_layout) = layouts(&device, true, 0);
        let (interp_bind_layout, interp_layout) = layouts(&device, false, 2);
        let (data_bind_layout, data_layout) = layouts(&device, false, 1);
        let errors = scopes.pop();
        if !errors.is_empty() {
            return Err(RenderError::Device(errors.join("; ")));
        }
        let device_handle = device.clone();
        let serial = Serial {
            gl: info.backend == wgpu::Backend::Gl,
        };
        Ok(Renderer(Arc::new(Shared {
            limits: device.limits(),
            device,
            queue,
            timestamps,
            description: describe(info),
            pipelines: Pipelines::new(
                device_handle,
                sink.clone(),
                [render_layout, eval_layout, interp_layout, data_layout],
                serial,
            ),
            render_bind_layout,
            eval_bind_layout,
            interp_bind_layout,
            data_bind_layout,
            interpreter_warm: Default::default(),
            background: Mutex::new(Vec::new()),
            sink,
            serial,
        })))
    }

    /// Waits until the work this renderer started in the background (the interpreter's
    /// warm-up) is done. A program calls this before it exits, so that no thread is inside
    /// the driver while the process ends.
    pub fn wait_for_background_work(&self) {
        loop {
            let handles: Vec<_> = match self.background.lock() {
                Ok(mut h) => std::mem::take(&mut *h),
                Err(_) => return,
            };
            if handles.is_empty() {
                return;
            }
            for h in handles {
                let _ = h.join();
            }
        }
    }

    /// Keeps a background thread's handle for [`Renderer::wait_for_background_work`],
    /// dropping those of threads that have finished (a long live-editing session starts
    /// threads without end).
    pub(crate) fn keep_in_background(&self, handle: std::thread::JoinHandle<()>) {
        if let Ok(mut background) = self.background.lock() {
            background.retain(|h| !h.is_finished());
            background.push(handle);
        }
    }

    /// The adapter in use: name, backend, device type, driver.
    pub fn adapter_description(&self) -> &AdapterDescription {
        &self.description
    }

    /// Frees the compiled pipelines of the scenes rendered so far (a live editor that has
    /// moved on from old versions calls it); the interpreter's stays. The cache keeps every
    /// pipeline until then, so that re-rendering a scene or changing a param never
    /// recompiles. Rendering a forgotten scene again compiles it again.
    pub fn forget_scene_pipelines(&self) {
        let _serial = self.serial.hold();
        self.pipelines.forget_scenes();
    }

    /// How many compute pipelines this renderer has compiled (cache misses).
    pub fn pipeline_compilations(&self) -> usize {
        self.pipelines.compilations()
    }

    /// Whether the device times its work with timestamp queries ([`crate::Frame::device_time`]).
    pub fn has_timestamps(&self) -> bool {
        self.timestamps
    }

    /// The largest storage buffer one binding may hold, in bytes.
    pub fn max_buffer_bytes(&self) -> u64 {
        self.limits
            .max_storage_buffer_binding_size
            .min(self.limits.max_buffer_size)
    }

    /// Destroys the device now, as a driver reset or a removed GPU would: every later call
    /// on this renderer fails with [`RenderError::DeviceLost`] (a new `Renderer` is needed).
    /// It exists so that tests and embedders can exercise their lost-device path.
    pub fn lose_device(&self) {
        let _serial = self.serial.hold();
        self.device.destroy();
    }

    /// Fails if the device was lost or reported errors nobody's scope caught.
    pub(crate) fn check_health(&self) -> Result<(), RenderError> {
        let _serial = self.serial.hold();
        health(&self.device, &self.sink)
    }

    /// Turns the errors of a piece of device work into a result.
    pub(crate) fn finish(&self, errors: Vec<String>) -> Result<(), RenderError> {
        self.check_health()?;
        if errors.is_empty() {
            Ok(())
        } else {
            Err(RenderError::Device(errors.join("; ")))
        }
    }

    /// The compute pipeline of `wgsl`, compiled on first use and cached by the text's hash.
    pub(crate) fn pipeline(
        &self,
        kind: Kind,
        wgsl: &str,
    ) -> Result<Arc<CachedPipeline>, RenderError> {
        self.pipelines.get(kind, wgsl)
    }
}

#[doc(hidden)]
impl std::ops::Deref for Renderer {
    type Target = Shared;

    fn deref(&self) -> &Shared {
        &self.0
    }
}

impl Drop for Shared {
    fn drop(&mut self) {
        self.sink.dropping.store(true, Ordering::Relaxed);
    }
}
