//! Large unions as data (`sdfc_ir::instances`): which unions are found, that the instances'
//! composed transforms give the union's distance (f64 evaluator), and that the hierarchy
//! holds every instance once, its boxes nested and its skip links right.

use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_ir::func::Func;
use sdfc_ir::instances::{find, turn, Instances};
use sdfc_ir::value::Value;
use sdfc_ir::Program;

fn program(src: &str) -> Program {
    let file = sdfc_syntax::parse(src).expect("parses");
    let (stages, diags) = sdfc_ir::compile(&file, src.len());
    match stages {
        Some(s) => s.program,
        None => panic!("does not compile: {diags:?}"),
    }
}

/// A union of `n` shapes of four kinds, moved, turned and scaled, two with materials.
fn union(n: usize) -> String {
    let mut s = String::from(
        "material red { color: [1, 0, 0] }\nmaterial blue { color: [0, 0, 1] }\nscene = union(\n",
    );
    for i in 0..n {
        let shape = match i % 4 {
            0 => "sphere(0.4)".to_string(),
            1 => format!("box([0.5, 0.3, 0.4]).rotate_y({}deg).material(red)", 17 * i),
            2 => format!("torus(0.4, 0.1).rotate_x({}deg).scale(1.3)", 11 * i),
            _ => "capsule([0, 0, 0], [0, 0.6, 0], 0.15).rotate_z(30deg).material(blue)".into(),
        };
        let (x, z) = (i % 7, i / 7);
        s += &format!(
            "    {shape}.translate([{x}.5, {}, -{z}]),\n",
            (i % 3) as f64 * 0.7
        );
    }
    s + ");\n"
}

/// The instances' union at `q`: each one's kind at `turn(q, q - centre) / scale` (turned
/// by the quaternion the shader reads), times `scale`.
fn instances_at(f: &Instances, templates: &[Func], q: [f64; 3]) -> f64 {
    f.items
        .iter()
        .map(|i| {
            let d = [0, 1, 2].map(|a| q[a] - i.centre[a]);
            let local = turn(i.q, d).map(|x| x / i.scale);
            let inputs = Inputs {
                params: i.args.clone(),
                ..Inputs::at(local)
            };
            match eval_func(&templates[i.template as usize], &[], &inputs)[0] {
                Value::F(d) => d * i.scale,
                ref v => panic!("{v:?}"),
            }
        })
        .fold(f64::INFINITY, f64::min)
}

fn found(src: &str) -> Option<(Program, Instances)> {
    let p = program(src);
    let f = find(&p.scene, &p.analysis, [0.0; 3])?;
    Some((p, f))
}

#[test]
fn a_union_of_moved_turned_and_scaled_shapes_is_found() {
    let (p, f) = found(&union(40)).expect("found");
    assert_eq!(f.items.len(), 40);
    assert_eq!(f.templates.len(), 4, "four kinds of primitive");
    let materials: Vec<u32> = f.items.iter().take(4).map(|i| i.material).collect();
    let index = |name: &str| {
        let found = p.scene.materials.iter().position(|m| m.name == name);
        found.expect("declared") as u32
    };
    let (red, blue) = (index("red"), index("blue"));
    assert_eq!(materials, vec![0, red, 0, blue]);
}

#[test]
fn other_unions_are_left_as_code() {
    // Too few children.
    assert!(found(&union(15)).is_none());
    // A smooth union, a param in a child, an unbounded child, a child that is not a
    // primitive under maps.
    let variants = [
        union(20).replace(");\n", "    smooth: 0.1,\n);\n"),
        format!(
            "param r = 0.4;\n{}",
            union(20).replace("sphere(0.4)", "sphere(r)")
        ),
        union(20).replacen("sphere(0.4)", "plane([0, 1, 0], 0)", 1),
        union(20).replacen("sphere(0.4)", "sphere(0.4).onion(0.05)", 1),
    ];
    for v in variants {
        let p = program(&v);
        assert!(find(&p.scene, &p.analysis, [0.0; 3]).is_none(), "{v}");
    }
}

/// Every instance's kind at `turn(q, p - centre) / scale`, times `scale`, is the union's child:
/// their minimum is the scene's distance, at points all over the union.
#[test]
fn the_instances_give_the_union_s_distance() {
    let (p, f) = found(&union(40)).expect("found");
    let templates = sdfc_ir::to_ssa::template_functions(&p.scene, &p.analysis, &f.templates);
    let mut worst = 0.0f64;
    for k in 0..500 {
        let t = k as f64;
        let q = [
            -1.0 + 9.0 * (t * 0.618).fract(),
            -1.0 + 3.5 * (t * 0.414).fract(),
            -6.5 + 8.0 * (t * 0.732).fract(),
        ];
        let want = match eval_func(&p.distance, &p.groups, &Inputs::at(q))[0] {
            Value::F(d) => d,
            v => panic!("{v:?}"),
        };
        let got = instances_at(&f, &templates, q);
        worst = worst.max((got - want).abs() / want.abs().max(1.0));
    }
    // The program's constants are f32 (its rotations' sines and cosines rounded): the
    // composed f64 transforms agree to f32 precision.
    assert!(worst < 1e-6, "largest relative difference {worst:e}");
}

