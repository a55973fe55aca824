//! Small f64 vector helpers for the reference renderer.

pub type V3 = [f64; 3];

pub fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub fn mul(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub fn length(a: V3) -> f64 {
    dot(a, a).sqrt()
}

/// `a / |a|`; a zero (or non-finite) vector gives +y, as the shaders' `safe_normalize` does.
pub fn safe_normalize(a: V3) -> V3 {
    let l = length(a);
    if l > 0.0 && l.is_finite() {
        mul(a, 1.0 / l)
    } else {
        [0.0, 1.0, 0.0]
    }
}

/// The mirror direction of `d` about the unit normal `n` (WGSL `reflect`).
pub fn reflect(d: V3, n: V3) -> V3 {
    sub(d, mul(n, 2.0 * dot(n, d)))
}

pub fn f64s(v: [f32; 3]) -> V3 {
    v.map(|x| x as f64)
}

/// The largest absolute coordinate, at least 1: the scale of a point for relative offsets.
pub fn scale(p: V3) -> f64 {
    p[0].abs().max(p[1].abs()).max(p[2].abs()).max(1.0)
}
