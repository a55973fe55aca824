//! The pipeline cache: each shader text built into a compute pipeline once, by whichever
//! thread asks first, without holding up builds of other texts.

use crate::device::{health, ErrorSink, Scopes};
use crate::serial::Serial;
use crate::RenderError;
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Which of the two shader interfaces a pipeline follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Kind {
    /// The render shader: entry `main`, the read-only frame + two read-write storage buffers.
    Render,
    /// The point-evaluation shader: entry `eval_main`, the read-only frame, the read-only
    /// points and the read-write distances.
    Eval,
    /// The interpreted marcher: the render interface plus the read-only bytecode and data.
    Interpreted,
    /// A render shader that reads its scene's union as data: the render interface plus the
    /// read-only data at binding 3 (`sdfc_wgsl::Compiled::data`).
    RenderData,
}

pub(crate) struct CachedPipeline {
    pub(crate) pipeline: wgpu::ComputePipeline,
    /// Whether the shader's entry point reads its dispatch's first tile from `frame.flags`
    /// (`sdfc_wgsl::screen::reads_first_tile`), so that part of the image may be dispatched:
    /// looked up once per text, not at every frame.
    pub(crate) tiled: bool,
    /// The pass that makes each block of pixels' candidates for its camera rays' lists
    /// (`blocks_main`, `shaders/instances_blocks.wgsl`), where a shader reading its union as
    /// data has it: run before each frame.
    pub(crate) blocks: Option<wgpu::ComputePipeline>,
}

/// The entry point of the blocks' pass, where a shader has one.
const BLOCKS_ENTRY: &str = "blocks_main";

/// One shader text's place in the pipeline cache. Its lock is held while the pipeline is
/// built, so a second thread asking for the same text waits for that build instead of
/// starting its own, while threads asking for other texts (the interpreter, say, while a
/// large scene builds in the background) go on.
struct Slot {
    kind: Kind,
    wgsl: String,
    built: Mutex<Option<Arc<CachedPipeline>>>,
}

/// The compiled pipelines of one device, by shader text. Nothing is evicted unless asked
/// ([`Pipelines::forget_scenes`]): a long live-editing session keeps one pipeline per version
/// of the scene it rendered.
pub(crate) struct Pipelines {
    device: wgpu::Device,
    sink: Arc<ErrorSink>,
    /// The pipeline layouts of [`Kind::Render`], [`Kind::Eval`], [`Kind::Interpreted`] and
    /// [`Kind::RenderData`].
    layouts: [wgpu::PipelineLayout; 4],
    slots: Mutex<HashMap<u64, Vec<Arc<Slot>>>>,
    compilations: AtomicUsize,
    serial: Serial,
}

impl Pipelines {
    pub(crate) fn new(
        device: wgpu::Device,
        sink: Arc<ErrorSink>,
        layouts: [wgpu::PipelineLayout; 4],
        serial: Serial,
    ) -> Pipelines {
        Pipelines {
            device,
            sink,
            layouts,
            slots: Mutex::new(HashMap::new()),
            compilations: AtomicUsize::new(0),
            serial,
        }
    }

    /// How many pipelines have been compiled (cache misses).
    pub(crate) fn compilations(&self) -> usize {
        self.compilations.load(Ordering::Relaxed)
    }

    /// Drops the cached pipelines of scenes (rendering and evaluation), keeping the
    /// interpreter's, which every scene shares. A build under way finishes for its asker.
    pub(crate) fn forget_scenes(&self) {
        let _serial = self.serial.hold();
        let mut cache = self.slots.lock().unwrap_or_else(|e| e.into_inner());
        cache.retain(|_, slots| {
            slots.retain(|s| s.kind == Kind::Interpreted);
            !slots.is_empty()
        });
    }

