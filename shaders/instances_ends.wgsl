// The signed distance from p to the scene, anywhere (soft shadows where no padding of their
// lists can hold their cones, `shadows.rs` in sdfc-wgsl): the walk. The march takes each
// listed instance alone instead (`shaders/march_instances.wgsl`), and ambient occlusion its
// own list (`shaders/shading/ambient_occlusion_list.wgsl`).
fn scene_distance(p: vec3<f32>) -> f32 {
    return scene_nearest(p, 3.0e38, 0.0).distance;
}

// The material at a surface point p, where a march ended: the instance's it hit
// (`end_leaf`).
fn scene_material(p: vec3<f32>) -> SceneMaterial {
    let leaf = end_leaf(p);
    var material = 0u;
    if leaf != 0u {
        material = scene_data[leaf + 1u].y;
    }
    return material_by_index(material);
}

// The union's distance near the march's end (`ray_nearest`), and the instance that gives
// it: the central and forward normals' samples.
fn normal_nearest(p: vec3<f32>) -> Nearest {
    return ray_nearest(p, ray_hit, 3.0e38, false);
}

// The distance the normal at the march's end samples.
fn normal_distance(p: vec3<f32>) -> f32 {
    return normal_nearest(p).distance;
}

// The normal's samples about the march's end (the tetrahedron's, `scene_normal`): the
// distance of the instance the march hit (`leaf`, `ray_end_leaf`) alone. Its surface is the
// union's within the normal's step of the end but where another instance comes that close
// (a crease, where the union's differences would blend the two); a sample through the ray's
// list cost a copy of the list's loop (on lavapipe every copy runs, under masks), so the
// union drew 1.07x to 1.09x faster on lavapipe, the same pictures (docs/performance.md, "The
// normal from the nearest instance"). A hit always has its instance; leaf 0 (a miss, whose
// normal nothing reads) gives samples of 0, read as leaf 1 (words at the data's start, in the
// buffer, their value discarded), since `select` computes both of its sides.
fn normal_sample(p: vec3<f32>, leaf: u32) -> f32 {
    return select(0.0, instance_distance(p, max(leaf, 1u)), leaf != 0u);
}
