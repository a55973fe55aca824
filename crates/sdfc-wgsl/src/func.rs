//! Emits one SSA function as a WGSL function: a `let` per computed node, named by its role
//! (`q` points, `d` distances, `h` blend weights, `m` materials), constants and inputs inline.

use crate::literal;
use sdfc_ir::func::{Func, FuncKind};
use sdfc_ir::graph::{Graph, NodeId};
use sdfc_ir::ops::Op;
use sdfc_ir::types::Ty;
use std::collections::BTreeMap;
use std::fmt::Write;

pub fn wgsl_type(ty: Ty) -> &'static str {
    match ty {
        Ty::F32 => "f32",
        Ty::Vec2 => "vec2<f32>",
        Ty::Vec3 => "vec3<f32>",
        Ty::Vec4 => "vec4<f32>",
        Ty::Bool => "bool",
        Ty::Mat3 => "mat3x3<f32>",
    }
}

/// Emits `fn NAME(p: vec3<f32>) -> RET { ... }` for a function of kind `f.kind`; `groups`
/// are the program's group functions, which `Op::Call` nodes name.
pub fn emit(f: &Func, groups: &[Func], doc: &str) -> String {
    let (ret_ty, ret): (&str, fn(&[String]) -> String) = match f.kind {
        FuncKind::Distance => ("f32", |r| r[0].clone()),
        FuncKind::Material => ("SceneMaterial", |r| {
            format!("SceneMaterial({}, {})", r[0], r[1])
        }),
        FuncKind::MaterialGroup => ("SceneSample", |r| {
            format!("SceneSample({}, {}, {})", r[0], r[1], r[2])
        }),
    };
    let g = &f.graph;
    let mut text: Vec<String> = vec![String::new(); g.len()];
    let mut counters: BTreeMap<&str, usize> = BTreeMap::new();
    let mut body = String::new();
    // One WGSL call per (group, argument): its results are fields of one value.
    let mut calls: BTreeMap<(u32, NodeId), String> = BTreeMap::new();
    for (id, node) in g.nodes() {
        if let Op::Call { func, result } = node.op {
            let arg = node.args()[0];
            let Some(callee) = groups.get(func as usize) else {
                continue;
            };
            let value = match calls.get(&(func, arg)) {
                Some(v) => v.clone(),
                None => {
                    let hint = if callee.kind == FuncKind::MaterialGroup {
                        "s"
                    } else {
                        "d"
                    };
                    let n = counters.entry(hint).or_insert(0);
                    let name = format!("{hint}{n}");
                    *n += 1;
                    let _ = writeln!(
                        body,
                        "    let {name} = {}({});",
                        callee.name,
                        text[arg.index()]
                    );
                    calls.insert((func, arg), name.clone());
                    name
                }
            };
            text[id.index()] = match (callee.kind, result) {
                (FuncKind::MaterialGroup, 0) => format!("{value}.distance"),
                (FuncKind::MaterialGroup, 1) => format!("{value}.albedo"),
                (FuncKind::MaterialGroup, _) => format!("{value}.phong"),
                _ => value,
            };
            continue;
        }
        let args: Vec<&str> = node
            .args()
            .iter()
            .map(|a| text[a.index()].as_str())
            .collect();
        let (expr, inline) = expression(g, id, &args);
        if inline {
            text[id.index()] = expr;
            continue;
        }
        let hint = g.hint(id);
        let n = counters.entry(hint).or_insert(0);
        let name = format!("{hint}{n}");
        *n += 1;
        let _ = writeln!(body, "    let {name} = {expr};");
        text[id.index()] = name;
    }
    let results: Vec<String> = f.results.iter().map(|r| text[r.index()].clone()).collect();
    let mut out = String::new();
    let _ = writeln!(out, "// {doc}");
    let _ = writeln!(out, "fn {}(p: vec3<f32>) -> {ret_ty} {{", f.name);
    out += &body;
    let _ = writeln!(out, "    return {};", ret(&results));
    out += "}\n";
    out
}

/// Wraps an operand that starts with `-` so `a - -1.0` never reads as a decrement.
fn operand(s: &str) -> String {
    if s.starts_with('-') {
        format!("({s})")
    } else {
        s.to_string()
    }
}

/// The WGSL expression of a node, and whether it is simple enough to inline at each use.
fn expression(g: &Graph, id: NodeId, a: &[&str]) -> (String, bool) {
    let node = g.node(id);
    let bin = |sym: &str| format!("{} {sym} {}", operand(a[0]), operand(a[1]));
    match node.op {
        Op::Const(c) => (literal::value(&c.to_value()), true),
        Op::Point => ("p".into(), true),
        Op::Time => ("scene_time".into(), true),
        Op::Param(i) => {
            let sw = match node.ty {
                Ty::F32 => "x",
                Ty::Vec2 => "xy",
                _ => "xyz",
            };
            (format!("scene_params[{i}].{sw}"), true)
        }
        // Only reachable if a lambda argument escaped substitution; zero keeps WGSL valid.
        Op::LambdaArg { .. } => (literal::value(&sdfc_ir::eval::zero_of(node.ty)), true),
        // Calls are emitted by `emit`, once per group and argument.
        Op::Call { .. } => ("0.0".into(), true),
        Op::Neg => (format!("-{}", operand(a[0])), false),
        Op::Add => (bin("+"), false),
        Op::Sub => (bin("-"), false),
        Op::Mul | Op::MatMul => (bin("*"), false),
        Op::Div => (bin("/"), false),
        // Floored modulo, spelled exactly as the evaluator computes it.
        Op::Mod => (
            format!("{0} - {1} * floor({0} / {1})", operand(a[0]), operand(a[1])),
            false,
        ),
        Op::Lt => (bin("<"), false),
        Op::Le => (bin("<="), false),
        Op::Gt => (bin(">"), false),
        Op::Ge => (bin(">="), false),
        Op::Eq => (bin("=="), false),
        Op::Ne => (bin("!="), false),
        Op::Select => (format!("select({}, {}, {})", a[0], a[1], a[2]), false),
        Op::Builtin(b) => (format!("{}({})", b.name(), a.join(", ")), false),
        Op::Helper(h) => (format!("{}({})", h.name(), a.join(", ")), false),
        Op::MakeVec => (format!("{}({})", wgsl_type(node.ty), a.join(", ")), false),
        Op::MakeMat3 => (format!("mat3x3<f32>({})", a.join(", ")), false),
        Op::Transpose => (format!("transpose({})", a[0]), false),
        Op::Swizzle(s) => {
            let src = node.args()[0];
            if g.ty(src) == Ty::F32 {
                (format!("{}({})", wgsl_type(node.ty), a[0]), true)
            } else if a[0]
                .chars()
                .all(|c| c.is_alphanumeric() || c == '_' || c == '.' || c == '[' || c == ']')
            {
                (format!("{}.{}", a[0], s.letters()), true)
            } else {
                (format!("({}).{}", a[0], s.letters()), true)
            }
        }
    }
}
