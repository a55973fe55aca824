// The colour a ray brings back, following mirror reflections up to REFLECTIONS bounces: each
// surface keeps (1 - reflectivity) of its own shading and passes reflectivity on to what its
// reflection sees; the last surface reached keeps all of its shading.
fn radiance(ro: vec3<f32>, rd: vec3<f32>, first: Hit, pixel: f32) -> vec3<f32> {
    var color = vec3<f32>(0.0);
    var weight = 1.0;
    var origin = ro;
    var dir = rd;
    var hit = first;
    for (var bounce = 0u; bounce <= REFLECTIONS; bounce = bounce + 1u) {
        if bounce > 0u {
            hit = march(origin, dir, pixel);
        }
        if !hit.hit {
            color = color + weight * BACKGROUND;
            break;
        }
        let p = origin + dir * hit.t;
        let n = surface_normal(p, dir, hit.t, pixel);
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
    return color;
}
