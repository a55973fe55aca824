// A hard shadow ray's sample h at t: dark (`light` 0) within 1e-5 (1 + t) of a surface; the
// step is h.
fn shadow_sampled(light: ptr<function, f32>, h: f32, t: f32) -> f32 {
    if h < 1e-5 * (1.0 + t) {
        *light = 0.0;
    }
    return h;
}
