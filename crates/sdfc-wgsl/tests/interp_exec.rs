//! The encoder against the IR: every scene's bytecode, run by the CPU twin of the
//! interpreter shader (`interp::exec`), gives the IR evaluator's distance, ray distance
//! (`scene_distance_ray`, along a random direction) and material at random points, plainly
//! compiled and culled (where a culled part is skipped exactly as the IR's evaluator skips
//! its call). The twin computes in f32 through the same `sdfc_ir::eval::apply` as the
//! evaluator, so the two agree to rounding: 1e-5 relative (at least 1e-5 absolute), on every
//! point. A device that disagrees with both is at fault.

use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_ir::value::Value;
use sdfc_ir::Program;
use sdfc_wgsl::interp::encode::encode;
use sdfc_wgsl::interp::exec::{run, Function};
use sdfc_wgsl::Options;
use std::path::{Path, PathBuf};

const POINTS: usize = 400;

fn scenes() -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut paths: Vec<PathBuf> = Vec::new();
    for dir in [
        "examples",
        "crates/sdfc-render/tests/scenes",
        "tests/scenes",
    ] {
        for e in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|e| e == "sdf") {
                paths.push(p);
            }
        }
    }
    paths.sort();
    assert!(paths.len() > 40, "the scenes are missing");
    let mut out: Vec<(String, String)> = paths
        .iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(p).unwrap())
        })
        .collect();
    out.push(("grid of 150 shapes".into(), grid(150)));
    out
}

/// Spheres, rotated boxes and tori in two materials on a 6 x 5 x 5 grid: a culled union of
/// two levels of parts.
fn grid(n: usize) -> String {
    let mut s = String::from(
        "material red { color: [0.9, 0.2, 0.1] }\nmaterial blue { color: [0.1, 0.2, 0.9] }\nscene = union(\n",
    );
    for i in 0..n {
        let (x, y, z) = (i % 6, (i / 6) % 5, i / 30);
        let shape = match i % 3 {
            0 => "sphere(0.4).material(red)".to_string(),
            1 => format!("box([0.3, 0.4, 0.3]).rotate_y({i}deg)"),
            _ => format!("torus(0.3, 0.1).rotate_x({i}deg).material(blue)"),
        };
        s += &format!("  {shape}.translate([{x}, {y}, {z}]),\n");
    }
    s + ");\n"
}

/// A deterministic generator of points in a box (no dependency for this).
struct Points(u64);

impl Points {
    fn unit(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn close(a: f32, b: f32) -> bool {
    a == b || (a - b).abs() <= 1e-5 * a.abs().max(b.abs()).max(1.0)
}

/// Checks the distance, the ray function (along a random direction) and the material at
/// `POINTS` points; the number of ray functions' checks.
fn agree(name: &str, program: &Program) -> usize {
    let mut rays = 0;
    let code = encode(program).unwrap_or_else(|e| panic!("{name}: {e}"));
    // The params' default values, as the data buffer holds them (floats splatted).
    let params: Vec<[f32; 4]> = program
        .scene
        .params
        .iter()
        .map(|p| match p.default {
            Value::F(x) => [x; 4],
            ref v => {
                let mut a = [0.0; 4];
                for (s, c) in a.iter_mut().zip(v.comps()) {
                    *s = c;
                }
                a
            }
        })
        .collect();
    let target = program.scene.camera.target;
    let mut points = Points(0x5dfc);
    for k in 0..POINTS {
        let p = [0, 1, 2].map(|i| target[i] + 8.0 * (points.unit() - 0.5));
        let inputs = Inputs {
            params: program.scene.params.iter().map(|d| d.default).collect(),
            time: 0.7,
            ..Inputs::at(p)
        };
        let want = eval_func(&program.distance, &program.groups, &inputs)[0]
            .scalar()
            .unwrap();
        let got = run(&code, Function::Distance, p, &params, 0.7)
            .unwrap_or_else(|e| panic!("{name}: {e}"))[0][0];
        assert!(
            close(want, got),
            "{name}: distance at {p:?} (point {k}): IR {want}, bytecode {got}"
        );
        if let Some(ray) = &program.distance_ray {
            let u = [0, 1, 2].map(|_| points.unit() - 0.5);
            let n = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt().max(1e-3);
            let rd = u.map(|c| c / n);
            let inputs = Inputs {
                ray: rd,
                ..inputs.clone()
            };
            let want = eval_func(ray, &program.groups, &inputs)[0]
                .scalar()
                .unwrap();
            let got = run(&code, Function::DistanceRay(rd), p, &params, 0.7)
                .unwrap_or_else(|e| panic!("{name}: {e}"))[0][0];
            rays += 1;
            assert!(
                close(want, got),
                "{name}: ray distance at {p:?} along {rd:?} (point {k}): IR {want}, bytecode {got}"
            );
        }
        let want = eval_func(&program.material, &program.groups, &inputs);
        let got = run(&code, Function::Material, p, &params, 0.7)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        for (w, g) in want.iter().zip(got) {
            let w = w.comps();
            assert!(
                w.iter().zip(g).all(|(a, b)| close(*a, b)),
                "{name}: material at {p:?} (point {k}): IR {w:?}, bytecode {g:?}"
            );
        }
    }
    rays
}

#[test]
fn bytecode_computes_what_the_ir_does_plain_and_culled() {
    let mut culled_skips = 0;
    let mut rays = 0;
    for (name, src) in scenes() {
        for cull in [false, true] {
            let opts = Options {
                cull,
                ..Options::default()
            };
            let Ok(c) = sdfc_wgsl::compile(&src, &opts) else {
                panic!("{name} does not compile");
            };
            rays += agree(&format!("{name} (cull {cull})"), c.program());
            if cull {
                let code = encode(c.program()).unwrap();
                culled_skips += code
                    .code
                    .iter()
                    .filter(|i| i[0] == sdfc_wgsl::interp::opcodes::Opcode::SkipUnlessLess.code())
                    .count();
            }
        }
    }
    // The ray functions are checked on many scenes (every one with a floor has one).
    assert!(rays >= 20 * POINTS, "{rays} checks of ray functions");
    // The check covers skipped parts: the grid alone has two levels of them.
    assert!(
        culled_skips >= 16,
        "{culled_skips} skips in all the culled scenes"
    );
}
