//! Closed-form Lipschitz constants of the bound-only point maps: a linear map's spectral
//! norm (stretch, shear), and the twist's and the bend's over the region they act on.

/// The spectral norm of a 3x3 matrix (rows), from the largest eigenvalue of `A^T A` in
/// closed form, rounded up slightly so that it stays an upper bound (a diagonal `A^T A`
/// needs no margin: its largest entry is the eigenvalue).
pub fn spectral_norm(a: [[f64; 3]; 3]) -> f64 {
    let b = |i: usize, j: usize| (0..3).map(|k| a[k][i] * a[k][j]).sum::<f64>();
    let p1 = b(0, 1).powi(2) + b(0, 2).powi(2) + b(1, 2).powi(2);
    if p1 == 0.0 {
        return b(0, 0).max(b(1, 1)).max(b(2, 2)).sqrt();
    }
    let lambda = {
        let q = (b(0, 0) + b(1, 1) + b(2, 2)) / 3.0;
        let p2 = (b(0, 0) - q).powi(2) + (b(1, 1) - q).powi(2) + (b(2, 2) - q).powi(2) + 2.0 * p1;
        let p = (p2 / 6.0).sqrt();
        let n = |i: usize, j: usize| (b(i, j) - if i == j { q } else { 0.0 }) / p;
        let det = n(0, 0) * (n(1, 1) * n(2, 2) - n(1, 2) * n(2, 1))
            - n(0, 1) * (n(1, 0) * n(2, 2) - n(1, 2) * n(2, 0))
            + n(0, 2) * (n(1, 0) * n(2, 1) - n(1, 1) * n(2, 0));
        let phi = (det / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
        q + 2.0 * p * phi.cos()
    };
    lambda.max(0.0).sqrt() * (1.0 + 1e-9)
}

/// The rows of the inverse of the shear `x += kxy y + kxz z, y += kyz z`.
pub fn shear_inverse(k: [f64; 3]) -> [[f64; 3]; 3] {
    let [kxy, kxz, kyz] = k;
    [
        [1.0, -kxy, kxy * kyz - kxz],
        [0.0, 1.0, -kyz],
        [0.0, 0.0, 1.0],
    ]
}

/// The Lipschitz constant of the twist map `p -> rot_y(-k p.y) p` where `|k| r <= kr`:
/// its Jacobian is `[[R, k w], [0, 1]]` with `|w| = r`, whose largest singular value is
/// `t + sqrt(1 + t^2)` with `t = |k| r / 2`.
pub fn twist_lipschitz(kr: f64) -> f64 {
    let t = kr.abs() * 0.5;
    t + (1.0 + t * t).sqrt()
}

/// The Lipschitz constant of the bend map (a rotation about z by `k p.x`) where
/// `|k| sqrt(x^2 + y^2) <= kr`: its Jacobian is a rotation times `I + u e_x^T` with
/// `|u| = kr`, whose norm is at most `1 + kr`.
pub fn bend_lipschitz(kr: f64) -> f64 {
    1.0 + kr.abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The spectral norm of `m` by power iteration on `m^T m` (a lower estimate that
    /// converges to the true value), for comparison with the closed form.
    fn power(m: [[f64; 3]; 3]) -> f64 {
        let mut v = [0.3, 0.5, 0.7];
        let mul = |v: [f64; 3]| [0, 1, 2].map(|i| (0..3).map(|j| m[i][j] * v[j]).sum::<f64>());
        let mul_t = |v: [f64; 3]| [0, 1, 2].map(|j| (0..3).map(|i| m[i][j] * v[i]).sum::<f64>());
        for _ in 0..500 {
            let w = mul_t(mul(v));
            let n = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
            v = w.map(|x| x / n);
        }
        let w = mul(v);
        (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt()
    }

    #[test]
    fn spectral_norm_matches_power_iteration_and_never_undershoots() {
        assert_eq!(
            spectral_norm([[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 3.0]]),
            3.0
        );
        for k in [
            [0.5, 0.0, 0.25],
            [1.0, -2.0, 0.5],
            [0.0, 0.0, 3.0],
            [0.1, 0.2, 0.3],
        ] {
            let m = shear_inverse(k);
            let (closed, iter) = (spectral_norm(m), power(m));
            assert!(closed >= iter, "{k:?}: {closed} < {iter}");
            assert!((closed - iter) / iter < 1e-8, "{k:?}: {closed} vs {iter}");
        }
        // The inverse really inverts the shear.
        let k = [0.5, -0.3, 0.25];
        let m = shear_inverse(k);
        let p = [0.7, -1.1, 0.4];
        let fwd = [p[0] + k[0] * p[1] + k[1] * p[2], p[1] + k[2] * p[2], p[2]];
        let back = [0, 1, 2].map(|i| (0..3).map(|j| m[i][j] * fwd[j]).sum::<f64>());
        for i in 0..3 {
            assert!((back[i] - p[i]).abs() < 1e-15);
        }
    }

    /// The Jacobian of `f` at `p` by central differences, as rows.
    fn jacobian(f: impl Fn([f64; 3]) -> [f64; 3], p: [f64; 3]) -> [[f64; 3]; 3] {
        let h = 1e-6;
        let mut j = [[0.0; 3]; 3];
        for c in 0..3 {
            let (mut a, mut b) = (p, p);
            a[c] += h;
            b[c] -= h;
            let (fa, fb) = (f(a), f(b));
            for r in 0..3 {
                j[r][c] = (fa[r] - fb[r]) / (2.0 * h);
            }
        }
        j
    }

    #[test]
    fn twist_and_bend_constants_bound_their_maps_jacobians() {
        let k: f64 = 1.5;
        let twist = |p: [f64; 3]| {
            let (s, c) = (k * p[1]).sin_cos();
            [c * p[0] - s * p[2], p[1], s * p[0] + c * p[2]]
        };
        let bend = |p: [f64; 3]| {
            let (s, c) = (k * p[0]).sin_cos();
            [c * p[0] + s * p[1], -s * p[0] + c * p[1], p[2]]
        };
        for r in [0.1, 0.7, 2.0] {
            let mut worst: f64 = 0.0;
            for a in 0..64 {
                let t = a as f64 * std::f64::consts::TAU / 64.0;
                let (s, c) = t.sin_cos();
                worst = worst.max(power(jacobian(twist, [r * c, 0.3, r * s])));
            }
            let l = twist_lipschitz(k * r);
            // t + sqrt(1 + t^2) is the largest singular value, reached at every angle (the
            // finite differences are good to about 1e-9).
            assert!((l - worst).abs() < 1e-8, "twist r {r}: {l} vs {worst}");
            let mut worst: f64 = 0.0;
            for a in 0..64 {
                let t = a as f64 * std::f64::consts::TAU / 64.0;
                let (s, c) = t.sin_cos();
                worst = worst.max(power(jacobian(bend, [r * c, r * s, 0.2])));
            }
            let l = bend_lipschitz(k * r);
            assert!(l >= worst - 1e-8, "bend r {r}: {l} vs {worst}");
        }
    }
}
