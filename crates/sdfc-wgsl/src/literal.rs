//! WGSL spellings of constants: floats with the shortest digits that round-trip exactly.

use sdfc_ir::value::Value;

/// An f32 as a WGSL float literal that parses back to the same bits (Rust's shortest
/// round-trip formatting always has a `.` or an exponent, so it is never an integer).
pub fn float(x: f32) -> String {
    // Non-finite constants are compile errors before emission; were one to slip through, its
    // text (`NaN`, `inf`) fails naga's validation and is reported as an internal error.
    let s = format!("{x:?}");
    if s.contains('.') || s.contains('e') {
        s
    } else {
        format!("{s}.0")
    }
}

fn list(c: &[f32]) -> String {
    if c.iter().all(|x| x.to_bits() == c[0].to_bits()) {
        return float(c[0]);
    }
    c.iter().map(|x| float(*x)).collect::<Vec<_>>().join(", ")
}

/// A constant value as a WGSL expression.
pub fn value(v: &Value<f32>) -> String {
    match v {
        Value::F(x) => float(*x),
        Value::V2(a) => format!("vec2<f32>({})", list(a)),
        Value::V3(a) => format!("vec3<f32>({})", list(a)),
        Value::V4(a) => format!("vec4<f32>({})", list(a)),
        Value::B(b) => b.to_string(),
        Value::M3(m) => {
            let c: Vec<String> = m.iter().flatten().map(|x| float(*x)).collect();
            format!("mat3x3<f32>({})", c.join(", "))
        }
    }
}

/// A vec3 constant.
pub fn vec3(a: [f32; 3]) -> String {
    value(&Value::V3(a))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_round_trip_and_stay_floats() {
        for x in [
            0.0f32,
            -0.0,
            1.0,
            0.1,
            1e-7,
            3.4028235e38,
            f32::MIN_POSITIVE,
            123456790.0,
            -2.5,
        ] {
            let s = float(x);
            assert!(s.contains('.') || s.contains('e'), "{s}");
            assert_eq!(s.parse::<f32>().unwrap().to_bits(), x.to_bits(), "{s}");
        }
    }

    #[test]
    fn splat_vectors_are_short() {
        assert_eq!(vec3([1.0, 1.0, 1.0]), "vec3<f32>(1.0)");
        assert_eq!(vec3([1.0, 0.0, 2.5]), "vec3<f32>(1.0, 0.0, 2.5)");
    }
}
