// Menger sponge in [-0.5, 0.5]^3, worked in the doubled frame [-1, 1]^3: the box, minus at
// each level the cross of square bars of half width 1/3 in every cell (cells folded by a
// mirrored repetition). The max of exact distances: a bound with the exact sign.
fn sd_menger_bar(u: f32, v: f32) -> f32 {
    let b = vec2<f32>(u, v) - vec2<f32>(1.0 / 3.0);
    return length(max(b, vec2<f32>(0.0))) + min(max(b.x, b.y), 0.0);
}

fn sd_menger(p: vec3<f32>, iterations: f32) -> f32 {
    let q = 2.0 * p;
    let o = abs(q) - vec3<f32>(1.0);
    var d = length(max(o, vec3<f32>(0.0))) + min(max(o.x, max(o.y, o.z)), 0.0);
    var s = 1.0;
    let count = u32(iterations);
    for (var i = 0u; i < count; i = i + 1u) {
        let t = q * s + vec3<f32>(1.0);
        let a = abs(t - 2.0 * floor(t * 0.5) - vec3<f32>(1.0));
        let holes = min(min(sd_menger_bar(a.x, a.y), sd_menger_bar(a.y, a.z)), sd_menger_bar(a.z, a.x));
        d = max(d, -holes / s);
        s = s * 3.0;
    }
    return 0.5 * d;
}
