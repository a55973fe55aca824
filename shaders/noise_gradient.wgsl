// The gradient of `noise` at p (for `normals: analytic`): the derivative of the same trilinear
// blend of the same corner gradients with the same quintic fade; zero where the value is
// clamped to [-1, 1]. Uses `noise_hash` and `noise_fade` from the noise part.
fn noise_corner(x: i32, y: i32, z: i32) -> vec3<f32> {
    let h = noise_hash(x, y, z) & 15u;
    let su = select(-1.0, 1.0, (h & 1u) == 0u);
    let sv = select(-1.0, 1.0, (h & 2u) == 0u);
    // As `noise_grad`: u is f.x below 8, else f.y; v is f.y below 4, f.x for 12 and 14,
    // else f.z.
    let eu = select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), h < 8u);
    let ev = select(select(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(1.0, 0.0, 0.0), h == 12u || h == 14u), vec3<f32>(0.0, 1.0, 0.0), h < 4u);
    return su * eu + sv * ev;
}

fn noise_gradient(p: vec3<f32>) -> vec3<f32> {
    let fl = floor(p);
    let i = vec3<i32>(fl);
    let f = p - fl;
    let w = noise_fade(f);
    let dw = 30.0 * f * f * (f * (f - 2.0) + 1.0);
    // Corner (dx, dy, dz): its gradient g and value dot(g, f - (dx, dy, dz)).
    var v: array<f32, 8>;
    var g: array<vec3<f32>, 8>;
    for (var c = 0; c < 8; c = c + 1) {
        let o = vec3<i32>(c & 1, (c >> 1u) & 1, (c >> 2u) & 1);
        g[c] = noise_corner(i.x + o.x, i.y + o.y, i.z + o.z);
        v[c] = dot(g[c], f - vec3<f32>(o));
    }
    // Blend along x (pairs 0-1, 2-3, 4-5, 6-7), then y, then z, carrying the derivative.
    var v2: array<f32, 4>;
    var g2: array<vec3<f32>, 4>;
    for (var k = 0; k < 4; k = k + 1) {
        v2[k] = mix(v[2 * k], v[2 * k + 1], w.x);
        g2[k] = mix(g[2 * k], g[2 * k + 1], w.x) + vec3<f32>((v[2 * k + 1] - v[2 * k]) * dw.x, 0.0, 0.0);
    }
    let vy0 = mix(v2[0], v2[1], w.y);
    let vy1 = mix(v2[2], v2[3], w.y);
    let gy0 = mix(g2[0], g2[1], w.y) + vec3<f32>(0.0, (v2[1] - v2[0]) * dw.y, 0.0);
    let gy1 = mix(g2[2], g2[3], w.y) + vec3<f32>(0.0, (v2[3] - v2[2]) * dw.y, 0.0);
    let n = mix(vy0, vy1, w.z);
    let gn = mix(gy0, gy1, w.z) + vec3<f32>(0.0, 0.0, (vy1 - vy0) * dw.z);
    return select(gn, vec3<f32>(0.0), abs(n) > 1.0);
}
