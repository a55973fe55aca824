// Torus arc in the xy plane: major radius ra, tube rb, covering the angles within the
// half-angle (sc = its sine and cosine; the angle in [0, pi]) of +y (exact). Within the arc
// the nearest point of the centre circle is the one above the point; beyond the arc's end
// it is the end point ra * sc. (Two lengths rather than iq's sqrt(|p|^2 + ra^2 - 2 ra k),
// which cancels badly in f32 near the centre circle.)
fn sd_capped_torus(p: vec3<f32>, sc: vec2<f32>, ra: f32, rb: f32) -> f32 {
    let q = vec3<f32>(abs(p.x), p.y, p.z);
    if sc.y * q.x > sc.x * q.y {
        return length(q - vec3<f32>(ra * sc, 0.0)) - rb;
    }
    return length(vec2<f32>(length(q.xy) - ra, q.z)) - rb;
}
