//! Property: the scalar passes (folding, simplification, CSE, DCE) never change the value of
//! an expression. Random expression DAGs over constants (0, 1, -1, -0 and others) and params
//! are evaluated with f32 semantics before and after `passes::optimise`, at random params.

use proptest::prelude::*;
use sdfc_ir::eval::{eval_graph, Inputs};
use sdfc_ir::func::Func;
use sdfc_ir::graph::{Graph, NodeId};
use sdfc_ir::ops::{Builtin, Op, Swizzle};
use sdfc_ir::types::Ty;
use sdfc_ir::value::Value;

/// A recipe for an expression: built into a graph by [`build`].
#[derive(Clone, Debug)]
enum E {
    Const(f32),
    Param(u16),
    Un(u8, Box<E>),
    Bin(u8, Box<E>, Box<E>),
    Sel(Box<E>, Box<E>, Box<E>, Box<E>),
    Vec(Box<E>, Box<E>, Box<E>, u8),
}

fn leaf() -> impl Strategy<Value = E> {
    prop_oneof![
        prop_oneof![
            Just(0.0f32),
            Just(-0.0),
            Just(1.0),
            Just(-1.0),
            Just(0.5),
            Just(2.0),
            -10.0f32..10.0
        ]
        .prop_map(E::Const),
        (0u16..3).prop_map(E::Param),
    ]
}

fn expr() -> impl Strategy<Value = E> {
    leaf().prop_recursive(6, 48, 4, |inner| {
        prop_oneof![
            (0u8..9, inner.clone()).prop_map(|(o, a)| E::Un(o, Box::new(a))),
            (0u8..9, inner.clone(), inner.clone()).prop_map(|(o, a, b)| E::Bin(
                o,
                Box::new(a),
                Box::new(b)
            )),
            (inner.clone(), inner.clone(), inner.clone(), inner.clone()).prop_map(
                |(a, b, c, d)| E::Sel(Box::new(a), Box::new(b), Box::new(c), Box::new(d))
            ),
            (inner.clone(), inner.clone(), inner, 0u8..3).prop_map(|(a, b, c, i)| E::Vec(
                Box::new(a),
                Box::new(b),
                Box::new(c),
                i
            )),
        ]
    })
}

fn build(g: &mut Graph, e: &E) -> NodeId {
    match e {
        E::Const(x) => g.f32(*x),
        E::Param(i) => g.input(Op::Param(*i), Ty::F32, Default::default()),
        E::Un(o, a) => {
            let a = build(g, a);
            match o {
                0 => g.op(Op::Neg, &[a]),
                1 => g.builtin(Builtin::Abs, &[a]),
                2 => g.builtin(Builtin::Sqrt, &[a]),
                3 => g.builtin(Builtin::Sin, &[a]),
                4 => g.builtin(Builtin::Floor, &[a]),
                5 => g.builtin(Builtin::Fract, &[a]),
                6 => g.builtin(Builtin::Exp, &[a]),
                7 => g.builtin(Builtin::Sign, &[a]),
                _ => g.builtin(Builtin::Round, &[a]),
            }
        }
        E::Bin(o, a, b) => {
            let (a, b) = (build(g, a), build(g, b));
            match o {
                0 => g.op(Op::Add, &[a, b]),
                1 => g.op(Op::Sub, &[a, b]),
                2 => g.op(Op::Mul, &[a, b]),
                3 => g.op(Op::Div, &[a, b]),
                4 => g.op(Op::Mod, &[a, b]),
                5 => g.builtin(Builtin::Min, &[a, b]),
                6 => g.builtin(Builtin::Max, &[a, b]),
                7 => g.builtin(Builtin::Step, &[a, b]),
                _ => {
                    let t = g.builtin(Builtin::Clamp, &[b, a, b]);
                    g.builtin(Builtin::Mix, &[a, b, t])
                }
            }
        }
        E::Sel(a, b, c, d) => {
            let (a, b, c, d) = (build(g, a), build(g, b), build(g, c), build(g, d));
            let cond = g.op(Op::Lt, &[c, d]);
            g.op(Op::Select, &[a, b, cond])
        }
        E::Vec(a, b, c, i) => {
            let (a, b, c) = (build(g, a), build(g, b), build(g, c));
            let v = g.op(Op::MakeVec, &[a, b, c]);
            // Exercise swizzle simplification and vector arithmetic with broadcasting.
            let w = g.op(Op::Swizzle(Swizzle::new(&[2, 1, 0])), &[v]);
            let one = g.f32(1.0);
            let w = g.op(Op::Mul, &[w, one]);
            let s = g.op(Op::Swizzle(Swizzle::new(&[0, 1, 2])), &[w]);
            let zero = g.f32(0.0);
            let s = g.op(Op::Add, &[s, zero]);
            let l = g.builtin(Builtin::Length, &[s]);
            let x = g.op(Op::Swizzle(Swizzle::new(&[*i])), &[s]);
            g.op(Op::Add, &[l, x])
        }
    }
}

fn same(a: &Value<f32>, b: &Value<f32>) -> bool {
    let (ca, cb) = (a.comps(), b.comps());
    ca.len() == cb.len()
        && ca
            .iter()
            .zip(&cb)
            .all(|(x, y)| x == y || (x.is_nan() && y.is_nan()))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn optimise_keeps_values(e in expr(), params in prop::array::uniform3(-5.0f32..5.0)) {
        let mut g = Graph::new();
        let root = build(&mut g, &e);
        let before = Func { name: "t".into(), kind: sdfc_ir::func::FuncKind::Distance, graph: g, results: vec![root] };
        let (after, _) = sdfc_ir::passes::optimise(&before);
        let inputs = Inputs { point: [0.0; 3], ray: [0.0; 3], params: params.iter().map(|x| Value::F(*x)).collect(), time: 0.0 };
        let vb = eval_graph(&before.graph, &before.results, &inputs);
        let va = eval_graph(&after.graph, &after.results, &inputs);
        prop_assert!(same(&vb[0], &va[0]), "before {:?} after {:?}\n{}", vb[0], va[0], sdfc_ir::dump::func_text(&after));
        prop_assert!(after.graph.len() <= before.graph.len() + 1);
    }
}

#[test]
fn folding_gives_f32_results() {
    // 0.1 + 0.2 in f32 is 0.3 rounded differently from f64: folding must give the f32 sum.
    let mut g = Graph::new();
    let a = g.f32(0.1);
    let b = g.f32(0.2);
    let s = g.op(Op::Add, &[a, b]);
    let f = Func {
        name: "t".into(),
        kind: sdfc_ir::func::FuncKind::Distance,
        graph: g,
        results: vec![s],
    };
    let (opt, errs) = sdfc_ir::passes::optimise(&f);
    assert!(errs.is_empty());
    assert_eq!(
        opt.graph.as_const(opt.results[0]),
        Some(Value::F(0.1f32 + 0.2f32))
    );
    assert_eq!(opt.graph.len(), 1);
}

#[test]
fn non_finite_constants_are_reported() {
    let mut g = Graph::new();
    let a = g.f32(1.0);
    let b = g.f32(0.0);
    let s = g.op(Op::Div, &[a, b]);
    let f = Func {
        name: "t".into(),
        kind: sdfc_ir::func::FuncKind::Distance,
        graph: g,
        results: vec![s],
    };
    let (_, errs) = sdfc_ir::passes::optimise(&f);
    assert_eq!(errs.len(), 1);
}
