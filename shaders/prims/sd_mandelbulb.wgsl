// Mandelbulb of power n (pole along y), `iterations` steps, bailout radius 2: the usual
// distance estimate 0.5 r ln(r) / dr. The set lies within radius `bound`; beyond 1.25 bound
// the distance to that sphere is returned without iterating (not beyond `bound` itself: the
// sphere's distance is 0 on the sphere, where the marcher would stop).
fn sd_mandelbulb(p: vec3<f32>, n: f32, iterations: f32, bound: f32) -> f32 {
    let lp = length(p);
    if lp > 1.25 * bound {
        return lp - bound;
    }
    var z = p;
    var dr = 1.0;
    var r = lp;
    let count = u32(iterations);
    for (var i = 0u; i < count && r <= 2.0; i = i + 1u) {
        let rs = max(r, 1e-20);
        let theta = acos(clamp(z.y / rs, -1.0, 1.0)) * n;
        let phi = atan2(z.z, z.x) * n;
        dr = n * pow(rs, n - 1.0) * dr + 1.0;
        let zr = pow(rs, n);
        z = zr * vec3<f32>(sin(theta) * cos(phi), cos(theta), sin(theta) * sin(phi)) + p;
        r = length(z);
    }
    let rf = max(r, 1e-20);
    return 0.5 * log(rf) * rf / dr;
}
