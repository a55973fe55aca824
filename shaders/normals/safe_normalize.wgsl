// normalize() of a zero vector is undefined in WGSL; a flat gradient gets the +y normal
// instead of NaN.
fn safe_normalize(v: vec3<f32>) -> vec3<f32> {
    let l2 = dot(v, v);
    if l2 > 1e-30 {
        return v * inverseSqrt(l2);
    }
    return vec3<f32>(0.0, 1.0, 0.0);
}
