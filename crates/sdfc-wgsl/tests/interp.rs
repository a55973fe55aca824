//! The interpreted marcher's compile side: the shader validates, the opcode table and the
//! WGSL switch agree, the encoder's output (golden) and its limits.

use sdfc_ir::ops::Helper;
use sdfc_wgsl::interp::encode::{encode, EncodeError, MAX_REGISTERS};
use sdfc_wgsl::interp::{self, opcodes};

fn program(src: &str) -> sdfc_ir::Program {
    match sdfc_wgsl::compile(src, &Default::default()) {
        Ok(c) => c.stages.program,
        Err(_) => panic!("does not compile:\n{src}"),
    }
}

fn root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn the_interpreter_shader_passes_naga() {
    let wgsl = interp::emit();
    if let Err(report) = sdfc_wgsl::validate::validate("interpreter.wgsl", &wgsl) {
        panic!("{report}");
    }
    assert!(interp::shader().is_ok());
    for f in [
        "fn scene_normal(",
        "fn shadow(",
        "fn ambient_occlusion(",
        "fn main(",
    ] {
        assert_eq!(wgsl.matches(f).count(), 1, "{f}");
    }
    // Drivers inline every call, and each call of the distance function is a copy of the
    // whole interpreter (its switch over every opcode): the march (which refines in its
    // stepping loop, `shaders/march_merged.wgsl`) calls the ray function, the normal, the
    // shadow and ambient occlusion the plain one, once each, every method of a feature
    // sharing its loop.
    let calls = |f: &str| -> Vec<&str> {
        wgsl.lines()
            .filter(|l| l.contains(&format!("{f}(")) && !l.contains(&format!("fn {f}(")))
            .collect()
    };
    assert_eq!(
        calls("scene_distance").len(),
        3,
        "{:#?}",
        calls("scene_distance")
    );
    assert_eq!(
        calls("scene_distance_ray"),
        ["        let d = scene_distance_ray(ro + rd * t, rd);"]
    );
    assert!(!wgsl.contains("fn refine("));
    assert_eq!(wgsl.matches("interpret(frame.").count(), 3);
    // One instruction per trip of the loop, and no loop inside an instruction: lavapipe
    // counts every loop reached against an invocation's 65 535 trips, lanes masked or not.
    assert_eq!(wgsl.matches("pc = execute(&regs, pc);").count(), 1);
    // A pixel whose run was cut short is marked in its alpha.
    assert_eq!(wgsl.matches("select(1.0, 0.0, cut)").count(), 1);
    let execute = &wgsl[wgsl.find("fn execute(").unwrap()..wgsl.find("fn interpret(").unwrap()];
    for word in ["for (", "loop {", "while "] {
        assert!(!execute.contains(word), "a loop in an instruction: {word}");
    }
}

/// The variant that walks a union read as data is the same module with the walk's four
/// cases and `shaders/interpreter/instances.wgsl` (and ambient occlusion and shadows
/// sampling through it), valid, and with no loop in an instruction either; the other has
/// none of the walk.
#[test]
fn the_walking_variant_adds_the_walk_only() {
    use interp::Variant;
    let code = interp::emit_variant(1, Variant::Code);
    let walk = interp::emit_variant(1, Variant::Walk);
    assert_eq!(code, interp::emit());
    if let Err(report) = sdfc_wgsl::validate::validate("walk.wgsl", &walk) {
        panic!("{report}");
    }
    assert!(interp::shader_variant(interp::CPU_UNROLL, Variant::Walk).is_ok());
    for word in [
        "case OP_INSTANCES:",
        "fn walk_trip(",
        "var<private> walk_at",
    ] {
        assert_eq!(walk.matches(word).count(), 1, "{word}");
        assert!(!code.contains(word), "{word}");
    }
    for word in ["walk_", "case OP_ARG"] {
        assert!(!code.contains(word), "{word}");
    }
    assert!(walk.contains(interp::INSTANCES));
    // Ambient occlusion's samples walk without far boxes' bounds (`occlusion_distance`).
    assert!(walk.contains("let d = occlusion_distance(p + n * h);"));
    assert!(code.contains("let d = scene_distance(p + n * h);"));
    // Soft shadows' samples take a far box's distance only where it cannot lower the light.
    assert!(
        walk.contains("let h = shadow_distance(q, select(light * t / frame.shadow_k, 0.0, hard));")
    );
    assert!(code.contains("let h = scene_distance(q);"));
    let execute = &walk[walk.find("fn execute(").unwrap()..walk.find("fn interpret(").unwrap()];
    let walk_fns = interp::INSTANCES;
    for word in ["for (", "loop {", "while "] {
        assert!(!execute.contains(word), "a loop in an instruction: {word}");
        assert!(!walk_fns.contains(word), "a loop in the walk: {word}");
    }
}

