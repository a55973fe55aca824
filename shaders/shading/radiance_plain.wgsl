// The colour a ray brings back: the shaded surface it hit, or the background.
fn radiance(ro: vec3<f32>, rd: vec3<f32>, hit: Hit, pixel: f32) -> vec3<f32> {
    if !hit.hit {
        return BACKGROUND;
    }
    let p = ro + rd * hit.t;
    let n = surface_normal(p, rd, hit.t, pixel);
    let material = scene_material(p);
    return finish(shade(p, n, rd, material, ray_offset(p, hit.t, pixel)), hit.t);
}
