//! Deterministic text dumps of the IR for golden tests and `sdfc compile --emit`.

use crate::func::Func;
use crate::graph::{Graph, NodeId};
use crate::ops::Op;
use crate::scene::Scene;
use crate::shape::{Declared, PointMap, ShapeId, ShapeKind, WarpMap};
use crate::value::Value;
use std::fmt::Write;

/// A constant as text (shortest round-trip digits).
pub fn const_text(v: &Value<f32>) -> String {
    let f = |x: &f32| format!("{x:?}");
    match v {
        Value::F(x) => f(x),
        Value::B(b) => b.to_string(),
        Value::M3(m) => format!(
            "mat3[{}]",
            m.iter()
                .map(|c| c.iter().map(f).collect::<Vec<_>>().join(", "))
                .collect::<Vec<_>>()
                .join("; ")
        ),
        v => format!(
            "[{}]",
            v.comps().iter().map(f).collect::<Vec<_>>().join(", ")
        ),
    }
}

fn op_text(op: &Op) -> String {
    match op {
        Op::Const(c) => const_text(&c.to_value()),
        Op::Param(i) => format!("param {i}"),
        Op::LambdaArg { lambda, index } => format!("lambda{lambda}.arg{index}"),
        Op::Builtin(b) => b.name().to_string(),
        Op::Helper(h) => h.name().to_string(),
        Op::Swizzle(s) => format!("swizzle .{}", s.letters()),
        Op::Call { func, result } => format!("call group{func}.{result}"),
        other => format!("{other:?}").to_lowercase(),
    }
}

/// One line per node: `%id: type = op %args`.
pub fn graph_text(g: &Graph, only: Option<&[bool]>) -> String {
    let mut s = String::new();
    for (id, n) in g.nodes() {
        if only.is_some_and(|o| !o[id.index()]) {
            continue;
        }
        let args: Vec<String> = n.args().iter().map(|a| format!("%{}", a.0)).collect();
        let _ = writeln!(
            s,
            "  %{}: {} = {}{}{}",
            id.0,
            n.ty,
            op_text(&n.op),
            if args.is_empty() { "" } else { " " },
            args.join(", ")
        );
    }
    s
}

/// The optimised program as `sdfc compile --emit opt-ir` prints it: the scene, then
/// `scene_distance`, `scene_distance_ray` where there is one, and `scene_material`.
pub fn program_text(p: &crate::Program) -> String {
    let mut parts = vec![scene_text(&p.scene), func_text(&p.distance)];
    parts.extend(p.distance_ray.as_ref().map(func_text));
    parts.push(func_text(&p.material));
    parts.join("\n")
}

pub fn func_text(f: &Func) -> String {
    let mut s = format!("fn {} ({} nodes)\n", f.name, f.graph.len());
    s += &graph_text(&f.graph, None);
    let r: Vec<String> = f.results.iter().map(|r| format!("%{}", r.0)).collect();
    let _ = writeln!(s, "  return {}", r.join(", "));
    s
}

/// The scene: settings, materials, params, the shape tree and the value nodes it uses.
pub fn scene_text(scene: &Scene) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "camera {:?}", scene.camera);
    let _ = writeln!(s, "render {:?}", scene.render);
    for l in &scene.lights {
        let _ = writeln!(s, "light {l:?}");
    }
    for (i, m) in scene.materials.iter().enumerate() {
        let _ = writeln!(s, "material {i} {m:?}");
    }
    for (i, p) in scene.params.iter().enumerate() {
        let _ = writeln!(
            s,
            "param {i} {}: {} = {}",
            p.name,
            p.ty,
            const_text(&p.default)
        );
    }
    let _ = writeln!(s, "shapes");
    let mut used = vec![false; scene.values.len()];
    shape_text(scene, scene.root, 1, &mut s, &mut used);
    // Mark everything the shapes' nodes depend on.
    for i in (0..scene.values.len()).rev() {
        if used[i] {
            for a in scene.values.node(NodeId(i as u32)).args() {
                used[a.index()] = true;
            }
        }
    }
    let _ = writeln!(s, "values");
    s += &graph_text(&scene.values, Some(&used));
    s
}

