//! The per-scene parts of the marcher: constants from the camera and render settings, the
//! surface threshold, the normal method and the shading for the scene's lights. Only what
//! the settings ask for is emitted.

use crate::literal::{float, vec3};
use crate::parts;
use sdfc_ir::rounding::{f32_down, f32_up};
use sdfc_ir::scene::{Epsilon, Light, LightKind, Normals, Scene, Shadows};
use std::fmt::Write;

/// Where the shader's coordinates are centred and the lights there: the world origin, or
/// the camera for camera-relative coordinates (`sdfc_ir::Relative`).
pub struct View<'a> {
    pub origin: [f32; 3],
    pub lights: &'a [Light],
    /// Whether the scene has `scene_distance_ray`, which the march and the hit refinement
    /// then call instead of `scene_distance` (shadows, AO and normals keep the latter).
    pub along_ray: bool,
    /// The scene's bounds (the analysis's box of the root, world coordinates; infinite on
    /// unbounded axes), from which `ray_span` starts and ends each march.
    pub bounds: ([f64; 3], [f64; 3]),
    /// The box shadow rays stop at ([`shadow_slabs`]).
    pub shadow: [Slab; 3],
    /// Whether the union is read as data (`shaders/instances_rays.wgsl`): each march lists
    /// the instances its ray passes, then marches them one by one, each alone
    /// (`shaders/march_instances.wgsl`), and keeps the instance it hit for the tetrahedron
    /// normal (`normal_sample`) and the material (`end_leaf`); the central and forward
    /// normals sample `normal_distance` near the march's end; shadow rays are listed and
    /// marched instance by instance too (`crate::shadows`), and ambient occlusion's samples
    /// take a list along the normal (`crate::occlusion`).
    pub ray_lists: bool,
    /// Where the union read as data has other children (a floor, a fractal): those are
    /// marched first, on their own (`march_rest`), and their hit bounds the instances'
    /// lists and marches.
    pub rest: Option<RestMarch>,
    /// For a union read as data, the least factor by which an instance's distance outside
    /// its box is at least the distance to it (`Instances::outside_factor`): shadow rays'
    /// lists pad their boxes by it (`crate::shadows`).
    pub instances_outside: f64,
    /// For a union read as data, the instances' usual spacing (`Instances::spacing`): ambient
    /// occlusion takes one list for its samples where they reach no farther
    /// (`crate::occlusion`).
    pub instances_spacing: Option<f64>,
    /// Whether the scene's distance is trusted never to exceed the true distance
    /// (`Analysis::distance_trusted`): a pass by its surface is then told from a touch far
    /// more finely (`touch_distance` in `shaders/hit.wgsl`).
    pub trusted: bool,
    /// Outside the scene's bounds its distance is at least this factor times the distance to
    /// them (`Analysis::outside_factor`; 0 where nothing is known): soft shadow rays stop at
    /// the bounds by it (`bounds_outside`; a union read as data pads its shadow rays' lists
    /// by [`View::instances_outside`] instead).
    pub outside: f64,
    /// Whether the march's distance is dear (a union read as data, or `dear::is_dear`): the
    /// march (plain or relaxed) then refines in its stepping loop (`shaders/march_merged.wgsl`).
    pub dear: bool,
    /// The size of the scene's smallest shape (`Analysis::feature`), below which the
    /// difference normals' step does not go (`FEATURE_SIZE`).
    pub feature: f64,
}

/// How a mixed union's other children are marched (`march_rest`).
#[derive(Clone, Copy, Debug)]
pub struct RestMarch {
    /// Whether their distance is dear, which picks their march's loops as [`View::dear`]
    /// picks the scene's.
    pub dear: bool,
    /// Whether they have `rest_distance_ray` (a plane's distance along the ray), which their
    /// march then samples, as [`View::along_ray`] has the scene's sample `scene_distance_ray`.
    pub along_ray: bool,
}

impl View<'_> {
    /// The distance a walk of the instances at the point `p` starts below: a mixed union's
    /// other children's (`rest_distance`), no more than `cap` where one is given; else `cap`,
    /// or nothing known (3e38).
    pub(crate) fn walk_below(&self, p: &str, cap: Option<&str>) -> String {
        match (self.rest.is_some(), cap) {
            (true, Some(cap)) => format!("min(rest_distance({p}), {cap})"),
            (true, None) => format!("rest_distance({p})"),
            (false, Some(cap)) => cap.to_string(),
            (false, None) => "3.0e38".to_string(),
        }
    }
}

