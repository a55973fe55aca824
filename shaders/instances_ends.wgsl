// The signed distance from p to the scene (the march loop calls only this).
fn scene_distance(p: vec3<f32>) -> f32 {
    return scene_nearest(p, 3.0e38).distance;
}

// The material at a surface point p: the nearest instance's (called once per hit).
fn scene_material(p: vec3<f32>) -> SceneMaterial {
    let leaf = scene_nearest(p, 3.0e38).leaf;
    var material = 0u;
    if leaf != 0u {
        material = scene_data[leaf + 1u].y;
    }
    return material_by_index(material);
}
