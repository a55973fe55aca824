// Mandelbulb of power n (pole along y), `iterations` steps, bailout radius 2: the usual
// distance estimate 0.5 r ln(r) / dr. The set lies within radius `bound`; beyond 1.25 bound
// the distance to that sphere is returned without iterating (not beyond `bound` itself: the
// sphere's distance is 0 on the sphere, where the marcher would stop). One iteration is a
// function of its own, so that the interpreter can run one per trip of its loop (a nested
// loop would cost lavapipe a trip of its loop budget per instruction, see interpret.wgsl).
fn sd_mandelbulb(p: vec3<f32>, n: f32, iterations: f32, bound: f32) -> f32 {
    let lp = length(p);
    if lp > 1.25 * bound {
        return lp - bound;
    }
    var o = MandelbulbOrbit(p, 1.0, lp);
    let count = u32(iterations);
    for (var i = 0u; i < count && o.r <= 2.0; i = i + 1u) {
        o = mandelbulb_step(o, p, n);
    }
    return mandelbulb_estimate(o);
}

// The orbit of a point between iterations: the point, the running derivative, its radius.
struct MandelbulbOrbit {
    z: vec3<f32>,
    dr: f32,
    r: f32,
}

fn mandelbulb_step(o: MandelbulbOrbit, p: vec3<f32>, n: f32) -> MandelbulbOrbit {
    let rs = max(o.r, 1e-20);
    let theta = acos(clamp(o.z.y / rs, -1.0, 1.0)) * n;
    let phi = atan2(o.z.z, o.z.x) * n;
    let dr = n * pow(rs, n - 1.0) * o.dr + 1.0;
    let zr = pow(rs, n);
    let z = zr * vec3<f32>(sin(theta) * cos(phi), cos(theta), sin(theta) * sin(phi)) + p;
    return MandelbulbOrbit(z, dr, length(z));
}

fn mandelbulb_estimate(o: MandelbulbOrbit) -> f32 {
    let rf = max(o.r, 1e-20);
    return 0.5 * log(rf) * rf / o.dr;
}
