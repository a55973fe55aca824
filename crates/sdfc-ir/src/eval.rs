//! Evaluates IR operations on concrete values: f32 for constant folding (what the GPU
//! computes), f64 for the reference evaluator behind `sdfc eval`.

use crate::func::Func;
use crate::graph::{Graph, NodeId};
use crate::ops::{Builtin, Helper, Op, NO_BEST};
use crate::types::Ty;
use crate::value::{dot, length, zip, zip3, Float, Value};
use std::cell::Cell;

/// The values of a function's inputs.
#[derive(Clone, Debug)]
pub struct Inputs<T> {
    pub point: [T; 3],
    /// The ray direction of `scene_distance_ray` (zero elsewhere).
    pub ray: [T; 3],
    pub params: Vec<Value<T>>,
    pub time: T,
}

impl<T: Float> Inputs<T> {
    pub fn at(point: [T; 3]) -> Inputs<T> {
        Inputs {
            point,
            ray: [T::zero(); 3],
            params: Vec::new(),
            time: T::zero(),
        }
    }
}

/// Evaluates the roots of a graph. Every reachable node must be computable from `inputs`
/// (a lambda argument left in the graph evaluates to zero; so does a group call: use
/// [`eval_func`] for functions that call groups).
pub fn eval_graph<T: Float>(g: &Graph, roots: &[NodeId], inputs: &Inputs<T>) -> Vec<Value<T>> {
    eval_graph_in(g, roots, inputs, &[], no_best(), &Cell::new(0))
}

/// Evaluates a function of a program, whose group functions are `groups`.
pub fn eval_func<T: Float>(f: &Func, groups: &[Func], inputs: &Inputs<T>) -> Vec<Value<T>> {
    eval_graph_in(
        &f.graph,
        &f.results,
        inputs,
        groups,
        no_best(),
        &Cell::new(0),
    )
}

/// [`eval_func`], and how many nodes it evaluated (in every group it called): the work a
/// shader does at this point where its branches are real (skipped calls cost nothing), the
/// measure of what culling saves (`tests/tests/culling.rs`).
pub fn eval_func_work<T: Float>(
    f: &Func,
    groups: &[Func],
    inputs: &Inputs<T>,
) -> (Vec<Value<T>>, usize) {
    let work = Cell::new(0);
    let v = eval_graph_in(&f.graph, &f.results, inputs, groups, no_best(), &work);
    (v, work.get())
}

fn no_best<T: Float>() -> T {
    T::from_f64(f64::from(NO_BEST))
}

/// `best` is the value of [`Op::Best`]: the caller's best distance in a guarded group.
fn eval_graph_in<T: Float>(
    g: &Graph,
    roots: &[NodeId],
    inputs: &Inputs<T>,
    groups: &[Func],
    best: T,
    work: &Cell<usize>,
) -> Vec<Value<T>> {
    let mut vals: Vec<Option<Value<T>>> = vec![None; g.len()];
    let mut need = vec![false; g.len()];
    for r in roots {
        need[r.index()] = true;
    }
    for i in (0..g.len()).rev() {
        if need[i] {
            for a in g.node(NodeId(i as u32)).args() {
                need[a.index()] = true;
            }
        }
    }
    // One evaluation per call site: a group's distance and material results are separate
    // `Call` nodes on the same argument, and evaluating the callee for each of them made
    // nested groups exponential.
    // Keyed by all arguments: a guarded group's value depends on the best distance too.
    let mut calls: crate::hash::FxHashMap<(u32, Vec<NodeId>), Vec<Value<T>>> = Default::default();
    for i in 0..g.len() {
        if !need[i] {
            continue;
        }
        let node = g.node(NodeId(i as u32));
        if !matches!(node.op, Op::Const(_)) {
            work.set(work.get() + 1);
        }
        let args: Vec<Value<T>> = node
            .args()
            .iter()
            .map(|a| vals[a.index()].unwrap_or(Value::F(T::zero())))
            .collect();
        let v = match node.op {
            Op::Point => Value::V3(inputs.point),
            Op::Ray => Value::V3(inputs.ray),
            Op::Time => Value::F(inputs.time),
            Op::Best => Value::F(best),
            Op::Param(k) => inputs
                .params
                .get(k as usize)
                .copied()
                .unwrap_or_else(|| zero_of(node.ty)),
            Op::LambdaArg { .. } => zero_of(node.ty),
            Op::Call { func, result } => match (groups.get(func as usize), args.first()) {
                // A guarded call (culled unions): skipped where `bound >= best`, and then
                // its distance is `bound` and its material zero, as the WGSL's `if` leaves it.
                (Some(_), Some(Value::V3(_)))
                    if matches!(
                        (args.get(1), args.get(2)),
                        (Some(Value::F(bound)), Some(Value::F(best))) if bound.partial_cmp(best) != Some(std::cmp::Ordering::Less)
                    ) =>
                {
                    match (result, args[1]) {
                        (0, b) => b,
                        _ => zero_of(node.ty),
                    }
                }
                (Some(f), Some(Value::V3(p))) => {
                    // A guarded call hands its best distance on (`[p, bound, best]`).
                    let best = match args.get(2) {
                        Some(Value::F(b)) => *b,
                        _ => no_best(),
                    };
                    let r = calls
                        .entry((func, node.args().to_vec()))
                        .or_insert_with(|| {
                            let sub = Inputs {
                                point: *p,
                                ray: inputs.ray,
                                params: inputs.params.clone(),
                                time: inputs.time,
                            };
                            eval_graph_in(&f.graph, &f.results, &sub, groups, best, work)
                        });
                    r.get(result as usize)
                        .copied()
                        .unwrap_or_else(|| zero_of(node.ty))
                }
                _ => zero_of(node.ty),
            },
            op => apply(op, node.ty, &args),
        };
        vals[i] = Some(v);
    }
    roots
        .iter()
        .map(|r| vals[r.index()].unwrap_or(Value::F(T::zero())))
        .collect()
}

