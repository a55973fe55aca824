// Candidates per block of 4x4 pixels: a pass of its own before the frame (`blocks_main`)
// walks the hierarchy once per block with the frustum of the block's four corner rays and
// writes the instances whose padded boxes (`ray_start`'s padding) it meets, in the walk's
// order, after the AOVs in `aov_out`; each primary ray then makes its list from its block's
// candidates instead of walking the hierarchy itself. Every ray through the block's pixels
// lies in that frustum, so its list is the walk's. On lavapipe this drew the 300-shape grid
// 1.3x faster from close by (docs/performance.md, "Each ray's list from its block's
// candidates"). A host that does not run the pass leaves bit 1 of `frame.flags` clear, and
// the rays walk as before.
const BLOCK: u32 = 4u;
// The candidates a block's slot holds: its count and the candidates' node indices, as f32
// (exact below 2^24), in BLOCK_VEC4S vec4s; a block with more says so by a count above it,
// and its rays walk.
const BLOCK_CANDIDATES: u32 = 19u;
const BLOCK_VEC4S: u32 = 5u;
const NO_BLOCK: u32 = 0xffffffffu;

// This invocation's block's slot (its first vec4 in `aov_out`), or NO_BLOCK; whether the
// next march is a camera ray's (set by the entry point before each sample, cleared by
// `ray_start`: reflections walk).
var<private> ray_slot: u32;
var<private> ray_primary: bool;

// Where the blocks' slots start in `aov_out`: after the AOVs where they are written, else
// after the 32 bytes a host binds for none.
fn block_base() -> u32 {
    let size = frame.resolution;
    return select(2u, 2u * size.x * size.y, (frame.flags & 1u) != 0u);
}

// The slot of block b (blocks counted from the image's top left corner).
fn block_slot(b: vec2<u32>) -> u32 {
    let across = (frame.resolution.x + BLOCK - 1u) / BLOCK;
    return block_base() + (b.y * across + b.x) * BLOCK_VEC4S;
}

// The slot of pixel gid's block, where the pass ran (bit 1 of `frame.flags`).
fn ray_blocks(gid: vec2<u32>) {
    ray_slot = NO_BLOCK;
    if (frame.flags & 2u) != 0u {
        ray_slot = block_slot(gid / BLOCK);
    }
}

// Candidate j of the slot at s.
fn block_candidate(s: u32, j: u32) -> u32 {
    return u32(aov_out[s + (j + 1u) / 4u][(j + 1u) & 3u]);
}

// The pass: one invocation per block, over the same 8x8 tiles as the frame (the dispatch's
// first tile in `frame.flags`, as `main` reads it). A box is a candidate unless it lies
// wholly outside one of the four planes through the camera and two neighbouring corner rays,
// with a slack of 1e-5 of its distance for rounding: a superset of the boxes the block's
// rays pass through.
@compute @workgroup_size(8, 8, 1)
fn blocks_main(@builtin(global_invocation_id) invocation: vec3<u32>) {
    let size = frame.resolution;
    let blocks = (size + BLOCK - 1u) / BLOCK;
    let first = vec2<u32>((frame.flags >> 8u) & 0xfffu, frame.flags >> 20u) * (8u / BLOCK);
    let b = invocation.xy + first;
    if b.x >= blocks.x || b.y >= blocks.y {
        return;
    }
    load_frame();
    let fsize = vec2<f32>(size);
    let pixel = 2.0 * TAN_HALF_FOV / fsize.y;
    let lo = vec2<f32>(b * BLOCK);
    let hi = vec2<f32>(min((b + 1u) * BLOCK, size));
    var corners = array<vec3<f32>, 4>(
        camera_ray(lo, fsize),
        camera_ray(vec2<f32>(hi.x, lo.y), fsize),
        camera_ray(hi, fsize),
        camera_ray(vec2<f32>(lo.x, hi.y), fsize),
    );
    let middle = camera_ray(0.5 * (lo + hi), fsize);
    var planes: array<vec3<f32>, 4>;
    for (var k = 0u; k < 4u; k = k + 1u) {
        let n = normalize(cross(corners[k], corners[(k + 1u) & 3u]));
        planes[k] = select(n, -n, dot(n, middle) < 0.0);
    }
    let ro = CAMERA_POSITION;
    let slot = block_slot(b);
    var count = 0u;
    let end = scene_data[0].w;
    var i = 0u;
    loop {
        if i >= end {
            break;
        }
        let a = scene_data[2u * i];
        let w = scene_data[2u * i + 1u];
        let c = bitcast<vec3<f32>>(a.xyz);
        let half = bitcast<vec3<f32>>(w.xyz);
        let h = ray_padded(c, half, ro, pixel, 0.0);
        let rel = c - ro;
        let slack = -1e-5 * (length(rel) + length(h));
        var inside = true;
        for (var k = 0u; k < 4u; k = k + 1u) {
            let n = planes[k];
            inside = inside && dot(n, rel) + dot(abs(n), h) >= slack;
        }
        if !inside {
            i = a.w;
            continue;
        }
        if w.w == 0u {
            i = i + 1u;
            continue;
        }
        if count == BLOCK_CANDIDATES {
            count = count + 1u;
            break;
        }
        aov_out[slot + (count + 1u) / 4u][(count + 1u) & 3u] = f32(i);
        count = count + 1u;
        i = a.w;
    }
    aov_out[slot].x = f32(count);
}
