//! The renderer's errors.

use std::fmt;
use std::path::PathBuf;

/// Why a render, an evaluation or a write failed. Never a panic.
#[derive(Clone, Debug, PartialEq)]
pub enum RenderError {
    /// No adapter could run the renderer; says what was tried.
    NoAdapter(String),
    /// `SDFC_BACKEND` holds a value other than `vulkan`, `gl` or `auto`.
    BadBackend(String),
    /// The device could not be opened, or reported an error while working (validation,
    /// out of memory, internal).
    Device(String),
    /// The device was lost (driver reset, removed GPU); a new [`crate::Renderer`] is needed.
    DeviceLost(String),
    /// The device rejected a shader: a bug in sdfc or in the driver, not in the scene.
    Shader(String),
    /// The point-evaluation shader could not be emitted (an internal compiler error).
    Emit(String),
    /// The image is empty, or too large for this device's buffers or dispatch limits.
    ImageSize(String),
    /// A param override or the time is wrong (unknown name, wrong number of components,
    /// not finite): a problem in the user's input.
    Param(String),
    /// An output file could not be written.
    Output {
        /// The file.
        path: PathBuf,
        /// Why (the operating system's or the encoder's words).
        message: String,
    },
    /// An AOV was asked of a frame rendered without them.
    NoAovs,
    /// The scene was compiled in the library form (`sdfc_wgsl::Options::lib`): scene
    /// functions without an entry point, for the caller's own shaders. Compile it without
    /// `lib` to render it.
    LibraryForm,
    /// The interpreted marcher cannot run the scene: beyond its limits (an input error,
    /// like a setting above its documented limit) or an operation it has no opcode for.
    Interpreter(sdfc_wgsl::interp::encode::EncodeError),
}

impl RenderError {
    /// True where the user's input is at fault (params, a library-form scene), false for
    /// environment problems (device, image sizes, files) and bugs.
    pub fn is_input_error(&self) -> bool {
        matches!(
            self,
            RenderError::Param(_)
                | RenderError::LibraryForm
                | RenderError::Interpreter(sdfc_wgsl::interp::encode::EncodeError::TooLarge(_))
        )
    }
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::NoAdapter(s) => write!(f, "no usable graphics adapter: {s}"),
            RenderError::BadBackend(s) => write!(
                f,
                "SDFC_BACKEND is `{s}`; it may be `vulkan`, `gl` or `auto` (or unset)"
            ),
            RenderError::Device(s) => write!(f, "device error: {s}"),
            RenderError::DeviceLost(s) => write!(f, "the device was lost: {s}"),
            RenderError::Shader(s) => write!(
                f,
                "the device rejected the shader (a bug in sdfc or the driver, not in the scene): {s}"
            ),
            RenderError::Emit(s) => write!(f, "internal compiler error: {s}"),
            RenderError::ImageSize(s) => f.write_str(s),
            RenderError::Param(s) => f.write_str(s),
            RenderError::Output { path, message } => {
                write!(f, "cannot write {}: {message}", path.display())
            }
            RenderError::NoAovs => f.write_str("the frame was rendered without AOVs"),
            RenderError::LibraryForm => f.write_str(
                "the scene was compiled as a library (`lib`), which has no entry point to \
                 render; compile it without `lib`",
            ),
            RenderError::Interpreter(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for RenderError {}
