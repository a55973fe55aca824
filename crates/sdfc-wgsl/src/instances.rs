//! A large union emitted as data (`Options::instances`): the instances and their hierarchy
//! (`sdfc_ir::instances`) laid out in the buffer at binding 3, and the WGSL that walks them
//! (`shaders/instances.wgsl`) with one function per kind of primitive.

use crate::consts::Consts;
use crate::func::emit_template;
use crate::literal;
use sdfc_ir::func::Func;
use sdfc_ir::instances::{
    find_at_least, find_mixed, rest_functions, Instances, Rest, MIN_CHILDREN,
};
use sdfc_ir::scene::{Material, Normals};
use sdfc_ir::value::Value;
use sdfc_ir::Program;
use std::fmt::Write;

/// The walk over the data.
const WALK: &str = include_str!("../../../shaders/instances.wgsl");
/// The march's lists of the instances each ray passes.
const RAYS: &str = include_str!("../../../shaders/instances_rays.wgsl");
/// The pass that lists each block of pixels' candidates for its camera rays' lists.
const BLOCKS: &str = include_str!("../../../shaders/instances_blocks.wgsl");
/// `scene_distance` and `scene_material` over a union of instances alone.
const ENDS: &str = include_str!("../../../shaders/instances_ends.wgsl");
/// The same over a mixed union: the walk beside the other children's code.
const ENDS_MIXED: &str = include_str!("../../../shaders/instances_mixed.wgsl");

/// A program's root union as data: what was found, its kinds' distance functions, and the
/// code of its other children where it is mixed (`sdfc_ir::instances::find_mixed`).
pub struct Plan {
    pub found: Instances,
    pub templates: Vec<Func>,
    pub rest: Option<Rest>,
}

/// The plan for `p`'s render shader, or `None` where its root is not a union holding
/// instances (`sdfc_ir::instances::find_mixed`), or where the shader needs the union as
/// code: analytic
/// normals differentiate the distance function, and `scene_distance_ray` steps along rays
/// through displacements and heightfields, which the walk does not have (not for planes
/// alone: the other children's march, `march_rest`, keeps their plain distance).
pub fn plan(p: &Program) -> Option<Plan> {
    plan_at_least(p, MIN_CHILDREN, None)
}

/// [`plan`] for a union of at least `min` instances, and none where more than `crowd` of
/// their boxes hold one point (the rule of `Instances::Auto`). The union may hold other
/// children too (a floor, a fractal): they stay code, evaluated beside the walk.
pub fn plan_at_least(p: &Program, min: usize, crowd: Option<usize>) -> Option<Plan> {
    let found = found_at_least(p, min)?;
    if crowd.is_some_and(|limit| found.crowd_exceeds(limit)) {
        return None;
    }
    let relative = p.relative.as_ref().map(|r| r.origin);
    let rest = rest_functions(&p.scene, &found, relative);
    Some(with_templates(p, found, rest))
}

/// The union of at least `min` instances the render shader could read as data, before its
/// kinds' functions are built.
fn found_at_least(p: &Program, min: usize) -> Option<Instances> {
    let frame = p.marched();
    // A ray function for planes alone does not count: the walk's march reaches a floor
    // through `march_rest` as before, and the data form's gain is the larger.
    if p.scene.render.normals == Normals::Analytic
        || (frame.distance_ray.is_some() && p.distance_ray_slopes)
    {
        return None;
    }
    find_mixed(&p.scene, &p.analysis, frame.origin.map(f64::from), min)
}

/// Whether `p`'s root union holds [`crate::AUTO_INSTANCES`] or more instances but crowds them
/// (more than [`crate::AUTO_CROWD`] of their boxes hold one point): [`crate::Instances::Auto`]
/// then keeps it code, and `sdfc render` says why.
pub fn crowded(p: &Program) -> bool {
    found_at_least(p, crate::AUTO_INSTANCES).is_some_and(|f| f.crowd_exceeds(crate::AUTO_CROWD))
}

/// The plan for `p`'s interpreted form (`interp::encode::encode_instances`), or `None` where
/// its root is not a union of instances. The interpreter takes difference normals only
/// (analytic normals fall back to the tetrahedron there), and a union of instances alone has
/// no ray function (no plane, no displacement beside the instances), so only the union
/// decides.
pub fn plan_interpreted(p: &Program) -> Option<Plan> {
    let frame = p.marched();
    // The program's own analysis of its scene: the instances' boxes, the kinds' functions.
    let found = find_at_least(
        &p.scene,
        &p.analysis,
        frame.origin.map(f64::from),
        MIN_CHILDREN,
    )?;
    Some(with_templates(p, found, None))
}

/// The plan of a union found in `p`: its kinds' distance functions built.
fn with_templates(p: &Program, found: Instances, rest: Option<Rest>) -> Plan {
    let templates = sdfc_ir::to_ssa::template_functions(&p.scene, &p.analysis, &found.templates)
        .iter()
        .map(|f| sdfc_ir::passes::optimise(f).0)
        .collect();
    Plan {
        found,
        templates,
        rest,
    }
}