/// How the march's and the hit refinement's parts sample the ray; a test checks that each
/// still does.
const RAY_SAMPLE: &str = "scene_distance(ro + rd * t)";

/// A marcher part with its samples along the ray taken as `view` asks: through
/// `scene_distance_ray` where the scene has it, else as written.
fn sampled(part: &str, view: &View) -> String {
    sampled_by(part, "scene_distance", view.along_ray)
}

/// A marcher part with its samples along the ray taken through `scene_distance_ray` (the
/// interpreter's always are: its ray function is the plain distance's code where the scene
/// has none).
pub(crate) fn along_ray(part: &str) -> String {
    sampled_by(part, "scene_distance", true)
}

/// A marcher part with its samples along the ray taken by the distance function `name`, or
/// by its ray function (`{name}_ray`, which takes the direction too) where `along_ray`.
fn sampled_by(part: &str, name: &str, along_ray: bool) -> String {
    let sample = if along_ray {
        format!("{name}_ray(ro + rd * t, rd)")
    } else {
        format!("{name}(ro + rd * t)")
    };
    part.replace(RAY_SAMPLE, &sample)
}

pub fn emit(scene: &Scene, view: &View) -> String {
    let mut s = String::new();
    s += &constants(scene, view.origin, view.feature);
    s += "\n";
    s += parts::HIT;
    s += "\n";
    s += &ray_span(view);
    s += "\n";
    s += &surface_epsilon(scene);
    s += "\n";
    s += &distance_trusted(view.trusted);
    s += "\n";
    let marcher = Marcher::for_scene(scene, view);
    if !marcher.merged && !view.ray_lists {
        // The two-loop marcher's refinement loop (the merged one refines in its own).
        s += &sampled(parts::REFINE, view);
        s += "\n";
    }
    s += marcher.step();
    s += "\n";
    if view.ray_lists {
        // Its own loop, which refines in it as the merged one does: an instance read from
        // the data is dear beside the loop's bookkeeping.
        match view.rest {
            None => s += parts::MARCH_INSTANCES,
            Some(rest) => {
                s += &march_rest(rest);
                s += &parts::MARCH_INSTANCES.replacen(MARCH_ALONE_HEAD, MARCH_REST_HEAD, 1);
            }
        }
    } else {
        s += &sampled(marcher.loops(), view);
    }
    s += "\n";
    s += parts::CAMERA;
    s += "\n";
    s += parts::SAFE_NORMALIZE;
    s += "\n";
    let analytic = scene.render.normals == Normals::Analytic;
    // Analytic normals need no `scene_normal`: `surface_normal` itself takes the gradient
    // (`analytic_surface_normal`).
    if let Some(part) = match scene.render.normals {
        Normals::Central => Some(parts::NORMALS_CENTRAL),
        Normals::Forward => Some(parts::NORMALS_FORWARD),
        Normals::Tetrahedron => Some(parts::NORMALS_TETRAHEDRON),
        Normals::Analytic => None,
    } {
        if view.ray_lists {
            s += &normal_listed(part, scene.render.normals);
        } else {
            s += part;
        }
        s += "\n";
    }
    s += &crate::shadows::emit(scene.render.shadows, view);
    if let Some(ao) = &scene.render.ao {
        s += &crate::occlusion::emit(ao, view);
        s += "\n";
    }
    s += &shade(scene, view.lights);
    s += "\n";
    s += &finish(scene);
    s += "\n";
    s += if scene.render.reflections > 0 {
        parts::RADIANCE_REFLECTIONS
    } else {
        parts::RADIANCE_PLAIN
    };
    s += "\n";
    let main = analytic_surface_normal(parts::MAIN, analytic);
    if view.ray_lists {
        s += &end_leaf(&main_blocks(&main));
    } else {
        s += &main;
    }
    s
}

/// The start of the march of a union of instances alone (`shaders/march_instances.wgsl`):
/// no hit yet, no sample taken. A test checks it is there.
const MARCH_ALONE_HEAD: &str = "    var best = span.y;
    var found = false;
    var best_leaf = 0u;
    var steps = 0u;
";

/// The same march's start for a mixed union: the other children's march first
/// (`march_rest`), whose hit, where it has one, is the nearest so far.
const MARCH_REST_HEAD: &str =
    "    // The union's other children first, on their own (`march_rest`): their hit bounds
    // the lists and the instances' marches; so does where they ran out of steps (the
    // union's march ended there too: nothing is known beyond). A march that neither hit nor
    // ran out ends at or beyond span.y.
    let rest = march_rest(ro, rd, pixel);
    var best = select(min(span.y, rest.t), rest.t, rest.hit);
    var found = rest.hit;
    var best_leaf = 0u;
    var steps = rest.steps;