#[test]
fn the_hierarchy_holds_each_instance_once_in_nested_boxes() {
    let (_, f) = found(&union(40)).expect("found");
    assert_eq!(f.nodes.len(), 2 * 40 - 1);
    assert_eq!(f.nodes[0].skip as usize, f.nodes.len());
    let mut leaves: Vec<u32> = f.nodes.iter().filter_map(|n| n.leaf).collect();
    leaves.sort_unstable();
    assert_eq!(leaves, (0..40).collect::<Vec<u32>>());
    for (i, n) in f.nodes.iter().enumerate() {
        let end = n.skip as usize;
        assert!(end > i && end <= f.nodes.len());
        assert_eq!(n.leaf.is_some(), end == i + 1, "a leaf's subtree is itself");
        // Every node in the subtree, and every instance under it, lies in its box.
        for m in &f.nodes[i + 1..end] {
            assert!(m.skip as usize <= end, "subtrees nest");
            for a in 0..3 {
                assert!((m.centre[a] - n.centre[a]).abs() + m.half[a] <= n.half[a] + 1e-12);
            }
        }
        if let Some(l) = n.leaf {
            let it = &f.items[l as usize];
            for a in 0..3 {
                assert!(it.lo[a] >= n.centre[a] - n.half[a] && it.hi[a] <= n.centre[a] + n.half[a]);
            }
        }
    }
}

/// A 7 x 7 grid of spheres 1.5 apart in x and y: a median split of its 49 centres along x
/// cuts a column in two, so that the children's boxes overlap there.
fn grid_of_spheres() -> String {
    let mut s = String::from("scene = union(\n");
    for i in 0..49 {
        s += &format!(
            "    sphere(0.4).translate([{}, {}, 0]),\n",
            1.5 * (i % 7) as f64,
            1.5 * (i / 7) as f64
        );
    }
    s + ");\n"
}

/// The node's two children (depth-first order: the first follows it, the second follows
/// the first's subtree).
fn children(f: &Instances, i: usize) -> Option<(usize, usize)> {
    f.nodes[i]
        .leaf
        .is_none()
        .then(|| (i + 1, f.nodes[i + 1].skip as usize))
}

#[test]
fn the_hierarchy_splits_between_rows_not_through_them() {
    // The surface area heuristic puts each split between columns or rows of the grid: no
    // two siblings' boxes overlap, so a ray along a row's gap meets neither.
    let (_, f) = found(&grid_of_spheres()).expect("found");
    for i in 0..f.nodes.len() {
        let Some((a, b)) = children(&f, i) else {
            continue;
        };
        let (na, nb) = (&f.nodes[a], &f.nodes[b]);
        let apart = (0..3).any(|k| (na.centre[k] - nb.centre[k]).abs() > na.half[k] + nb.half[k]);
        assert!(
            apart,
            "node {i}: children {a} and {b} overlap: {na:?} {nb:?}"
        );
    }
}

#[test]
fn the_child_nearer_the_origin_comes_first() {
    // Seen from the origin (the camera's frame) a ray's walk meets the instances nearly in
    // the order it enters them, which keeps its list's sort short.
    let p = program(&grid_of_spheres());
    let origin = [-4.0, -6.0, 9.0];
    let f = find(&p.scene, &p.analysis, origin).expect("found");
    let distance = |n: &sdfc_ir::instances::Node| {
        let d = [0, 1, 2].map(|k| (n.centre[k].abs() - n.half[k]).max(0.0));
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
    };
    let mut ordered = 0;
    for i in 0..f.nodes.len() {
        let Some((a, b)) = children(&f, i) else {
            continue;
        };
        let (da, db) = (distance(&f.nodes[a]), distance(&f.nodes[b]));
        // The nodes' boxes are padded by a thousandth: ties may fall either way.
        assert!(
            da <= db + 1e-2,
            "node {i}: first child {da} away, second {db}"
        );
        ordered += usize::from(da < db);
    }
    assert!(ordered > 20, "{ordered} nodes with a nearer child");
}

#[test]
fn a_crowd_counts_the_boxes_that_hold_one_point() {
    // In the grid each box holds only its own middle.
    let (_, f) = found(&grid_of_spheres()).expect("found");
    assert!(f.crowd_exceeds(0) && !f.crowd_exceeds(1));
    // 20 spheres about one point, and 20 apart: every box of the first holds their middle.
    let mut s = String::from("scene = union(\n");
    for i in 0..20 {
        s += &format!("    sphere(0.5).translate([0.0{}, 0, 0]),\n", i % 10);
        s += &format!("    sphere(0.4).translate([{}, 5, 0]),\n", 2 * i);
    }
    let (_, f) = found(&(s + ");\n")).expect("found");
    assert!(f.crowd_exceeds(19) && !f.crowd_exceeds(20));
}

