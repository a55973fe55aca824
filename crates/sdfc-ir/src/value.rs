//! Concrete values of IR types, generic over the float width (f32 folds, f64 is the reference).

use crate::types::Ty;

/// The float arithmetic the evaluator needs. `f32` does `+ - * / sqrt` natively (correctly
/// rounded, as the GPU does) and the transcendental functions through f64, rounded once.
pub trait Float:
    Copy
    + PartialOrd
    + std::fmt::Debug
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
    + std::ops::Neg<Output = Self>
{
    fn from_f64(x: f64) -> Self;
    fn to_f64(self) -> f64;
    fn sqrt(self) -> Self;
    fn floor(self) -> Self;
    fn ceil(self) -> Self;
    fn round_even(self) -> Self;
    fn abs(self) -> Self;
    fn is_finite(self) -> bool;
    fn map64(self, f: impl Fn(f64) -> f64) -> Self {
        Self::from_f64(f(self.to_f64()))
    }
    fn zero() -> Self {
        Self::from_f64(0.0)
    }
    fn one() -> Self {
        Self::from_f64(1.0)
    }
    /// WGSL `min`: the smaller; for equal values either.
    fn min(self, o: Self) -> Self {
        if o < self {
            o
        } else {
            self
        }
    }
    fn max(self, o: Self) -> Self {
        if o > self {
            o
        } else {
            self
        }
    }
}

macro_rules! impl_float {
    ($t:ty) => {
        impl Float for $t {
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            fn to_f64(self) -> f64 {
                self as f64
            }
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            fn floor(self) -> Self {
                <$t>::floor(self)
            }
            fn ceil(self) -> Self {
                <$t>::ceil(self)
            }
            fn round_even(self) -> Self {
                <$t>::round_ties_even(self)
            }
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
        }
    };
}
impl_float!(f32);
impl_float!(f64);

/// A value: scalar, vector, boolean or column-major 3x3 matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value<T> {
    F(T),
    V2([T; 2]),
    V3([T; 3]),
    V4([T; 4]),
    B(bool),
    M3([[T; 3]; 3]),
}

impl<T: Float> Value<T> {
    pub fn ty(&self) -> Ty {
        match self {
            Value::F(_) => Ty::F32,
            Value::V2(_) => Ty::Vec2,
            Value::V3(_) => Ty::Vec3,
            Value::V4(_) => Ty::Vec4,
            Value::B(_) => Ty::Bool,
            Value::M3(_) => Ty::Mat3,
        }
    }

    /// The float components in order (columns for a matrix); empty for a boolean.
    pub fn comps(&self) -> Vec<T> {
        match *self {
            Value::F(a) => vec![a],
            Value::V2(a) => a.to_vec(),
            Value::V3(a) => a.to_vec(),
            Value::V4(a) => a.to_vec(),
            Value::B(_) => vec![],
            Value::M3(m) => m.iter().flatten().copied().collect(),
        }
    }

    /// Builds a value of type `ty` from components (as [`Value::comps`] lists them).
    pub fn from_comps(ty: Ty, c: &[T]) -> Value<T> {
        match ty {
            Ty::F32 => Value::F(c[0]),
            Ty::Vec2 => Value::V2([c[0], c[1]]),
            Ty::Vec3 => Value::V3([c[0], c[1], c[2]]),
            Ty::Vec4 => Value::V4([c[0], c[1], c[2], c[3]]),
            Ty::Bool => Value::B(false),
            Ty::Mat3 => Value::M3([[c[0], c[1], c[2]], [c[3], c[4], c[5]], [c[6], c[7], c[8]]]),
        }
    }

    /// Applies `f` to each float component.
    pub fn map(&self, f: impl Fn(T) -> T) -> Value<T> {
        let c: Vec<T> = self.comps().into_iter().map(f).collect();
        match self {
            Value::B(b) => Value::B(*b),
            _ => Value::from_comps(self.ty(), &c),
        }
    }

    pub fn scalar(&self) -> Option<T> {
        match self {
            Value::F(a) => Some(*a),
            _ => None,
        }
    }

