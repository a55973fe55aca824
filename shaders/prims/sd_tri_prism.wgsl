// Triangular prism along z (exact): an equilateral triangle of inradius r pointing to +y,
// centroid on the axis (vertices (0, 2r) and (+-sqrt(3) r, -r)), half length h. With x
// folded, the distance to the bottom edge and the right edge, negative inside.
fn sd_tri_prism(p: vec3<f32>, r: f32, h: f32) -> f32 {
    let x = abs(p.x);
    let y = p.y;
    let c = 1.7320508075688772 * r;
    let bottom = length(vec2<f32>(max(x - c, 0.0), y + r));
    let pa = vec2<f32>(x - c, y + r);
    let e = vec2<f32>(-c, 3.0 * r);
    let t = clamp(dot(pa, e) / max(dot(e, e), 1e-30), 0.0, 1.0);
    let side = length(pa - e * t);
    var d2 = min(bottom, side);
    if y >= -r && 0.86602540378443865 * x + 0.5 * y <= r {
        d2 = -d2;
    }
    let dz = abs(p.z) - h;
    return min(max(d2, dz), 0.0) + length(max(vec2<f32>(d2, dz), vec2<f32>(0.0)));
}
