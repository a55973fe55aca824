// Mandelbulb of a whole power n (the classic 8), the same estimate as sd_mandelbulb without
// trigonometry: the angles' cosines and sines come from the orbit point itself
// (cos θ = y / r, sin θ = ρ / r, cos φ = x / ρ, sin φ = z / ρ with ρ = |(x, z)|), and
// (cos θ + i sin θ)^n, (cos φ + i sin φ)^n and r^n are raised by repeated squaring. Only
// multiplications, divisions and square roots are left, each rounded to half an ulp, where a
// device's acos, atan2, pow, sin and cos are allowed several ulps; the chaotic orbit then
// amplifies less error (measured in docs/accuracy.md).
fn sd_mandelbulb_int(p: vec3<f32>, n: f32, iterations: f32, bound: f32) -> f32 {
    let lp = length(p);
    if lp > 1.25 * bound {
        return lp - bound;
    }
    let power = u32(n);
    var z = p;
    var dr = 1.0;
    var r = lp;
    let count = u32(iterations);
    for (var i = 0u; i < count && r <= 2.0; i = i + 1u) {
        let rs = max(r, 1e-20);
        let rho = length(z.xz);
        var theta = vec2<f32>(clamp(z.y / rs, -1.0, 1.0), rho / rs);
        var phi = vec2<f32>(1.0, 0.0);
        if rho > 0.0 {
            phi = z.xz / rho;
        }
        var radius = rs;
        var theta_n = vec2<f32>(1.0, 0.0);
        var phi_n = vec2<f32>(1.0, 0.0);
        var radius_n = 1.0;
        for (var e = power; e > 0u; e = e >> 1u) {
            if (e & 1u) == 1u {
                theta_n = mandelbulb_cmul(theta_n, theta);
                phi_n = mandelbulb_cmul(phi_n, phi);
                radius_n = radius_n * radius;
            }
            theta = mandelbulb_cmul(theta, theta);
            phi = mandelbulb_cmul(phi, phi);
            radius = radius * radius;
        }
        dr = n * (radius_n / rs) * dr + 1.0;
        z = radius_n * vec3<f32>(theta_n.y * phi_n.x, theta_n.x, theta_n.y * phi_n.y) + p;
        r = length(z);
    }
    let rf = max(r, 1e-20);
    return 0.5 * log(rf) * rf / dr;
}

// The product of two complex numbers (real, imaginary), for sd_mandelbulb_int.
fn mandelbulb_cmul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}
