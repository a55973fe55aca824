// Normal from four samples at the vertices of a tetrahedron (iq). A loop, so that the
// distance function is inlined once here rather than four times: drivers that inline every
// call (Mesa's do) build the pipeline that much faster. Sums in the same order as the
// unrolled form, so the result is the same.
fn scene_normal(p: vec3<f32>, h: f32) -> vec3<f32> {
    var k = array<vec3<f32>, 4>(
        vec3<f32>(1.0, -1.0, -1.0),
        vec3<f32>(-1.0, -1.0, 1.0),
        vec3<f32>(-1.0, 1.0, -1.0),
        vec3<f32>(1.0, 1.0, 1.0),
    );
    var n = vec3<f32>(0.0);
    for (var i = 0u; i < 4u; i = i + 1u) {
        n = n + k[i] * scene_distance(p + k[i] * h);
    }
    return safe_normalize(n);
}
