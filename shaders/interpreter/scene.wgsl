// The scene functions and the per-scene parts of the marcher, driven by the Frame's values
// where the specialised shader has them compiled in.

// The signed distance from p to the scene.
fn scene_distance(p: vec3<f32>) -> f32 {
    return interpret(frame.distance_code, p).a.x;
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

fn scene_normal(p: vec3<f32>, h: f32) -> vec3<f32> {
    switch frame.normals {
        case 1u: { return scene_normal_central(p, h); }
        case 2u: { return scene_normal_forward(p, h); }
        default: { return scene_normal_tetrahedron(p, h); }
    }
}

fn shadow(ro: vec3<f32>, rd: vec3<f32>, tmax: f32) -> f32 {
    if frame.shadows == 1u {
        return shadow_hard(ro, rd, tmax);
    }
    return shadow_soft(ro, rd, tmax);
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

// The stretch of the ray the marcher searches: all of it up to MAX_DISTANCE (the
// specialised shader narrows it to the scene's bounds; the bytecode carries none).
fn ray_span(ro: vec3<f32>, rd: vec3<f32>) -> vec2<f32> {
    return vec2<f32>(0.0, MAX_DISTANCE);
}