#[test]
fn the_spacing_is_the_usual_distance_between_neighbours() {
    // The grid's neighbours are 1.5 apart; the same grid twice as wide, 3; 20 spheres 2
    // apart beside 20 crowded about one point: the median of sibling pairs falls in one of
    // the two groups, never on the gap between them.
    let (_, f) = found(&grid_of_spheres()).expect("found");
    assert!((f.spacing().expect("pairs") - 1.5).abs() < 1e-9);
    let mut s = String::from("scene = union(\n");
    for i in 0..49 {
        s += &format!(
            "    sphere(0.4).translate([{}, {}, 0]),\n",
            3.0 * (i % 7) as f64,
            3.0 * (i / 7) as f64
        );
    }
    let (_, f) = found(&(s + ");\n")).expect("found");
    assert!((f.spacing().expect("pairs") - 3.0).abs() < 1e-9);
    let mut s = String::from("scene = union(\n");
    for i in 0..20 {
        s += &format!("    sphere(0.5).translate([0.00{}, 0, 0]),\n", i % 10);
        s += &format!("    sphere(0.4).translate([{}, 5, 0]),\n", 2 * i);
    }
    let (_, f) = found(&(s + ");\n")).expect("found");
    let spacing = f.spacing().expect("pairs");
    assert!(spacing < 0.01 || (spacing - 2.0).abs() < 1e-9, "{spacing}");
}

#[test]
fn instances_are_found_relative_to_an_origin() {
    let p = program(&union(20));
    let a = &p.analysis;
    let at = find(&p.scene, a, [0.0; 3]).unwrap();
    let origin = [1e5, -3.0, 2.5];
    let moved = find(&p.scene, a, origin).unwrap();
    for (a, b) in at.items.iter().zip(&moved.items) {
        for (k, o) in origin.into_iter().enumerate() {
            assert!((a.centre[k] - o - b.centre[k]).abs() < 1e-9);
            assert!((a.lo[k] - o - b.lo[k]).abs() < 1e-9);
        }
    }
}

/// A union with other children beside its instances (a floor, a shell, a child with a
/// param) is found by `find_mixed` with those children as its rest, and the rest's
/// functions plus the instances give the union's distance and material.
#[test]
fn a_mixed_union_keeps_its_other_children_as_code() {
    use sdfc_ir::instances::{find_mixed, rest_functions, MIN_CHILDREN};
    let src = format!(
        "param r = 0.4;\n{}",
        union(20)
            .replacen("sphere(0.4)", "plane([0, 1, 0], 2)", 1)
            .replacen("sphere(0.4)", "sphere(r)", 1)
            .replacen("sphere(0.4)", "sphere(0.4).onion(0.05)", 1)
    );
    let p = program(&src);
    assert!(find(&p.scene, &p.analysis, [0.0; 3]).is_none(), "strict");
    let f = find_mixed(&p.scene, &p.analysis, [0.0; 3], MIN_CHILDREN).expect("mixed");
    assert_eq!((f.items.len(), f.rest.len()), (17, 3));
    // Fewer instances than asked for: none.
    assert!(find_mixed(&p.scene, &p.analysis, [0.0; 3], 18).is_none());
    let rest = rest_functions(&p.scene, &f, None).expect("a rest");
    assert_eq!(rest.distance.name, "rest_distance");
    let templates = sdfc_ir::to_ssa::template_functions(&p.scene, &p.analysis, &f.templates);
    let scalar = |v: &Value<f64>| match v {
        Value::F(d) => *d,
        v => panic!("{v:?}"),
    };
    let mut rest_nearest = 0;
    for k in 0..400 {
        let t = k as f64;
        let q = [
            -1.0 + 9.0 * (t * 0.618).fract(),
            -2.5 + 5.0 * (t * 0.414).fract(),
            -3.5 + 5.0 * (t * 0.732).fract(),
        ];
        // The param at its default.
        let at = Inputs {
            params: vec![Value::F(0.4)],
            ..Inputs::at(q)
        };
        let want = scalar(&eval_func(&p.distance, &p.groups, &at)[0]);
        let r = scalar(&eval_func(&rest.distance, &rest.groups, &at)[0]);
        let walk = instances_at(&f, &templates, q);
        let got = r.min(walk);
        // The program's constants are f32, the instances' frames f64 (as above).
        let off = (got - want).abs() / want.abs().max(1.0);
        assert!(off < 1e-6, "at {q:?}: {got} against {want}");
        if r < walk {
            rest_nearest += 1;
            // Where the rest is nearer, its material is the scene's.
            let m = eval_func(&p.material, &p.groups, &at);
            assert_eq!(m, eval_func(&rest.material, &rest.groups, &at), "at {q:?}");
        }
    }
    assert!(
        rest_nearest > 40,
        "the rest nearest at {rest_nearest} points"
    );
}
