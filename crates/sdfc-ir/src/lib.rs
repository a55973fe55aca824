//! The sdfc IR: lowering of the AST to a scene of shapes over a hash-consed value DAG,
//! shape-level transform merging, the scalar SSA functions `scene_distance` and
//! `scene_material`, their optimisation passes, and an evaluator (f32 for folding, f64 as
//! the reference). No I/O; never panics on user input.

pub mod analysis;
pub mod diff;
pub mod dump;
pub mod eval;
pub mod func;
pub mod graph;
mod hash;
pub mod instances;
pub mod lower;
pub mod noise;
pub mod ops;
pub mod passes;
pub mod prim_dist;
pub mod rounding;
pub mod scene;
pub mod shape;
pub mod to_ssa;
pub mod types;
pub mod value;

use func::Func;
use scene::Scene;
use sdfc_syntax::ast::File;
use sdfc_syntax::diag::Diagnostic;

/// Everything the back end needs: the optimised scene and its two functions.
#[derive(Clone, Debug)]
pub struct Program {
    /// The scene after the shape-level passes (settings, materials, params, lights, camera).
    pub scene: Scene,
    pub distance: Func,
    /// `scene_distance_ray(p, rd)`, which the marcher steps with where the scene has nodes
    /// whose slope along a ray is below their isotropic bound (`to_ssa::along_ray`) or planes.
    pub distance_ray: Option<Func>,
    /// Whether a displacement or heightfield divides by its slope along the ray in
    /// `distance_ray` or the camera-relative one (built from the same shapes), rather than
    /// planes alone: a union read as data is marched without the ray function, which only
    /// planes can do without (sdfc-wgsl's `instances::plan`: `march_rest` reaches them).
    pub distance_ray_slopes: bool,
    pub material: Func,
    /// Group functions called by `distance`, `material` and each other (`Op::Call`).
    pub groups: Vec<Func>,
    /// Exactness and Lipschitz bounds of the scene's shapes (indexed like `scene.shapes`).
    pub analysis: analysis::Analysis,
    /// For a camera far from the origin, the same functions in camera-relative coordinates
    /// (see [`passes::relative`]), which the render shader and the interpreter's bytecode
    /// march with, and the reference (and `sdfc eval`) evaluate at points nearer the camera
    /// than the origin; `distance`, `material` and `groups` stay in world coordinates (the
    /// library form, `eval --gpu`, points nearer the origin).
    pub relative: Option<Relative>,
}

impl Program {
    /// Whether the distance reaches a culled union (`IrOptions::cull` found one to cull): a
    /// group call guarded by a part's box and the best distance so far (`to_ssa/cull.rs`).
    pub fn culls(&self) -> bool {
        std::iter::once(&self.distance)
            .chain(&self.groups)
            .any(|f| {
                f.graph
                    .nodes()
                    .any(|(_, n)| matches!(n.op, ops::Op::Call { .. }) && n.args().len() == 3)
            })
    }
}

/// One set of the scene functions and the world point their origin stands for: the world
/// ones at the origin, or the camera-relative ones at the camera ([`Program::marched`]).
#[derive(Clone, Copy, Debug)]
pub struct SceneFunctions<'a> {
    pub origin: [f32; 3],
    pub distance: &'a Func,
    pub distance_ray: Option<&'a Func>,
    pub material: &'a Func,
    pub groups: &'a [Func],
    /// The scene's lights as seen in this frame.
    pub lights: &'a [scene::Light],
}

impl Program {
    /// The world functions: the library form, `eval --gpu`, points near the origin.
    pub fn world(&self) -> SceneFunctions<'_> {
        SceneFunctions {
            origin: [0.0; 3],
            distance: &self.distance,
            distance_ray: self.distance_ray.as_ref(),
            material: &self.material,
            groups: &self.groups,
            lights: &self.scene.lights,
        }
    }

    /// The functions a renderer marches with (the render shader, the interpreter's
    /// bytecode): camera-relative where the program has them, else the world ones.
    pub fn marched(&self) -> SceneFunctions<'_> {
        match &self.relative {
            Some(r) => SceneFunctions {
                origin: r.origin,
                distance: &r.distance,
                distance_ray: r.distance_ray.as_ref(),
                material: &r.material,
                groups: &r.groups,
                lights: &r.lights,
            },
            None => self.world(),
        }
    }
}

/// The scene functions in coordinates centred on `origin` (the camera position): each takes
/// a point q and gives the world function's value at q + origin.
#[derive(Clone, Debug)]
pub struct Relative {
    pub origin: [f32; 3],
    pub distance: Func,
    pub distance_ray: Option<Func>,
    pub material: Func,
    pub groups: Vec<Func>,
    /// The scene's lights moved by -origin.
    pub lights: Vec<scene::Light>,
}

/// The IR at each stage, for golden tests and `--emit`.
#[derive(Clone, Debug)]
pub struct Stages {
    /// As lowered, before any pass.
    pub lowered: Scene,
    /// After the passes: what the back ends emit.
    pub program: Program,
}

/// Choices of the compiler that do not change what a scene means.
#[derive(Clone, Debug, Default)]
pub struct IrOptions {
    /// Bounding-box early-outs in large unions (`to_ssa/cull.rs`); off by default (slower
    /// on the software device measured so far, docs/performance.md).
    pub cull: bool,
}

/// Lowers and optimises a parsed file with the default options. Returns the stages, or the
/// diagnostics; warnings are returned in both cases.
pub fn compile(file: &File, source_len: usize) -> (Option<Stages>, Vec<Diagnostic>) {
    compile_with(file, source_len, &IrOptions::default())
}

