// Hard shadow: 0 if the segment from ro along rd (unit) up to tmax meets a surface, else 1.
// The ray stops once it is outside the scene's bounds and heading away from them: the box is
// convex, so it never comes back, and every surface lies in it.
fn shadow(ro: vec3<f32>, rd: vec3<f32>, tmax: f32) -> f32 {
    var light = 1.0;
    var t = 0.0;
    for (var i = 0u; i < MAX_STEPS; i = i + 1u) {
        if t >= tmax {
            break;
        }
        let q = ro + rd * t;
        let step = shadow_sampled(&light, scene_distance(q), t);
        if light <= 0.0 {
            return 0.0;
        }
        if dot(bounds_outside(q), rd) > 0.0 {
            break;
        }
        t = t + step;
    }
    return light;
}
