// Soft shadow (Quilez): the narrowest cone around the shadow ray that the scene leaves free,
// relative to SHADOW_K; 1 is fully lit, 0 fully shadowed. Steps never shrink below a small
// fraction of t, so grazing rays cannot stall.
fn shadow(ro: vec3<f32>, rd: vec3<f32>, tmax: f32) -> f32 {
    var light = 1.0;
    var t = 0.0;
    for (var i = 0u; i < MAX_STEPS; i = i + 1u) {
        if t >= tmax {
            break;
        }
        let h = scene_distance(ro + rd * t);
        light = min(light, SHADOW_K * h / max(t, 1e-6));
        if light <= 0.0 {
            return 0.0;
        }
        t = t + max(h, 1e-3 * t + 1e-5);
    }
    return clamp(light, 0.0, 1.0);
}
