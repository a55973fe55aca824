// A lower bound of the distance to the ellipsoid with semi-axes r: the larger of two
// 1-Lipschitz functions negative exactly inside, (|p / r| - 1) * min(r) and the bounding
// sphere's |p| - max(r). Radii below 1e-6 count as 1e-6 (a constant 0 is an error; a param
// may be 0), so that nothing divides by zero and |p / r| stays far from f32 overflow.
fn sd_ellipsoid(p: vec3<f32>, radii: vec3<f32>) -> f32 {
    let r = max(radii, vec3<f32>(1e-6));
    let d1 = (length(p / r) - 1.0) * min(r.x, min(r.y, r.z));
    let d2 = length(p) - max(r.x, max(r.y, r.z));
    return max(d1, d2);
}
