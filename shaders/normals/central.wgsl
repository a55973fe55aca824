// Normal from central differences (six samples).
fn scene_normal(p: vec3<f32>, h: f32) -> vec3<f32> {
    let ex = vec3<f32>(h, 0.0, 0.0);
    let ey = vec3<f32>(0.0, h, 0.0);
    let ez = vec3<f32>(0.0, 0.0, h);
    let n = vec3<f32>(
        scene_distance(p + ex) - scene_distance(p - ex),
        scene_distance(p + ey) - scene_distance(p - ey),
        scene_distance(p + ez) - scene_distance(p - ez),
    );
    return safe_normalize(n);
}
