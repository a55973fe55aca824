//! Rounding f64 values to the f32 on the safe side: constants that must not shrink (divisors,
//! bounds) or grow.

/// The smallest f32 at least `x` (a divisor rounded down would step too far).
pub fn f32_up(x: f64) -> f32 {
    let f = x as f32;
    if (f as f64) < x && f.is_finite() {
        f.next_up()
    } else {
        f
    }
}

/// The largest f32 at most `x`.
pub fn f32_down(x: f64) -> f32 {
    -f32_up(-x)
}

#[cfg(test)]
mod tests {
    use super::{f32_down, f32_up};

    #[test]
    fn rounding_is_outward_and_exact_where_it_can_be() {
        let x = 0.1f64;
        assert!(f32_up(x) as f64 >= x && f32_down(x) as f64 <= x);
        assert!(f32_up(x).next_down() as f64 <= x);
        assert_eq!(f32_up(0.5), 0.5);
        assert_eq!(f32_down(-0.5), -0.5);
        assert!(f32_down(-x) as f64 <= -x);
    }
}
