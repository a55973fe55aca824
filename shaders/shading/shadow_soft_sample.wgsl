// A soft shadow ray's sample h at t (Quilez): `light` is the narrowest cone around the ray
// that the samples leave free, relative to SHADOW_K. Steps never shrink below a small
// fraction of t, so grazing rays cannot stall.
fn shadow_sampled(light: ptr<function, f32>, h: f32, t: f32) -> f32 {
    *light = min(*light, SHADOW_K * h / max(t, 1e-6));
    return max(h, 1e-3 * t + 1e-5);
}
