//! Writing frames: PNG for colour; OpenEXR and NumPy `.npy` for the float AOVs.
//!
//! - PNG: 8-bit RGBA, as rendered.
//! - OpenEXR: 32-bit float channels, ZIP compression (lossless, so every float, `inf`
//!   included, reads back bit for bit). Depth is one channel `Z`, steps one channel `Y`, the
//!   normal three channels `R`, `G`, `B` (x, y, z), so viewers show it as a normal map.
//! - NumPy `.npy` (format version 1.0): little-endian `<f4`, C order, shape `(H, W)` for depth
//!   and steps, `(H, W, 3)` for the normal. `numpy.load` reads it.

use crate::{Frame, RenderError};
use std::path::Path;
use std::str::FromStr;

/// One of the per-pixel float outputs of [`crate::Aovs`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AovKind {
    /// t along the ray, `inf` on a miss.
    Depth,
    /// World-space normal, 0 on a miss.
    Normal,
    /// March steps.
    Steps,
}

impl FromStr for AovKind {
    type Err = String;
    fn from_str(s: &str) -> Result<AovKind, String> {
        match s {
            "depth" => Ok(AovKind::Depth),
            "normal" => Ok(AovKind::Normal),
            "steps" => Ok(AovKind::Steps),
            _ => Err(format!("unknown AOV `{s}`: use depth, normal or steps")),
        }
    }
}

impl AovKind {
    /// Components per pixel.
    pub fn channels(self) -> usize {
        match self {
            AovKind::Normal => 3,
            _ => 1,
        }
    }

    /// The AOV's values, pixel by pixel with the components of a pixel together.
    pub fn values(self, frame: &Frame) -> Result<Vec<f32>, RenderError> {
        let aovs = frame.aovs.as_ref().ok_or(RenderError::NoAovs)?;
        Ok(match self {
            AovKind::Depth => aovs.depth.clone(),
            AovKind::Steps => aovs.steps.clone(),
            AovKind::Normal => aovs.normal.iter().flatten().copied().collect(),
        })
    }
}

/// The float file formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FloatFormat {
    /// OpenEXR, 32-bit float channels, ZIP-compressed.
    Exr,
    /// NumPy's `.npy`, little-endian `f32`, shape `(height, width)` or `(height, width, 3)`.
    Npy,
}

impl FloatFormat {
    /// The format a file name's extension asks for (`.exr` or `.npy`, any case).
    pub fn from_path(path: &Path) -> Option<FloatFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "exr" => Some(FloatFormat::Exr),
            "npy" => Some(FloatFormat::Npy),
            _ => None,
        }
    }
}

fn output_error(path: &Path, message: impl ToString) -> RenderError {
    RenderError::Output {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}

/// Writes the frame's colour as an RGBA PNG. A frame whose `rgba` does not hold
/// `4 * width * height` bytes (its fields are public) is refused, not written.
pub fn write_png(path: impl AsRef<Path>, frame: &Frame) -> Result<(), RenderError> {
    let path = path.as_ref();
    if Some(frame.rgba.len()) != frame.byte_len() {
        return Err(output_error(
            path,
            "the frame's RGBA bytes do not match its width and height",
        ));
    }
    image::save_buffer_with_format(
        path,
        &frame.rgba,
        frame.width,
        frame.height,
        image::ExtendedColorType::Rgba8,
        image::ImageFormat::Png,
    )
    .map_err(|e| output_error(path, e))
}

/// Writes one AOV in the format the path's extension names (`.exr` or `.npy`).
pub fn write_aov(path: impl AsRef<Path>, frame: &Frame, kind: AovKind) -> Result<(), RenderError> {
    let path = path.as_ref();
    let values = kind.values(frame)?;
    let (w, h) = (frame.width as usize, frame.height as usize);
    match FloatFormat::from_path(path) {
        Some(FloatFormat::Npy) => {
            let shape: &[usize] = match kind.channels() {
                1 => &[h, w],
                c => &[h, w, c],
            };
            write_npy(path, shape, &values)
        }
        Some(FloatFormat::Exr) => {
            let channels: Vec<(&str, Vec<f32>)> = match kind {
                AovKind::Depth => vec![("Z", values)],
                AovKind::Steps => vec![("Y", values)],
                AovKind::Normal => ["R", "G", "B"]
                    .iter()
                    .enumerate()
                    .map(|(c, name)| (*name, values.iter().skip(c).step_by(3).copied().collect()))
                    .collect(),
            };
            write_exr(path, frame.width, frame.height, &channels)
        }
        None => Err(output_error(
            path,
            "AOVs are float images: the file name must end in .exr or .npy",
        )),
    }
}

/// The bytes of a `.npy` file (format 1.0) holding `data` as little-endian f32 of `shape`.
pub fn npy_bytes(shape: &[usize], data: &[f32]) -> Vec<u8> {
    let dims = match shape {
        [n] => format!("{n},"),
        _ => shape
            .iter()
            .map(|d| d.to_string())
            .collect::<Vec<_>>()
            .join(", "),
    };
    let mut header = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': ({dims}), }}");
    // Magic (6) + version (2) + header length (2) + header, padded with spaces and ended
    // by a newline to a multiple of 64 bytes.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len() + 4 * data.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    for v in data {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// Writes `data` (C order) of `shape` as a `.npy` file.
pub fn write_npy(path: impl AsRef<Path>, shape: &[usize], data: &[f32]) -> Result<(), RenderError> {
    let path = path.as_ref();
    if shape.iter().product::<usize>() != data.len() {
        return Err(output_error(path, "the shape does not match the data"));
    }
    std::fs::write(path, npy_bytes(shape, data)).map_err(|e| output_error(path, e))
}

/// Writes float channels of a `width x height` image (row-major, top row first) as OpenEXR
/// with lossless ZIP compression.
pub fn write_exr(
    path: impl AsRef<Path>,
    width: u32,
    height: u32,
    channels: &[(&str, Vec<f32>)],
) -> Result<(), RenderError> {
    use exr::prelude::*;
    let path = path.as_ref();
    let size = (width as usize, height as usize);
    if channels.iter().any(|(_, v)| v.len() != size.0 * size.1) {
        return Err(output_error(
            path,
            "a channel does not match the image size",
        ));
    }
    let list: SmallVec<[AnyChannel<FlatSamples>; 4]> = channels
        .iter()
        .map(|(name, v)| AnyChannel::new(*name, FlatSamples::F32(v.clone())))
        .collect();
    let layer = Layer::new(
        size,
        LayerAttributes::default(),
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(list),
    );
    Image::from_layer(layer)
        .write()
        .to_file(path)
        .map_err(|e| output_error(path, e))
}