/// On a CPU device two instructions run per trip: the same module otherwise, and valid.
#[test]
fn the_cpu_devices_interpreter_runs_two_instructions_per_trip() {
    let one = interp::shader().unwrap();
    let two = interp::shader_unrolled(interp::CPU_UNROLL).unwrap();
    assert_eq!(interp::CPU_UNROLL, 2);
    assert_eq!(two.matches("pc = execute(&regs, pc);").count(), 2);
    let again = "        if pc < last {\n            pc = execute(&regs, pc);\n        }\n";
    assert_eq!(two.replacen(again, "", 1), one);
}

#[test]
fn every_opcode_has_one_case_and_every_helper_an_opcode() {
    for op in opcodes::Opcode::ALL {
        let case = format!("case {}:", op.wgsl_name());
        assert_eq!(
            interp::INTERPRET.matches(&case).count(),
            1,
            "{case} in shaders/interpreter/interpret.wgsl"
        );
    }
    let codes: std::collections::BTreeSet<u32> =
        opcodes::Opcode::ALL.iter().map(|o| o.code()).collect();
    assert_eq!(
        codes.len(),
        opcodes::Opcode::ALL.len(),
        "opcode numbers repeat"
    );
    let missing: Vec<&str> = Helper::ALL
        .iter()
        .filter(|h| opcodes::helper_opcode(**h).is_none())
        .map(|h| h.name())
        .collect();
    assert!(
        missing.is_empty(),
        "helpers without an interpreter opcode (add them to src/interp/opcodes.rs and \
         shaders/interpreter/interpret.wgsl): {missing:?}"
    );
}

#[test]
fn bytecode_of_a_small_scene() {
    let p = program(
        "material red { color: [0.9, 0.2, 0.1] }\n\
         param r = 0.5;\n\
         scene = union(sphere(1).material(red), box([1, 2, 1]).rotate_y(30deg).translate([2, 0, 0]), smooth: 0.25)\n\
               | torus(1, r).translate([0, sin(time), 0]);\n",
    );
    let code = encode(&p).expect("encodes");
    insta::assert_snapshot!("small_scene_bytecode", code.listing());
}

/// A culled union of 16 spheres in a row: four parts of four, each behind a skip over its
/// code, the skipped call's results set before it and the part's after it.
#[test]
fn bytecode_of_a_culled_union() {
    let spheres: Vec<String> = (0..16)
        .map(|i| format!("sphere(0.4).translate([{i}, 0, 0])"))
        .collect();
    let src = format!("scene = union({});\n", spheres.join(", "));
    let opts = sdfc_wgsl::Options {
        cull: true,
        ..Default::default()
    };
    let c = sdfc_wgsl::compile(&src, &opts).unwrap_or_else(|_| panic!("compiles"));
    let code = encode(c.program()).expect("encodes");
    let listing = code.listing();
    assert!(listing.contains("skip_unless_less"), "{listing}");
    insta::assert_snapshot!("culled_union_bytecode", listing);
}

/// A union of 16 shapes of two kinds read as data (`encode_as_data`): each kind's code
/// before the functions, reading its arguments from the record (`arg`) and ending in
/// `instance_done`; the distance one walk; the material a walk and two rows of the
/// materials' table.
#[test]
fn bytecode_of_a_union_read_as_data() {
    let shapes: Vec<String> = (0..16)
        .map(|i| match i % 2 {
            0 => format!("sphere(0.4).translate([{i}, 0, 0])"),
            _ => format!(
                "box([0.3, 0.2, 0.3]).rotate_y({i}0deg).material(red).translate([{i}, 0, 0])"
            ),
        })
        .collect();
    let src = format!(
        "material red {{ color: [1, 0, 0] }}\nscene = union({});\n",
        shapes.join(", ")
    );
    let p = program(&src);
    let code = sdfc_wgsl::interp::encode_instances::encode_as_data(&p)
        .expect("a union of instances")
        .expect("encodes");
    // Two vec4s per node (31 for 16 leaves), then the records: ten words before the
    // arguments, padded to whole vec4s (a sphere's one word: 3; a box's three: 4).
    assert_eq!(code.instances.len(), 2 * 31 + 8 * 3 + 8 * 4);
    insta::assert_snapshot!("union_as_data_bytecode", code.listing());
}

