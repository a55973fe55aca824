//! The text of `sdfc compile --explain`: the scene's exactness and Lipschitz bound, then one
//! line per shape node whose distance is not exact, with its line and column (materials and
//! rigid motions, which only pass their child's on, are left out).

use super::{Analysis, Exactness, Source};
use crate::scene::Scene;
use crate::shape::{PointMap, ShapeKind};
use sdfc_syntax::diag::line_col;
use std::fmt::Write;

/// A short name for a shape node.
fn kind_name(kind: &ShapeKind) -> String {
    match kind {
        ShapeKind::Prim { prim, .. } => prim.name().into(),
        ShapeKind::Sdf { .. } => "sdf".into(),
        ShapeKind::Displace { .. } => "displace".into(),
        ShapeKind::Warp { map, .. } => map.name().into(),
        ShapeKind::Heightfield { .. } => "heightfield".into(),
        ShapeKind::Combine { op, smooth, .. } => {
            format!(
                "{}{}",
                op.name(),
                if smooth.is_some() { " (smooth)" } else { "" }
            )
        }
        ShapeKind::Map { map, .. } => match map {
            PointMap::Affine { .. } => "transform".into(),
            PointMap::Mirror(_) => "mirror".into(),
            PointMap::Repeat { .. } | PointMap::RepeatLimited { .. } => "repeat".into(),
            PointMap::Elongate(_) => "elongate".into(),
        },
        ShapeKind::Modify { modifier, .. } => match modifier {
            crate::shape::DistMod::Round(_) => "round".into(),
            crate::shape::DistMod::Onion(_) => "onion".into(),
        },
        ShapeKind::Material { .. } => "material".into(),
    }
}

/// The explanation, reachable nodes in source order.
pub fn explain(scene: &Scene, analysis: &Analysis, source: &str) -> String {
    let mut out = String::new();
    let root = &analysis.nodes[scene.root.index()];
    let normalising = analysis.nodes.iter().filter(|n| n.normalises).count();
    let largest = analysis
        .nodes
        .iter()
        .filter_map(|n| n.lipschitz)
        .fold(1.0, f64::max);
    let _ = writeln!(
        out,
        "scene: {}, L = 1 ({})",
        root.exactness.name(),
        if normalising == 0 {
            "no bound-only node".to_string()
        } else {
            format!(
                "{normalising} bound-only node(s) divide by their own L, the largest {largest:.4}"
            )
        }
    );
    if root.exactness == Exactness::Neither {
        let _ = writeln!(
            out,
            "  a repeated shape that does not fit its cell may hide a nearer copy"
        );
    }
    let mut lines: Vec<(u32, String)> = Vec::new();
    for (i, info) in analysis.nodes.iter().enumerate() {
        if info.exactness == Exactness::Exact {
            continue;
        }
        let node = &scene.shapes[i];
        // Materials and rigid motions pass their child's exactness on: nothing to add.
        if matches!(
            node.kind,
            ShapeKind::Material { .. }
                | ShapeKind::Map {
                    map: PointMap::Affine { .. },
                    ..
                }
        ) {
            continue;
        }
        let (line, col) = line_col(source, node.span.start as usize);
        let mut s = format!(
            "{line}:{col}: {}: {}",
            kind_name(&node.kind),
            info.exactness.name()
        );
        if info.normalises {
            let src = match info.source {
                Some(Source::Declared) => "declared",
                Some(Source::Default) => "the default",
                Some(Source::Symbolic) => "per point, this inside the child's bounds",
                _ => "derived",
            };
            match info.lipschitz {
                Some(l) => {
                    let _ = write!(s, ", L = {l:.4} ({src}), divided at the node");
                }
                None => {
                    let _ = write!(s, ", L depends on a param (bounded at run time)");
                }
            }
        }
        lines.push((node.span.start, s));
    }
    lines.sort();
    lines.dedup();
    for (_, l) in lines {
        let _ = writeln!(out, "{l}");
    }
    out
}
