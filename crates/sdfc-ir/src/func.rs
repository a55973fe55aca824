//! A scalar SSA function: a graph plus the nodes it returns.

use crate::graph::{Graph, NodeId};

/// `scene_distance(p) -> f32` or `scene_material(p) -> SceneMaterial`, as a DAG over the
/// input `p` (`Op::Point`), the params and time.
#[derive(Clone, Debug)]
pub struct Func {
    pub name: String,
    pub kind: FuncKind,
    pub graph: Graph,
    pub results: Vec<NodeId>,
}

/// What a function returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FuncKind {
    /// One result: the distance.
    Distance,
    /// `scene_distance_ray(p, rd)`: the distance for marching along `rd`, one result.
    DistanceRay,
    /// `scene_material`: albedo and phong.
    Material,
    /// A group of a large union: distance, albedo and phong. Callers that need only the
    /// distance (result 0) skip the material part.
    Group,
    /// `scene_gradient` and the groups' gradient functions (`diff`): the distance and the
    /// x, y and z components of its gradient with respect to p, four results.
    Gradient,
}
