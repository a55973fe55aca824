// Capped cylinder along y: radius r, half height h (exact).
fn sd_cylinder(p: vec3<f32>, r: f32, h: f32) -> f32 {
    let d = vec2<f32>(abs(length(p.xz)) - r, abs(p.y) - h);
    return min(max(d.x, d.y), 0.0) + length(max(d, vec2<f32>(0.0)));
}
