//! The per-frame inputs (binding 0, read-only storage): a 16-byte header and one `vec4<f32>`
//! per param.

use crate::RenderError;
use sdfc_ir::Program;

/// The scene's params in declaration order, defaults overridden by `overrides`.
pub(crate) fn values(
    program: &Program,
    overrides: &[(String, Vec<f32>)],
) -> Result<Vec<[f32; 4]>, RenderError> {
    let decls = &program.scene.params;
    let mut out: Vec<[f32; 4]> = decls
        .iter()
        .map(|p| {
            let mut v = [0.0; 4];
            for (slot, c) in v.iter_mut().zip(p.default.comps()) {
                *slot = c;
            }
            v
        })
        .collect();
    for (name, value) in overrides {
        let Some(i) = decls.iter().position(|p| &p.name == name) else {
            let known: Vec<&str> = decls.iter().map(|p| p.name.as_str()).collect();
            return Err(RenderError::Param(if known.is_empty() {
                format!("the scene has no param `{name}` (it declares none)")
            } else {
                format!(
                    "the scene has no param `{name}` (its params: {})",
                    known.join(", ")
                )
            }));
        };
        let width = decls[i].ty.width();
        if value.len() != width {
            return Err(RenderError::Param(format!(
                "param `{name}` takes {width} number(s), found {}",
                value.len()
            )));
        }
        if value.iter().any(|c| !c.is_finite()) {
            return Err(RenderError::Param(format!(
                "param `{name}` must be finite, found {value:?}"
            )));
        }
        let wide: Vec<f64> = value.iter().map(|&c| c as f64).collect();
        sdfc_ir::scene::limits::check_param_magnitude(name, &wide).map_err(RenderError::Param)?;
        let mut v = [0.0; 4];
        v[..width].copy_from_slice(value);
        out[i] = v;
    }
    Ok(out)
}

/// The frame buffer's bytes: the header words, then the params.
pub(crate) fn frame_bytes(header: [u32; 4], params: &[[f32; 4]]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(16 + 16 * params.len());
    for w in header {
        bytes.extend_from_slice(&w.to_le_bytes());
    }
    for p in params {
        for c in p {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    bytes
}

pub(crate) fn check_time(time: f32) -> Result<(), RenderError> {
    if time.is_finite() {
        Ok(())
    } else {
        Err(RenderError::Param(format!(
            "the time must be finite, found {time}"
        )))
    }
}
