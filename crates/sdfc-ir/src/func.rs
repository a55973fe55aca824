//! A scalar SSA function: a graph plus the nodes it returns.

use crate::graph::{Graph, NodeId};

/// `scene_distance(p) -> f32` or `scene_material(p) -> SceneMaterial`, as a DAG over the
/// input `p` (`Op::Point`), the params and time.
#[derive(Clone, Debug)]
pub struct Func {
    pub name: &'static str,
    pub graph: Graph,
    pub results: Vec<NodeId>,
}