    /// The compute pipeline of `wgsl`, compiled on first use and cached by the text's hash.
    pub(crate) fn get(&self, kind: Kind, wgsl: &str) -> Result<Arc<CachedPipeline>, RenderError> {
        // Before the slot's lock: a thread holding the slot waits for no other's GL work.
        let _serial = self.serial.hold();
        health(&self.device, &self.sink)?;
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        kind.hash(&mut hasher);
        wgsl.hash(&mut hasher);
        let key = hasher.finish();
        let slot = {
            let mut cache = self
                .slots
                .lock()
                .map_err(|_| RenderError::Device("the pipeline cache is poisoned".into()))?;
            let slots = cache.entry(key).or_default();
            match slots.iter().find(|s| s.kind == kind && s.wgsl == wgsl) {
                Some(s) => s.clone(),
                None => {
                    let s = Arc::new(Slot {
                        kind,
                        wgsl: wgsl.to_string(),
                        built: Mutex::new(None),
                    });
                    slots.push(s.clone());
                    s
                }
            }
        };
        // A build that panicked poisons the lock but leaves `None`: the next asker builds.
        let mut built = slot.built.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(p) = built.as_ref() {
            return Ok(p.clone());
        }
        // Nothing built yet, or an earlier build failed: build it (again) here.
        let (pipeline, blocks) = self.build(kind, wgsl)?;
        let p = Arc::new(CachedPipeline {
            pipeline,
            tiled: sdfc_wgsl::screen::reads_first_tile(wgsl),
            blocks,
        });
        *built = Some(p.clone());
        Ok(p)
    }

    /// Compiles one compute pipeline, and the blocks' pass of a shader that reads its union
    /// as data and has one, their errors caught.
    fn build(
        &self,
        kind: Kind,
        wgsl: &str,
    ) -> Result<(wgpu::ComputePipeline, Option<wgpu::ComputePipeline>), RenderError> {
        let (layout, entry) = match kind {
            Kind::Render => (&self.layouts[0], "main"),
            Kind::Eval => (&self.layouts[1], "eval_main"),
            Kind::Interpreted => (&self.layouts[2], "main"),
            Kind::RenderData => (&self.layouts[3], "main"),
        };
        self.compilations.fetch_add(1, Ordering::Relaxed);
        let scopes = Scopes::push(&self.device);
        let built = std::panic::catch_unwind(AssertUnwindSafe(|| {
            let module = self
                .device
                .create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some("sdfc scene"),
                    source: wgpu::ShaderSource::Wgsl(wgsl.into()),
                });
            let info = pollster::block_on(module.get_compilation_info());
            let messages: Vec<(String, String)> = info
                .messages
                .iter()
                .filter(|m| m.message_type == wgpu::CompilationMessageType::Error)
                .map(|m| {
                    let text = match &m.location {
                        Some(l) => {
                            format!("{}:{}: {}", l.line_number, l.line_position, m.message)
                        }
                        None => m.message.clone(),
                    };
                    (m.message.clone(), text)
                })
                .collect();
            let create = |entry: &str| {
                self.device
                    .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                        label: Some("sdfc scene"),
                        layout: Some(layout),
                        module: &module,
                        entry_point: Some(entry),
                        compilation_options: Default::default(),
                        cache: None,
                    })
            };
            let pipeline = create(entry);
            let has_blocks = wgsl.contains(&format!("fn {BLOCKS_ENTRY}("));
            let blocks = (kind == Kind::RenderData && has_blocks).then(|| create(BLOCKS_ENTRY));
            ((pipeline, blocks), messages)
        }));
        let mut errors = scopes.pop();
        let pipeline = match built {
            Ok((pipeline, messages)) => {
                // The scopes usually caught the same message already.
                for (message, text) in messages {
                    if !errors.iter().any(|e| e.contains(message.trim())) {
                        errors.push(text);
                    }
                }
                pipeline
            }
            Err(panic) => {
                let what = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "a panic in wgpu".into());
                return Err(RenderError::Shader(what));
            }
        };
        health(&self.device, &self.sink).map_err(|e| RenderError::Shader(e.to_string()))?;
        if !errors.is_empty() {
            return Err(RenderError::Shader(errors.join("; ")));
        }
        Ok(pipeline)
    }
}
