//! The point-evaluation shader behind `sdfc eval --gpu`: the scene's `scene_distance` run at
//! a list of points.
//!
//! Interface: entry point `eval_main`, `@workgroup_size(64)`; dispatch `ceil(count / 64)`
//! workgroups in x (at most 65 535 per dispatch: evaluate larger sets in batches).
//! - `@group(0) @binding(0) var<storage, read> eval_frame: EvalFrame` with
//!   `struct EvalFrame { count: u32, time: f32, pad0: u32, pad1: u32, params: array<vec4<f32>, N> }`
//!   (16 + 16 N bytes; `params` as in the render shader's `Frame`, absent without params).
//! - `@group(0) @binding(1) var<storage, read> eval_points: array<vec4<f32>>`: xyz per point.
//! - `@group(0) @binding(2) var<storage, read_write> eval_out: array<f32>`: one distance each.

use crate::{module, validate, Failure};
use sdfc_ir::ops::Op;
use sdfc_ir::Program;
use std::fmt::Write;

/// The validated evaluation shader of a compiled scene.
pub fn eval_shader(program: &Program) -> Result<String, Failure> {
    let mut s = module::emit(program, true, None);
    let funcs = [&program.distance, &program.material]
        .into_iter()
        .chain(&program.groups);
    let uses = |pred: &dyn Fn(&Op) -> bool| {
        funcs
            .clone()
            .any(|f| f.graph.nodes().any(|(_, n)| pred(&n.op)))
    };
    let uses_time = uses(&|o| *o == Op::Time);
    let uses_params = uses(&|o| matches!(o, Op::Param(_)));
    let n = program.scene.params.len();
    s += "\n// Evaluation entry point: scene_distance at each point.\n";
    s += "struct EvalFrame {\n    count: u32,\n    time: f32,\n    pad0: u32,\n    pad1: u32,\n";
    if n > 0 {
        let _ = writeln!(s, "    params: array<vec4<f32>, {n}>,");
    }
    s += "}\n\n";
    s += "@group(0) @binding(0) var<storage, read> eval_frame: EvalFrame;\n";
    s += "@group(0) @binding(1) var<storage, read> eval_points: array<vec4<f32>>;\n";
    s += "@group(0) @binding(2) var<storage, read_write> eval_out: array<f32>;\n\n";
    s += "@compute @workgroup_size(64, 1, 1)\nfn eval_main(@builtin(global_invocation_id) gid: vec3<u32>) {\n";
    s += "    let i = gid.x;\n    if i >= eval_frame.count {\n        return;\n    }\n";
    if uses_time {
        s += "    scene_time = eval_frame.time;\n";
    }
    if uses_params {
        s += "    scene_params = eval_frame.params;\n";
    }
    s += "    eval_out[i] = scene_distance(eval_points[i].xyz);\n}\n";
    match validate::validate("eval.wgsl", &s) {
        Ok(()) => Ok(s),
        Err(report) => Err(Failure::Internal { report, wgsl: s }),
    }
}
