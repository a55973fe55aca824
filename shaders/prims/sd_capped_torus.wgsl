// Torus arc in the xy plane: major radius ra, tube rb, covering the angles within the
// half-angle (sc = its sine and cosine; the angle in [0, pi]) of +y (exact). Beyond the
// arc's end the nearest point of the centre circle is the end point ra * sc.
fn sd_capped_torus(p: vec3<f32>, sc: vec2<f32>, ra: f32, rb: f32) -> f32 {
    let x = abs(p.x);
    var k = length(vec2<f32>(x, p.y));
    if sc.y * x > sc.x * p.y {
        k = x * sc.x + p.y * sc.y;
    }
    return sqrt(max(dot(p, p) + ra * ra - 2.0 * ra * k, 0.0)) - rb;
}