";

/// The march of a mixed union's other children alone (`rest_distance`, or
/// `rest_distance_ray` along the ray), over the same span: the scene's own march (and
/// refinement), merged where their distance is dear.
fn march_rest(how: RestMarch) -> String {
    let rest = |part: &str| sampled_by(part, "rest_distance", how.along_ray);
    let mut s = String::new();
    if how.dear {
        s += &rest(parts::MARCH_MERGED).replacen("fn march(", "fn march_rest(", 1);
    } else {
        s += &rest(parts::REFINE);
        s += "\n";
        s += &rest(parts::MARCH_TWO_LOOPS).replacen("fn march(", "fn march_rest(", 1);
    }
    s += "\n";
    s
}

/// The march's two choices, each made once. Its step: over-relaxed where `relaxation` asks
/// for it (`shaders/march_step_relaxed.wgsl`), else plain (`shaders/march_step.wgsl`); both
/// have the same interface, so either loop takes either. Its loops: refinement in the
/// stepping loop where the distance is dear (`View::dear`, `shaders/march_merged.wgsl`: one
/// copy of the distance instead of two; the union read as data 1.08x to 1.14x faster on
/// lavapipe, the 300-shape union's code 1.31x to 1.34x), in a loop of its own elsewhere
/// (`shaders/march_two_loops.wgsl`: a cheap distance's march pays more for refinement's
/// masked arithmetic at every step than for the second copy, spec section 10 0.77x merged;
/// docs/performance.md, "The marcher's two loops").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Marcher {
    relaxed: bool,
    merged: bool,
}

impl Marcher {
    fn for_scene(scene: &Scene, view: &View) -> Marcher {
        Marcher {
            relaxed: scene.render.relaxation > 1.0,
            merged: view.dear,
        }
    }

    fn step(self) -> &'static str {
        if self.relaxed {
            parts::MARCH_STEP_RELAXED
        } else {
            parts::MARCH_STEP
        }
    }

    fn loops(self) -> &'static str {
        if self.merged {
            parts::MARCH_MERGED
        } else {
            parts::MARCH_TWO_LOOPS
        }
    }
}

/// The tetrahedron normal's loop as `shaders/normals/tetrahedron.wgsl` writes it; a test
/// checks it is there.
const TETRAHEDRON_LOOP: &str = "    for (var i = 0u; i < 4u; i = i + 1u) {
        n = n + k[i] * scene_distance(p + k[i] * h);
    }";

/// A difference normal's part for a union read as data. The tetrahedron's samples take the
/// distance of what the march hit alone (`normal_sample`, `shaders/instances_ends.wgsl`):
/// the march kept its instance (`ray_end_leaf`; 0 for a mixed union's other children), where
/// a sample through the ray's list cost a copy of the list's loop (on lavapipe every inlined
/// copy runs, under masks; docs/performance.md, "The normal from the nearest instance"). The
/// central and forward normals' samples go through the ray's list (`normal_distance`).
fn normal_listed(part: &str, normals: Normals) -> String {
    if normals == Normals::Tetrahedron {
        part.replace(
            TETRAHEDRON_LOOP,
            "    // What the march hit (`shaders/march_instances.wgsl`); the samples take its
    // distance alone (`normal_sample`).
    let leaf = ray_end_leaf;
    for (var i = 0u; i < 4u; i = i + 1u) {
        n = n + k[i] * normal_sample(p + k[i] * h, leaf);
    }",
        )
    } else {
        part.replace("scene_distance(", "normal_distance(")
    }
}

/// The entry point's lines after which a union read as data finds its block's candidates
/// (`ray_blocks`) and marks each sample's march a camera ray's (`ray_primary`); a test checks
/// both are there.
const MAIN_FRAME: &str = "    load_frame();\n";
const MAIN_RAY: &str = "        let rd = camera_ray(vec2<f32>(gid) + offset, fsize);\n";

/// The entry point's part for a union read as data: each camera ray makes its list from its
/// block's candidates where the pass made them (`shaders/instances_blocks.wgsl`).
fn main_blocks(main: &str) -> String {
    main.replacen(
        MAIN_FRAME,
        &format!("{MAIN_FRAME}    ray_blocks(gid);\n"),
        1,
    )
    .replacen(
        MAIN_RAY,
        &format!("{MAIN_RAY}        ray_primary = true;\n"),
        1,
    )
}

