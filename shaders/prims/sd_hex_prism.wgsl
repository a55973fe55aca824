// Hexagonal prism along z: inradius r (flat faces at y = +-r), half length h (exact).
// The 0-60 degree wedge is reflected onto the 60-120 one, whose nearest side is the top.
fn sd_hex_prism(p: vec3<f32>, r: f32, h: f32) -> f32 {
    let n = vec2<f32>(-0.86602540378443865, 0.5);
    var q = abs(p.xy);
    q = q - 2.0 * min(dot(n, q), 0.0) * n;
    let half_side = r * 0.57735026918962576;
    var d2 = length(vec2<f32>(q.x - clamp(q.x, -half_side, half_side), q.y - r));
    if q.y < r {
        d2 = -d2;
    }
    let dz = abs(p.z) - h;
    return min(max(d2, dz), 0.0) + length(max(vec2<f32>(d2, dz), vec2<f32>(0.0)));
}
