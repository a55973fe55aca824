// Normal from forward differences (four samples: p, then one step along each axis), the
// distance function inlined once (see tetrahedron.wgsl).
fn scene_normal(p: vec3<f32>, h: f32) -> vec3<f32> {
    var d0 = 0.0;
    var n = vec3<f32>(0.0);
    for (var i = 0u; i < 4u; i = i + 1u) {
        var e = vec3<f32>(0.0);
        if i > 0u {
            e[i - 1u] = h;
        }
        let d = scene_distance(p + e);
        if i == 0u {
            d0 = d;
        } else {
            n[i - 1u] = d - d0;
        }
    }
    return safe_normalize(n);
}
