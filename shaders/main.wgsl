// The entry point: one invocation per pixel, n x n samples, colour packed as RGBA8 (row
// major, top row first); with bit 0 of `frame.flags` set it also writes the AOVs of the
// pixel centre's ray: (normal, depth) then (steps, 0, 0, 0), depth -1 on a miss. Bits 8 to
// 19 and 20 to 31 are the column and row of the dispatch's first 8x8 tile: a host may
// dispatch only the tiles whose rays can meet the scene's bounds (the others only show the
// background, and llvmpipe runs every line of the shader under masks for them).
@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) invocation: vec3<u32>) {
    let first = vec2<u32>((frame.flags >> 8u) & 0xfffu, frame.flags >> 20u) * 8u;
    let gid = invocation.xy + first;
    let size = frame.resolution;
    if gid.x >= size.x || gid.y >= size.y {
        return;
    }
    load_frame();
    let fsize = vec2<f32>(size);
    // Angle subtended by one pixel: the surface threshold of `epsilon: pixel` grows with it.
    let pixel = 2.0 * TAN_HALF_FOV / fsize.y;
    var color = vec3<f32>(0.0);
    // The sample at the pixel's centre, for the AOVs: odd ANTIALIAS has one among its
    // samples; even ANTIALIAS takes it as one more sample that adds no colour. One loop, so
    // that `radiance` (and the marcher and the distance function in it, which drivers inline
    // at every call) is called once.
    var centre = Sample(vec3<f32>(0.0), Hit(0.0, 0u, false), vec3<f32>(0.0));
    let aovs = (frame.flags & 1u) != 0u;
    let samples = ANTIALIAS * ANTIALIAS;
    let extra = select(0u, 1u, aovs && ANTIALIAS % 2u == 0u);
    for (var i = 0u; i < samples + extra; i = i + 1u) {
        let sx = i % ANTIALIAS;
        let sy = i / ANTIALIAS;
        var offset = (vec2<f32>(f32(sx), f32(sy)) + 0.5) / f32(ANTIALIAS);
        if i == samples {
            offset = vec2<f32>(0.5);
        }
        let rd = camera_ray(vec2<f32>(gid) + offset, fsize);
        let sample = radiance(CAMERA_POSITION, rd, pixel);
        if i < samples {
            color = color + sample.color;
        }
        if i == samples || (2u * sx + 1u == ANTIALIAS && 2u * sy + 1u == ANTIALIAS) {
            centre = sample;
        }
    }
    color = color / f32(samples);
    let mapped = pow(clamp(color, vec3<f32>(0.0), vec3<f32>(1.0)), vec3<f32>(INV_GAMMA));
    let index = gid.y * size.x + gid.x;
    color_out[index] = pack4x8unorm(vec4<f32>(mapped, 1.0));
    if aovs {
        var aov = vec4<f32>(0.0, 0.0, 0.0, -1.0);
        if centre.hit.hit {
            aov = vec4<f32>(centre.normal, centre.hit.t);
        }
        aov_out[2u * index] = aov;
        aov_out[2u * index + 1u] = vec4<f32>(f32(centre.hit.steps), 0.0, 0.0, 0.0);
    }
}

// The finite-difference step for normals: a small fraction of the surface threshold (so a
// crease or a seam blends only the normals of points that close to it), and never below what
// f32 can resolve at this distance from the origin and the camera. Against the f64 reference
// (64x48 stress scenes) 0.5 of the threshold gave a median error of 0.5 degree on spheres and
// 48 degrees at the 99th percentile on boxes; 0.002 gives 0.01 and 0.03. Near the origin the
// scale is at least t up to 1 (at least 1e-3), or FEATURE_SIZE, the size of the smallest of the
// scene's shapes, if larger: their distances round like numbers of that size, however near
// the point is to the origin (the camera, in camera-relative coordinates). A floor of 1 made
// the step 3e-5 on a sphere of radius 1e-3 seen from 0.03 (normal 99th percentile 1.6
// degrees); without FEATURE_SIZE, a unit sphere seen from 0.05 had a median of 0.42 degree.
fn normal_step(p: vec3<f32>, t: f32, pixel: f32) -> f32 {
    let near = max(clamp(t, 1e-3, 1.0), FEATURE_SIZE);
    let scale = max(max(abs(p.x), abs(p.y)), max(abs(p.z), near));
    return max(0.002 * surface_epsilon(t, pixel), 2e-5 * scale);
}

// The normal at a hit p. The step is rounded up to a power of two and p to a multiple of it,
// so that every sample point p + k h is exact in f32: the samples are then as far apart as
// the formula says, and only the distance function's own rounding remains. p moves by at most
// half the step, far below the surface threshold. A normal facing away from the ray `rd`
// comes from a surface of no thickness (the distance is |y| across it, so the differences
// cancel): it is taken again a few steps back along the ray, on the side the ray comes from.
// Two tries in a loop: one call of scene_normal to inline, not two.
fn surface_normal(p: vec3<f32>, rd: vec3<f32>, t: f32, pixel: f32) -> vec3<f32> {
    let h = exp2(ceil(log2(normal_step(p, t, pixel))));
    var q = p;
    var n = vec3<f32>(0.0);
    for (var attempt = 0u; attempt < 2u; attempt = attempt + 1u) {
        n = scene_normal(round(q / h) * h, h);
        if dot(n, rd) <= 0.0 {
            break;
        }
        q = p - 4.0 * h * rd;
    }
    return n;
}

// How far a secondary ray (shadow, reflection) starts off the surface: far enough that
// rounding at this distance from the origin cannot put it back inside (the refined hit is
// within about 1e-7 of it), and a small fraction of the surface threshold, not several
// thresholds: a start four thresholds out (as before) stepped past contact shadows and
// nearby reflected surfaces (colour error against the f64 reference, 64x48: hard shadows
// 3.0 -> 2.3, soft 3.7 -> 2.6, reflections 1.25 -> 0.03 in 0..255).
fn ray_offset(p: vec3<f32>, t: f32, pixel: f32) -> f32 {
    let scale = max(max(abs(p.x), abs(p.y)), max(abs(p.z), 1.0));
    return max(0.05 * surface_epsilon(t, pixel), 1e-4 * scale);
}
