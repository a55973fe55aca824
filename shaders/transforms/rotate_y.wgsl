// The point in the frame of a shape turned about y (cosine c, sine s of the shape's angle).
fn rotate_y(p: vec3<f32>, c: f32, s: f32) -> vec3<f32> {
    return vec3<f32>(c * p.x - s * p.z, p.y, s * p.x + c * p.z);
}
