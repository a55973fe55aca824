// Ambient occlusion: compares the distance at AO_SAMPLES points along the normal with the
// distance an open surface would have there; nearer samples weigh more (AO_FALLOFF per
// step). The sum is normalised by its largest possible value, so `strength: 1` darkens a
// fully enclosed point to black whatever the step size.
fn ambient_occlusion(p: vec3<f32>, n: vec3<f32>) -> f32 {
    var occlusion = 0.0;
    var most = 0.0;
    var weight = 1.0;
    // A falloff above 1 weighs the far samples more: then the loop starts at the far end,
    // so that the weights fall from 1 either way (falloff^i from the near end overflowed to
    // infinity, and infinity times a zero occlusion is NaN: black pixels).
    let reverse = AO_FALLOFF > 1.0;
    let factor = select(AO_FALLOFF, 1.0 / AO_FALLOFF, reverse);
    for (var j = 0u; j < AO_SAMPLES; j = j + 1u) {
        let i = select(j + 1u, AO_SAMPLES - j, reverse);
        let h = AO_STEP * f32(i);
        let d = scene_distance(p + n * h);
        occlusion = occlusion + weight * clamp(h - d, 0.0, h);
        most = most + weight * h;
        weight = weight * factor;
    }
    return clamp(1.0 - AO_STRENGTH * occlusion / most, 0.0, 1.0);
}
