// Mandelbulb of a whole power n (the classic 8), the same estimate as sd_mandelbulb without
// trigonometry: the angles' cosines and sines come from the orbit point itself
// (cos θ = y / r, sin θ = ρ / r, cos φ = x / ρ, sin φ = z / ρ with ρ = |(x, z)|), and
// (cos θ + i sin θ)^n, (cos φ + i sin φ)^n and r^n are raised by repeated squaring. Only
// multiplications, divisions and square roots are left, each rounded to half an ulp, where a
// device's acos, atan2, pow, sin and cos are allowed several ulps; the chaotic orbit then
// amplifies less error (measured in docs/accuracy.md). One iteration is a function of its
// own, as in sd_mandelbulb.
fn sd_mandelbulb_int(p: vec3<f32>, n: f32, iterations: f32, bound: f32) -> f32 {
    let lp = length(p);
    if lp > 1.25 * bound {
        return lp - bound;
    }
    var o = MandelbulbIntOrbit(p, 1.0, lp);
    let count = u32(iterations);
    for (var i = 0u; i < count && o.r <= 2.0; i = i + 1u) {
        o = mandelbulb_int_step(o, p, n);
    }
    return mandelbulb_int_estimate(o);
}

// The orbit of a point between iterations: the point, the running derivative, its radius.
struct MandelbulbIntOrbit {
    z: vec3<f32>,
    dr: f32,
    r: f32,
}

fn mandelbulb_int_step(o: MandelbulbIntOrbit, p: vec3<f32>, n: f32) -> MandelbulbIntOrbit {
    let rs = max(o.r, 1e-20);
    let rho = length(o.z.xz);
    let theta = vec2<f32>(clamp(o.z.y / rs, -1.0, 1.0), rho / rs);
    var phi = vec2<f32>(1.0, 0.0);
    if rho > 0.0 {
        phi = o.z.xz / rho;
    }
    let raised = mandelbulb_raise(MandelbulbPowers(theta, phi, rs), u32(n));
    let dr = n * (raised.radius / rs) * o.dr + 1.0;
    let z = raised.radius * vec3<f32>(raised.theta.y * raised.phi.x, raised.theta.x, raised.theta.y * raised.phi.y) + p;
    return MandelbulbIntOrbit(z, dr, length(z));
}

fn mandelbulb_int_estimate(o: MandelbulbIntOrbit) -> f32 {
    let rf = max(o.r, 1e-20);
    return 0.5 * log(rf) * rf / o.dr;
}

// Two unit complex numbers and a radius, raised together.
struct MandelbulbPowers {
    theta: vec2<f32>,
    phi: vec2<f32>,
    radius: f32,
}

// base^n by repeated squaring over the five bits of a power up to 16, written out rather
// than looped (the interpreter runs a whole step per trip of its loop; see sd_mandelbulb).
// A bit above the power's highest is 0 and multiplies nothing in.
fn mandelbulb_raise(base: MandelbulbPowers, n: u32) -> MandelbulbPowers {
    var b = base;
    var acc = MandelbulbPowers(vec2<f32>(1.0, 0.0), vec2<f32>(1.0, 0.0), 1.0);
    acc = mandelbulb_bit(acc, b, (n & 1u) != 0u);
    b = mandelbulb_mul(b, b);
    acc = mandelbulb_bit(acc, b, (n & 2u) != 0u);
    b = mandelbulb_mul(b, b);
    acc = mandelbulb_bit(acc, b, (n & 4u) != 0u);
    b = mandelbulb_mul(b, b);
    acc = mandelbulb_bit(acc, b, (n & 8u) != 0u);
    b = mandelbulb_mul(b, b);
    return mandelbulb_bit(acc, b, (n & 16u) != 0u);
}

fn mandelbulb_bit(acc: MandelbulbPowers, b: MandelbulbPowers, bit: bool) -> MandelbulbPowers {
    if bit {
        return mandelbulb_mul(acc, b);
    }
    return acc;
}

fn mandelbulb_mul(a: MandelbulbPowers, b: MandelbulbPowers) -> MandelbulbPowers {
    return MandelbulbPowers(mandelbulb_cmul(a.theta, b.theta), mandelbulb_cmul(a.phi, b.phi), a.radius * b.radius);
}

// The product of two complex numbers (real, imaginary).
fn mandelbulb_cmul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}
