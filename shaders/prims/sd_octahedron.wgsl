// The octahedron |x| + |y| + |z| <= s (exact). Inside, the depth below the face plane;
// outside, the plane distance, or the distance to the edge across which the point's
// projection leaves the face triangle.
fn sd_octahedron(p: vec3<f32>, s: f32) -> f32 {
    let a = abs(p);
    let m = a.x + a.y + a.z - s;
    var q: vec3<f32>;
    if 3.0 * a.x < m {
        q = a;
    } else if 3.0 * a.y < m {
        q = a.yzx;
    } else if 3.0 * a.z < m {
        q = a.zxy;
    } else {
        return m * 0.57735026918962576;
    }
    let k = clamp(0.5 * (q.z - q.y + s), 0.0, s);
    return length(vec3<f32>(q.x, q.y - s + k, q.z - k));
}
