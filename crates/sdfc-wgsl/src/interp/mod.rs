//! The generic interpreted marcher (`sdfc render --interpreted`): one fixed compute shader
//! that reads the scene as bytecode from a storage buffer, so a new scene never needs a new
//! pipeline.
//!
//! # Shader interface
//!
//! As the render shader's (see the crate documentation: entry point `main`, 8x8 workgroups,
//! `color_out` at binding 1, `aov_out` at binding 2, `frame.flags` bit 0 for AOVs and bits 8
//! to 31 for the first tile of a dispatch of part of the image), except:
//!
//! - `@group(0) @binding(0) var<storage, read> frame: Frame` is the [`frame::FRAME_BYTES`]-byte
//!   struct of `shaders/interpreter/interface.wgsl` (image, time, flags, camera, render
//!   settings, code ranges, data offsets), written by [`frame::frame_data`];
//! - `@group(0) @binding(3) var<storage, read> code: array<vec4<u32>>`: the bytecode;
//! - `@group(0) @binding(4) var<storage, read> data: array<vec4<f32>>`: lights, params and
//!   constants.
//!
//! The shader reuses the specialised shader's hand-written parts (hit refinement, the
//! relaxed step in the merged marcher, camera, ambient occlusion, reflections, entry point;
//! the normals and shadows are `shaders/interpreter/scene.wgsl`'s, every method in one loop,
//! so that the interpreter is inlined at as few calls as possible):
//! each compile-time constant they name (`MAX_STEPS`, `CAMERA_POSITION`, ...) is rewritten
//! to the frame's field ([`RUNTIME_SETTINGS`]). The relaxed step with `RELAXATION = 1` takes
//! the plain step's samples up to a leap while receding from a surface passed by (there the
//! relaxed step tests the spheres' overlap with |d| and then remembers the sample it took
//! back, the plain one the last good one, so the paths may part from that sample on), and the
//! reflection loop with `REFLECTIONS = 0` returns exactly the plain radiance, so one shader
//! covers every setting.
//!
//! The march samples `scene_distance_ray`, as the specialised shader's does where the scene
//! has one: the bytecode holds that function after the material function (where the scene
//! has none, `Frame.distance_ray_code` is the distance's range), and `OP_RAY` reads the
//! ray's direction, so both forms divide by the same slopes along the ray and take the same
//! steps (a union the specialised shader reads as data marches its other children with their
//! own ray function, `rest_distance_ray`). Where the ray function would pass the encoder's
//! limits the march takes the distance instead.
//!
//! The interpreter's distance is the dearest there is (the whole bytecode loop), so its march
//! refines in the stepping loop (`shaders/march_merged.wgsl`): one inlined copy of the
//! interpreter in the march instead of two. On lavapipe that drew the suite 1.04x (spec
//! section 10) to 1.79x (the 300-shape grid) faster, the same pictures and steps
//! (docs/performance.md, "Relaxation in the merged marcher").

mod allocate;
pub mod encode;
pub mod encode_instances;
pub mod exec;
mod exec_walk;
pub mod frame;
mod listing;
pub mod opcodes;
mod peephole;
mod schedule;

use crate::{parts, validate, Failure};
use encode::MAX_REGISTERS;
use sdfc_ir::ops::Helper;
use std::fmt::Write;
use std::sync::OnceLock;

pub const INTERFACE: &str = include_str!("../../../../shaders/interpreter/interface.wgsl");
pub const INTERPRET: &str = include_str!("../../../../shaders/interpreter/interpret.wgsl");
pub const SCENE: &str = include_str!("../../../../shaders/interpreter/scene.wgsl");
pub const INSTANCES: &str = include_str!("../../../../shaders/interpreter/instances.wgsl");

/// The specialised shader's constants and the `Frame` fields that hold them here.
pub const RUNTIME_SETTINGS: &[(&str, &str)] = &[
    ("CAMERA_POSITION", "frame.camera_position"),
    ("CAMERA_FORWARD", "frame.camera_forward"),
    ("CAMERA_RIGHT", "frame.camera_right"),
    ("CAMERA_UP", "frame.camera_up"),
    ("TAN_HALF_FOV", "frame.tan_half_fov"),
    ("MAX_STEPS", "frame.max_steps"),
    ("MAX_DISTANCE", "frame.max_distance"),
    ("RELAXATION", "frame.relaxation"),
    ("ANTIALIAS", "frame.antialias"),
    ("BACKGROUND", "frame.background"),
    ("INV_GAMMA", "frame.inv_gamma"),
    ("SHADOW_K", "frame.shadow_k"),
    ("AO_SAMPLES", "frame.ao_samples"),
    ("AO_STEP", "frame.ao_step"),
    ("AO_STRENGTH", "frame.ao_strength"),
    ("AO_FALLOFF", "frame.ao_falloff"),
    ("REFLECTIONS", "frame.reflections"),
    ("FEATURE_SIZE", "frame.feature_size"),
];

