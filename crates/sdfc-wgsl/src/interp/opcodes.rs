//! The interpreter's opcode table: the one place that numbers opcodes. The WGSL side reads
//! the numbers as the `OP_*` constants emitted from this table, so the two cannot drift.
//!
//! Adding a distance helper: one line in `helper_opcode` (and in the table below), one
//! `case` in `shaders/interpreter/interpret.wgsl`.

use sdfc_ir::ops::{Builtin, Helper};
use std::fmt::Write;

macro_rules! opcodes {
    ($($variant:ident = $num:literal, $wgsl:literal, $text:literal;)*) => {
        /// One instruction kind of the register machine.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum Opcode { $($variant),* }

        impl Opcode {
            /// Every opcode, in table order.
            pub const ALL: &'static [Opcode] = &[$(Opcode::$variant),*];

            /// The number written into the bytecode.
            pub fn code(self) -> u32 {
                match self { $(Opcode::$variant => $num),* }
            }

            /// The WGSL constant that names it in the interpreter's `switch`.
            pub fn wgsl_name(self) -> &'static str {
                match self { $(Opcode::$variant => $wgsl),* }
            }

            /// The mnemonic of bytecode listings.
            pub fn mnemonic(self) -> &'static str {
                match self { $(Opcode::$variant => $text),* }
            }
        }
    };
}

