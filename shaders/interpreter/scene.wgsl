// The scene functions and the per-scene parts of the marcher, driven by the Frame's values
// where the specialised shader has them compiled in.

// The signed distance from p to the scene.
fn scene_distance(p: vec3<f32>) -> f32 {
    return interpret(frame.distance_code, p).a.x;
}

// The distance the march steps with along the unit direction rd, as the specialised
// shader's `scene_distance_ray` (the same as `scene_distance` where the scene has none):
// `OP_RAY` reads rd.
fn scene_distance_ray(p: vec3<f32>, rd: vec3<f32>) -> f32 {
    ray_dir = rd;
    return interpret(frame.distance_ray_code, p).a.x;
}

// The material at a surface point p.
fn scene_material(p: vec3<f32>) -> SceneMaterial {
    let o = interpret(frame.material_code, p);
    return SceneMaterial(o.a, o.b);
}

// The surface threshold: half the pixel's footprint at t (`epsilon: pixel`), or absolute.
fn surface_epsilon(t: f32, pixel: f32) -> f32 {
    if (frame.switches & 1u) != 0u {
        return 0.5 * pixel * t;
    }
    return frame.epsilon;
}

// Whether the scene's distance is trusted (`touch_distance` reads it; the compiler's
// `Analysis::distance_trusted` sets the switch).
fn distance_trusted() -> bool {
    return (frame.switches & 4u) != 0u;
}

// The three difference normals of shaders/normals in one loop, the method chosen by
// `frame.normals` (1 central, 2 forward, else tetrahedron): the interpreter is inlined at one
// call here instead of three. Each method samples and sums as its own part does.
fn scene_normal(p: vec3<f32>, h: f32) -> vec3<f32> {
    var k = array<vec3<f32>, 4>(
        vec3<f32>(1.0, -1.0, -1.0),
        vec3<f32>(-1.0, -1.0, 1.0),
        vec3<f32>(-1.0, 1.0, -1.0),
        vec3<f32>(1.0, 1.0, 1.0),
    );
    let method = frame.normals;
    let count = select(4u, 6u, method == 1u);
    var d0 = 0.0;
    var n = vec3<f32>(0.0);
    for (var i = 0u; i < count; i = i + 1u) {
        var e = vec3<f32>(0.0);
        if method == 1u {
            e[i / 2u] = select(h, -h, (i & 1u) != 0u);
        } else if method == 2u {
            if i > 0u {
                e[i - 1u] = h;
            }
        } else {
            e = k[i] * h;
        }
        let d = scene_distance(p + e);
        if method == 1u {
            n[i / 2u] = select(d, n[i / 2u] - d, (i & 1u) != 0u);
        } else if method == 2u {
            if i == 0u {
                d0 = d;
            } else {
                n[i - 1u] = d - d0;
            }
        } else {
            n = n + k[i] * d;
        }
    }
    return safe_normalize(n);
}

// The hard (`frame.shadows` 1) and soft shadows of shaders/shading in one loop, each
// stepping and stopping as its own part does (at the scene's bounds too, `bounds_outside`):
// one call of the interpreter to inline instead of two.
fn shadow(ro: vec3<f32>, rd: vec3<f32>, tmax: f32) -> f32 {
    let hard = frame.shadows == 1u;
    // The specialised shader's SHADOW_K * OUTSIDE_FACTOR (0: a soft shadow never stops).
    let reach = SHADOW_K * data[frame.bounds_at + 1u].w;
    var light = 1.0;
    var t = 0.0;
    for (var i = 0u; i < MAX_STEPS; i = i + 1u) {
        if t >= tmax {
            break;
        }
        let q = ro + rd * t;
        let h = scene_distance(q);
        let v = bounds_outside(q);
        if hard {
            if h < 1e-5 * (1.0 + t) {
                return 0.0;
            }
            if dot(v, rd) > 0.0 {
                break;
            }
            t = t + h;
        } else {
            light = min(light, SHADOW_K * h / max(t, 1e-6));
            if light <= 0.0 {
                return 0.0;
            }
            let out = length(v);
            if reach * out > t && reach * dot(v, rd) >= out {
                break;
            }
            t = t + max(h, 1e-3 * t + 1e-5);
        }
    }
    return select(clamp(light, 0.0, 1.0), 1.0, hard);
}

