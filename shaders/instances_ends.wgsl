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

// The normal's samples about the march's end (the tetrahedron's, `scene_normal`): the
// distance of the instance nearest the end (`leaf`, from `normal_nearest` there) alone. Its
// surface is the union's within the normal's step of the end but where another instance
// comes that close (a crease, where the union's differences would blend the two); a sample
// through the ray's list cost a copy of the list's loop (on lavapipe every copy runs, under
// masks), so the 300-shape grid drew 1.07x to 1.08x faster, the same pictures
// (docs/performance.md, "The normal from the nearest instance"). Leaf 0 (no instance's
// distance below 3e38: NaN or infinite) is read as 1, words at the data's start, so that no
// sample reads outside the buffer; the normal is then meaningless, as the union's would be
// (`safe_normalize` gives any such normal a direction).
fn normal_sample(p: vec3<f32>, leaf: u32) -> f32 {
    return instance_distance(p, max(leaf, 1u));
}