opcodes! {
    // Control and inputs.
    Ret = 0, "OP_RET", "ret";
    // The ray's direction in `scene_distance_ray` (the shader's `ray_dir`).
    Ray = 1, "OP_RAY", "ray";
    Param = 2, "OP_PARAM", "param";
    Time = 3, "OP_TIME", "time";
    // A culled union's early-out: unless a.x < b.x (the part's box is nearer than the best
    // distance so far), jump over the next `imm` instructions (the part's inlined code).
    SkipUnlessLess = 4, "OP_SKIP_UNLESS_LESS", "skip_unless_less";
    // A copy: a skipped part's results are written before the skip and again after it.
    Mov = 5, "OP_MOV", "mov";
    // A union read as data (`encode::encode_instances`): one node of its hierarchy per
    // trip, staying at its pc, and at a leaf a jump to its kind's code with register 0 set
    // to the instance's local point; when the walk is over, (distance, material index).
    // `imm`: where the kinds' first instructions are listed in the pool.
    Instances = 6, "OP_INSTANCES", "instances";
    // The end of a kind's code: its distance, back to the walk.
    InstanceDone = 7, "OP_INSTANCE_DONE", "instance_done";
    // An argument of the instance being evaluated: word `imm & 0xff` of its record, `imm >> 8`
    // words wide (a scalar splatted).
    Arg = 8, "OP_ARG", "arg";
    // Row `imm + 2 a.y` of the pool: a material's albedo or phong by its index.
    MaterialRow = 9, "OP_MATERIAL_ROW", "material_row";
    // Arithmetic and comparisons (component-wise; scalars are kept splatted).
    Neg = 10, "OP_NEG", "neg";
    Add = 11, "OP_ADD", "add";
    Sub = 12, "OP_SUB", "sub";
    Mul = 13, "OP_MUL", "mul";
    Div = 14, "OP_DIV", "div";
    Mod = 15, "OP_MOD", "mod";
    Lt = 16, "OP_LT", "lt";
    Le = 17, "OP_LE", "le";
    Gt = 18, "OP_GT", "gt";
    Ge = 19, "OP_GE", "ge";
    Eq = 20, "OP_EQ", "eq";
    Ne = 21, "OP_NE", "ne";
    Select = 22, "OP_SELECT", "select";
    // Vectors and matrices (a mat3 lives in three registers, one per column).
    MakeVec = 30, "OP_MAKE_VEC", "make_vec";
    Swizzle = 31, "OP_SWIZZLE", "swizzle";
    Mat3Vec = 32, "OP_MAT3_VEC", "mat3_vec";
    MatRow = 33, "OP_MAT_ROW", "mat_row";
    // WGSL built-ins, component-wise.
    Abs = 40, "OP_ABS", "abs";
    Sign = 41, "OP_SIGN", "sign";
    Floor = 42, "OP_FLOOR", "floor";
    Ceil = 43, "OP_CEIL", "ceil";
    Fract = 44, "OP_FRACT", "fract";
    Round = 45, "OP_ROUND", "round";
    Sqrt = 46, "OP_SQRT", "sqrt";
    Pow = 47, "OP_POW", "pow";
    Exp = 48, "OP_EXP", "exp";
    Log = 49, "OP_LOG", "log";
    Sin = 50, "OP_SIN", "sin";
    Cos = 51, "OP_COS", "cos";
    Tan = 52, "OP_TAN", "tan";
    Asin = 53, "OP_ASIN", "asin";
    Acos = 54, "OP_ACOS", "acos";
    Atan = 55, "OP_ATAN", "atan";
    Atan2 = 56, "OP_ATAN2", "atan2";
    Min = 57, "OP_MIN", "min";
    Max = 58, "OP_MAX", "max";
    Clamp = 59, "OP_CLAMP", "clamp";
    Mix = 60, "OP_MIX", "mix";
    Step = 61, "OP_STEP", "step";
    Smoothstep = 62, "OP_SMOOTHSTEP", "smoothstep";
    Radians = 63, "OP_RADIANS", "radians";
    Degrees = 64, "OP_DEGREES", "degrees";
    // WGSL built-ins whose meaning depends on the vector width.
    Length2 = 70, "OP_LENGTH2", "length2";
    Length3 = 71, "OP_LENGTH3", "length3";
    Length4 = 72, "OP_LENGTH4", "length4";
    Dot2 = 73, "OP_DOT2", "dot2";
    Dot3 = 74, "OP_DOT3", "dot3";
    Dot4 = 75, "OP_DOT4", "dot4";
    Normalize2 = 76, "OP_NORMALIZE2", "normalize2";
    Normalize3 = 77, "OP_NORMALIZE3", "normalize3";
    Normalize4 = 78, "OP_NORMALIZE4", "normalize4";
    Cross = 79, "OP_CROSS", "cross";
    // length(abs(a.xyz) + b.xyz): a culled part's farthest corner from the point, the
    // `abs`, `add` and `length3` of its bound in one trip (`peephole::fold_far_corners`).
    FarCorner = 80, "OP_FAR_CORNER", "far_corner";
    // Distance helpers (`shaders/prims`, `shaders/transforms`, `shaders/noise.wgsl`).
    SdSphere = 100, "OP_SD_SPHERE", "sd_sphere";
    SdBox = 101, "OP_SD_BOX", "sd_box";
    SdRoundBox = 102, "OP_SD_ROUND_BOX", "sd_round_box";
    SdTorus = 103, "OP_SD_TORUS", "sd_torus";
    SdCylinder = 104, "OP_SD_CYLINDER", "sd_cylinder";
    SdCapsule = 105, "OP_SD_CAPSULE", "sd_capsule";
    RotateX = 106, "OP_ROTATE_X", "rotate_x";
    RotateY = 107, "OP_ROTATE_Y", "rotate_y";
    RotateZ = 108, "OP_ROTATE_Z", "rotate_z";
    Noise = 109, "OP_NOISE", "noise";
    SdBoxFrame = 110, "OP_SD_BOX_FRAME", "sd_box_frame";
    SdCappedTorus = 111, "OP_SD_CAPPED_TORUS", "sd_capped_torus";
    SdCappedCone = 112, "OP_SD_CAPPED_CONE", "sd_capped_cone";
    SdEllipsoid = 113, "OP_SD_ELLIPSOID", "sd_ellipsoid";
    SdOctahedron = 114, "OP_SD_OCTAHEDRON", "sd_octahedron";
    SdHexPrism = 115, "OP_SD_HEX_PRISM", "sd_hex_prism";
    SdTriPrism = 116, "OP_SD_TRI_PRISM", "sd_tri_prism";
    SdPyramid = 117, "OP_SD_PYRAMID", "sd_pyramid";
    SdMandelbulb = 118, "OP_SD_MANDELBULB", "sd_mandelbulb";
    SdMenger = 119, "OP_SD_MENGER", "sd_menger";
    SdSierpinski = 120, "OP_SD_SIERPINSKI", "sd_sierpinski";
    NoiseGradient = 121, "OP_NOISE_GRADIENT", "noise_gradient";
    SdMandelbulbInt = 122, "OP_SD_MANDELBULB_INT", "sd_mandelbulb_int";
}

