//! The value types of the IR.

use std::fmt;

/// The type of an IR value. `Vec4` and `Mat3` are internal (materials, rotations); users
/// see floats, vec2, vec3 and booleans.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Ty {
    F32,
    Vec2,
    Vec3,
    Vec4,
    Bool,
    Mat3,
}

impl Ty {
    /// Number of float components (0 for bool).
    pub fn width(self) -> usize {
        match self {
            Ty::F32 => 1,
            Ty::Vec2 => 2,
            Ty::Vec3 => 3,
            Ty::Vec4 => 4,
            Ty::Mat3 => 9,
            Ty::Bool => 0,
        }
    }

    /// The float vector type of `n` components (1 is `F32`).
    pub fn vec(n: usize) -> Option<Ty> {
        match n {
            1 => Some(Ty::F32),
            2 => Some(Ty::Vec2),
            3 => Some(Ty::Vec3),
            4 => Some(Ty::Vec4),
            _ => None,
        }
    }

    pub fn is_float_like(self) -> bool {
        matches!(self, Ty::F32 | Ty::Vec2 | Ty::Vec3 | Ty::Vec4)
    }

    /// The name users see in diagnostics.
    pub fn user_name(self) -> &'static str {
        match self {
            Ty::F32 => "a number",
            Ty::Vec2 => "a vec2",
            Ty::Vec3 => "a vec3",
            Ty::Vec4 => "a vec4",
            Ty::Bool => "a boolean",
            Ty::Mat3 => "a 3x3 matrix",
        }
    }
}

impl fmt::Display for Ty {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Ty::F32 => "f32",
            Ty::Vec2 => "vec2",
            Ty::Vec3 => "vec3",
            Ty::Vec4 => "vec4",
            Ty::Bool => "bool",
            Ty::Mat3 => "mat3",
        })
    }
}
