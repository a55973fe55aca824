// Capsule around the segment a-b with radius r (exact). A zero-length segment is a sphere:
// the division is guarded rather than left to produce NaN.
fn sd_capsule(p: vec3<f32>, a: vec3<f32>, b: vec3<f32>, r: f32) -> f32 {
    let pa = p - a;
    let ba = b - a;
    let h = clamp(dot(pa, ba) / max(dot(ba, ba), 1e-30), 0.0, 1.0);
    return length(pa - ba * h) - r;
}
