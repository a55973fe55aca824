// Ambient occlusion of a union read as data: one list for all the samples, and each sample
// takes only the listed instances that can be nearer than its height (`ray_nearest`). A
// sample at height h needs no distance above h (`clamp(h - d, 0, h)`), so an instance counts
// there only if its box comes within h of the sample: the sample's point p + n h lies in the
// box grown by h. As h grows the point moves by h and the box grows by h on every axis, so
// once in, the point stays in: each box has one height from which it counts (`ao_enter`),
// and the list holds those from no higher than the highest sample, sorted. Past a full list's
// cut the walk answers. A walk at each sample cost more than the march: on lavapipe `ao()`
// took the 300-shape grid on a floor from 7.0 to 16.3 ms a frame, and the list drew it 1.75x
// faster (docs/performance.md, "Ambient occlusion through one list"); samples that reach
// farther than 0.8 of the instances' spacing keep the walk (`occlusion.rs` in sdfc-wgsl).
// The list is ambient occlusion's from here on: the normal and the material were taken
// before, and shadow rays make their own.
fn ao_list(p: vec3<f32>, n: vec3<f32>) {
    let top = AO_STEP * f32(AO_SAMPLES);
    // 1 / (1 + n) and 1 / (1 - n), each at most 1e30 (n is a unit vector, give or take
    // rounding).
    let up = 1.0 / max(1.0 + n, vec3<f32>(1e-30));
    let down = 1.0 / max(1.0 - n, vec3<f32>(1e-30));
    var count = 0u;
    var cut = 3.0e38;
    let end = scene_data[0].w;
    var i = 0u;
    loop {
        if i >= end {
            break;
        }
        let a = scene_data[2u * i];
        let b = scene_data[2u * i + 1u];
        let enter = ao_enter(bitcast<vec3<f32>>(a.xyz) - p, bitcast<vec3<f32>>(b.xyz), up, down);
        // A subtree's boxes lie in its node's, so none counts lower than the node.
        if enter > top {
            i = a.w;
            continue;
        }
        if count == RAY_LIST || enter >= cut {
            cut = min(cut, enter);
            i = a.w;
            continue;
        }
        if b.w == 0u {
            i = i + 1u;
            continue;
        }
        ray_in[count] = enter;
        ray_out[count] = top;
        ray_leaf[count] = b.w;
        count = count + 1u;
        i = a.w;
    }
    ray_sort(count);
    ray_pixel = 0.0;
    ray_n = count;
    ray_lo = 0.0;
    ray_cut = cut;
    ray_resume = NO_RESUME;
}

// The least height h from which p + n h lies in a box (centre p + v, half size `half`, and
// 1e-3 for rounding) grown by h on every axis: on each axis |n h - v| <= half + h, that is
// h (1 + n) >= v - half and h (1 - n) >= -v - half (`up`, `down`: their inverses; where
// 1 + n or 1 - n is 0 the bound is a large negative number, clamped to 0, or, where the box
// is beyond, 1e30 times its distance: never).
fn ao_enter(v: vec3<f32>, half: vec3<f32>, up: vec3<f32>, down: vec3<f32>) -> f32 {
    let grown = half + 1e-3;
    let least = max((v - grown) * up, (-v - grown) * down);
    return max(max(least.x, least.y), max(least.z, 0.0));
}

// The scene's distance at q, h along the normal, or h where it is no nearer.
fn ao_below(q: vec3<f32>, h: f32) -> f32 {
    return ray_nearest(q, h, h, true).distance;
}
