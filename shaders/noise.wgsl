// 3D gradient noise (Perlin's improved noise with an integer hash instead of a permutation
// table): smooth (quintic fade), deterministic, in [-1, 1]. The CPU evaluator computes the
// same hash bit for bit and the same float arithmetic.
fn noise_hash(x: i32, y: i32, z: i32) -> u32 {
    // WGSL gives `*` and `^` no relative precedence: browsers (Tint) reject them unbracketed.
    var h = (bitcast<u32>(x) * 73856093u) ^ (bitcast<u32>(y) * 19349663u)
        ^ (bitcast<u32>(z) * 83492791u);
    h = h ^ (h >> 16u);
    h = h * 0x7feb352du;
    h = h ^ (h >> 15u);
    h = h * 0x846ca68bu;
    h = h ^ (h >> 16u);
    return h;
}

// The dot product of corner (x, y, z)'s gradient (one of Perlin's 12 edge directions) with
// the offset f from that corner.
fn noise_grad(x: i32, y: i32, z: i32, f: vec3<f32>) -> f32 {
    let h = noise_hash(x, y, z) & 15u;
    let u = select(f.y, f.x, h < 8u);
    let v = select(select(f.z, f.x, h == 12u || h == 14u), f.y, h < 4u);
    return select(-u, u, (h & 1u) == 0u) + select(-v, v, (h & 2u) == 0u);
}

fn noise_fade(t: vec3<f32>) -> vec3<f32> {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

fn noise(p: vec3<f32>) -> f32 {
    let fl = floor(p);
    let i = vec3<i32>(fl);
    let f = p - fl;
    let w = noise_fade(f);
    let x0 = mix(noise_grad(i.x, i.y, i.z, f), noise_grad(i.x + 1, i.y, i.z, f - vec3<f32>(1.0, 0.0, 0.0)), w.x);
    let x1 = mix(noise_grad(i.x, i.y + 1, i.z, f - vec3<f32>(0.0, 1.0, 0.0)), noise_grad(i.x + 1, i.y + 1, i.z, f - vec3<f32>(1.0, 1.0, 0.0)), w.x);
    let x2 = mix(noise_grad(i.x, i.y, i.z + 1, f - vec3<f32>(0.0, 0.0, 1.0)), noise_grad(i.x + 1, i.y, i.z + 1, f - vec3<f32>(1.0, 0.0, 1.0)), w.x);
    let x3 = mix(noise_grad(i.x, i.y + 1, i.z + 1, f - vec3<f32>(0.0, 1.0, 1.0)), noise_grad(i.x + 1, i.y + 1, i.z + 1, f - vec3<f32>(1.0)), w.x);
    return clamp(mix(mix(x0, x1, w.y), mix(x2, x3, w.y), w.z), -1.0, 1.0);
}