pub fn zero_of<T: Float>(ty: Ty) -> Value<T> {
    Value::from_comps(ty, &[T::zero(); 9])
}

/// Applies a pure operation (not an input) to argument values.
pub fn apply<T: Float>(op: Op, ty: Ty, a: &[Value<T>]) -> Value<T> {
    let cmp = |f: fn(T, T) -> bool| match (a[0], a[1]) {
        (Value::F(x), Value::F(y)) => Value::B(f(x, y)),
        _ => Value::B(false),
    };
    match op {
        Op::Const(c) => c.to_value().cast(),
        Op::Point
        | Op::Ray
        | Op::Time
        | Op::Best
        | Op::Param(_)
        | Op::LambdaArg { .. }
        | Op::Call { .. } => zero_of(ty),
        Op::Neg => a[0].map(|x| -x),
        Op::Add => zip(&a[0], &a[1], |x, y| x + y),
        Op::Sub => zip(&a[0], &a[1], |x, y| x - y),
        Op::Mul => match (a[0], a[1]) {
            (Value::M3(m), Value::V3(v)) => Value::V3(mat_vec(&m, &v)),
            _ => zip(&a[0], &a[1], |x, y| x * y),
        },
        Op::Div => zip(&a[0], &a[1], |x, y| x / y),
        Op::Mod => zip(&a[0], &a[1], |x, y| x - y * (x / y).floor()),
        Op::Lt => cmp(|x, y| x < y),
        Op::Le => cmp(|x, y| x <= y),
        Op::Gt => cmp(|x, y| x > y),
        Op::Ge => cmp(|x, y| x >= y),
        Op::Eq => cmp(|x, y| x == y),
        Op::Ne => cmp(|x, y| x != y),
        Op::Select => match a[2] {
            Value::B(true) => a[1],
            _ => a[0],
        },
        Op::MakeVec => {
            let c: Vec<T> = a.iter().flat_map(|v| v.comps()).collect();
            Value::from_comps(ty, &c)
        }
        Op::Swizzle(s) => {
            let c = a[0].comps();
            let out: Vec<T> = s
                .indices()
                .iter()
                .map(|&i| c.get(i as usize).copied().unwrap_or(T::zero()))
                .collect();
            Value::from_comps(ty, &out)
        }
        Op::MakeMat3 => {
            let c: Vec<T> = a.iter().flat_map(|v| v.comps()).collect();
            Value::from_comps(Ty::Mat3, &c)
        }
        Op::MatMul => match (a[0], a[1]) {
            (Value::M3(m), Value::V3(v)) => Value::V3(mat_vec(&m, &v)),
            (Value::M3(m), Value::M3(n)) => Value::M3(n.map(|col| mat_vec(&m, &col))),
            _ => zero_of(ty),
        },
        Op::Transpose => match a[0] {
            Value::M3(m) => Value::M3([0, 1, 2].map(|c| [m[0][c], m[1][c], m[2][c]])),
            v => v,
        },
        Op::Builtin(b) => builtin(b, a),
        Op::Helper(h @ (Helper::RotateX | Helper::RotateY | Helper::RotateZ)) => {
            let (p, c, s) = (v3(&a[0]), f(&a[1]), f(&a[2]));
            // The matrix product's terms, zeros dropped (adding a zero product changes nothing).
            Value::V3(match h {
                Helper::RotateX => [p[0], c * p[1] + s * p[2], -s * p[1] + c * p[2]],
                Helper::RotateY => [c * p[0] - s * p[2], p[1], s * p[0] + c * p[2]],
                _ => [c * p[0] + s * p[1], -s * p[0] + c * p[1], p[2]],
            })
        }
        Op::Helper(Helper::NoiseGradient) => Value::V3(crate::noise::noise_gradient(v3(&a[0]))),
        Op::Helper(h) => Value::F(helper(h, a)),
    }
}