/// [`compile`] with options.
pub fn compile_with(
    file: &File,
    source_len: usize,
    opts: &IrOptions,
) -> (Option<Stages>, Vec<Diagnostic>) {
    match front(file, source_len) {
        Ok(f) => back(f, opts),
        Err(diags) => (None, diags),
    }
}

/// What every program of a file shares, whatever the [`IrOptions`]: the scene lowered,
/// merged and analysed ([`front`]), before its functions are built ([`back`]). The live path
/// builds two programs from one (`sdfc_wgsl::lower_live`).
#[derive(Clone, Debug)]
pub struct Front {
    lowered: Scene,
    merged: Scene,
    analysis: analysis::Analysis,
    diags: Vec<Diagnostic>,
}

impl Front {
    /// The scene after the passes on the scene (what [`Program::scene`] will be).
    pub fn scene(&self) -> &Scene {
        &self.merged
    }

    /// Its analysis (what [`Program::analysis`] will be).
    pub fn analysis(&self) -> &analysis::Analysis {
        &self.analysis
    }
}

/// The first half of [`compile_with`]: lowers, merges and analyses; the diagnostics where
/// that fails.
pub fn front(file: &File, source_len: usize) -> Result<Front, Vec<Diagnostic>> {
    let lowered = lower::lower(file, source_len);
    let mut diags = lowered.diagnostics;
    let Some(scene) = lowered.scene else {
        return Err(diags);
    };
    let merged = passes::merge::run(&scene);
    // Bound-only nodes need their Lipschitz constants; declared ones are checked by sampling.
    let mut analysis = analysis::analyse(&merged, true);
    diags.append(&mut analysis.diagnostics);
    if diags.iter().any(|d| d.is_error()) {
        return Err(diags);
    }
    Ok(Front {
        lowered: scene,
        merged,
        analysis,
        diags,
    })
}

/// The second half of [`compile_with`]: the scene functions, built and optimised.
pub fn back(front: Front, opts: &IrOptions) -> (Option<Stages>, Vec<Diagnostic>) {
    let Front {
        lowered: scene,
        merged,
        analysis,
        mut diags,
    } = front;
    let funcs = to_ssa::functions(&merged, opts.cull);
    let mut errors = Vec::new();
    let mut opt = |f: &Func| {
        let (f, e) = passes::optimise(f);
        errors.extend(e);
        f
    };
    let distance = opt(&funcs.distance);
    let distance_ray = funcs.distance_ray.as_ref().map(&mut opt);
    let material = opt(&funcs.material);
    let groups: Vec<Func> = funcs.groups.iter().map(&mut opt).collect();
    // Whether a ray function divides by a slope (the camera-relative one is built from the
    // same shapes and agrees, but the marched one is what `instances::plan` reads).
    let mut distance_ray_slopes = funcs.distance_ray_slopes;
    let relative = passes::relative::wanted(&scene).then(|| {
        let origin = scene.camera.position;
        let shifted = passes::relative::shift(&scene, origin);
        let lights = shifted.lights.clone();
        let rel = to_ssa::functions(&passes::merge::run(&shifted), opts.cull);
        distance_ray_slopes |= rel.distance_ray_slopes;
        Relative {
            origin,
            distance_ray: rel.distance_ray.as_ref().map(&mut opt),
            distance: opt(&rel.distance),
            material: opt(&rel.material),
            groups: rel.groups.iter().map(&mut opt).collect(),
            lights,
        }
    });
    // A non-finite constant that reached a function unfolded (a transform of infinite size,
    // say) is as much an error as one that folding met.
    let rel_funcs = relative.iter().flat_map(|r| {
        [&r.distance, &r.material]
            .into_iter()
            .chain(&r.distance_ray)
            .chain(&r.groups)
    });
    for f in [&distance, &material]
        .into_iter()
        .chain(&distance_ray)
        .chain(&groups)
        .chain(rel_funcs.clone())
    {
        for (id, node) in f.graph.nodes() {
            if node.as_const().is_some_and(|v| !v.all_finite()) {
                errors.push((f.graph.span(id), passes::fold::NON_FINITE.to_string()));
            }
        }
    }
    // Nodes the compiler made itself have no span of their own: point at the scene.
    let root_span = merged.shape(merged.root).span;
    let mut seen = Vec::new();
    for (span, msg) in errors {
        let span = if span == Default::default() {
            root_span
        } else {
            span
        };
        if !seen.contains(&span) {
            seen.push(span);
            diags.push(
                Diagnostic::error(span, "a constant expression is not finite")
                    .with_label(msg)
                    .with_hint(lower::NOT_FINITE_HINT),
            );
        }
    }
    for f in [&distance, &material]
        .into_iter()
        .chain(&distance_ray)
        .chain(&groups)
        .chain(rel_funcs)
    {
        if let Some(what) = &f.graph.ill_typed {
            diags.push(Diagnostic::error(
                Default::default(),
                format!(
                    "internal compiler error: ill-typed IR in {}: {what}",
                    f.name
                ),
            ));
        }
    }
    if diags.iter().any(|d| d.is_error()) {
        return (None, diags);
    }
    let program = Program {
        scene: merged,
        distance,
        distance_ray,
        distance_ray_slopes,
        material,
        groups,
        analysis,
        relative,
    };
    (
        Some(Stages {
            lowered: scene,
            program,
        }),
        diags,
    )
}

/// The optimised `scene_gradient` of a distance function and its groups, for
/// `normals: analytic` (the emitter derives it from the functions it emits).
pub fn gradient_of(distance: &Func, groups: &[Func]) -> diff::Gradient {
    let opt = |f: &Func| passes::optimise(f).0;
    let g = diff::gradient(distance, groups);
    diff::Gradient {
        func: opt(&g.func),
        groups: g.groups.iter().map(opt).collect(),
    }
}
