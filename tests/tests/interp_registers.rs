//! The benchmarks' scene suite against the interpreter's limits: every scene the interpreted
//! baseline is measured on must encode (`sdfc_wgsl::interp::encode`), the 300-shape grid
//! included (it once needed 81 registers of the 64), and the 5 000-shape grid.

use sdfc_wgsl::interp::encode::{encode, MAX_REGISTERS};
use sdfc_wgsl::{compile, Options};

fn fits(name: &str, src: &str) {
    let c = compile(src, &Options::default()).unwrap_or_else(|_| panic!("{name} compiles"));
    match encode(c.program()) {
        Ok(code) => {
            eprintln!("{name}: {} registers", code.registers);
            assert!(code.registers <= MAX_REGISTERS, "{name}");
        }
        Err(e) => panic!("{name} does not encode: {e}"),
    }
}

#[test]
fn the_300_shape_grid_fits() {
    fits("grid_scene(300)", &sdfc_tests::grid_scene(300));
}

/// The suite's largest scene: since the encoder also tries the graph's order regrouped call
/// by call, a union's material keeps only one child's results live at a time (1 000 shapes
/// needed more than 64 registers before; now 42, and 45 for 5 000).
#[test]
fn the_5000_shape_grid_fits() {
    for n in [1000, 5000] {
        fits(&format!("grid_scene({n})"), &sdfc_tests::grid_scene(n));
    }
}

#[test]
fn the_examples_fit() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples");
    for path in sdfc_tests::sdf_files(&dir) {
        let src = std::fs::read_to_string(&path).unwrap();
        fits(&path.display().to_string(), &src);
    }
}
