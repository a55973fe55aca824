// The signed distance from p to the scene (the march loop calls only this). The other
// children's distance comes first: the walk then skips every part no nearer than it.
fn scene_distance(p: vec3<f32>) -> f32 {
    return scene_nearest(p, rest_distance(p)).distance;
}

// The material at a surface point p: the nearest instance's, or the other children's where
// no instance is nearer (called once per hit).
fn scene_material(p: vec3<f32>) -> SceneMaterial {
    let leaf = scene_nearest(p, rest_distance(p)).leaf;
    if leaf == 0u {
        return rest_material(p);
    }
    return material_by_index(scene_data[leaf + 1u].y);
}