    pub fn all_finite(&self) -> bool {
        self.comps().iter().all(|c| c.is_finite())
    }

    /// Converts the float width.
    pub fn cast<U: Float>(&self) -> Value<U> {
        match self {
            Value::B(b) => Value::B(*b),
            _ => {
                let c: Vec<U> = self
                    .comps()
                    .iter()
                    .map(|x| U::from_f64(x.to_f64()))
                    .collect();
                Value::from_comps(self.ty(), &c)
            }
        }
    }
}

/// Component-wise binary operation with scalar broadcasting (`vec op f32`, `f32 op vec`).
pub fn zip<T: Float>(a: &Value<T>, b: &Value<T>, f: impl Fn(T, T) -> T) -> Value<T> {
    let (ca, cb) = (a.comps(), b.comps());
    let ty = if ca.len() >= cb.len() { a.ty() } else { b.ty() };
    let n = ca.len().max(cb.len());
    let get = |c: &Vec<T>, i: usize| if c.len() == 1 { c[0] } else { c[i] };
    let out: Vec<T> = (0..n).map(|i| f(get(&ca, i), get(&cb, i))).collect();
    Value::from_comps(ty, &out)
}

/// Component-wise ternary operation with scalar broadcasting.
pub fn zip3<T: Float>(
    a: &Value<T>,
    b: &Value<T>,
    c: &Value<T>,
    f: impl Fn(T, T, T) -> T,
) -> Value<T> {
    let cs = [a.comps(), b.comps(), c.comps()];
    let (ty, n) = [a, b, c]
        .iter()
        .map(|v| (v.ty(), v.comps().len()))
        .max_by_key(|(_, n)| *n)
        .unwrap_or((Ty::F32, 1));
    let get = |c: &Vec<T>, i: usize| if c.len() == 1 { c[0] } else { c[i] };
    let out: Vec<T> = (0..n)
        .map(|i| f(get(&cs[0], i), get(&cs[1], i), get(&cs[2], i)))
        .collect();
    Value::from_comps(ty, &out)
}

pub fn dot<T: Float>(a: &[T], b: &[T]) -> T {
    let mut s = a[0] * b[0];
    for i in 1..a.len() {
        s = s + a[i] * b[i];
    }
    s
}

pub fn length<T: Float>(a: &[T]) -> T {
    dot(a, a).sqrt()
}

/// Bit pattern of an f32, for hashing constants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Bits(pub u32);

/// A constant as stored in the graph: hashable, compared bit for bit.
pub type Const = Value<Bits>;

impl Const {
    pub fn from_value(v: &Value<f32>) -> Const {
        match *v {
            Value::F(a) => Value::F(Bits(a.to_bits())),
            Value::V2(a) => Value::V2(a.map(|x| Bits(x.to_bits()))),
            Value::V3(a) => Value::V3(a.map(|x| Bits(x.to_bits()))),
            Value::V4(a) => Value::V4(a.map(|x| Bits(x.to_bits()))),
            Value::B(b) => Value::B(b),
            Value::M3(m) => Value::M3(m.map(|c| c.map(|x| Bits(x.to_bits())))),
        }
    }

    pub fn to_value(&self) -> Value<f32> {
        let f = |b: Bits| f32::from_bits(b.0);
        match *self {
            Value::F(a) => Value::F(f(a)),
            Value::V2(a) => Value::V2(a.map(f)),
            Value::V3(a) => Value::V3(a.map(f)),
            Value::V4(a) => Value::V4(a.map(f)),
            Value::B(b) => Value::B(b),
            Value::M3(m) => Value::M3(m.map(|c| c.map(f))),
        }
    }
}

impl std::hash::Hash for Const {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        match self {
            Value::F(a) => (0u8, a).hash(state),
            Value::V2(a) => (1u8, a).hash(state),
            Value::V3(a) => (2u8, a).hash(state),
            Value::V4(a) => (3u8, a).hash(state),
            Value::B(b) => (4u8, b).hash(state),
            Value::M3(m) => (5u8, m).hash(state),
        }
    }
}
impl Eq for Const {}