// Phong shading as the specialised shader's, with a loop over the lights instead of one
// unrolled block per light; without shadows the light factor is exactly 1.
fn shade(p: vec3<f32>, n: vec3<f32>, rd: vec3<f32>, m: SceneMaterial, offset: f32) -> vec3<f32> {
    let base = m.albedo.rgb;
    var c = m.phong.x * base;
    if AO_SAMPLES > 0u {
        c = m.phong.x * ambient_occlusion(p, n) * base;
    }
    let origin = p + n * offset;
    for (var i = 0u; i < frame.light_count; i = i + 1u) {
        let light = data[frame.lights_at + 2u * i];
        let radiance = data[frame.lights_at + 2u * i + 1u].xyz;
        var l = light.xyz;
        var tmax = MAX_DISTANCE;
        if light.w > 0.5 {
            let to_light = light.xyz - p;
            l = safe_normalize(to_light);
            tmax = length(to_light);
        }
        let diffuse = max(dot(n, l), 0.0);
        var lit = 1.0;
        if frame.shadows != 0u {
            // A surface facing away from the light gets nothing from it: no shadow ray then.
            lit = 0.0;
            if diffuse > 0.0 {
                lit = shadow(origin, l, tmax);
            }
        }
        let r = reflect(-l, n);
        let specular = select(0.0, pow(max(dot(r, -rd), 1e-6), m.phong.w), diffuse > 0.0);
        c = c + lit * radiance * (m.phong.y * diffuse * base + m.phong.z * specular);
    }
    return c;
}

// Exponential fog where the scene asks for it.
fn finish(c: vec3<f32>, t: f32) -> vec3<f32> {
    if (frame.switches & 2u) != 0u {
        return mix(frame.fog_color, c, exp(-frame.fog_density * t));
    }
    return c;
}

// How far p lies outside the box shadow rays stop at (the scene's bounds, padded a little
// more), per axis (0 inside), as the specialised shader's `bounds_outside` computes it from
// its constants: an end whose bit is not set in the mask (see `ray_span`) is open, and clamps
// to +-3e38 as there.
fn bounds_outside(p: vec3<f32>) -> vec3<f32> {
    let ends = vec3<u32>(u32(data[frame.bounds_at].w));
    let lo = data[frame.bounds_at + 2u];
    let hi = data[frame.bounds_at + 3u];
    let a = select(vec3<f32>(-3e38), lo.xyz, (ends & vec3<u32>(1u, 2u, 4u)) != vec3<u32>(0u));
    let b = select(vec3<f32>(3e38), hi.xyz, (ends & vec3<u32>(8u, 16u, 32u)) != vec3<u32>(0u));
    return p - clamp(p, a, b);
}

// The stretch of the ray inside the scene's bounds (padded), as the specialised shader's
// `ray_span` computes it from its constants: marching starts and ends there, and a ray that
// misses them takes no step. Only the ends whose bit is set in the mask bound the box (bit k:
// axis k's low end; bit k + 3: its high end); the arithmetic is the specialised shader's, so
// both give the same stretch bit for bit.
fn ray_span(ro: vec3<f32>, rd: vec3<f32>) -> vec2<f32> {
    let lo = data[frame.bounds_at];
    let hi = data[frame.bounds_at + 1u];
    let ends = u32(lo.w);
    var t0 = 0.0;
    var t1 = MAX_DISTANCE;
    for (var k = 0u; k < 3u; k = k + 1u) {
        let has_lo = (ends & (1u << k)) != 0u;
        let has_hi = (ends & (8u << k)) != 0u;
        if has_lo && has_hi {
            if abs(rd[k]) > 1e-30 {
                let a = (lo[k] - ro[k]) / rd[k];
                let b = (hi[k] - ro[k]) / rd[k];
                t0 = max(t0, min(a, b));
                t1 = min(t1, max(a, b));
            } else if ro[k] < lo[k] || ro[k] > hi[k] {
                t1 = -1.0;
            }
        } else if has_lo || has_hi {
            // One end: a ray heading for the open side leaves there.
            let v = select(hi[k], lo[k], has_lo);
            let rising = rd[k] > 1e-30;
            if rising || rd[k] < -1e-30 {
                let t = (v - ro[k]) / rd[k];
                if rising == has_lo {
                    t0 = max(t0, t);
                } else {
                    t1 = min(t1, t);
                }
            } else if select(ro[k] > v, ro[k] < v, has_lo) {
                t1 = -1.0;
            }
        }
    }
    return vec2<f32>(t0, t1);
}
