// Torus in the xz plane: major radius R, tube radius r (exact).
fn sd_torus(p: vec3<f32>, R: f32, r: f32) -> f32 {
    let q = vec2<f32>(length(p.xz) - R, p.y);
    return length(q) - r;
}