/// A shared part with each settings constant (a whole identifier) replaced by its field.
fn runtime(part: &str) -> String {
    let mut out = String::with_capacity(part.len());
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        match RUNTIME_SETTINGS.iter().find(|(c, _)| *c == word.as_str()) {
            Some((_, field)) => out.push_str(field),
            None => out.push_str(word),
        }
        word.clear();
    };
    for ch in part.chars() {
        if ch.is_ascii_alphanumeric() || ch == '_' {
            word.push(ch);
        } else {
            flush(&mut word, &mut out);
            out.push(ch);
        }
    }
    flush(&mut word, &mut out);
    out
}

/// Which of the interpreter's two modules: the one every bytecode runs on, or the one that
/// also walks a union read as data (`encode_instances`). They are apart because lavapipe runs
/// every case of the register machine's `switch` at every instruction: the walk's four
/// cases made every other scene's frames 12 to 17% slower there (docs/performance.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variant {
    Code,
    Walk,
}

impl Variant {
    /// 0 or 1: where tables of the two variants keep this one.
    pub fn index(self) -> usize {
        usize::from(self == Variant::Walk)
    }

    /// The module `code` runs on.
    pub fn of(code: &encode::Bytecode) -> Variant {
        if code.instances.is_empty() {
            Variant::Code
        } else {
            Variant::Walk
        }
    }
}

/// The interpreter module's text (not yet validated), running `unroll` instructions per
/// trip of its loop.
pub fn emit_unrolled(unroll: u32) -> String {
    emit_variant(unroll, Variant::Code)
}

