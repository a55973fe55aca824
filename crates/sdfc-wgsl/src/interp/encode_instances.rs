//! `encode_instances`: a program whose root is a large union of instances as bytecode that
//! walks the union read as data (`shaders/interpreter/instances.wgsl`), as the specialised
//! shader's `--instances` form does, instead of one inlined copy of code per shape. The live
//! path previews such a union so: its bytecode no longer grows with the shapes.

use super::allocate::allocate;
use super::encode::{
    reg, unsupported, Bytecode, Chunk, EncodeError, Encoder, Inputs, VIns, Val, MAX_CONSTANTS,
    MAX_INSTRUCTIONS, POINT,
};
use super::opcodes::Opcode;
use super::peephole::fold;
use crate::instances::{plan_interpreted, Plan, HEAD};
use sdfc_ir::scene::Material;
use sdfc_ir::Program;
use std::collections::HashMap;

/// `program` as the walk of its root union read as data ([`encode_instances`]), or `None`
/// where its root is not such a union (`instances::plan_interpreted`).
pub fn encode_as_data(program: &Program) -> Option<Result<Bytecode, EncodeError>> {
    let plan = plan_interpreted(program)?;
    Some(encode_instances(&plan, &program.scene.materials))
}

/// Encodes `plan`'s union (found in `materials`' program) as the interpreter's walk. The
/// code starts with each kind's distance at a local point (register 0), ending in
/// `instance_done`; the distance function is one `instances` and its `ret`; the material
/// function walks again and reads the nearest instance's material from a table in the
/// pool. The kinds' first instructions and the materials' table are runs of the pool,
/// whose starts are the instructions' immediates.
pub fn encode_instances(plan: &Plan, materials: &[Material]) -> Result<Bytecode, EncodeError> {
    let mut e = Encoder {
        groups: &[],
        consts: Vec::new(),
        const_index: HashMap::new(),
        args: None,
    };
    let top = Inputs {
        point: Val::Reg(POINT),
        best: None,
    };
    let mut code = Vec::new();
    let mut registers = 1;
    let mut starts = Vec::with_capacity(plan.templates.len());
    for (f, (_, tys)) in plan.templates.iter().zip(&plan.found.templates) {
        // Argument i: its first word in the record and its width (`instance_arg`).
        let mut word = HEAD as u32;
        let mut args = Vec::with_capacity(tys.len());
        for ty in tys {
            let width = ty.width() as u32;
            args.push(word | width << 8);
            word += width;
        }
        if word > 0xff {
            return Err(unsupported("a kind's arguments beyond 255 words"));
        }
        e.args = Some(args);
        let mut chunk = Chunk::new();
        let d = e.func(&mut chunk, f, &f.results, top, 0)?;
        let d = reg(chunk.materialize(d[0]), "a kind's distance")?;
        chunk.ins.push(VIns::control(Opcode::InstanceDone, vec![d]));
        starts.push(code.len());
        registers = registers.max(allocate(&fold(chunk.ins), &mut code)?);
    }
    e.args = None;
    let kinds = code.len() as u32;

    // The runs of the pool, not shared with other constants: the kinds' first instructions,
    // then each material's albedo and phong (the scene's index 2i and 2i + 1; one default
    // where the scene has none).
    let mut pool = e.consts;
    let kinds_at = pool.len() as u32;
    pool.extend(starts.iter().map(|&s| [s as f32, 0.0, 0.0, 0.0]));
    let table = pool.len() as u32;
    let default = [Material::default()];
    let materials = if materials.is_empty() {
        &default[..]
    } else {
        materials
    };
    for m in materials {
        pool.push(m.albedo());
        pool.push(m.phong());
    }
    // Both starts are 16-bit immediates.
    if pool.len() > MAX_CONSTANTS || table + 1 > 0xffff {
        return Err(EncodeError::TooLarge(format!(
            "more than {MAX_CONSTANTS} constants with the kinds and materials"
        )));
    }

    let walk = |c: &mut Chunk| c.emit(Opcode::Instances, &[POINT], kinds_at);
    let ret = |args: Vec<u32>| VIns::control(Opcode::Ret, args);
    let mut chunk = Chunk::new();
    let d = walk(&mut chunk);
    chunk.ins.push(ret(vec![d]));
    let start = code.len() as u32;
    registers = registers.max(allocate(&chunk.ins, &mut code)?);
    let distance = [start, code.len() as u32];

    let mut chunk = Chunk::new();
    let nearest = walk(&mut chunk);
    let albedo = chunk.emit(Opcode::MaterialRow, &[nearest], table);
    let phong = chunk.emit(Opcode::MaterialRow, &[nearest], table + 1);
    chunk.ins.push(ret(vec![albedo, phong]));
    let start = code.len() as u32;
    registers = registers.max(allocate(&chunk.ins, &mut code)?);
    let material = [start, code.len() as u32];

    if code.len() > MAX_INSTRUCTIONS {
        return Err(EncodeError::TooLarge(format!(
            "{} instructions, at most {MAX_INSTRUCTIONS}",
            code.len()
        )));
    }
    let instances = plan
        .words()
        .chunks_exact(4)
        .map(|v| [v[0], v[1], v[2], v[3]])
        .collect();
    Ok(Bytecode {
        code,
        consts: pool,
        distance,
        // The instances' march is the plain distance's in the specialised shader too (a plane
        // alone leaves a union read as data: `instances::plan`).
        distance_ray: distance,
        material,
        registers,
        kinds,
        instances,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interp::encode::encode;
    use crate::interp::exec::{run, Function};

    /// 40 shapes of five kinds, moved, turned and scaled, three
    /// with materials.
    fn union() -> String {
        let mut s = String::from(
            "material red { color: [1, 0, 0] }\nmaterial blue { color: [0, 0, 1] }\n\
             material green { color: [0, 1, 0], specular: 0.2 }\nscene = union(\n",
        );
        for i in 0..40 {
            let shape = match i % 5 {
                0 => "sphere(0.4)".to_string(),
                1 => format!("box([0.5, 0.3, 0.4]).rotate_y({}deg).material(red)", 17 * i),
                2 => format!("torus(0.4, 0.1).rotate_x({}deg).scale(1.3)", 11 * i),
                3 => "capsule([0, 0, 0], [0, 0.6, 0], 0.15).rotate_z(30deg).material(blue)".into(),
                _ => format!(
                    "capped_torus(0.4, 0.1, 60deg).rotate_y({}deg).material(green)",
                    7 * i
                ),
            };
            let (x, z) = (i % 7, i / 7);
            s += &format!(
                "    {shape}.translate([{x}.5, {}, -{z}]),\n",
                (i % 3) as f64 * 0.7
            );
        }
        s + ");\n"
    }

    /// Points over the union's box and around it, spread by a fixed sequence.
    fn points() -> impl Iterator<Item = [f32; 3]> {
        (0..600u32).map(|i| {
            // A hash of (i, k): the three coordinates independent of each other.
            let f = |k: u32| {
                let mut h = (3 * i + k).wrapping_mul(0x9e37_79b9);
                h ^= h >> 15;
                h = h.wrapping_mul(0x85eb_ca6b);
                h ^= h >> 13;
                (h % 10007) as f32 / 10007.0
            };
            [-0.5 + 8.0 * f(1), -0.5 + 2.5 * f(2), -6.0 + 7.0 * f(3)]
        })
    }

    /// The walk gives the union's distance where the plain bytecode's is small (there it is
    /// exact: every instance within reach is evaluated), a lower bound of it everywhere, and
    /// the nearest shape's material at the surface; one `instances` is the whole distance
    /// function.
    #[test]
    fn the_walk_gives_the_unions_distance_and_material() {
        let c = crate::compile(&union(), &Default::default()).unwrap();
        let p = c.program();
        let plain = encode(p).unwrap();
        let plan = plan_interpreted(p).expect("a union of instances");
        let walked = encode_instances(&plan, &p.scene.materials).unwrap();
        assert_eq!(
            walked.distance[1] - walked.distance[0],
            2,
            "{}",
            walked.listing()
        );
        assert!(walked.code.len() < plain.code.len() / 4);
        let (mut exact, mut surfaces) = (0, 0);
        for q in points() {
            let d = run(&plain, Function::Distance, q, &[], 0.0).unwrap()[0][0];
            let w = run(&walked, Function::Distance, q, &[], 0.0).unwrap()[0][0];
            assert!(
                w <= d + 1e-5 * (1.0 + d.abs()),
                "at {q:?}: walk {w} above {d}"
            );
            assert!((w > 0.0) == (d > 0.0), "at {q:?}: walk {w}, code {d}");
            if d < 0.3 {
                exact += 1;
                assert!(
                    (w - d).abs() <= 2e-6 * (1.0 + d.abs()),
                    "at {q:?}: walk {w}, code {d}"
                );
            }
            if d.abs() < 0.05 {
                surfaces += 1;
                let m = run(&plain, Function::Material, q, &[], 0.0).unwrap();
                let n = run(&walked, Function::Material, q, &[], 0.0).unwrap();
                assert_eq!(m, n, "material at {q:?}");
            }
        }
        assert!(
            exact > 100 && surfaces > 10,
            "{exact} near, {surfaces} at a surface"
        );
    }

    /// The listing shows the kinds' code, the walk and the materials' table.
    #[test]
    fn the_listing_names_the_kinds_and_the_table() {
        let c = crate::compile(&union(), &Default::default()).unwrap();
        let p = c.program();
        let walked = encode_instances(&plan_interpreted(p).unwrap(), &p.scene.materials).unwrap();
        let listing = walked.listing();
        for needle in [
            "kinds:",
            "instance_done",
            "arg word 10 x",
            "instances kinds c",
            "material_row table c",
        ] {
            assert!(listing.contains(needle), "{needle}:\n{listing}");
        }
    }
}
