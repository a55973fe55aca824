// The primary ray of spec section 8 through image position `xy` (pixel units, from the top
// left corner) of an image of `size` pixels.
fn camera_ray(xy: vec2<f32>, size: vec2<f32>) -> vec3<f32> {
    let sx = 2.0 * xy.x / size.x - 1.0;
    let sy = 1.0 - 2.0 * xy.y / size.y;
    let aspect = size.x / size.y;
    return normalize(CAMERA_FORWARD + sx * TAN_HALF_FOV * aspect * CAMERA_RIGHT + sy * TAN_HALF_FOV * CAMERA_UP);
}
