// Menger sponge in [-0.5, 0.5]^3, worked in the doubled frame [-1, 1]^3: the box, minus at
// each level the cross of square bars of half width 1/3 in every cell (cells folded by a
// mirrored repetition). The max of exact distances: a bound with the exact sign.
fn sd_menger_bar(u: f32, v: f32) -> f32 {
    let b = vec2<f32>(u, v) - vec2<f32>(1.0 / 3.0);
    return length(max(b, vec2<f32>(0.0))) + min(max(b.x, b.y), 0.0);
}

fn sd_menger(p: vec3<f32>, iterations: f32) -> f32 {
    var o = menger_start(p);
    let count = u32(iterations);
    for (var i = 0u; i < count; i = i + 1u) {
        o = menger_step(o, p);
    }
    return 0.5 * o.dist;
}

// The sponge between levels: the distance so far (doubled frame) and the level's scale.
struct MengerLevel {
    dist: f32,
    s: f32,
}

fn menger_start(p: vec3<f32>) -> MengerLevel {
    let o = abs(2.0 * p) - vec3<f32>(1.0);
    return MengerLevel(length(max(o, vec3<f32>(0.0))) + min(max(o.x, max(o.y, o.z)), 0.0), 1.0);
}

// One level: a function of its own, so that the interpreter can run one per trip of its
// loop (see sd_mandelbulb).
fn menger_step(o: MengerLevel, p: vec3<f32>) -> MengerLevel {
    let t = 2.0 * p * o.s + vec3<f32>(1.0);
    let a = abs(t - 2.0 * floor(t * 0.5) - vec3<f32>(1.0));
    let holes = min(min(sd_menger_bar(a.x, a.y), sd_menger_bar(a.y, a.z)), sd_menger_bar(a.z, a.x));
    return MengerLevel(max(o.dist, -holes / o.s), o.s * 3.0);
}
