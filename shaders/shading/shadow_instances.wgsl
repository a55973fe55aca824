// The shadow of a union read as data: the shadow ray's list (`ray_start`, each box padded by
// SHADOW_REACH times the t of its far side, so that no instance outside it could darken the
// ray), and each listed instance marched alone over its stretch (`shadow_sampled`: a hard
// shadow's hit, or a soft shadow's narrowest cone), after a mixed union's other children
// alone (`shadow_rest`, emitted in place of the first line). The walk at every step
// (`scene_distance`) cost more than the code's whole union: with hard shadows the 300-shape
// grid on a floor drew 7.5x slower than without on lavapipe (docs/performance.md, "Shadow
// rays through the ray's list"). A full list lists again from the first node it left out
// (`ray_resume`); the order does not matter, every listed instance darkens alone. Each
// stretch has MAX_STEPS samples of its own. The list and its state are the shadow ray's
// from here on: the normal and the material at the point shaded were taken before.
fn shadow(ro: vec3<f32>, rd: vec3<f32>, tmax: f32) -> f32 {
    var light = 1.0;
    var start = 0u;
    loop {
        // (Dark already, from the other children: no list.)
        if light <= 0.0 {
            return 0.0;
        }
        ray_start(ro, rd, 0.0, tmax, 0.0, SHADOW_REACH, start);
        // The list's next entry, the instance being marched, where along the ray and where
        // its stretch ends, and its samples so far.
        var k = 0u;
        var leaf = 0u;
        var t = 0.0;
        var stop = -1.0;
        var taken = 0u;
        loop {
            if light <= 0.0 {
                return 0.0;
            }
            if t > stop || taken >= MAX_STEPS {
                if k >= ray_n {
                    break;
                }
                leaf = ray_leaf[k];
                t = ray_in[k];
                stop = ray_out[k];
                taken = 0u;
                k = k + 1u;
            }
            let h = instance_distance(ro + rd * t, leaf);
            taken = taken + 1u;
            t = t + shadow_sampled(&light, h, t);
        }
        if ray_resume == NO_RESUME {
            break;
        }
        start = ray_resume;
    }
    return clamp(light, 0.0, 1.0);
}
