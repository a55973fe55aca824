// The colour a ray brings back, following mirror reflections up to REFLECTIONS bounces: each
// surface keeps (1 - reflectivity) of its own shading and passes reflectivity on to what its
// reflection sees; the last surface reached keeps all of its shading. Every bounce, the first
// included, marches at the one call of the marcher here (drivers inline the distance function
// at every call).
fn radiance(ro: vec3<f32>, rd: vec3<f32>, pixel: f32) -> Sample {
    var color = vec3<f32>(0.0);
    var weight = 1.0;
    var origin = ro;
    var dir = rd;
    var first = Hit(0.0, 0u, false);
    var first_normal = vec3<f32>(0.0);
    for (var bounce = 0u; bounce <= REFLECTIONS; bounce = bounce + 1u) {
        let hit = march(origin, dir, pixel);
        if bounce == 0u {
            first = hit;
        }
        if !hit.hit {
            color = color + weight * BACKGROUND;
            break;
        }
        let p = origin + dir * hit.t;
        let n = surface_normal(p, dir, hit.t, pixel);
        if bounce == 0u {
            first_normal = n;
        }
        let material = scene_material(p);
        let offset = ray_offset(p, hit.t, pixel);
        let local = finish(shade(p, n, dir, material, offset), hit.t);
        let r = clamp(material.albedo.w, 0.0, 1.0);
        if bounce == REFLECTIONS || r <= 0.0 {
            color = color + weight * local;
            break;
        }
        color = color + weight * (1.0 - r) * local;
        weight = weight * r;
        dir = reflect(dir, n);
        origin = p + n * offset;
    }
    return Sample(color, first, first_normal);
}