/// The entry point's part for a union read as data, and `end_leaf`, the leaf word of the
/// instance the march hit that `scene_material` takes: the march kept it.
fn end_leaf(main: &str) -> String {
    format!(
        "{main}\n// The leaf word of the instance the march hit, ending at p (0 if none): for its\n\
         // material. The march kept it (`shaders/march_instances.wgsl`).\n\
         fn end_leaf(p: vec3<f32>) -> u32 {{\n    return ray_end_leaf;\n}}\n"
    )
}

/// The entry point's part with its `surface_normal` (difference normals at a rounded point)
/// replaced by the gradient's (`shaders/normals/analytic.wgsl`) for `normals: analytic`. The
/// function is cut out between its comment and the next one; a test checks both are there.
pub(crate) fn analytic_surface_normal(main: &str, on: bool) -> String {
    const START: &str = "// The normal at a hit p.";
    const END: &str = "// How far a secondary ray";
    match (on, main.find(START), main.find(END)) {
        (true, Some(a), Some(b)) if a < b => {
            format!("{}{}\n{}", &main[..a], parts::NORMALS_ANALYTIC, &main[b..])
        }
        _ => main.to_string(),
    }
}

/// The camera basis of spec section 8, computed in f64 and rounded once.
pub(crate) fn camera_basis(scene: &Scene) -> ([f32; 3], [f32; 3], [f32; 3], f32) {
    let c = &scene.camera;
    let v = |a: [f32; 3]| a.map(|x| x as f64);
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let norm = |a: [f64; 3]| {
        let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        a.map(|x| x / l)
    };
    let forward = norm(sub(v(c.target), v(c.position)));
    let right = norm(cross(forward, v(c.up)));
    let up = cross(right, forward);
    let f = |a: [f64; 3]| a.map(|x| x as f32);
    (
        f(forward),
        f(right),
        f(up),
        (c.fov as f64 * 0.5).tan() as f32,
    )
}

fn constants(scene: &Scene, origin: [f32; 3], feature: f64) -> String {
    let r = &scene.render;
    let (forward, right, up, tan_half) = camera_basis(scene);
    let mut s = String::from("// Camera (spec section 8) and render settings (spec section 7).\n");
    if origin != [0.0; 3] {
        let _ = writeln!(
            s,
            "// Camera-relative coordinates: the world point p is p - {} here.",
            vec3(origin)
        );
    }
    let position: Vec<f32> = (0..3)
        .map(|k| (scene.camera.position[k] as f64 - origin[k] as f64) as f32)
        .collect();
    let _ = writeln!(
        s,
        "const CAMERA_POSITION: vec3<f32> = {};",
        vec3([position[0], position[1], position[2]])
    );
    let _ = writeln!(s, "const CAMERA_FORWARD: vec3<f32> = {};", vec3(forward));
    let _ = writeln!(s, "const CAMERA_RIGHT: vec3<f32> = {};", vec3(right));
    let _ = writeln!(s, "const CAMERA_UP: vec3<f32> = {};", vec3(up));
    let _ = writeln!(s, "const TAN_HALF_FOV: f32 = {};", float(tan_half));
    let _ = writeln!(s, "const MAX_STEPS: u32 = {}u;", r.max_steps);
    let _ = writeln!(s, "const MAX_DISTANCE: f32 = {};", float(r.max_distance));
    let _ = writeln!(
        s,
        "// The size of the scene's smallest shape: the difference normals' step is at \
         least 2e-5 of it.\nconst FEATURE_SIZE: f32 = {};",
        float(f32_down(feature))
    );
    if r.relaxation > 1.0 {
        let _ = writeln!(s, "const RELAXATION: f32 = {};", float(r.relaxation));
    }
    let _ = writeln!(s, "const ANTIALIAS: u32 = {}u;", r.antialias);
    let _ = writeln!(s, "const BACKGROUND: vec3<f32> = {};", vec3(r.background));
    let _ = writeln!(
        s,
        "const INV_GAMMA: f32 = {};",
        float((1.0 / r.gamma as f64) as f32)
    );
    if let Shadows::Soft(k) = r.shadows {
        let _ = writeln!(s, "const SHADOW_K: f32 = {};", float(k));
    }
    if let Some(ao) = &r.ao {
        let _ = writeln!(s, "const AO_SAMPLES: u32 = {}u;", ao.samples);
        let _ = writeln!(s, "const AO_STEP: f32 = {};", float(ao.step));
        let _ = writeln!(s, "const AO_STRENGTH: f32 = {};", float(ao.strength));
        let _ = writeln!(s, "const AO_FALLOFF: f32 = {};", float(ao.falloff));
    }
    if r.reflections > 0 {
        let _ = writeln!(s, "const REFLECTIONS: u32 = {}u;", r.reflections);
    }
    s
}

