//! Only what a scene asks for is in its shader: adding a shading feature adds its code (and
//! grows the shader), removing it takes the code out; one material means no material choice.

use sdfc_wgsl::{compile, Options};

fn wgsl(render: &str, scene: &str) -> String {
    let src = format!("render {{ {render} }}\nscene = {scene};\n");
    match compile(&src, &Options::default()) {
        Ok(c) => {
            assert!(
                c.warnings.is_empty(),
                "{src}: unexpected warnings {:?}",
                c.warnings
            );
            c.wgsl
        }
        Err(e) => panic!("{src}: {e:?}"),
    }
}

const SCENE: &str = "sphere(1) | plane([0, 1, 0], -1)";

#[test]
fn each_feature_adds_its_code_and_only_then() {
    let base = wgsl("", SCENE);
    let features: &[(&str, &[&str])] = &[
        ("shadows: hard", &["fn shadow(", "lit = shadow("]),
        (
            "shadows: soft(8)",
            &["fn shadow(", "const SHADOW_K: f32 = 8.0;"],
        ),
        (
            "ao: ao()",
            &["fn ambient_occlusion(", "const AO_SAMPLES: u32 = 5u;"],
        ),
        (
            "ao: ao(samples: 3, step: 0.1, strength: 2, falloff: 0.5)",
            &[
                "const AO_SAMPLES: u32 = 3u;",
                "const AO_FALLOFF: f32 = 0.5;",
            ],
        ),
        (
            "reflections: 2",
            &[
                "const REFLECTIONS: u32 = 2u;",
                "hit = march(origin, dir, pixel);",
            ],
        ),
        ("fog: fog(0.1, [0.5, 0.6, 0.7])", &["exp(-0.1 * t)"]),
        (
            "relaxation: 1.5",
            &["const RELAXATION: f32 = 1.5;", "overshot"],
        ),
        ("normals: central", &["Normal from central differences"]),
        ("normals: forward", &["Normal from forward differences"]),
        ("epsilon: 0.001", &["return 0.001;"]),
    ];
    for (setting, markers) in features {
        let with = wgsl(setting, SCENE);
        for m in *markers {
            assert!(with.contains(m), "`{setting}` should add `{m}`");
            assert!(
                !base.contains(m),
                "the plain shader should not contain `{m}`"
            );
        }
        if !setting.starts_with("normals") && !setting.starts_with("epsilon") {
            assert!(
                with.len() > base.len(),
                "`{setting}` should grow the shader"
            );
        }
    }
    // The defaults: plain marching, tetrahedron normals, no shadow, AO, reflection or fog code.
    for absent in [
        "fn shadow(",
        "fn ambient_occlusion(",
        "REFLECTIONS",
        "RELAXATION",
        "exp(-",
    ] {
        assert!(!base.contains(absent), "default shader contains `{absent}`");
    }
    assert!(base.contains("Normal from four samples"));
}

#[test]
fn one_material_means_no_material_choice() {
    let one = wgsl("", "sphere(1) | box(1).translate([2, 0, 0])");
    let material_fn = &one[one.find("fn scene_material").unwrap()..];
    let body = &material_fn[..material_fn.find("\n}").unwrap()];
    assert!(!body.contains("select(") && !body.contains("sd_"), "{body}");
    let two = wgsl(
        "",
        "sphere(1).color([1, 0, 0]) | box(1).translate([2, 0, 0])",
    );
    let material_fn = &two[two.find("fn scene_material").unwrap()..];
    assert!(material_fn[..material_fn.find("\n}").unwrap()].contains("select("));
}

#[test]
fn the_march_loop_never_calls_the_material_lookup() {
    let w = wgsl(
        "",
        "sphere(1).color([1, 0, 0]) | box(1).translate([2, 0, 0])",
    );
    let distance = &w[w.find("fn scene_distance").unwrap()..];
    let distance = &distance[..distance.find("\n}").unwrap()];
    assert!(
        !distance.contains("select(") && !distance.contains("vec4"),
        "{distance}"
    );
    let march = &w[w.find("fn march(").unwrap()..];
    let march = &march[..march.find("\n}").unwrap()];
    assert!(!march.contains("scene_material"), "{march}");
}

#[test]
fn the_eval_shader_validates_for_every_scene() {
    for path in sdfc_tests::corpus("scenes") {
        let src = std::fs::read_to_string(&path).unwrap();
        let c = compile(&src, &Options::default())
            .unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
        sdfc_wgsl::eval_shader::eval_shader(c.program())
            .unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
    }
}

#[test]
fn large_unions_split_into_groups_that_compute_the_same_distance() {
    use sdfc_ir::eval::{eval_func, Inputs};
    use sdfc_ir::value::Value;
    // 100 spheres on a line: the union is split into groups; the distance must still be the
    // exact minimum, and the material the nearest sphere's colour.
    let mut src = String::from("scene = union(\n");
    for i in 0..100 {
        let c = if i % 2 == 0 { "[1, 0, 0]" } else { "[0, 0, 1]" };
        src += &format!(
            "    sphere({}).translate([{}, 0, 0]).color({c}),\n",
            0.3 + (i % 3) as f64 * 0.1,
            i * 2
        );
    }
    src += ");\n";
    // As code: by default a union this large is read as data (`AUTO_INSTANCES`), which has
    // no groups.
    let code = Options {
        instances: sdfc_wgsl::Instances::Never,
        ..Options::default()
    };
    let c = compile(&src, &code).expect("compiles");
    let p = c.program();
    assert!(
        p.groups.len() >= 4,
        "expected group functions, got {}",
        p.groups.len()
    );
    assert!(c.wgsl.contains("fn scene_group0("));
    for k in 0..400 {
        let x = k as f64 * 0.5 - 2.0;
        let pt = [x, 0.7, 0.1];
        let want = (0..100)
            .map(|i| {
                let d = [pt[0] - (i * 2) as f64, pt[1], pt[2]];
                (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() - (0.3 + (i % 3) as f64 * 0.1)
            })
            .fold(f64::INFINITY, f64::min);
        let got = eval_func(&p.distance, &p.groups, &Inputs::at(pt))[0]
            .scalar()
            .unwrap();
        assert!((got - want).abs() < 1e-5, "at {pt:?}: {got} vs {want}");
        let nearest = (0..100)
            .min_by(|a, b| {
                let da = (pt[0] - (*a * 2) as f64).hypot(0.7f64.hypot(0.1))
                    - (0.3 + (*a % 3) as f64 * 0.1);
                let db = (pt[0] - (*b * 2) as f64).hypot(0.7f64.hypot(0.1))
                    - (0.3 + (*b % 3) as f64 * 0.1);
                da.total_cmp(&db)
            })
            .unwrap();
        let albedo = eval_func(&p.material, &p.groups, &Inputs::at(pt))[0];
        let want_red = nearest % 2 == 0;
        match albedo {
            Value::V4(a) => assert_eq!(a[0] == 1.0, want_red, "at {pt:?}: {a:?}"),
            v => panic!("{v:?}"),
        }
    }
}
