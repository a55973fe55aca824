// The result of marching one ray.
struct Hit {
    t: f32,
    steps: u32,
    hit: bool,
}

// Takes up to four plain steps from a point already within the surface threshold. For an
// exact distance each step removes most of the remaining error; a step that would cross the
// surface (negative distance) is taken too, since it moves back onto it.
fn refine(ro: vec3<f32>, rd: vec3<f32>, t0: f32, d0: f32, steps0: u32) -> Hit {
    var t = t0 + d0;
    var steps = steps0;
    for (var i = 0u; i < 4u; i = i + 1u) {
        let d = scene_distance(ro + rd * t);
        steps = steps + 1u;
        t = t + d;
        if abs(d) <= 1e-7 * max(t, 1.0) {
            break;
        }
    }
    return Hit(t, steps, true);
}
