//! Emits one SSA function as a WGSL function: a `let` per computed node, named by its role
//! (`q` points, `d` distances, `h` blend weights, `m` materials, `k` material indices),
//! constants and inputs inline, and so is a point read once as a call argument.

use crate::consts::Consts;
use crate::literal;
use crate::material_index::{self, Index, Plan};
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

/// Emits a function of kind `f.kind`; `groups` are the program's group functions, which
/// `Op::Call` nodes name.
///
/// A group function takes `(p, with_material: bool)` and returns a `SceneSample`: the nodes
/// its distance needs are emitted first, the rest (material selects and blends) inside
/// `if with_material { ... }`, so a caller that wants the distance alone (the march loop)
/// skips them. A call is spelled with `false` where only its distance is used.
///
/// Where `material_index` plans it, the material is a `u32` index select per condition
/// (named `k`) and one lookup of the index's materials at the end; the vector selects it
/// replaces are not emitted.
pub fn emit(f: &Func, groups: &[Func], consts: &Consts, doc: &str) -> String {
    emit_with(f, groups, consts, doc, None)
}

/// Emits the distance function of one kind of a union's instances (`crate::instances`) as
/// `name(p: vec3<f32>, a0: vec4<u32>, ...) -> f32`, with `vec4s` such parameters: its
/// `Op::Param(i)` nodes (of types `tys`) are the instance's arguments, read from the record's
/// vec4s (`crate::instances::arg_word`), not the scene's params.
pub fn emit_template(f: &Func, tys: &[Ty], vec4s: usize, consts: &Consts, doc: &str) -> String {
    emit_with(f, &[], consts, doc, Some((tys, vec4s)))
}

