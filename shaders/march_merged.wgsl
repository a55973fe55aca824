// Sphere tracing with refinement in the same loop: each trip takes one sample, and the state
// says whether it is a step of the march (`march_sampled`, plain or relaxed) or of the
// refinement (`refine_start`, `refine_next`, `refine_sampled`). The same samples in the same
// order as the two-loop marcher (`shaders/march_two_loops.wgsl`), so the same steps and
// pictures, with one copy of the distance instead of two. Emitted where the distance is dear
// (a union read as data, noise, a fractal, dozens of shapes as code: `dear.rs` in sdfc-wgsl;
// the interpreter): llvmpipe runs a loop's first trip and an `if`'s body under masks where no
// lane needs them, so the refinement's loop cost a masked copy of the distance at every
// march. On lavapipe the 300-shape grid as data drew 1.08x to 1.14x faster so, as code 1.34x,
// terrain 1.07x, the fractals 1.11x (relaxed: 1.07x to 1.31x; the interpreter 1.04x to
// 1.79x). Where the distance is cheap the refinement's arithmetic, masked at every step,
// costs more (spec section 10 0.77x): docs/performance.md, "The marcher's two loops".
fn march(ro: vec3<f32>, rd: vec3<f32>, pixel: f32) -> Hit {
    // Only the stretch inside the scene's bounds can hold a surface.
    let span = ray_span(ro, rd);
    var s = march_start(span);
    // Every sample, and those of refinements that passed by (`march_spent`).
    var steps = 0u;
    var passed = 0u;
    // Whether a sample within the threshold is being refined, and the refinement's state.
    var refining = false;
    var r = refine_start(0.0, 0.0, 0.0);
    loop {
        if refining {
            let next = refine_next(&r);
            if next == REFINE_HIT {
                // A surface refined to beyond MAX_DISTANCE is out of range: a miss.
                return Hit(r.t, steps, r.t <= MAX_DISTANCE);
            }
            if next == REFINE_PASS {
                passed = passed + r.i;
                march_passed(&s, r.t);
                refining = false;
            }
        }
        if !refining && (march_spent(steps, passed) || s.t > span.y) {
            break;
        }
        let t = select(s.t, r.t, refining);
        let d = scene_distance(ro + rd * t);
        steps = steps + 1u;
        if refining {
            refine_sampled(&r, d);
            continue;
        }
        let eps = march_sampled(&s, d, pixel);
        if eps >= 0.0 {
            r = refine_start(t, d, eps);
            refining = true;
        }
    }
    return march_end(s.t, steps, passed, s.passing && s.close);
}
