// The normal at a hit p from the distance's gradient there (`normals: analytic`):
// `scene_gradient` is the forward-mode derivative of `scene_distance`, so there is no
// difference step and p is used as it is (the difference methods round p to a multiple of
// their step, which moves it by up to 1.5e-5: a degree on a sphere of radius 1e-3). A normal
// facing away from the ray `rd` comes from a surface of no thickness (|y| across it, whose
// gradient flips there): it is taken again a few steps back along the ray, on the side the
// ray comes from.
// Two tries in a loop: one call of scene_gradient to inline, not two.
fn surface_normal(p: vec3<f32>, rd: vec3<f32>, t: f32, pixel: f32) -> vec3<f32> {
    var q = p;
    var n = vec3<f32>(0.0);
    for (var attempt = 0u; attempt < 2u; attempt = attempt + 1u) {
        n = safe_normalize(scene_gradient(q).xyz);
        if dot(n, rd) <= 0.0 {
            break;
        }
        q = p - 4.0 * normal_step(p, t, pixel) * rd;
    }
    return n;
}