/// The opcode of a distance helper; `None` for a helper the interpreter does not know yet
/// (the encoder turns that into an error, so a new helper can never crash a render).
#[allow(unreachable_patterns)] // helpers added after this table fall through to `None`
pub fn helper_opcode(h: Helper) -> Option<Opcode> {
    Some(match h {
        Helper::SdSphere => Opcode::SdSphere,
        Helper::SdBox => Opcode::SdBox,
        Helper::SdRoundBox => Opcode::SdRoundBox,
        Helper::SdTorus => Opcode::SdTorus,
        Helper::SdCylinder => Opcode::SdCylinder,
        Helper::SdCapsule => Opcode::SdCapsule,
        Helper::RotateX => Opcode::RotateX,
        Helper::RotateY => Opcode::RotateY,
        Helper::RotateZ => Opcode::RotateZ,
        Helper::Noise => Opcode::Noise,
        Helper::NoiseGradient => Opcode::NoiseGradient,
        Helper::SdBoxFrame => Opcode::SdBoxFrame,
        Helper::SdCappedTorus => Opcode::SdCappedTorus,
        Helper::SdCappedCone => Opcode::SdCappedCone,
        Helper::SdEllipsoid => Opcode::SdEllipsoid,
        Helper::SdOctahedron => Opcode::SdOctahedron,
        Helper::SdHexPrism => Opcode::SdHexPrism,
        Helper::SdTriPrism => Opcode::SdTriPrism,
        Helper::SdPyramid => Opcode::SdPyramid,
        Helper::SdMandelbulb => Opcode::SdMandelbulb,
        Helper::SdMandelbulbInt => Opcode::SdMandelbulbInt,
        Helper::SdMenger => Opcode::SdMenger,
        Helper::SdSierpinski => Opcode::SdSierpinski,
        _ => return None,
    })
}

/// The opcode of a component-wise built-in; `None` for the width-dependent ones (length,
/// distance, dot, normalize, cross), which the encoder picks by type.
#[allow(unreachable_patterns)]
pub fn builtin_opcode(b: Builtin) -> Option<Opcode> {
    use Builtin as B;
    Some(match b {
        B::Abs => Opcode::Abs,
        B::Sign => Opcode::Sign,
        B::Floor => Opcode::Floor,
        B::Ceil => Opcode::Ceil,
        B::Fract => Opcode::Fract,
        B::Round => Opcode::Round,
        B::Sqrt => Opcode::Sqrt,
        B::Pow => Opcode::Pow,
        B::Exp => Opcode::Exp,
        B::Log => Opcode::Log,
        B::Sin => Opcode::Sin,
        B::Cos => Opcode::Cos,
        B::Tan => Opcode::Tan,
        B::Asin => Opcode::Asin,
        B::Acos => Opcode::Acos,
        B::Atan => Opcode::Atan,
        B::Atan2 => Opcode::Atan2,
        B::Min => Opcode::Min,
        B::Max => Opcode::Max,
        B::Clamp => Opcode::Clamp,
        B::Mix => Opcode::Mix,
        B::Step => Opcode::Step,
        B::Smoothstep => Opcode::Smoothstep,
        B::Radians => Opcode::Radians,
        B::Degrees => Opcode::Degrees,
        _ => return None,
    })
}

/// Set in an instruction's opcode word: its first argument is `a - d`, not `a`. A translated
/// shape's `sub` of the point and its offset, folded into the instructions that read it
/// (`peephole::fold_translations`): one trip of the interpreter's loop less for each.
pub const FOLDED_SUB: u32 = 1 << 31;

/// `const OP_*: u32 = N;` for every opcode: the WGSL side's numbering.
pub fn wgsl_constants() -> String {
    let mut s = String::from(
        "// Opcode numbers, emitted from the encoder's table (sdfc-wgsl src/interp/opcodes.rs).\n",
    );
    for op in Opcode::ALL {
        let _ = writeln!(s, "const {}: u32 = {}u;", op.wgsl_name(), op.code());
    }
    let _ = writeln!(s, "const OP_FOLDED_SUB: u32 = {FOLDED_SUB}u;");
    s
}

/// The opcode of an instruction's opcode word, and whether its first argument is `a - d`
/// ([`FOLDED_SUB`]).
pub fn decode(word: u32) -> (Option<Opcode>, bool) {
    let code = word & !FOLDED_SUB;
    (
        Opcode::ALL.iter().copied().find(|o| o.code() == code),
        word & FOLDED_SUB != 0,
    )
}
