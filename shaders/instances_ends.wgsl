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
// it: the instance nearest the end (the material's, and the one the tetrahedron normal
// samples, `normal_sample`) and the central and forward normals' samples.
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
// masks), so the union drew 1.07x to 1.09x faster on lavapipe, the same pictures
// (docs/performance.md, "The normal from the nearest instance"). Leaf 0 is rare: where the
// walk answers at the end (`ray_walk`) and a node out of its reach gives the best distance,
// its box's (an instance smaller than the threshold, far off), with no hint before it, or
// where every distance is NaN or infinite. Every sample is then 0, and `safe_normalize`
// gives the normal its fixed direction; leaf 0 is read as 1 (words at the data's start, in
// the buffer, their value discarded), since `select` computes both of its sides.
fn normal_sample(p: vec3<f32>, leaf: u32) -> f32 {
    return select(0.0, instance_distance(p, max(leaf, 1u)), leaf != 0u);
}
