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
    /// When a root union of many instances (a primitive with constant arguments under
    /// constant moves, turns and uniform scales) is emitted as data, walked by one loop over
    /// a hierarchy of their boxes (`sdfc render --instances`): the shader then reads the
    /// buffer [`crate::Compiled::data`] at binding 3. Never where the scene has no such
    /// union (`sdfc_ir::instances`); only for the full shader. By default from
    /// [`AUTO_INSTANCES`] instances up ([`Instances::Auto`]).
    pub instances: Instances,
}

/// When a root union of instances is emitted as data ([`Options::instances`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Instances {
    /// Where the union has [`AUTO_INSTANCES`] or more instances, no more than [`AUTO_CROWD`]
    /// of whose boxes hold one point, the full shader is emitted and `cull` is not asked for.
    #[default]
    Auto,
    /// Wherever the root is a union of instances (`sdfc_ir::instances::MIN_CHILDREN` or
    /// more): `sdfc render --instances`. Not with `lib`.
    Always,
    /// Never: the union stays code (`sdfc render --no-instances`).
    Never,
}

/// The size from which [`Instances::Auto`] reads a union as data. The data form's pipeline is
/// the same size whatever the count (0.6 s to build on lavapipe), the code's grows with the
/// shapes on every driver measured (lavapipe 1.4 s for 300 shapes, the H200 3.4 s, both more
/// than a minute for 5 000), and with its rays' lists the data form draws faster (the
/// 300-shape grid 3.7x to 5.5x on lavapipe, the same marcher). `sdfc render` at its default
/// 512x512 on lavapipe, Mesa's cache off, took as long either way at 80 shapes and was 1.06x
/// to 1.4x faster as data from 100 to 120 (2026-12-07; at stop 33 the two met at 130 to 160,
/// before the data form's frames got faster), and with the cache warm the data form was 1.4x
/// to 1.6x faster at 100. docs/performance.md, "Data by default", "From 150 shapes" and
/// "From 100 shapes".
pub const AUTO_INSTANCES: usize = 100;

/// The most instances' boxes that may hold one point (`Instances::crowd_exceeds` in sdfc-ir)
/// for [`Instances::Auto`] to read a union as data: a ray's list holds as many
/// (`RAY_LIST` in `shaders/instances_rays.wgsl`), and a ray through a larger crowd walks the
/// whole hierarchy at every step there. 48 spheres about one point drew 30x slower as data
/// than as code on lavapipe (docs/performance.md, "Cheaper lists").
pub const AUTO_CROWD: usize = 32;

impl Options {
    /// The fewest instances these options read as data, or `None` for code.
    pub fn data_from(&self) -> Option<usize> {
        match self.instances {
            Instances::Always => Some(sdfc_ir::instances::MIN_CHILDREN),
            Instances::Auto if !self.lib && !self.cull => Some(AUTO_INSTANCES),
            Instances::Auto | Instances::Never => None,
        }
    }

    /// The most instances' boxes holding one point with which these options read a union
    /// as data: [`AUTO_CROWD`] by default, any when data is asked for.
    pub fn crowd_limit(&self) -> Option<usize> {
        (self.instances == Instances::Auto).then_some(AUTO_CROWD)
    }

    /// Whether the options make sense together; the reason, if not.
    pub fn check(&self) -> Result<(), String> {
        if self.instances == Instances::Always && self.lib {
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
