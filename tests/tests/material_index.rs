//! The material index (`sdfc_wgsl::material_index`) picks the material the vector selects
//! it replaces pick: for every function of a scene that gets a plan, at random points, the
//! plan's index tree, read with the conditions the IR evaluator computes there, lands on the
//! constant (albedo, phong) pair the evaluator returns, bit for bit. The WGSL's lookup of each
//! index's albedo and phong is checked end to end by `sdfc-render`'s `materials_indexed` test.

use sdfc_ir::eval::{eval_graph, Inputs};
use sdfc_ir::func::{Func, FuncKind};
use sdfc_ir::ops::Op;
use sdfc_ir::value::Value;
use sdfc_wgsl::material_index::{plan, Index, Material};
use sdfc_wgsl::Options;

/// A small deterministic generator (xorshift), so failures reproduce.
fn points(n: usize, lo: [f32; 3], hi: [f32; 3]) -> Vec<[f32; 3]> {
    let mut s: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..n)
        .map(|_| std::array::from_fn(|i| lo[i] + (hi[i] - lo[i]) * next()))
        .collect()
}

fn bits(v: &Value<f32>) -> [u32; 4] {
    match v {
        Value::V4(a) => a.map(f32::to_bits),
        other => panic!("a material vector is {other:?}"),
    }
}

/// Checks every planned function of `funcs`; returns how many had a plan.
fn check(name: &str, funcs: &[&Func], pts: &[[f32; 3]]) -> usize {
    let mut planned = 0;
    for f in funcs {
        let Some(plan) = plan(f) else { continue };
        planned += 1;
        assert!(
            !f.graph
                .nodes()
                .any(|(_, n)| matches!(n.op, Op::Call { .. })),
            "{name}/{}: a planned function calls groups; evaluate it with eval_func",
            f.name
        );
        let (albedo, phong) = match f.kind {
            FuncKind::Group => (f.results[1], f.results[2]),
            _ => (f.results[0], f.results[1]),
        };
        let conds: Vec<_> = plan
            .exprs
            .iter()
            .filter_map(|e| match e {
                Index::Select { cond, .. } => Some(*cond),
                Index::Leaf(_) => None,
            })
            .collect();
        let mut roots = conds.clone();
        roots.extend([albedo, phong]);
        for p in pts {
            let values = eval_graph(&f.graph, &roots, &Inputs::at(*p));
            let want: Material = (bits(&values[conds.len()]), bits(&values[conds.len() + 1]));
            let mut picked: Vec<Material> = Vec::with_capacity(plan.exprs.len());
            let mut c = 0;
            for e in &plan.exprs {
                let m = match e {
                    Index::Leaf(m) => *m,
                    Index::Select {
                        if_false, if_true, ..
                    } => {
                        let Value::B(b) = values[c] else {
                            panic!("{name}/{}: a condition is not a bool", f.name)
                        };
                        c += 1;
                        picked[if b { *if_true } else { *if_false }]
                    }
                };
                picked.push(m);
            }
            assert_eq!(
                picked.last(),
                Some(&want),
                "{name}/{}: at {p:?} the index picks another material than the selects",
                f.name
            );
        }
    }
    planned
}

fn funcs_of(program: &sdfc_ir::Program) -> Vec<&Func> {
    let mut funcs = vec![&program.material];
    funcs.extend(&program.groups);
    if let Some(r) = &program.relative {
        funcs.push(&r.material);
        funcs.extend(&r.groups);
    }
    funcs
}

#[test]
fn grid_groups_pick_the_selects_material() {
    let src = sdfc_tests::grid_scene(300);
    let compiled = sdfc_wgsl::compile(&src, &Options::default()).expect("grid compiles");
    let pts = points(300, [-8.0, -1.0, -11.0], [8.0, 11.0, 1.0]);
    let planned = check("grid_scene(300)", &funcs_of(compiled.program()), &pts);
    // 300 shapes in groups of up to 32: every full group is planned.
    assert!(planned >= 9, "only {planned} functions planned");
}

#[test]
fn the_corpus_scene_of_many_materials() {
    let path = sdfc_tests::root().join("scenes/materials_many.sdf");
    let src = std::fs::read_to_string(&path).expect("the scene is in the corpus");
    let compiled = sdfc_wgsl::compile(&src, &Options::default()).expect("it compiles");
    let pts = points(2000, [-5.0, -1.0, -1.0], [5.0, 1.0, 1.0]);
    let planned = check("materials_many", &funcs_of(compiled.program()), &pts);
    assert!(planned >= 1, "its material function is not planned");
}

/// Albedo and phong that change on different conditions: the first shapes share the
/// default phong (the phong stays one constant while the albedo is already a select), gold's
/// phong comes in later.
#[test]
fn a_phong_that_changes_later_than_the_albedo() {
    let mut src = String::from(
        "material red { color: [1, 0, 0] }\n\
         material blue { color: [0, 0, 1] }\n\
         material gold { color: [0.9, 0.7, 0.2], specular: 0.8, shininess: 64 }\n\
         scene = union(\n",
    );
    for (i, m) in [
        "red", "blue", "red", "blue", "red", "gold", "blue", "red", "gold", "red",
    ]
    .iter()
    .enumerate()
    {
        src += &format!(
            "  sphere(0.4).material({m}).translate([{}, 0, 0]),\n",
            i as f32 - 4.5
        );
    }
    src += ");\n";
    let compiled = sdfc_wgsl::compile(&src, &Options::default()).expect("it compiles");
    let pts = points(2000, [-5.0, -1.0, -1.0], [5.0, 1.0, 1.0]);
    assert_eq!(check("late phong", &funcs_of(compiled.program()), &pts), 1);
}

/// A union of two shapes keeps its vector selects.
#[test]
fn a_union_below_the_threshold_keeps_its_selects() {
    let src = "material a { color: [1, 0, 0] }\n\
               scene = union(sphere(1).material(a), box(1).translate([3, 0, 0]));";
    let compiled = sdfc_wgsl::compile(src, &Options::default()).expect("it compiles");
    assert!(!compiled.wgsl.contains("let k0 = "), "{}", compiled.wgsl);
    assert_eq!(check("two shapes", &funcs_of(compiled.program()), &[]), 0);
}