/// `m * v` for a column-major matrix, summed in the order WGSL's definition gives.
pub fn mat_vec<T: Float>(m: &[[T; 3]; 3], v: &[T; 3]) -> [T; 3] {
    [0, 1, 2].map(|r| m[0][r] * v[0] + m[1][r] * v[1] + m[2][r] * v[2])
}

fn builtin<T: Float>(b: Builtin, a: &[Value<T>]) -> Value<T> {
    use Builtin::*;
    let one = T::one();
    let zero = T::zero();
    match b {
        Abs => a[0].map(|x| x.abs()),
        Sign => a[0].map(|x| {
            if x > zero {
                one
            } else if x < zero {
                -one
            } else {
                zero
            }
        }),
        Floor => a[0].map(|x| x.floor()),
        Ceil => a[0].map(|x| x.ceil()),
        Fract => a[0].map(|x| x - x.floor()),
        Round => a[0].map(|x| x.round_even()),
        Sqrt => a[0].map(|x| x.sqrt()),
        // As GPUs compute WGSL's `pow` (and naga lowers it): `exp2(y * log2(x))`, so a
        // negative base is NaN and `pow(0, 0)` too, where `powf` would give -8 for
        // `pow(-2, 3)` and the device NaN (found by the language audit of 2026-12-04).
        Pow => zip(&a[0], &a[1], |x, y| {
            T::from_f64((y.to_f64() * x.to_f64().log2()).exp2())
        }),
        Exp => a[0].map(|x| x.map64(f64::exp)),
        Log => a[0].map(|x| x.map64(f64::ln)),
        Sin => a[0].map(|x| x.map64(f64::sin)),
        Cos => a[0].map(|x| x.map64(f64::cos)),
        Tan => a[0].map(|x| x.map64(f64::tan)),
        Asin => a[0].map(|x| x.map64(f64::asin)),
        Acos => a[0].map(|x| x.map64(f64::acos)),
        Atan => a[0].map(|x| x.map64(f64::atan)),
        Atan2 => zip(&a[0], &a[1], |y, x| {
            T::from_f64(y.to_f64().atan2(x.to_f64()))
        }),
        Min => zip(&a[0], &a[1], |x, y| x.min(y)),
        Max => zip(&a[0], &a[1], |x, y| x.max(y)),
        Clamp => zip3(&a[0], &a[1], &a[2], |x, lo, hi| x.max(lo).min(hi)),
        Mix => zip3(&a[0], &a[1], &a[2], |x, y, t| x * (one - t) + y * t),
        Step => zip(&a[0], &a[1], |edge, x| if x >= edge { one } else { zero }),
        Smoothstep => zip3(&a[0], &a[1], &a[2], |lo, hi, x| {
            let t = ((x - lo) / (hi - lo)).max(zero).min(one);
            t * t * (T::from_f64(3.0) - T::from_f64(2.0) * t)
        }),
        Length => Value::F(length(&a[0].comps())),
        Distance => {
            let d = zip(&a[0], &a[1], |x, y| x - y);
            Value::F(length(&d.comps()))
        }
        Dot => Value::F(dot(&a[0].comps(), &a[1].comps())),
        Cross => {
            let (x, y) = (a[0].comps(), a[1].comps());
            Value::V3([
                x[1] * y[2] - x[2] * y[1],
                x[2] * y[0] - x[0] * y[2],
                x[0] * y[1] - x[1] * y[0],
            ])
        }
        Normalize => {
            let l = length(&a[0].comps());
            a[0].map(|x| x / l)
        }
        Radians => a[0].map(|x| x * T::from_f64(std::f64::consts::PI / 180.0)),
        Degrees => a[0].map(|x| x * T::from_f64(180.0 / std::f64::consts::PI)),
    }
}

