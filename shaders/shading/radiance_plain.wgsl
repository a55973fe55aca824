// The colour a ray brings back: the shaded surface it hits, or the background. The march is
// in here, not in the caller, so that the entry point calls the marcher (and so the distance
// function, which drivers inline at every call) once.
fn radiance(ro: vec3<f32>, rd: vec3<f32>, pixel: f32) -> Sample {
    let hit = march(ro, rd, pixel);
    if !hit.hit {
        return Sample(BACKGROUND, hit, vec3<f32>(0.0));
    }
    let p = ro + rd * hit.t;
    let n = surface_normal(p, rd, hit.t, pixel);
    let material = scene_material(p);
    let color = finish(shade(p, n, rd, material, ray_offset(p, hit.t, pixel)), hit.t);
    return Sample(color, hit, n);
}
