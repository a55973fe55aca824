//! Whether a scene's distance is dear enough that its march refines in the stepping loop
//! (`shaders/march_merged.wgsl`, one inlined copy of the distance) rather than in a loop of
//! its own (`shaders/march_two_loops.wgsl`, two copies). llvmpipe runs a loop's first trip and an
//! `if`'s body under masks where no lane needs them: the second copy costs a masked distance
//! once a march, the merged loop refinement's arithmetic at every step. Measured on lavapipe
//! (docs/performance.md, "The marcher's two loops"): merged, the 300-shape union's code drew
//! 1.31x to 1.34x faster, terrain (six octaves of noise) 1.07x to 1.09x, the fractals 1.11x
//! to 1.14x; spec section 10 (28 nodes) 0.77x, the ribbed sphere (15) 0.74x, `sphere_box`
//! (34) 0.82x.

use sdfc_ir::func::Func;
use sdfc_ir::graph::NodeId;
use sdfc_ir::ops::{Helper, Op};

/// The cost from which a distance is dear: well above the cheap scenes measured (15 to 34)
/// and below terrain's (about 400) and a union of a few dozen shapes.
pub const DEAR: usize = 256;

/// A node's cost, in plain operations: one, but a noise sample (eight gradients, a hash
/// each) and a fractal's iterations cost many.
fn op_cost(op: Op) -> usize {
    match op {
        Op::Helper(Helper::Noise | Helper::NoiseGradient) => 64,
        Op::Helper(
            Helper::SdMandelbulb
            | Helper::SdMandelbulbInt
            | Helper::SdMenger
            | Helper::SdSierpinski,
        ) => 256,
        _ => 1,
    }
}

/// The cost of evaluating `f` once: its nodes that its results depend on, and each group
/// function it calls (`groups`, by index) at each of its call nodes. Stops counting at
/// `limit`, so a union of thousands is not walked whole to learn that it is dear.
pub fn cost(f: &Func, groups: &[Func], limit: usize) -> usize {
    let graph = &f.graph;
    let mut seen = vec![false; graph.len()];
    let mut stack: Vec<NodeId> = f.results.clone();
    let mut total = 0;
    while let Some(id) = stack.pop() {
        if total >= limit {
            break;
        }
        let Some(slot) = seen.get_mut(id.index()) else {
            continue;
        };
        if *slot {
            continue;
        }
        *slot = true;
        let node = graph.node(id);
        total += op_cost(node.op);
        if let Op::Call { func, .. } = node.op {
            if let Some(g) = groups.get(func as usize) {
                total += cost(g, groups, limit.saturating_sub(total));
            }
        }
        stack.extend_from_slice(node.args.as_slice());
    }
    total
}

/// Whether marching `f` (with its `groups`) should refine in the stepping loop.
pub fn is_dear(f: &Func, groups: &[Func]) -> bool {
    cost(f, groups, DEAR) >= DEAR
}

#[cfg(test)]
mod tests {
    use super::{cost, is_dear, DEAR};

    fn distance(source: &str) -> (sdfc_ir::func::Func, Vec<sdfc_ir::func::Func>) {
        let p = crate::lower(source, &crate::Options::default())
            .unwrap_or_else(|_| panic!("{source}"))
            .stages
            .program;
        (p.distance, p.groups)
    }

    #[test]
    fn a_few_shapes_are_cheap_and_noise_a_fractal_or_many_shapes_dear() {
        let (f, g) = distance("scene = sphere(1) | box([1, 2, 3]).translate([2, 0, 0]);");
        assert!(!is_dear(&f, &g), "cost {}", cost(&f, &g, usize::MAX));
        let (f, g) = distance(
            "scene = sphere(1) | plane([0, 1, 0], 0).displace(|p| 0.1 * fbm(p, octaves: 6));",
        );
        assert!(is_dear(&f, &g), "cost {}", cost(&f, &g, usize::MAX));
        let (f, g) = distance("scene = mandelbulb(power: 8, iterations: 8);");
        assert!(is_dear(&f, &g), "cost {}", cost(&f, &g, usize::MAX));
        let many: Vec<String> = (0..64)
            .map(|i| format!("sphere(0.3).translate([{i}, 0, 0])"))
            .collect();
        let (f, g) = distance(&format!("scene = union({});", many.join(", ")));
        assert!(is_dear(&f, &g), "cost {}", cost(&f, &g, usize::MAX));
    }

    #[test]
    fn counting_stops_at_the_limit() {
        let many: Vec<String> = (0..500)
            .map(|i| format!("box([0.3, 0.2, 0.1]).translate([{i}, 0, 0])"))
            .collect();
        let (f, g) = distance(&format!("scene = union({});", many.join(", ")));
        let c = cost(&f, &g, DEAR);
        assert!((DEAR..DEAR + 300).contains(&c), "cost {c}");
    }
}