/// The analysis's box of the scene's root (world coordinates; infinite on unbounded axes).
pub fn root_bounds(p: &sdfc_ir::Program) -> ([f64; 3], [f64; 3]) {
    p.analysis
        .nodes
        .get(p.scene.root.index())
        .map_or(([f64::NEG_INFINITY; 3], [f64::INFINITY; 3]), |n| {
            (n.bounds.lo, n.bounds.hi)
        })
}

/// One axis of the box `ray_span` clips rays to: its low and high ends where they are finite
/// (a floor's half-space has only a high end on y).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slab {
    pub lo: Option<f32>,
    pub hi: Option<f32>,
}

/// Whether no end of any axis is finite: the box bounds nothing.
pub fn all_open(slabs: &[Slab; 3]) -> bool {
    slabs.iter().all(|s| s.lo.is_none() && s.hi.is_none())
}

/// The slabs `ray_span` clips rays to: per axis, the ends of the scene's bounds that are
/// finite, in shader coordinates (`origin` subtracted), each padded by a thousandth of the
/// box's size over its axes bounded on both sides (and at least 1e-3) so that f32 rounding of
/// the slab test never cuts a surface off, computed in f64 and rounded outwards. Shared by the
/// specialised shader (as constants), the interpreter (in its data buffer) and the tiles
/// ([`crate::screen`]), so all clip alike.
pub fn span_slabs(bounds: ([f64; 3], [f64; 3]), origin: [f32; 3]) -> [Slab; 3] {
    let (lo, hi) = bounds;
    let both = |k: usize| lo[k].is_finite() && hi[k].is_finite() && lo[k] <= hi[k];
    let size = (0..3)
        .filter(|&k| both(k))
        .map(|k| hi[k] - lo[k])
        .fold(0.0f64, f64::max);
    let pad = (1e-3 * size).max(1e-3);
    // An empty box (lo above hi) clips nothing, like an unbounded one; an end past f32's
    // range (bounds grown by nested scales) clips nothing either.
    let end = |v: f64, k: usize| (v.is_finite() && lo[k] <= hi[k]).then(|| v - origin[k] as f64);
    std::array::from_fn(|k| Slab {
        lo: end(lo[k], k)
            .map(|v| f32_down(v - pad))
            .filter(|x| x.is_finite()),
        hi: end(hi[k], k)
            .map(|v| f32_up(v + pad))
            .filter(|x| x.is_finite()),
    })
}

/// `ray_span(ro, rd)`: the stretch of the ray, from 0 to MAX_DISTANCE, inside the scene's
/// bounds on the ends where they are finite ([`span_slabs`]). No surface lies before or after
/// it, so the marchers start and end there, and a ray that misses the box takes no step.
fn ray_span(view: &View) -> String {
    let slabs = span_slabs(view.bounds, view.origin);
    let mut s = String::from(
        "// The stretch of the ray inside the scene's bounds (padded): marching starts and ends\n\
         // there, and a ray that misses them takes no step.\n\
         fn ray_span(ro: vec3<f32>, rd: vec3<f32>) -> vec2<f32> {\n",
    );
    if all_open(&slabs) {
        s += "    return vec2<f32>(0.0, MAX_DISTANCE);\n}\n";
        return s;
    }
    s += "    var t0 = 0.0;\n    var t1 = MAX_DISTANCE;\n";
    for (k, slab) in slabs.iter().enumerate() {
        let c = ["x", "y", "z"][k];
        let _ = match (slab.lo, slab.hi) {
            (Some(a), Some(b)) => write!(
                s,
                "    if abs(rd.{c}) > 1e-30 {{\n\
                 \x20       let a = ({} - ro.{c}) / rd.{c};\n\
                 \x20       let b = ({} - ro.{c}) / rd.{c};\n\
                 \x20       t0 = max(t0, min(a, b));\n\
                 \x20       t1 = min(t1, max(a, b));\n\
                 \x20   }} else if ro.{c} < {} || ro.{c} > {} {{\n\
                 \x20       t1 = -1.0;\n\
                 \x20   }}\n",
                float(a),
                float(b),
                float(a),
                float(b),
            ),
            // One end: a ray going towards the open side leaves through it, one coming from
            // the open side enters through it.
            (Some(a), None) => half_slab(&mut s, c, a, true),
            (None, Some(b)) => half_slab(&mut s, c, b, false),
            (None, None) => Ok(()),
        };
    }
    s += "    return vec2<f32>(t0, t1);\n}\n";
    s
}

