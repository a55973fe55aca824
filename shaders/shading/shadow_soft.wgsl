// Soft shadow (Quilez): the narrowest cone around the shadow ray that the scene leaves free,
// relative to SHADOW_K (`shadow_sampled`); 1 is fully lit, 0 fully shadowed.
//
// The ray stops once the cone has left the scene's bounds for good. Outside the (convex) box
// the scene's distance is at least OUTSIDE_FACTOR times the distance to the box (1 for an
// exact distance), and that times SHADOW_K, g(t), is convex along the ray: where g exceeds t
// and grows at least 1 per unit of t, it stays above t' at every t' beyond, so no sample
// there could lower the light. A ray towards a light above a floor used to march on to
// MAX_DISTANCE through empty sky (docs/performance.md, "Shadow rays stop at the bounds").
fn shadow(ro: vec3<f32>, rd: vec3<f32>, tmax: f32) -> f32 {
    let reach = SHADOW_K * OUTSIDE_FACTOR;
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
        let v = bounds_outside(q);
        let out = length(v);
        if reach * out > t && reach * dot(v, rd) >= out {
            break;
        }
        t = t + step;
    }
    return clamp(light, 0.0, 1.0);
}
