//! The operations of the scalar SSA level: arithmetic, WGSL built-ins and distance helpers.

use crate::value::Const;

/// One operation of the expression DAG. Arguments live in the node, not here, so that
/// `(Op, args)` is the hash-consing key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Op {
    Const(Const),
    /// The point a function is evaluated at (`p: vec3<f32>`).
    Point,
    /// The unit direction of the ray being marched (`rd: vec3<f32>`); only in
    /// `scene_distance_ray`, whose bound-only nodes divide by their slope along it.
    Ray,
    /// A runtime `param`, by index; its type is the node's.
    Param(u16),
    /// Seconds, from the frame uniform.
    Time,
    /// In a culled union's group function: the caller's best distance so far, an upper bound
    /// above which the group's exact value is not needed (`to_ssa/cull.rs`). A group whose
    /// graph reads it takes it as a parameter; where it is not known it is [`NO_BEST`].
    Best,
    /// A lambda's parameter, replaced by a real value when the lambda is applied.
    LambdaArg {
        lambda: u32,
        index: u8,
    },
    Neg,
    Add,
    Sub,
    Mul,
    Div,
    /// Floored modulo, `a - b * floor(a / b)`, as GLSL `mod`.
    Mod,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    /// `[if_false, if_true, cond]`, as WGSL `select`.
    Select,
    Builtin(Builtin),
    /// Builds a vector from scalars (2 to 4 arguments).
    MakeVec,
    Swizzle(Swizzle),
    /// A 3x3 matrix from three column vectors.
    MakeMat3,
    /// `mat * mat` or `mat * vec`, by the argument types.
    MatMul,
    Transpose,
    Helper(Helper),
    /// Result `result` of group function `func` of the program (see `Program::groups`),
    /// called with the point; calls with equal arguments are one call in WGSL.
    Call {
        func: u32,
        result: u8,
    },
}

impl Op {
    /// Whether the node is an input of its function (the point, the ray, a param, time, the
    /// caller's best distance, a lambda's argument, a group call's result): its value comes
    /// from outside the graph, not from its arguments, so no pass may fold or differentiate
    /// it as arithmetic. Passes whose match has a catch-all arm ask this, so a new input is
    /// added here once (the exhaustive matches of `eval::apply` and `diff::rules` list them,
    /// and the compiler names any they miss).
    pub fn is_input(self) -> bool {
        matches!(
            self,
            Op::Point
                | Op::Ray
                | Op::Param(_)
                | Op::Time
                | Op::Best
                | Op::LambdaArg { .. }
                | Op::Call { .. }
        )
    }
}

/// The value of [`Op::Best`] where no caller bounds the group (the interpreter, gradient
/// functions): finite, so that it stays an ordinary number, and above any real distance.
pub const NO_BEST: f32 = 3.0e38;

/// Component selection, `.x` to `.zyx`; `idx[..len]` are the components.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Swizzle {
    pub len: u8,
    pub idx: [u8; 4],
}

impl Swizzle {
    pub fn new(idx: &[u8]) -> Swizzle {
        let mut a = [0u8; 4];
        a[..idx.len()].copy_from_slice(idx);
        Swizzle {
            len: idx.len() as u8,
            idx: a,
        }
    }

    pub fn indices(&self) -> &[u8] {
        &self.idx[..self.len as usize]
    }

    /// `xzy`-style letters.
    pub fn letters(&self) -> String {
        self.indices()
            .iter()
            .map(|&i| ['x', 'y', 'z', 'w'][i as usize])
            .collect()
    }
}

macro_rules! builtins {
    ($($variant:ident => $name:literal, $arity:literal;)*) => {
        /// WGSL built-in functions, with their WGSL meaning.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Builtin { $($variant),* }

        impl Builtin {
            /// Every built-in, for lookups and suggestions.
            pub const ALL: &'static [Builtin] = &[$(Builtin::$variant),*];

            /// The WGSL (and scene-language) name.
            pub fn name(self) -> &'static str {
                match self { $(Builtin::$variant => $name),* }
            }

            pub fn arity(self) -> usize {
                match self { $(Builtin::$variant => $arity),* }
            }
        }
    };
}

builtins! {
    Abs => "abs", 1;
    Sign => "sign", 1;
    Floor => "floor", 1;
    Ceil => "ceil", 1;
    Fract => "fract", 1;
    Round => "round", 1;
    Sqrt => "sqrt", 1;
    Pow => "pow", 2;
    Exp => "exp", 1;
    Log => "log", 1;
    Sin => "sin", 1;
    Cos => "cos", 1;
    Tan => "tan", 1;
    Asin => "asin", 1;
    Acos => "acos", 1;
    Atan => "atan", 1;
    Atan2 => "atan2", 2;
    Min => "min", 2;
    Max => "max", 2;
    Clamp => "clamp", 3;
    Mix => "mix", 3;
    Step => "step", 2;
    Smoothstep => "smoothstep", 3;
    Length => "length", 1;
    Distance => "distance", 2;
    Dot => "dot", 2;
    Cross => "cross", 2;
    Normalize => "normalize", 1;
    Radians => "radians", 1;
    Degrees => "degrees", 1;
}

impl Builtin {
    pub fn from_name(name: &str) -> Option<Builtin> {
        Builtin::ALL.iter().copied().find(|b| b.name() == name)
    }

    /// Built-ins that reduce a vector to a scalar.
    pub fn is_reduction(self) -> bool {
        matches!(self, Builtin::Length | Builtin::Distance | Builtin::Dot)
    }
}

