// Frustum along y from -h (radius r1) to h (radius r2); a cone when r2 is 0 (exact). In the
// half-plane (radius, y): the distance to the bottom, top and slanted edges, negative inside.
fn sd_capped_cone(p: vec3<f32>, h: f32, r1: f32, r2: f32) -> f32 {
    let x = length(p.xz);
    let y = p.y;
    let bottom = length(vec2<f32>(max(x - r1, 0.0), y + h));
    let top = length(vec2<f32>(max(x - r2, 0.0), y - h));
    let pa = vec2<f32>(x - r1, y + h);
    let e = vec2<f32>(r2 - r1, 2.0 * h);
    let t = clamp(dot(pa, e) / max(dot(e, e), 1e-30), 0.0, 1.0);
    let side = length(pa - e * t);
    let d = min(min(bottom, top), side);
    if abs(y) <= h && x * (2.0 * h) <= r1 * (h - y) + r2 * (h + y) {
        return -d;
    }
    return d;
}
