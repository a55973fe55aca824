// Hard shadow: 0 if the segment from ro along rd (unit) up to tmax meets a surface, else 1.
fn shadow(ro: vec3<f32>, rd: vec3<f32>, tmax: f32) -> f32 {
    var t = 0.0;
    for (var i = 0u; i < MAX_STEPS; i = i + 1u) {
        if t >= tmax {
            break;
        }
        let h = scene_distance(ro + rd * t);
        if h < 1e-5 * (1.0 + t) {
            return 0.0;
        }
        t = t + h;
    }
    return 1.0;
}
