// Normal from central differences (six samples), one axis per iteration: the distance
// function is inlined once here rather than six times (see tetrahedron.wgsl).
fn scene_normal(p: vec3<f32>, h: f32) -> vec3<f32> {
    var n = vec3<f32>(0.0);
    for (var i = 0u; i < 6u; i = i + 1u) {
        var e = vec3<f32>(0.0);
        e[i / 2u] = select(h, -h, (i & 1u) != 0u);
        let d = scene_distance(p + e);
        n[i / 2u] = select(d, n[i / 2u] - d, (i & 1u) != 0u);
    }
    return safe_normalize(n);
}