fn v3<T: Float>(v: &Value<T>) -> [T; 3] {
    match v {
        Value::V3(a) => *a,
        Value::F(x) => [*x; 3],
        _ => [T::zero(); 3],
    }
}

fn f<T: Float>(v: &Value<T>) -> T {
    v.scalar().unwrap_or(T::zero())
}

/// The helpers of `prim_dist`, in f64 (see there why that is safe for folding).
fn later_prim<T: Float>(h: Helper, a: &[Value<T>]) -> f64 {
    use crate::prim_dist as d;
    let p = v3(&a[0]).map(|x| x.to_f64());
    let x = |i: usize| f(&a[i]).to_f64();
    let v = |i: usize| v3(&a[i]).map(|c| c.to_f64());
    match h {
        Helper::SdBoxFrame => d::box_frame(p, v(1), x(2)),
        Helper::SdCappedTorus => {
            let sc = a[1].comps();
            let (s, c) = (sc[0].to_f64(), sc.get(1).map_or(0.0, |c| c.to_f64()));
            d::capped_torus(p, s, c, x(2), x(3))
        }
        Helper::SdCappedCone => d::capped_cone(p, x(1), x(2), x(3)),
        Helper::SdEllipsoid => d::ellipsoid(p, v(1)),
        Helper::SdOctahedron => d::octahedron(p, x(1)),
        Helper::SdHexPrism => d::hex_prism(p, x(1), x(2)),
        Helper::SdTriPrism => d::tri_prism(p, x(1), x(2)),
        Helper::SdPyramid => d::pyramid(p, x(1)),
        Helper::SdMandelbulb => d::mandelbulb(p, x(1), x(2), x(3)),
        Helper::SdMandelbulbInt => d::mandelbulb_int(p, x(1) as u32, x(2), x(3)),
        Helper::SdMenger => d::menger(p, x(1)),
        Helper::SdSierpinski => d::sierpinski(p, x(1)),
        _ => 0.0,
    }
}

/// The distance helpers, computed exactly as `shaders/prims/*.wgsl` spell them.
fn helper<T: Float>(h: Helper, a: &[Value<T>]) -> T {
    let zero = T::zero();
    let p = v3(&a[0]);
    let box_dist = |p: [T; 3], b: [T; 3]| {
        let q = [0, 1, 2].map(|i| p[i].abs() - b[i]);
        let outside = length(&q.map(|x| x.max(zero)));
        outside + q[0].max(q[1].max(q[2])).min(zero)
    };
    match h {
        Helper::SdSphere => length(&p) - f(&a[1]),
        Helper::SdBox => box_dist(p, v3(&a[1])),
        Helper::SdRoundBox => box_dist(p, v3(&a[1])) - f(&a[2]),
        Helper::SdTorus => {
            let q = [length(&[p[0], p[2]]) - f(&a[1]), p[1]];
            length(&q) - f(&a[2])
        }
        Helper::SdCylinder => {
            let d = [
                length(&[p[0], p[2]]).abs() - f(&a[1]),
                p[1].abs() - f(&a[2]),
            ];
            d[0].max(d[1]).min(zero) + length(&d.map(|x| x.max(zero)))
        }
        Helper::RotateX | Helper::RotateY | Helper::RotateZ | Helper::NoiseGradient => zero,
        Helper::SdBoxFrame
        | Helper::SdCappedTorus
        | Helper::SdCappedCone
        | Helper::SdEllipsoid
        | Helper::SdOctahedron
        | Helper::SdHexPrism
        | Helper::SdTriPrism
        | Helper::SdPyramid
        | Helper::SdMandelbulb
        | Helper::SdMandelbulbInt
        | Helper::SdMenger
        | Helper::SdSierpinski => T::from_f64(later_prim(h, a)),
        Helper::Noise => crate::noise::noise(p),
        Helper::SdCapsule => {
            let (ea, eb) = (v3(&a[1]), v3(&a[2]));
            let pa = [0, 1, 2].map(|i| p[i] - ea[i]);
            let ba = [0, 1, 2].map(|i| eb[i] - ea[i]);
            // A zero-length segment is a sphere: guard the division instead of making NaN.
            let bb = dot(&ba, &ba).max(T::from_f64(1e-30));
            let h = (dot(&pa, &ba) / bb).max(zero).min(T::one());
            length(&[0, 1, 2].map(|i| pa[i] - ba[i] * h)) - f(&a[3])
        }
    }
}
