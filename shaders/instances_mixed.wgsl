// The signed distance from p to the scene, anywhere (soft shadows where no padding of their
// lists can hold their cones, `shadows.rs` in sdfc-wgsl). The other children's distance
// comes first: the walk then skips every part no nearer than it. The march takes the other
// children alone (`march_rest`), then each listed instance alone
// (`shaders/march_instances.wgsl`), and ambient occlusion its own list
// (`shaders/shading/ambient_occlusion_list.wgsl`).
fn scene_distance(p: vec3<f32>) -> f32 {
    return scene_nearest(p, rest_distance(p), 0.0).distance;
}

// The material at a surface point p, where a march ended: the instance's it hit
// (`end_leaf`), or the other children's where it hit them (leaf 0).
fn scene_material(p: vec3<f32>) -> SceneMaterial {
    let leaf = end_leaf(p);
    if leaf == 0u {
        return rest_material(p);
    }
    return material_by_index(scene_data[leaf + 1u].y);
}

// The union's distance near the march's end: the other children's, and the instances the
// ray's list holds there (`ray_nearest`), with the instance that gives it (0 if none is
// nearer): the central and forward normals' samples.
fn normal_nearest(p: vec3<f32>) -> Nearest {
    return ray_nearest(p, ray_hit, rest_distance(p), false);
}

// The distance the normal at the march's end samples.
fn normal_distance(p: vec3<f32>) -> f32 {
    return normal_nearest(p).distance;
}

// The normal's samples about the march's end (the tetrahedron's, `scene_normal`): the
// distance of what the march hit alone (`leaf`, `ray_end_leaf`): an instance, or the other
// children (leaf 0; also a miss, whose normal nothing reads). Both are computed and one kept:
// on lavapipe an `if` runs its body under masks whatever the lanes need, and the instance's
// distance is cheap. Leaf 0 is read as 1, in the buffer.
fn normal_sample(p: vec3<f32>, leaf: u32) -> f32 {
    return select(rest_distance(p), instance_distance(p, max(leaf, 1u)), leaf != 0u);
}
