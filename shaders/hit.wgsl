// The result of marching one ray.
struct Hit {
    t: f32,
    steps: u32,
    hit: bool,
}

// Refines a hit found within the surface threshold with up to four secant steps on the
// distance along the ray. Each step is kept on the far side of the plain step t + d: a
// distance bound never overestimates, so the surface along the ray is at least that far
// (behind, when d < 0). A plain step alone converges slowly where the ray meets the surface
// at a grazing angle; the secant converges fast there too.
fn refine(ro: vec3<f32>, rd: vec3<f32>, t0: f32, d0: f32, steps0: u32) -> Hit {
    var ta = t0;
    var da = d0;
    var t = t0 + d0;
    var d = scene_distance(ro + rd * t);
    var steps = steps0 + 1u;
    for (var i = 0u; i < 4u; i = i + 1u) {
        if abs(d) <= 1e-7 * max(t, 1.0) {
            break;
        }
        var next = t + d;
        let slope = d - da;
        if abs(slope) > 1e-30 {
            let secant = t - d * (t - ta) / slope;
            // On the same side as the plain step, and no closer than it.
            // Beyond the plain step (the surface is at least that far), at most 16 times it.
            if d > 0.0 && secant > next {
                next = min(secant, t + 16.0 * d);
            } else if d < 0.0 && secant < next {
                next = max(secant, t + 16.0 * d);
            }
        }
        ta = t;
        da = d;
        t = next;
        d = scene_distance(ro + rd * t);
        steps = steps + 1u;
    }
    return Hit(t, steps, true);
}
