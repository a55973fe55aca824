// Pyramid with the base [-0.5, 0.5]^2 on y = 0 and its apex at (0, h, 0) (exact). Folded so
// that x >= z >= 0, the nearest faces are the base and the +x side. Inside: the depth below
// the nearer of the two planes. Outside: the nearer of the two face polygons, the side face
// measured in its own plane coordinates (u along its base edge, v up the face, w normal).
fn sd_pyramid(p: vec3<f32>, h: f32) -> f32 {
    let ax = abs(p.x);
    let az = abs(p.z);
    let x = max(ax, az);
    let z = min(ax, az);
    let y = p.y;
    let sv = sqrt(0.25 + h * h);
    let u = z;
    let v = (-0.5 * (x - 0.5) + h * y) / sv;
    let w = (h * (x - 0.5) + 0.5 * y) / sv;
    if y >= 0.0 && w <= 0.0 {
        return -min(y, -w);
    }
    let base = length(vec3<f32>(max(x - 0.5, 0.0), y, max(z - 0.5, 0.0)));
    var t = 0.0;
    if !(v >= 0.0 && u * sv + 0.5 * v <= 0.5 * sv) {
        let pa = vec2<f32>(u - 0.5, v);
        let e = vec2<f32>(-0.5, sv);
        let s = clamp(dot(pa, e) / dot(e, e), 0.0, 1.0);
        t = min(length(vec2<f32>(max(u - 0.5, 0.0), v)), length(pa - e * s));
    }
    return min(base, length(vec2<f32>(t, w)));
}
