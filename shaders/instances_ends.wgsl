// The signed distance from p to the scene, anywhere (shadows, ambient occlusion): the walk.
// The march samples `march_distance` instead.
fn scene_distance(p: vec3<f32>) -> f32 {
    return scene_nearest(p, 3.0e38).distance;
}

// The material at a surface point p, where a march ended: the nearest instance's
// (`ray_nearest`).
fn scene_material(p: vec3<f32>) -> SceneMaterial {
    let leaf = ray_nearest(p, 3.0e38).leaf;
    var material = 0u;
    if leaf != 0u {
        material = scene_data[leaf + 1u].y;
    }
    return material_by_index(material);
}

// The march's distance at p, t along the ray being marched (`ray_distance`).
fn march_distance(p: vec3<f32>, t: f32) -> f32 {
    return ray_distance(p, t, 3.0e38);
}

// The distance the normal at the march's end samples (`ray_nearest`).
fn normal_distance(p: vec3<f32>) -> f32 {
    return ray_nearest(p, 3.0e38).distance;
}