fn emit_with(
    f: &Func,
    groups: &[Func],
    consts: &Consts,
    doc: &str,
    template: Option<(&[Ty], usize)>,
) -> String {
    let g = &f.graph;
    let plan = material_index::plan(f);
    let plan = plan.as_ref();
    // Nodes in the unconditional part: everything for a plain function, the distance's
    // dependencies for a group.
    let mut first = vec![f.kind != FuncKind::Group; g.len()];
    if f.kind == FuncKind::Group {
        first[f.results[0].index()] = true;
        for i in (0..g.len()).rev() {
            if first[i] {
                for a in g.node(NodeId(i as u32)).args() {
                    first[a.index()] = true;
                }
            }
        }
    }
    // Which (group, argument) calls need more than the distance, per part.
    // Calls are keyed by part, group and arguments (the point, and for a guarded call its
    // bound and the best distance so far).
    type CallKey = (bool, u32, Vec<NodeId>);
    let mut wants_material: BTreeMap<CallKey, bool> = BTreeMap::new();
    for (id, node) in g.nodes() {
        if let Op::Call { func, result } = node.op {
            *wants_material
                .entry((first[id.index()], func, node.args().to_vec()))
                .or_default() |= result > 0;
        }
    }
    let mut text: Vec<String> = vec![String::new(); g.len()];
    let mut counters: BTreeMap<&str, usize> = BTreeMap::new();
    let mut calls: BTreeMap<CallKey, String> = BTreeMap::new();
    let mut parts = [String::new(), String::new()];
    let spelled_inline = inline_points(f, plan);
    // Index expressions' texts, and how many have been emitted.
    let mut index_text: Vec<String> = Vec::new();
    for (id, node) in g.nodes() {
        if let Some(plan) = plan {
            emit_index(
                plan,
                id,
                &text,
                &first,
                &mut counters,
                &mut index_text,
                &mut parts,
            );
            if plan.replaced[id.index()] {
                continue;
            }
        }
        let part = first[id.index()];
        let out = &mut parts[usize::from(!part)];
        let indent = if part { "    " } else { "        " };
        if let Op::Call { func, result } = node.op {
            let arg = node.args()[0];
            let Some(callee) = groups.get(func as usize) else {
                continue;
            };
            let key = (part, func, node.args().to_vec());
            let value = match calls.get(&key) {
                Some(v) => v.clone(),
                None => {
                    let n = counters.entry("s").or_insert(0);
                    let name = format!("s{n}");
                    *n += 1;
                    let flag = wants_material.get(&key).copied().unwrap_or(false);
                    let call = if callee.kind == FuncKind::Gradient {
                        format!("{}({})", callee.name, text[arg.index()])
                    } else if let (true, [_, _, best]) = (reads_best(callee), node.args()) {
                        let best = &text[best.index()];
                        format!("{}({}, {best}, {flag})", callee.name, text[arg.index()])
                    } else {
                        format!("{}({}, {flag})", callee.name, text[arg.index()])
                    };
                    if let [_, bound, best] = node.args() {
                        // A culled union's early-out: the group runs only where its box
                        // is nearer than the best distance so far.
                        let (bound, best) = (&text[bound.index()], &text[best.index()]);
                        let _ = writeln!(
                            out,
                            "{indent}var {name} = SceneSample({bound}, vec4<f32>(0.0), vec4<f32>(0.0));\n\
                             {indent}if {bound} < {best} {{\n\
                             {indent}    {name} = {call};\n\
                             {indent}}}"
                        );
                    } else {
                        let _ = writeln!(out, "{indent}let {name} = {call};");
                    }
                    calls.insert(key, name.clone());
                    name
                }
            };
            text[id.index()] = match (callee.kind, result) {
                // A gradient function returns vec4(gradient, distance).
                (FuncKind::Gradient, 0) => format!("{value}.w"),
                (FuncKind::Gradient, 1) => format!("{value}.x"),
                (FuncKind::Gradient, 2) => format!("{value}.y"),
                (FuncKind::Gradient, _) => format!("{value}.z"),
                (_, 0) => format!("{value}.distance"),
                (_, 1) => format!("{value}.albedo"),
                _ => format!("{value}.phong"),
            };
            continue;
        }
        let args: Vec<&str> = node
            .args()
            .iter()
            .map(|a| text[a.index()].as_str())
            .collect();
        let (expr, inline) = expression(g, id, &args, consts, template);
        if inline || spelled_inline[id.index()] || plan.is_some_and(|p| p.inline[id.index()]) {
            text[id.index()] = expr;
            continue;
        }
        let hint = g.hint(id);
        let n = counters.entry(hint).or_insert(0);
        let name = format!("{hint}{n}");
        *n += 1;
        let _ = writeln!(out, "{indent}let {name} = {expr};");
        text[id.index()] = name;
    }
    if let Some(plan) = plan {
        emit_index(
            plan,
            NodeId(g.len() as u32),
            &text,
            &first,
            &mut counters,
            &mut index_text,
            &mut parts,
        );
    }
    // The material, where it is an index: its albedo and phong looked up.
    let index = plan.zip(index_text.last()).map(|(p, k)| {
        // In the material part of a group, in the body of a material function.
        let (part, indent) = match f.kind {
            FuncKind::Group => (1, "        "),
            _ => (0, "    "),
        };
        lookup(p, k, consts, &mut counters, &mut parts[part], indent)
    });
    let r: Vec<&str> = f.results.iter().map(|r| text[r.index()].as_str()).collect();
    let mut s = String::new();
    let _ = writeln!(s, "// {doc}");
    match f.kind {
        FuncKind::Distance if template.is_some() => {
            let n = template.map_or(0, |t| t.1);
            let params: Vec<String> = (0..n).map(|v| format!(", a{v}: vec4<u32>")).collect();
            let _ = writeln!(
                s,
                "fn {}(p: vec3<f32>{}) -> f32 {{",
                f.name,
                params.concat()
            );
            s += &parts[0];
            let _ = writeln!(s, "    return {};", r[0]);
        }
        FuncKind::Distance => {
            let _ = writeln!(s, "fn {}(p: vec3<f32>) -> f32 {{", f.name);
            s += &parts[0];
            let _ = writeln!(s, "    return {};", r[0]);
        }
        FuncKind::DistanceRay => {
            let _ = writeln!(s, "fn {}(p: vec3<f32>, rd: vec3<f32>) -> f32 {{", f.name);
            s += &parts[0];
            let _ = writeln!(s, "    return {};", r[0]);
        }
        FuncKind::Gradient => {
            let _ = writeln!(s, "fn {}(p: vec3<f32>) -> vec4<f32> {{", f.name);
            s += &parts[0];
            let _ = writeln!(
                s,
                "    return vec4<f32>({}, {}, {}, {});",
                r[1], r[2], r[3], r[0]
            );
        }
        FuncKind::Material => {
            let _ = writeln!(s, "fn {}(p: vec3<f32>) -> SceneMaterial {{", f.name);
            s += &parts[0];
            match &index {
                Some((albedo, phong)) => {
                    let _ = writeln!(s, "    return SceneMaterial({albedo}, {phong});");
                }
                None => {
                    let _ = writeln!(s, "    return SceneMaterial({}, {});", r[0], r[1]);
                }
            }
        }
        FuncKind::Group => {
            // A culled half also takes the caller's best distance (`Op::Best`).
            let best = if reads_best(f) { " best: f32," } else { "" };
            let _ = writeln!(
                s,
                "fn {}(p: vec3<f32>,{best} with_material: bool) -> SceneSample {{",
                f.name
            );
            s += &parts[0];
            let _ = writeln!(
                s,
                "    var sample = SceneSample({}, vec4<f32>(0.0), vec4<f32>(0.0));",
                r[0]
            );
            s += "    if with_material {\n";
            s += &parts[1];
            match &index {
                Some((albedo, phong)) => {
                    let _ = writeln!(s, "        sample.albedo = {albedo};");
                    let _ = writeln!(s, "        sample.phong = {phong};");
                }
                None => {
                    let _ = writeln!(s, "        sample.albedo = {};", r[1]);
                    let _ = writeln!(s, "        sample.phong = {};", r[2]);
                }
            }
            s += "    }\n    return sample;\n";
        }
    }
    s += "}\n";
    s
}