/// The box shadow rays stop at (`bounds_outside`): `ray_span`'s ([`span_slabs`]), on the same
/// finite ends, widened by what the fields shadow rays sample may answer beyond it. A union
/// read as data answers the distance to its hierarchy's root box (`data_root`: centre and
/// half-size in shader coordinates, as the data buffer has them, padded by a thousandth of
/// the size and 1e-3 in `sdfc_ir::instances`), which may stick out of the scene's; the
/// culled union's early-outs (`to_ssa/cull.rs`) the distance to boxes widened by 1e-5 of
/// their coordinates; and f32 arithmetic far from the origin rounds by about 1e-7 of them.
/// So every end also moves out by 1e-5 of the bounds' largest finite coordinate (at least
/// 1).
pub fn shadow_slabs(
    bounds: ([f64; 3], [f64; 3]),
    origin: [f32; 3],
    data_root: Option<([f32; 3], [f32; 3])>,
) -> [Slab; 3] {
    let slabs = span_slabs(bounds, origin);
    let far = bounds
        .0
        .iter()
        .chain(&bounds.1)
        .filter(|x| x.is_finite())
        .fold(1.0f64, |m, x| m.max(x.abs()));
    let e = 1e-5 * far;
    std::array::from_fn(|k| {
        let (mut lo, mut hi) = (slabs[k].lo.map(f64::from), slabs[k].hi.map(f64::from));
        if let Some((c, h)) = data_root {
            let (c, h) = (f64::from(c[k]), f64::from(h[k]).abs());
            lo = lo.map(|v| v.min(c - h));
            hi = hi.map(|v| v.max(c + h));
        }
        Slab {
            lo: lo.map(|v| f32_down(v - e)).filter(|x| x.is_finite()),
            hi: hi.map(|v| f32_up(v + e)).filter(|x| x.is_finite()),
        }
    })
}

/// `ray_span`'s test for an axis bounded at one end `v` only, its low end if `low`: a ray
/// heading for the open side leaves the box there (a low end is where a rising ray enters),
/// and one parallel to the end misses where it is outside of it.
fn half_slab(s: &mut String, c: &str, v: f32, low: bool) -> std::fmt::Result {
    let (rising, falling, outside) = if low {
        ("t0 = max(t0", "t1 = min(t1", "<")
    } else {
        ("t1 = min(t1", "t0 = max(t0", ">")
    };
    let v = float(v);
    write!(
        s,
        "    if rd.{c} > 1e-30 {{\n\
         \x20       {rising}, ({v} - ro.{c}) / rd.{c});\n\
         \x20   }} else if rd.{c} < -1e-30 {{\n\
         \x20       {falling}, ({v} - ro.{c}) / rd.{c});\n\
         \x20   }} else if ro.{c} {outside} {v} {{\n\
         \x20       t1 = -1.0;\n\
         \x20   }}\n",
    )
}

fn surface_epsilon(scene: &Scene) -> String {
    match scene.render.epsilon {
        Epsilon::Pixel => "// `epsilon: pixel`: half the pixel's footprint at distance t.\n\
             fn surface_epsilon(t: f32, pixel: f32) -> f32 {\n    return 0.5 * pixel * t;\n}\n"
            .to_string(),
        Epsilon::Absolute(e) => format!(
            "// `epsilon: {}`: an absolute surface threshold.\n\
             fn surface_epsilon(t: f32, pixel: f32) -> f32 {{\n    return {};\n}}\n",
            float(e),
            float(e)
        ),
    }
}

/// `distance_trusted()`, which `touch_distance` (`shaders/hit.wgsl`) reads: whether the
/// scene's distance is trusted (`Analysis::distance_trusted`).
fn distance_trusted(trusted: bool) -> String {
    format!(
        "// Whether the scene's distance never exceeds the true distance (exact, or a proven\n\
         // bound): a pass by its surface is then told from a touch down to rounding.\n\
         fn distance_trusted() -> bool {{\n    return {trusted};\n}}\n"
    )
}

