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

    #[test]
    fn deterministic_and_varied() {
        let a = noise([1.3f32, 2.7, -0.4]);
        assert_eq!(a, noise([1.3f32, 2.7, -0.4]));
        assert_ne!(a, noise([1.3f32, 2.7, 0.4]));
    }
}