/// Emits, as `let k{n} = select(..);`, the plan's index expressions that can be emitted
/// before node `next` (all nodes before it have their text); leaves are `u32` literals.
#[allow(clippy::too_many_arguments)]
fn emit_index(
    plan: &Plan,
    next: NodeId,
    text: &[String],
    first: &[bool],
    counters: &mut BTreeMap<&str, usize>,
    done: &mut Vec<String>,
    parts: &mut [String; 2],
) {
    while let Some(e) = plan.exprs.get(done.len()) {
        let t = match e {
            Index::Leaf(m) => format!("{}u", plan.local(m)),
            Index::Select {
                if_false,
                if_true,
                cond,
                ready,
            } => {
                if *ready >= next {
                    return;
                }
                let part = first[ready.index()];
                let indent = if part { "    " } else { "        " };
                let n = counters.entry("k").or_insert(0);
                let name = format!("k{n}");
                *n += 1;
                let _ = writeln!(
                    parts[usize::from(!part)],
                    "{indent}let {name} = select({}, {}, {});",
                    done[*if_false],
                    done[*if_true],
                    text[cond.index()]
                );
                name
            }
        };
        done.push(t);
    }
}

/// Points spelled where they are read rather than named by a `let`: a vec3 read once, as
/// an argument of a built-in, helper or constructor (so its text needs no parentheses), at
/// most two levels deep (`sd_box(rotate_y(p - c, cos, sin), b)`). A union of thousands of
/// transformed shapes has two such points per shape; naming each cost naga a tenth of its
/// parse.
fn inline_points(f: &Func, plan: Option<&Plan>) -> Vec<bool> {
    let g = &f.graph;
    let mut uses = vec![0u32; g.len()];
    let mut arg_uses = vec![0u32; g.len()];
    for (id, n) in g.nodes() {
        if plan.is_some_and(|p| p.replaced[id.index()]) {
            continue;
        }
        let as_argument = matches!(n.op, Op::Builtin(_) | Op::Helper(_) | Op::MakeVec);
        for a in n.args() {
            uses[a.index()] += 1;
            arg_uses[a.index()] += u32::from(as_argument);
        }
    }
    for r in &f.results {
        uses[r.index()] += 1;
    }
    let mut depth = vec![0u8; g.len()];
    let mut out = vec![false; g.len()];
    for (id, n) in g.nodes() {
        let i = id.index();
        let inner = n.args().iter().map(|a| depth[a.index()]).max().unwrap_or(0);
        if n.ty == Ty::Vec3
            && uses[i] == 1
            && arg_uses[i] == 1
            && inner < 2
            && !matches!(n.op, Op::Call { .. })
        {
            out[i] = true;
            depth[i] = inner + 1;
        }
    }
    out
}