/// Phong shading (spec section 6) for each light of the scene, unrolled; shadows and ambient
/// occlusion appear only when the settings ask for them. `offset` is how far shadow rays start
/// off the surface.
fn shade(scene: &Scene, lights: &[Light]) -> String {
    let shadows = scene.render.shadows != Shadows::None;
    let mut s =
        String::from("// Phong shading: ambient, then diffuse and specular for each light.\n");
    if shadows {
        s += "// Each light is attenuated by the shadow its ray to p casts.\n";
    }
    if scene.render.ao.is_some() {
        s += "// Ambient occlusion darkens the ambient term.\n";
    }
    s += "fn shade(p: vec3<f32>, n: vec3<f32>, rd: vec3<f32>, m: SceneMaterial, offset: f32) -> vec3<f32> {\n";
    s += "    let base = m.albedo.rgb;\n";
    if scene.render.ao.is_some() {
        s += "    var c = m.phong.x * ambient_occlusion(p, n) * base;\n";
    } else {
        s += "    var c = m.phong.x * base;\n";
    }
    if shadows {
        s += "    let origin = p + n * offset;\n";
    }
    for (i, light) in lights.iter().enumerate() {
        let radiance: Vec<f32> = light.color.iter().map(|c| c * light.intensity).collect();
        let _ = writeln!(s, "    {{");
        let tmax = match &light.kind {
            LightKind::Directional { direction } => {
                let _ = writeln!(s, "        // light {i}: directional");
                let _ = writeln!(s, "        let l = {};", vec3(direction.map(|x| -x)));
                "MAX_DISTANCE"
            }
            LightKind::Point { position } => {
                let _ = writeln!(s, "        // light {i}: point");
                let _ = writeln!(s, "        let to_light = {} - p;", vec3(*position));
                let _ = writeln!(s, "        let l = safe_normalize(to_light);");
                "length(to_light)"
            }
        };
        let _ = writeln!(s, "        let diffuse = max(dot(n, l), 0.0);");
        if shadows {
            // A surface facing away from the light gets nothing from it: no shadow ray then.
            let _ = writeln!(s, "        var lit = 0.0;");
            let _ = writeln!(s, "        if diffuse > 0.0 {{");
            let _ = writeln!(s, "            lit = shadow(origin, l, {tmax});");
            let _ = writeln!(s, "        }}");
        }
        let _ = writeln!(s, "        let r = reflect(-l, n);");
        let _ = writeln!(s, "        let specular = select(0.0, pow(max(dot(r, -rd), 1e-6), m.phong.w), diffuse > 0.0);");
        let lit = if shadows { "lit * " } else { "" };
        let _ = writeln!(
            s,
            "        c = c + {lit}{} * (m.phong.y * diffuse * base + m.phong.z * specular);",
            vec3([radiance[0], radiance[1], radiance[2]])
        );
        let _ = writeln!(s, "    }}");
    }
    s += "    return c;\n}\n";
    s
}