#[test]
fn large_and_grouped_scenes_fit_the_register_file() {
    // Spheres in a union large enough to be split into group functions.
    let mut src = String::from("scene = union(\n");
    for i in 0..400 {
        src += &format!("    sphere(0.3).translate([{}, {}, 0]),\n", i % 20, i / 20);
    }
    src += ");\n";
    let p = program(&src);
    assert!(!p.groups.is_empty(), "the union was not split into groups");
    let code = encode(&p).expect("encodes");
    assert!(code.registers <= MAX_REGISTERS);
    let spec = std::fs::read_to_string(root().join("examples/spec_section10.sdf")).unwrap();
    let code = encode(&program(&spec)).expect("encodes");
    assert!(code.registers <= MAX_REGISTERS);
}

/// Rotations shared by shapes far apart in a union (here `rotate_y(i % 90)` and
/// `rotate_x(i % 180)`, as in the benchmarks' grid scene) are loaded where they are used, so
/// they do not hold registers between uses: the 300-shape grid once needed 81.
#[test]
fn a_grid_of_300_rotated_shapes_fits_the_register_file() {
    let mut src = String::from("scene = union(\n");
    for i in 0..300 {
        let pos = format!("[{}, {}, {}]", i % 7, (i / 7) % 7, i / 49);
        src += &match i % 3 {
            0 => format!("    sphere(0.3).translate({pos}),\n"),
            1 => format!(
                "    box([0.5, 0.4, 0.5]).rotate_y({}deg).translate({pos}),\n",
                i % 90
            ),
            _ => format!(
                "    torus(0.4, 0.1).rotate_x({}deg).translate({pos}),\n",
                i % 180
            ),
        };
    }
    src += ");\n";
    let code = encode(&program(&src)).expect("encodes");
    assert!(
        code.registers <= MAX_REGISTERS,
        "{} registers",
        code.registers
    );
}

#[test]
fn too_many_live_values_is_a_clean_error() {
    // Terms t_i used twice: by a sum, then by a product. Whatever the order, every term
    // computed for the sum stays live until the product reads it, so MAX_REGISTERS + 8
    // terms need more registers than there are.
    let n = MAX_REGISTERS as usize + 8;
    let terms: Vec<String> = (0..n).map(|i| format!("sin(p.x * {}.5)", i + 1)).collect();
    let sum = terms.join(" + ");
    let product = terms.join(" * ");
    let src = format!(
        "scene = sdf(|p| length(p) - 1 + 0.001 * ({sum}) + 0.001 * ({product}), lipschitz: 2);\n"
    );
    match encode(&program(&src)) {
        Err(EncodeError::TooLarge(msg)) => assert!(msg.contains("live"), "{msg}"),
        Ok(code) => panic!("encoded in {} registers", code.registers),
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn the_preview_keeps_the_primary_ray_and_drops_the_secondary_ones() {
    let p = program(
        "render { shadows: soft(8), ao: ao(samples: 4, step: 0.1), reflections: 2, antialias: 3,
                  fog: fog(0.05, [0.6, 0.7, 0.8]), max_steps: 300, normals: central }
         scene = sphere(1);\n",
    );
    let r = &p.scene.render;
    let preview = sdfc_wgsl::interp::frame::preview_settings(r);
    assert_eq!(preview.shadows, sdfc_ir::scene::Shadows::None);
    assert_eq!(preview.ao, None);
    assert_eq!((preview.reflections, preview.antialias), (0, 1));
    // What the primary ray and its shading need stays.
    assert_eq!(preview.fog, r.fog);
    assert_eq!(preview.max_steps, 300);
    assert_eq!(preview.normals, r.normals);
    assert_eq!(preview.epsilon, r.epsilon);
}

#[test]
fn cut_pixels_are_counted_and_made_opaque() {
    let mut rgba = vec![10, 20, 30, 255, 1, 2, 3, 0, 0, 0, 0, 0];
    assert_eq!(interp::cut_pixels(&mut rgba), 2);
    assert_eq!(rgba, vec![10, 20, 30, 255, 1, 2, 3, 255, 0, 0, 0, 255]);
    assert_eq!(interp::cut_pixels(&mut rgba), 0);
}
