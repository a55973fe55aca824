// Normal from four samples at the vertices of a tetrahedron (iq).
fn scene_normal(p: vec3<f32>, h: f32) -> vec3<f32> {
    let k = vec2<f32>(1.0, -1.0);
    let n = k.xyy * scene_distance(p + k.xyy * h)
        + k.yyx * scene_distance(p + k.yyx * h)
        + k.yxy * scene_distance(p + k.yxy * h)
        + k.xxx * scene_distance(p + k.xxx * h);
    return safe_normalize(n);
}