/// Hand-written WGSL distance helpers (in `shaders/`); the evaluator mirrors each one.
/// Sizes here are the helpers' own conventions (half extents), converted when lowering.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Helper {
    /// `(p, r)`
    SdSphere,
    /// `(p, half_size)`
    SdBox,
    /// `(p, half_size, r)`: half_size already shrunk by r.
    SdRoundBox,
    /// `(p, major, minor)`
    SdTorus,
    /// `(p, r, half_height)`
    SdCylinder,
    /// `(p, a, b, r)`
    SdCapsule,
    /// `(p, half_size: vec3, w)`: the edges of a box, bars of square cross-section w x w
    /// flush with the box's faces.
    SdBoxFrame,
    /// `(p, sc: vec2, major, minor)`: a torus arc in the xy plane covering the angles within
    /// the half-angle (`sc` its sine and cosine, the angle in [0, pi]) of +y.
    SdCappedTorus,
    /// `(p, half_height, r_bottom, r_top)`: a frustum along y from -half_height to
    /// +half_height (a cone when r_top is 0).
    SdCappedCone,
    /// `(p, radii: vec3)`: a lower bound of the distance to an ellipsoid.
    SdEllipsoid,
    /// `(p, s)`: the octahedron `|x| + |y| + |z| <= s`.
    SdOctahedron,
    /// `(p, r, half_length)`: hexagonal prism along z, inradius r, flat faces at y = +-r.
    SdHexPrism,
    /// `(p, r, half_length)`: triangular prism along z, an equilateral triangle of inradius r
    /// pointing to +y with its centroid on the axis.
    SdTriPrism,
    /// `(p, h)`: pyramid with the square base [-0.5, 0.5]^2 on y = 0 and its apex at (0, h, 0).
    SdPyramid,
    /// `(p, power, iterations, bound)`: the mandelbulb's distance estimate; the set lies within
    /// radius `bound`, and beyond `1.25 bound` the distance to that sphere is returned.
    SdMandelbulb,
    /// `(p, power, iterations, bound)`: `SdMandelbulb` for a whole power, computed without
    /// trigonometry (`shaders/prims/sd_mandelbulb_int.wgsl`): the same value, less rounding.
    SdMandelbulbInt,
    /// `(p, iterations)`: Menger sponge in the cube [-0.5, 0.5]^3.
    SdMenger,
    /// `(p, iterations)`: Sierpinski tetrahedron on alternate corners of [-0.5, 0.5]^3.
    SdSierpinski,
    /// `(p, c, s)`: `p` turned by the inverse of a rotation about x with cosine `c` and sine `s`
    /// (what a constant `rotate_x` does to the point); the same numbers as the matrix product.
    RotateX,
    /// `(p, c, s)`, about y.
    RotateY,
    /// `(p, c, s)`, about z.
    RotateZ,
    /// `(p)`: 3D gradient noise in [-1, 1] (`shaders/noise.wgsl`).
    Noise,
    /// `(p)`: the gradient (vec3) of `Noise` at p (`shaders/noise_gradient.wgsl`), for the
    /// analytic normals' derivative (`crate::diff`).
    NoiseGradient,
}

impl Helper {
    pub const ALL: &'static [Helper] = &[
        Helper::SdSphere,
        Helper::SdBox,
        Helper::SdRoundBox,
        Helper::SdTorus,
        Helper::SdCylinder,
        Helper::SdCapsule,
        Helper::SdBoxFrame,
        Helper::SdCappedTorus,
        Helper::SdCappedCone,
        Helper::SdEllipsoid,
        Helper::SdOctahedron,
        Helper::SdHexPrism,
        Helper::SdTriPrism,
        Helper::SdPyramid,
        Helper::SdMandelbulb,
        Helper::SdMandelbulbInt,
        Helper::SdMenger,
        Helper::SdSierpinski,
        Helper::RotateX,
        Helper::RotateY,
        Helper::RotateZ,
        Helper::Noise,
        Helper::NoiseGradient,
    ];

    /// The WGSL function name.
    pub fn name(self) -> &'static str {
        match self {
            Helper::SdSphere => "sd_sphere",
            Helper::SdBox => "sd_box",
            Helper::SdRoundBox => "sd_round_box",
            Helper::SdTorus => "sd_torus",
            Helper::SdCylinder => "sd_cylinder",
            Helper::SdCapsule => "sd_capsule",
            Helper::SdBoxFrame => "sd_box_frame",
            Helper::SdCappedTorus => "sd_capped_torus",
            Helper::SdCappedCone => "sd_capped_cone",
            Helper::SdEllipsoid => "sd_ellipsoid",
            Helper::SdOctahedron => "sd_octahedron",
            Helper::SdHexPrism => "sd_hex_prism",
            Helper::SdTriPrism => "sd_tri_prism",
            Helper::SdPyramid => "sd_pyramid",
            Helper::SdMandelbulb => "sd_mandelbulb",
            Helper::SdMandelbulbInt => "sd_mandelbulb_int",
            Helper::SdMenger => "sd_menger",
            Helper::SdSierpinski => "sd_sierpinski",
            Helper::RotateX => "rotate_x",
            Helper::RotateY => "rotate_y",
            Helper::RotateZ => "rotate_z",
            Helper::Noise => "noise",
            Helper::NoiseGradient => "noise_gradient",
        }
    }
}