/// Words of an instance's record before its arguments: quaternion, centre and scale, kind
/// and material. The record is padded to whole vec4s.
pub const HEAD: usize = 10;

/// The bits of an f32.
fn bits(x: f64) -> u32 {
    (x as f32).to_bits()
}

/// Where argument word `k` of a record lies: its vec4, counted from the record's third (the
/// kind's), and lane.
pub fn arg_word(k: usize) -> (usize, usize) {
    ((HEAD + k) / 4 - 2, (HEAD + k) % 4)
}

impl Plan {
    /// The buffer at binding 3, as `shaders/instances.wgsl` reads it: the nodes, then the
    /// instances' records in leaf order, little-endian.
    pub fn data(&self) -> Vec<u8> {
        self.words().iter().flat_map(|w| w.to_le_bytes()).collect()
    }

    /// The buffer's words ([`Plan::data`]), a whole number of vec4s.
    pub fn words(&self) -> Vec<u32> {
        let nodes = &self.found.nodes;
        let leaves: Vec<u32> = nodes.iter().filter_map(|n| n.leaf).collect();
        let mut record = vec![0u32; self.found.items.len()];
        let mut words: Vec<u32> = Vec::new();
        for n in nodes {
            words.extend(n.centre.map(bits));
            words.push(n.skip);
            words.extend(n.half.map(bits));
            words.push(0);
        }
        for &i in &leaves {
            record[i as usize] = (words.len() / 4) as u32;
            let it = &self.found.items[i as usize];
            words.extend(it.q.map(bits));
            words.extend(it.centre.map(bits));
            words.push(bits(it.scale));
            words.push(it.template);
            words.push(it.material);
            for v in &it.args {
                words.extend(v.comps().iter().map(|&x| bits(x)));
            }
            words.resize(words.len().div_ceil(4) * 4, 0);
        }
        for (k, n) in nodes.iter().enumerate() {
            if let Some(i) = n.leaf {
                words[8 * k + 7] = 1 + record[i as usize];
            }
        }
        words
    }

    /// The WGSL of the scene functions: the kinds' functions, their `switch`, the materials'
    /// lookup and the walk.
    pub fn emit(&self, materials: &[Material], consts: &Consts) -> String {
        let mut s = String::new();
        // The record's vec4s from the kind's on, as many as the longest arguments need.
        let words = |tys: &Vec<sdfc_ir::types::Ty>| tys.iter().map(|t| t.width()).sum::<usize>();
        let vec4s = self
            .found
            .templates
            .iter()
            .map(|(_, tys)| (HEAD + words(tys)).div_ceil(4) - 2)
            .max()
            .unwrap_or(1);
        for (f, (_, tys)) in self.templates.iter().zip(&self.found.templates) {
            s.push('\n');
            s += &emit_template(
                f,
                tys,
                vec4s,
                consts,
                "One kind of the union's shapes: its distance in its own frame, with an instance's arguments.",
            );
        }
        let args: String = (0..vec4s).map(|v| format!(", a{v}")).collect();
        let loads: String = (0..vec4s)
            .map(|v| format!("    let a{v} = scene_data[r + {}u];\n", v + 2))
            .collect();
        s += "\n// One instance's distance at its local point, from its record at vec4 r: its\n";
        s += "// arguments' vec4s loaded once, then its kind's function.\n";
        let _ = writeln!(s, "fn instance_kind(p: vec3<f32>, r: u32) -> f32 {{");
        s += &loads;
        s += "    switch a0.x {\n";
        let last = self.templates.len() - 1;
        for (k, f) in self.templates.iter().enumerate() {
            let case = if k == last {
                "default".into()
            } else {
                format!("case {k}u")
            };
            let _ = writeln!(
                s,
                "        {case}: {{\n            return {}(p{args});\n        }}",
                f.name
            );
        }
        s += "    }\n}\n";
        let mut used: Vec<u32> = self.found.items.iter().map(|i| i.material).collect();
        used.sort_unstable();
        used.dedup();
        s += "\n// A material, by the scene's index (the instances' only).\n";
        s += "fn material_by_index(i: u32) -> SceneMaterial {\n    switch i {\n";
        for (k, &m) in used.iter().enumerate() {
            let material = materials.get(m as usize).cloned().unwrap_or_default();
            let v = |x: [f32; 4]| literal::value(&Value::V4(x));
            let case = if k == used.len() - 1 {
                "default".into()
            } else {
                format!("case {m}u")
            };
            let _ = writeln!(
                s,
                "        {case}: {{\n            return SceneMaterial({}, {});\n        }}",
                v(material.albedo()),
                v(material.phong())
            );
        }
        s += "    }\n}\n\n";
        s += WALK;
        s += "\n";
        s += RAYS;
        s += "\n";
        s += BLOCKS;
        s += "\n";
        s += if self.rest.is_some() {
            ENDS_MIXED
        } else {
            ENDS
        };
        s
    }
}
