//! What to emit, and the check of the options that the caller (not the scene) gets wrong.

/// What to emit.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Only the scene functions, no entry point (`sdfc compile --lib`). Such WGSL cannot be
    /// rendered: `sdfc_render` refuses it.
    pub lib: bool,
    /// A naga_oil `#define_import_path` for the library form: identifiers joined by `::`
    /// ([`check_import_path`]); only with `lib`.
    pub import_path: Option<String>,
    /// Bounding-box early-outs in large unions (`sdfc compile --cull`); the distances are the
    /// same near the surface, and a lower bound far from every part of the union. Off by
    /// default until it is measured to win on a device (docs/performance.md).
    pub cull: bool,
    /// A root union of many instances (a primitive with constant arguments under constant
    /// moves, turns and uniform scales) emitted as data, walked by one loop over a hierarchy
    /// of their boxes (`sdfc render --instances`): the shader then reads the buffer
    /// [`crate::Compiled::data`] at binding 3. Ignored where the scene has no such union
    /// (`sdfc_ir::instances`); only for the full shader. Off by default: on lavapipe it wins
    /// from about a thousand shapes (docs/performance.md, "Large unions as data").
    pub instances: bool,
}

impl Options {
    /// Whether the options make sense together; the reason, if not.
    pub fn check(&self) -> Result<(), String> {
        if self.instances && self.lib {
            return Err(
                "instances are emitted as data for the full shader: the library form has no buffer to read them from"
                    .into(),
            );
        }
        match (&self.import_path, self.lib) {
            (Some(_), false) => Err("an import path is for the library form: set `lib` too".into()),
            (Some(path), true) => check_import_path(path),
            (None, _) => Ok(()),
        }
    }
}

/// A naga_oil module path: identifiers joined by `::` (`my_scene`, `scenes::city`). Anything
/// else would make the first line of a validated module something naga_oil cannot read (a
/// newline in it would even start WGSL that naga never saw).
pub fn check_import_path(path: &str) -> Result<(), String> {
    let ident = |w: &str| {
        let mut c = w.chars();
        c.next()
            .is_some_and(|f| f.is_ascii_alphabetic() || f == '_')
            && c.all(|c| c.is_ascii_alphanumeric() || c == '_')
            && w != "_"
    };
    if path.split("::").all(ident) {
        Ok(())
    } else {
        Err(format!(
            "the import path `{}` is not identifiers joined by `::` (e.g. `my_scene` or `scenes::city`)",
            path.escape_debug()
        ))
    }
}
