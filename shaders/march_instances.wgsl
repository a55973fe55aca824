// The march of a union read as data: the ray's first hit on a hard union is the nearest of
// its children's first hits, so each instance the ray's list holds (`ray_start`, sorted by
// entry) is marched alone over its stretch, one after the other, and an instance whose
// stretch begins beyond the nearest hit so far is not marched at all. A mixed union's other
// children (a floor, a fractal) are marched first, on their own (`march_rest`, emitted in
// place of this function's first lines), and their hit is the nearest so far. Each sample
// evaluates one instance, where the union's march evaluated every listed instance whose
// stretch held t (a loop within the loop, with the walk beside it for what the list left
// out, and a mixed union's other children, all of it run under masks on lavapipe). On
// lavapipe the 300-shape grid drew 1.8x faster from close by and 1.4x to 1.5x from the
// suite's camera, the same pictures, and with a floor 2.0x (docs/performance.md, "Each
// instance marched alone", "A mixed union's other children marched alone"). Each stretch is
// marched as the union was (`march_sampled` plain or relaxed, `refine_start` and the rest,
// in one loop as in `shaders/march_merged.wgsl`), from a fresh state at its entry, with
// budgets of its own (`march_spent`): one sample of the union's march moved every instance
// whose stretch held t, and a crowd of 48 spheres about one point (`tests/instances.rs`)
// took 65 samples a ray, missing silhouettes, with one budget for all. `steps` counts every
// sample.
// Where a full list left nodes out (`ray_resume`), the ray lists again from there, up to the
// nearest hit so far, and marches those too. The instance hit (0: the other children, or
// none) is kept for the normal and the material (`ray_end_leaf`), and the t for the other
// normals' samples (`ray_hit`).
fn march(ro: vec3<f32>, rd: vec3<f32>, pixel: f32) -> Hit {
    let span = ray_span(ro, rd);
    // The nearest hit so far, and its instance's leaf word.
    var best = span.y;
    var found = false;
    var best_leaf = 0u;
    var steps = 0u;
    // The state of the stretch being marched, and whether a refinement of it is under way.
    var s = march_start(span);
    var refining = false;
    var r = refine_start(0.0, 0.0, 0.0);
    // The node the list starts at: the root, then where a full list stopped.
    var start = 0u;
    loop {
        ray_start(ro, rd, span.x, best, pixel, 0.0, start);
        // The list's next entry, the leaf word of the one being marched, where its stretch
        // ends, and whether it is done (a hit found, or none before no entry is left).
        var k = 0u;
        var leaf = 0u;
        var stop = -1.0;
        var done = true;
        // The samples taken before the stretch being marched, and the stretch's samples in
        // refinements that passed by (`march_spent`).
        var begun = 0u;
        var passed = 0u;
        loop {
            if refining {
                let next = refine_next(&r);
                if next == REFINE_HIT {
                    // A surface refined to beyond MAX_DISTANCE is out of range: a miss.
                    if r.t < best && r.t <= MAX_DISTANCE {
                        best = r.t;
                        found = true;
                        best_leaf = leaf;
                    }
                    refining = false;
                    done = true;
                }
                if next == REFINE_PASS {
                    passed = passed + r.i;
                    march_passed(&s, r.t);
                    refining = false;
                }
            }
            if !refining && !done && march_spent(steps - begun, passed) {
                // Out of steps while passing the stretch's surface within a tenth of the
                // threshold is a hit where the ray is (`march_end`); either way the stretch
                // is done.
                let e = march_end(s.t, steps - begun, passed, s.passing && s.close);
                if e.hit && e.t < best {
                    best = e.t;
                    found = true;
                    best_leaf = leaf;
                }
                done = true;
            }
            if !refining && (done || s.t > stop) {
                // The next stretch, unless it begins beyond the nearest hit so far: the list
                // is sorted by entry, so no later one can hold a nearer hit.
                if k >= ray_n || ray_in[k] >= best {
                    break;
                }
                leaf = ray_leaf[k];
                stop = min(ray_out[k], best);
                // The relaxed step goes no further than the stretch's end (`march_start`'s
                // span): past it a nearer hit of this instance would be stepped over.
                s = march_start(vec2<f32>(ray_in[k], stop));
                done = false;
                begun = steps;
                passed = 0u;
                k = k + 1u;
            }
            let t = select(s.t, r.t, refining);
            let d = instance_distance(ro + rd * t, leaf);
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
        // Every node the list left out enters at the cut or beyond: none can hold a nearer
        // hit once the cut is beyond the nearest.
        if ray_resume == NO_RESUME || ray_cut >= best {
            break;
        }
        start = ray_resume;
    }
    if start != 0u {
        // More than one list (the root is never left out), and the last does not hold the
        // instances of the ones before it: the central and forward normals' samples at the
        // end take the walk (`ray_nearest`).
        ray_lo = 3.0e38;
    }
    ray_end_leaf = best_leaf;
    ray_hit = best;
    return Hit(best, steps, found);
}
