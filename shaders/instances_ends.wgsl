// The signed distance from p to the scene, anywhere (shadows, ambient occlusion): the walk.
// The march samples `march_distance` instead.
fn scene_distance(p: vec3<f32>) -> f32 {
    return scene_nearest(p, 3.0e38).distance;
}

// The material at a surface point p, where a march ended: the nearest instance's
// (`end_leaf`).
fn scene_material(p: vec3<f32>) -> SceneMaterial {
    let leaf = end_leaf(p);
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

// The union's distance near the march's end (`ray_nearest`), and the instance that gives
// it: the normal's samples and the material.
fn normal_nearest(p: vec3<f32>) -> Nearest {
    return ray_nearest(p, 3.0e38);
}

// The distance the normal at the march's end samples.
fn normal_distance(p: vec3<f32>) -> f32 {
    return normal_nearest(p).distance;
}