/// `interpret.wgsl` with its walk's lines (between `//WALK:BEGIN` and `//WALK:END`) kept
/// for [`Variant::Walk`] and dropped otherwise.
fn walk_lines(interpret: &str, variant: Variant) -> String {
    let mut out = String::with_capacity(interpret.len());
    let mut inside = false;
    for line in interpret.lines() {
        if line.starts_with("//WALK:BEGIN") {
            inside = true;
        } else if line.starts_with("//WALK:END") {
            inside = false;
        } else if !inside || variant == Variant::Walk {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

/// The text of the interpreter `variant`, running `unroll` instructions per trip of its
/// loop.
pub fn emit_variant(unroll: u32, variant: Variant) -> String {
    let mut s = format!(
        "// Generated by sdfc {}: the generic interpreted marcher. The scene comes as bytecode\n\
         // (binding 3) and data (binding 4); the settings come in the Frame buffer.\n\n",
        env!("CARGO_PKG_VERSION")
    );
    s += &opcodes::wgsl_constants();
    let _ = writeln!(
        s,
        "// Size of the register file (the encoder's limit).\nconst MAX_REGISTERS: u32 = {MAX_REGISTERS}u;\n"
    );
    s += INTERFACE;
    for h in Helper::ALL {
        if opcodes::helper_opcode(*h).is_some() {
            s += "\n";
            s += parts::helper(*h);
        }
    }
    s += "\n";
    s += &unrolled(&walk_lines(INTERPRET, variant), unroll);
    s += "\n";
    if variant == Variant::Walk {
        s += INSTANCES;
        s += "\n";
    }
    // The walking variant's shadow and ambient occlusion samples take a far box's distance
    // for its instances' only where it cannot lower the light (`shadow_distance`), or never
    // (`occlusion_distance`).
    let walk = variant == Variant::Walk;
    let sample = |part: &str, plain: &str, walked: &str| {
        runtime(&if walk {
            part.replacen(plain, walked, 1)
        } else {
            part.to_string()
        })
    };
    s += &sample(
        SCENE,
        SHADOW_SAMPLE,
        "let h = shadow_distance(q, select(light * t / SHADOW_K, 0.0, hard));",
    );
    s += "\n";
    s += &runtime(parts::HIT);
    s += "\n";
    s += &runtime(parts::MARCH_STEP_RELAXED);
    s += "\n";
    s += &runtime(&crate::marcher::along_ray(parts::MARCH_MERGED));
    s += "\n";
    s += &runtime(parts::CAMERA);
    s += "\n";
    s += &runtime(parts::SAFE_NORMALIZE);
    s += "\n";
    s += &sample(
        parts::AMBIENT_OCCLUSION,
        crate::occlusion::AO_SAMPLE,
        "occlusion_distance(p + n * h)",
    );
    s += "\n";
    s += &runtime(parts::RADIANCE_REFLECTIONS);
    s += "\n";
    s += &runtime(parts::MAIN).replace(OPAQUE, CUT_MARKED);
    s
}

/// The shadow ray's sample of the scene in `shaders/interpreter/scene.wgsl`, which the
/// walking variant rewrites; a test checks it is rewritten.
const SHADOW_SAMPLE: &str = "let h = scene_distance(q);";

/// The entry point's colour write, and the interpreter's: alpha 0 where the driver cut a run
/// of the code short ([`cut_pixels`]).
const OPAQUE: &str = "pack4x8unorm(vec4<f32>(mapped, 1.0))";
const CUT_MARKED: &str = "pack4x8unorm(vec4<f32>(mapped, select(1.0, 0.0, cut)))";

/// Counts the pixels of an interpreted frame's RGBA8 whose run of the code was cut short
/// (alpha 0) and makes every pixel opaque again, as the specialised shader's are.
pub fn cut_pixels(rgba: &mut [u8]) -> usize {
    let mut n = 0;
    for px in rgba.chunks_exact_mut(4) {
        if px[3] == 0 {
            n += 1;
            px[3] = 255;
        }
    }
    n
}

/// The interpreter module's text, one instruction per trip.
pub fn emit() -> String {
    emit_unrolled(1)
}

/// `interpret.wgsl` with `unroll - 1` more instructions run in each trip of its loop.
fn unrolled(interpret: &str, unroll: u32) -> String {
    let one = "        if pc < last {\n            pc = execute(&regs, pc);\n        }\n";
    interpret.replace("//UNROLL\n", &one.repeat(unroll.saturating_sub(1) as usize))
}

/// Instructions per trip of the interpreter's loop on a device that bounds an invocation's
/// loop trips: lavapipe and llvmpipe (gallivm) end every loop of an invocation once 65 535
/// trips have been taken in all, and a frame of a large or richly shaded scene needs more
/// than that per pixel (the 300-shape grid, a reflective scene with antialiasing and
/// shadows: docs/performance.md). Two halve the trips; the pipeline takes about 1.4 times
/// as long to build there.
pub const CPU_UNROLL: u32 = 2;

/// The validated interpreter module for one instruction per trip (a GPU's), built once per
/// process.
pub fn shader() -> Result<&'static str, Failure> {
    shader_unrolled(1)
}

/// The validated interpreter module running `unroll` (1 or [`CPU_UNROLL`]) instructions per
/// trip of its loop, built once per process for each.
pub fn shader_unrolled(unroll: u32) -> Result<&'static str, Failure> {
    shader_variant(unroll, Variant::Code)
}

/// The validated interpreter `variant` running `unroll` (1 or [`CPU_UNROLL`]) instructions
/// per trip of its loop, built once per process for each.
pub fn shader_variant(unroll: u32, variant: Variant) -> Result<&'static str, Failure> {
    type Built = OnceLock<Result<String, (String, String)>>;
    static BUILT: [Built; 4] = [const { OnceLock::new() }; 4];
    let unroll = if unroll <= 1 { 1 } else { CPU_UNROLL };
    let slot = &BUILT[usize::from(unroll > 1) + 2 * variant.index()];
    let r = slot.get_or_init(|| {
        let wgsl = emit_variant(unroll, variant);
        match validate::validate("interpreter.wgsl", &wgsl) {
            Ok(()) => Ok(wgsl),
            Err(report) => Err((report, wgsl)),
        }
    });
    match r {
        Ok(s) => Ok(s.as_str()),
        Err((report, wgsl)) => Err(Failure::Internal {
            report: report.clone(),
            wgsl: wgsl.clone(),
        }),
    }
}