fn shape_text(scene: &Scene, id: ShapeId, depth: usize, s: &mut String, used: &mut [bool]) {
    let pad = "  ".repeat(depth);
    let ids = |ns: &[NodeId], used: &mut [bool]| -> String {
        ns.iter()
            .map(|n| {
                used[n.index()] = true;
                format!("%{}", n.0)
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let node = scene.shape(id);
    let (line, kids): (String, Vec<ShapeId>) = match &node.kind {
        ShapeKind::Prim { prim, args } => (format!("{} {}", prim.name(), ids(args, used)), vec![]),
        ShapeKind::Sdf {
            body,
            lambda,
            lipschitz,
            ..
        } => (
            format!(
                "sdf lambda{lambda} body {} lipschitz {}",
                ids(&[*body], used),
                ids(&[*lipschitz], used)
            ),
            vec![],
        ),
        ShapeKind::Displace {
            child,
            body,
            lambda,
            lipschitz,
        } => (
            format!(
                "displace lambda{lambda} body {} lipschitz {}",
                ids(&[*body], used),
                declared_text(lipschitz, used)
            ),
            vec![*child],
        ),
        ShapeKind::Warp {
            map,
            child,
            lipschitz,
        } => {
            let arg = match map {
                WarpMap::Stretch(n) | WarpMap::Shear(n) | WarpMap::Twist(n) | WarpMap::Bend(n) => {
                    ids(&[*n], used)
                }
                WarpMap::Lambda { body, lambda } => {
                    format!("lambda{lambda} body {}", ids(&[*body], used))
                }
            };
            (
                format!(
                    "{} {arg} lipschitz {}",
                    map.name(),
                    declared_text(lipschitz, used)
                ),
                vec![*child],
            )
        }
        ShapeKind::Heightfield {
            body,
            lambda,
            lipschitz,
        } => (
            format!(
                "heightfield lambda{lambda} body {} lipschitz {}",
                ids(&[*body], used),
                declared_text(lipschitz, used)
            ),
            vec![],
        ),
        ShapeKind::Combine {
            op,
            smooth,
            children,
        } => {
            let k = smooth
                .map(|k| format!(" smooth {}", ids(&[k], used)))
                .unwrap_or_default();
            (format!("{}{k}", op.name()), children.clone())
        }
        ShapeKind::Map { map, child } => {
            let t = match map {
                PointMap::Affine { m, o, s: sc } => {
                    let part = |name: &str, n: &Option<NodeId>, used: &mut [bool]| {
                        n.map(|n| format!(" {name} {}", ids(&[n], used)))
                            .unwrap_or_default()
                    };
                    format!(
                        "affine{}{}{}",
                        part("m", m, used),
                        part("o", o, used),
                        part("s", sc, used)
                    )
                }
                PointMap::Mirror(a) => format!("mirror {}", ["x", "y", "z"][*a as usize]),
                PointMap::Repeat { period } => format!("repeat {period:?}"),
                PointMap::RepeatLimited { period, count } => {
                    format!("repeat {period:?} count {count:?}")
                }
                PointMap::Elongate(h) => format!("elongate {}", ids(&[*h], used)),
            };
            (t, vec![*child])
        }
        ShapeKind::Modify { modifier, child } => {
            let (name, n) = match modifier {
                crate::shape::DistMod::Round(n) => ("round", n),
                crate::shape::DistMod::Onion(n) => ("onion", n),
            };
            (format!("{name} {}", ids(&[*n], used)), vec![*child])
        }
        ShapeKind::Material { material, child } => (
            format!(
                "material {} ({})",
                material, scene.materials[*material as usize].name
            ),
            vec![*child],
        ),
    };
    let _ = writeln!(s, "{pad}{line}");
    for k in kids {
        shape_text(scene, k, depth + 1, s, used);
    }
}

/// A declared `lipschitz:` as its node, or `derived` when the compiler bounds it.
fn declared_text(d: &Declared, used: &mut [bool]) -> String {
    match d {
        Some((n, _)) => {
            used[n.index()] = true;
            format!("%{}", n.0)
        }
        None => "derived".into(),
    }
}