fn finish(scene: &Scene) -> String {
    match &scene.render.fog {
        None => "// No fog: the shaded colour is final.\n\
             fn finish(c: vec3<f32>, t: f32) -> vec3<f32> {\n    return c;\n}\n"
            .to_string(),
        Some(f) => format!(
            "// Exponential fog.\n\
             fn finish(c: vec3<f32>, t: f32) -> vec3<f32> {{\n    return mix({}, c, exp(-{} * t));\n}}\n",
            vec3(f.color),
            float(f.density)
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::{
        analytic_surface_normal, end_leaf, main_blocks, march_rest, normal_listed, sampled,
        RestMarch, Slab, View, MAIN_FRAME, MAIN_RAY, MARCH_ALONE_HEAD, RAY_SAMPLE,
        TETRAHEDRON_LOOP,
    };
    use crate::parts;
    use sdfc_ir::scene::Normals;

    fn view(along_ray: bool, ray_lists: bool) -> View<'static> {
        View {
            origin: [0.0; 3],
            lights: &[],
            along_ray,
            bounds: ([0.0; 3], [0.0; 3]),
            shadow: [Slab { lo: None, hi: None }; 3],
            ray_lists,
            rest: None,
            instances_outside: 1.0,
            instances_spacing: None,
            trusted: true,
            outside: 1.0,
            dear: ray_lists,
            feature: 0.0,
        }
    }

    /// The analytic `surface_normal` replaces the difference one in the entry point's part,
    /// exactly once, and the rest of the part stays.
    #[test]
    fn analytic_normals_replace_the_difference_surface_normal() {
        let main = analytic_surface_normal(parts::MAIN, true);
        assert_eq!(main.matches("fn surface_normal(").count(), 1);
        assert!(main.contains("scene_gradient(q)"));
        assert!(!main.contains("scene_normal("));
        assert!(main.contains("fn ray_offset(") && main.contains("fn normal_step("));
        assert_eq!(analytic_surface_normal(parts::MAIN, false), parts::MAIN);
    }

    /// `sampled` finds its text in every part it rewrites: were a part's ray sample written
    /// differently, its march would silently keep the isotropic bound (`scene_distance_ray`),
    /// or a mixed union's other children's march (`march_rest`) would sample the whole
    /// union. And each difference normal samples `scene_distance(p + ...)`, which `emit`
    /// rewrites for the list (`normal_listed`).
    #[test]
    fn every_ray_sampling_part_is_rewritten() {
        for part in [parts::REFINE, parts::MARCH_TWO_LOOPS, parts::MARCH_MERGED] {
            let rewritten = sampled(part, &view(true, false));
            assert!(rewritten.contains("scene_distance_ray(ro + rd * t, rd)"));
            assert!(!rewritten.contains(RAY_SAMPLE));
            assert_eq!(sampled(part, &view(false, false)), part);
        }
        for part in [
            parts::NORMALS_CENTRAL,
            parts::NORMALS_FORWARD,
            parts::NORMALS_TETRAHEDRON,
        ] {
            assert!(part.contains("scene_distance(p + "), "{part}");
        }
    }

    /// A mixed union's other children are marched first, alone, with the scene's loops
    /// (merged where their distance is dear, else with the refinement's own loop), and the
    /// instances' march starts from their hit. Were the texts rewritten here written
    /// differently, the instances' march would ignore the other children: so each must be
    /// there.
    #[test]
    fn a_mixed_union_marches_its_other_children_first() {
        assert_eq!(parts::MARCH_INSTANCES.matches(MARCH_ALONE_HEAD).count(), 1);
        for dear in [true, false] {
            for along_ray in [true, false] {
                let rest = march_rest(RestMarch { dear, along_ray });
                assert_eq!(rest.matches("fn march_rest(").count(), 1);
                assert!(!rest.contains("fn march("));
                assert!(!rest.contains(RAY_SAMPLE));
                assert_eq!(rest.contains("fn refine("), !dear);
                let samples = if dear { 1 } else { 2 };
                let sample = if along_ray {
                    "rest_distance_ray(ro + rd * t, rd)"
                } else {
                    "rest_distance(ro + rd * t)"
                };
                assert_eq!(rest.matches(sample).count(), samples, "{rest}");
            }
        }
    }

    /// For a union read as data, the tetrahedron normal samples what the march hit alone,
    /// and `end_leaf` reads the instance the march kept; the other normals sample through
    /// the list. Were the texts rewritten here written differently, the shader would not
    /// build or would sample the whole union: so each must be there.
    #[test]
    fn the_normal_and_the_material_of_a_union_read_as_data_take_what_the_march_hit() {
        assert!(parts::NORMALS_TETRAHEDRON.contains(TETRAHEDRON_LOOP));
        let tetrahedron = normal_listed(parts::NORMALS_TETRAHEDRON, Normals::Tetrahedron);
        assert!(tetrahedron.contains("let leaf = ray_end_leaf;"));
        assert!(tetrahedron.contains("normal_sample(p + k[i] * h, leaf)"));
        assert!(
            !tetrahedron.contains("normal_nearest(") && !tetrahedron.contains("scene_distance(")
        );
        for (part, normals) in [
            (parts::NORMALS_CENTRAL, Normals::Central),
            (parts::NORMALS_FORWARD, Normals::Forward),
        ] {
            let listed = normal_listed(part, normals);
            assert!(listed.contains("normal_distance(p + ") && !listed.contains("scene_distance("));
        }
        // The entry point finds its block's candidates and marks each sample's march a
        // camera ray's (`main_blocks`).
        assert_eq!(parts::MAIN.matches(MAIN_FRAME).count(), 1);
        assert_eq!(parts::MAIN.matches(MAIN_RAY).count(), 1);
        let blocks = main_blocks(parts::MAIN);
        assert!(blocks.contains("    load_frame();\n    ray_blocks(gid);\n"));
        assert!(blocks.contains("fsize);\n        ray_primary = true;\n"));
        let main = end_leaf(parts::MAIN);
        assert!(main.starts_with(parts::MAIN) && main.contains("return ray_end_leaf;"));
        assert!(parts::MARCH_INSTANCES.contains("ray_end_leaf = best_leaf;"));
        assert!(parts::MARCH_INSTANCES.contains("instance_distance(ro + rd * t, leaf)"));
        // `end_leaf` is what the march hit at the same point: both radiance parts take a
        // surface point's normal before its material.
        for part in [parts::RADIANCE_PLAIN, parts::RADIANCE_REFLECTIONS] {
            let normal = part.find("surface_normal(p,").expect("a normal at p");
            let material = part.find("scene_material(p)").expect("a material at p");
            assert!(normal < material);
        }
    }
}
