// Sphere of radius r at the origin (exact).
fn sd_sphere(p: vec3<f32>, r: f32) -> f32 {
    return length(p) - r;
}
