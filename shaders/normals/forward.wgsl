// Normal from forward differences (four samples).
fn scene_normal(p: vec3<f32>, h: f32) -> vec3<f32> {
    let d = scene_distance(p);
    let n = vec3<f32>(
        scene_distance(p + vec3<f32>(h, 0.0, 0.0)) - d,
        scene_distance(p + vec3<f32>(0.0, h, 0.0)) - d,
        scene_distance(p + vec3<f32>(0.0, 0.0, h)) - d,
    );
    return safe_normalize(n);
}
