//! 3D gradient noise, computed exactly as `shaders/noise.wgsl` computes it: the same integer
//! hash (bit for bit) and the same float operations in the same order.

use crate::value::Float;

fn hash(x: i32, y: i32, z: i32) -> u32 {
    let mut h = (x as u32).wrapping_mul(73856093)
        ^ (y as u32).wrapping_mul(19349663)
        ^ (z as u32).wrapping_mul(83492791);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846ca68b);
    h ^= h >> 16;
    h
}

fn grad<T: Float>(x: i32, y: i32, z: i32, f: [T; 3]) -> T {
    let h = hash(x, y, z) & 15;
    let u = if h < 8 { f[0] } else { f[1] };
    let v = if h < 4 {
        f[1]
    } else if h == 12 || h == 14 {
        f[0]
    } else {
        f[2]
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

fn fade<T: Float>(t: T) -> T {
    let c = |x: f64| T::from_f64(x);
    t * t * t * (t * (t * c(6.0) - c(15.0)) + c(10.0))
}

fn mix<T: Float>(a: T, b: T, t: T) -> T {
    a * (T::one() - t) + b * t
}

/// Gradient noise at `p`, in [-1, 1].
pub fn noise<T: Float>(p: [T; 3]) -> T {
    let fl = p.map(|x| x.floor());
    // WGSL's float-to-i32 conversion saturates, as Rust's `as` does.
    let i = fl.map(|x| x.to_f64() as i32);
    let f = [p[0] - fl[0], p[1] - fl[1], p[2] - fl[2]];
    let w = f.map(fade);
    let one = T::one();
    let zero = T::zero();
    let off = |dx: T, dy: T, dz: T| [f[0] - dx, f[1] - dy, f[2] - dz];
    let g = |dx: i32, dy: i32, dz: i32, o: [T; 3]| {
        grad(
            i[0].wrapping_add(dx),
            i[1].wrapping_add(dy),
            i[2].wrapping_add(dz),
            o,
        )
    };
    let x0 = mix(g(0, 0, 0, f), g(1, 0, 0, off(one, zero, zero)), w[0]);
    let x1 = mix(
        g(0, 1, 0, off(zero, one, zero)),
        g(1, 1, 0, off(one, one, zero)),
        w[0],
    );
    let x2 = mix(
        g(0, 0, 1, off(zero, zero, one)),
        g(1, 0, 1, off(one, zero, one)),
        w[0],
    );
    let x3 = mix(
        g(0, 1, 1, off(zero, one, one)),
        g(1, 1, 1, off(one, one, one)),
        w[0],
    );
    mix(mix(x0, x1, w[1]), mix(x2, x3, w[1]), w[2])
        .max(-one)
        .min(one)
}

/// The corner gradient `grad` dots with its offset: `grad(x, y, z, f) = corner(x, y, z) . f`.
fn corner<T: Float>(x: i32, y: i32, z: i32) -> [T; 3] {
    let h = hash(x, y, z) & 15;
    let (one, zero) = (T::one(), T::zero());
    let su = if h & 1 == 0 { one } else { -one };
    let sv = if h & 2 == 0 { one } else { -one };
    let mut g = [zero; 3];
    g[if h < 8 { 0 } else { 1 }] = su;
    let v = if h < 4 {
        1
    } else if h == 12 || h == 14 {
        0
    } else {
        2
    };
    g[v] = g[v] + sv;
    g
}

/// The gradient of [`noise`] at `p`, as `shaders/noise_gradient.wgsl` computes it: the
/// derivative of the same blend (zero where the value is clamped).
pub fn noise_gradient<T: Float>(p: [T; 3]) -> [T; 3] {
    let fl = p.map(|x| x.floor());
    let i = fl.map(|x| x.to_f64() as i32);
    let f = [p[0] - fl[0], p[1] - fl[1], p[2] - fl[2]];
    let w = f.map(fade);
    let c = |x: f64| T::from_f64(x);
    let dw = f.map(|t| c(30.0) * t * t * (t * (t - c(2.0)) + T::one()));
    let mut v = [T::zero(); 8];
    let mut g = [[T::zero(); 3]; 8];
    for k in 0..8 {
        let o = [k & 1, (k >> 1) & 1, (k >> 2) & 1];
        g[k] = corner(
            i[0].wrapping_add(o[0] as i32),
            i[1].wrapping_add(o[1] as i32),
            i[2].wrapping_add(o[2] as i32),
        );
        let off = [0, 1, 2].map(|a| f[a] - c(o[a] as f64));
        v[k] = g[k][0] * off[0] + g[k][1] * off[1] + g[k][2] * off[2];
    }
    let mixv = |a: [T; 3], b: [T; 3], t: T| [0, 1, 2].map(|k| mix(a[k], b[k], t));
    let mut v2 = [T::zero(); 4];
    let mut g2 = [[T::zero(); 3]; 4];
    for k in 0..4 {
        v2[k] = mix(v[2 * k], v[2 * k + 1], w[0]);
        g2[k] = mixv(g[2 * k], g[2 * k + 1], w[0]);
        g2[k][0] = g2[k][0] + (v[2 * k + 1] - v[2 * k]) * dw[0];
    }
    let (vy0, vy1) = (mix(v2[0], v2[1], w[1]), mix(v2[2], v2[3], w[1]));
    let mut gy0 = mixv(g2[0], g2[1], w[1]);
    gy0[1] = gy0[1] + (v2[1] - v2[0]) * dw[1];
    let mut gy1 = mixv(g2[2], g2[3], w[1]);
    gy1[1] = gy1[1] + (v2[3] - v2[2]) * dw[1];
    let n = mix(vy0, vy1, w[2]);
    let mut gn = mixv(gy0, gy1, w[2]);
    gn[2] = gn[2] + (vy1 - vy0) * dw[2];
    if n.abs() > T::one() {
        return [T::zero(); 3];
    }
    gn
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_at_lattice_points_smooth_and_bounded() {
        assert_eq!(noise([3.0f64, -2.0, 7.0]), 0.0);
        let mut max: f64 = 0.0;
        let mut prev = noise([0.0f64, 0.3, 0.7]);
        for k in 1..20000 {
            let x = k as f64 * 0.001;
            let v = noise([x, 0.3, 0.7]);
            // Lipschitz: gradient noise changes slowly.
            assert!((v - prev).abs() < 0.01, "jump at {x}");
            prev = v;
            max = max.max(v.abs());
        }
        assert!(max <= 1.0 && max > 0.2, "{max}");
    }

    /// The gradient against central differences of the noise in f64, across cells.
    #[test]
    fn gradient_matches_differences() {
        let mut worst: f64 = 0.0;
        for k in 0..4000 {
            let t = k as f64;
            let p = [
                (t * 0.7371).sin() * 9.3,
                (t * 1.3117).cos() * 7.1,
                (t * 0.4513).sin() * 5.7 + 0.3,
            ];
            let g = noise_gradient(p);
            let h = 1e-6;
            for a in 0..3 {
                let (mut x, mut y) = (p, p);
                x[a] += h;
                y[a] -= h;
                let fd = (noise(x) - noise(y)) / (2.0 * h);
                worst = worst.max((fd - g[a]).abs());
            }
        }
        assert!(worst < 1e-6, "noise gradient off by {worst:e}");
    }

    #[test]
    fn deterministic_and_varied() {
        let a = noise([1.3f32, 2.7, -0.4]);
        assert_eq!(a, noise([1.3f32, 2.7, -0.4]));
        assert_ne!(a, noise([1.3f32, 2.7, 0.4]));
    }
}
