// The point in the frame of a shape turned about x (cosine c, sine s of the shape's angle).
fn rotate_x(p: vec3<f32>, c: f32, s: f32) -> vec3<f32> {
    return vec3<f32>(p.x, c * p.y + s * p.z, -s * p.y + c * p.z);
}