/// The albedo and phong of the plan's material `k`, as `let`s of select chains over the
/// materials it picks from (`k == i` picks material `i`); returns their names or constants.
/// Not an array read: indexing a constant array at run time made lavapipe take twice as
/// long to build the 1 000-shape grid's pipeline.
fn lookup(
    plan: &Plan,
    k: &str,
    consts: &Consts,
    counters: &mut BTreeMap<&str, usize>,
    out: &mut String,
    indent: &str,
) -> (String, String) {
    let mut chain = |part: fn(&material_index::Material) -> [u32; 4]| {
        // At `k == i` every earlier `k == j` is false, so the chain so far gives material
        // 0's vector: material `i` needs a select only where its vector differs from that.
        let first = part(&plan.locals[0]);
        let mut acc = consts.spell_v4(&first);
        for (i, m) in plan.locals.iter().enumerate().skip(1) {
            if part(m) != first {
                let n = counters.entry("m").or_insert(0);
                let name = format!("m{n}");
                *n += 1;
                let v = consts.spell_v4(&part(m));
                let _ = writeln!(out, "{indent}let {name} = select({acc}, {v}, {k} == {i}u);");
                acc = name;
            }
        }
        acc
    };
    let albedo = chain(|m| m.0);
    (albedo, chain(|m| m.1))
}

/// Whether a group function reads its caller's best distance, and so takes it as a parameter.
pub fn reads_best(f: &Func) -> bool {
    f.graph.nodes().any(|(_, n)| n.op == Op::Best)
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
fn expression(
    g: &Graph,
    id: NodeId,
    a: &[&str],
    consts: &Consts,
    template: Option<(&[Ty], usize)>,
) -> (String, bool) {
    let node = g.node(id);
    let bin = |sym: &str| format!("{} {sym} {}", operand(a[0]), operand(a[1]));
    match node.op {
        Op::Const(c) => {
            let v = c.to_value();
            let text = consts
                .name(&v)
                .map_or_else(|| literal::value(&v), str::to_string);
            (text, true)
        }
        Op::Point => ("p".into(), true),
        Op::Ray => ("rd".into(), true),
        Op::Time => ("scene_time".into(), true),
        Op::Best => ("best".into(), true),
        Op::Param(i) => {
            let sw = match node.ty {
                Ty::F32 => "x",
                Ty::Vec2 => "xy",
                _ => "xyz",
            };
            match template {
                // The argument's words, loaded once into a `let`.
                Some((tys, _)) => {
                    let at: usize = tys[..i as usize].iter().map(|t| t.width()).sum();
                    let word = |k: usize| {
                        let (v, lane) = crate::instances::arg_word(at + k);
                        format!("a{v}.{}", ["x", "y", "z", "w"][lane])
                    };
                    let text = match node.ty {
                        Ty::F32 => format!("bitcast<f32>({})", word(0)),
                        _ => format!(
                            "bitcast<vec3<f32>>(vec3<u32>({}, {}, {}))",
                            word(0),
                            word(1),
                            word(2)
                        ),
                    };
                    (text, false)
                }
                None => (format!("scene_params[{i}].{sw}"), true),
            }
        }
        // Only reachable if a lambda argument escaped substitution; zero keeps WGSL valid.
        Op::LambdaArg { .. } => (literal::value(&sdfc_ir::eval::zero_of(node.ty)), true),
        // Calls are emitted by `emit`, once per group, argument and part.
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
