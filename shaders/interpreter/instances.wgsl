// A large union read as data by the interpreter (`interp::encode_instances`: the live path's
// preview of such a union, `sdfc render --interpreted --instances`): the hierarchy and
// records of shaders/instances.wgsl, at `frame.instances_at` in `data`, walked as that
// file's `scene_nearest` walks them (same rules, same hint, same result). The walk runs one
// node per trip of the interpreter's loop and stays at its pc, as a fractal's orbit does (a
// loop inside the switch would spend the loop budget of lavapipe, see interpret.wgsl); at a
// leaf it jumps to its kind's code (before the functions' ranges) with register 0 set to the
// instance's local point, and that code's OP_INSTANCE_DONE comes back to the walk with the
// point restored. No kind is a fractal, so the walk and an orbit are never in progress at
// once. Only the interpreter's variant for such bytecode has this file and the four cases
// (`interp::Variant::Walk`).

// The pc of the walk in progress, its point, the next node, the node after the leaf being
// evaluated, the best distance so far and the leaf word that gave it, the leaf word being
// evaluated and its instance's scale.
var<private> walk_at: u32 = NO_JUMP;
var<private> walk_p: vec3<f32>;
var<private> walk_node: u32;
var<private> walk_after: u32;
var<private> walk_best: f32;
var<private> walk_nearest: u32;
var<private> walk_leaf: u32;
var<private> walk_scale: f32;
// The leaf word of the instance nearest at the invocation's last walk, evaluated first.
var<private> walk_hint: u32;
// A finished walk's result: (distance, material index as f32, 0, 0).
var<private> walk_out: vec4<f32>;
// The least box distance a subtree whose box the point is beyond the reach of may answer
// with, a lower bound of its field (`walk_node` in shaders/instances.wgsl): 0 for a march;
// ambient occlusion's samples need the distance itself (`occlusion_distance`), a soft shadow
// wherever it could lower the light (`shadow_distance`).
var<private> walk_least: f32 = 0.0;

// The scene's distance at an ambient occlusion sample: the walk takes no box's distance for
// its subtree's, which darkened samples near no instance (at `ao(samples: 8, step: 0.3)` the
// 120-shape grid parted from its code on 55 channels at 64x48, `tests/instances.rs`).
fn occlusion_distance(p: vec3<f32>) -> f32 {
    walk_least = 3.0e38;
    let d = scene_distance(p);
    walk_least = 0.0;
    return d;
}

// The scene's distance at a shadow ray's sample, a box's distance taken for its subtree's
// only where no less than `least` (for a soft shadow, where it cannot lower the light: with
// it anywhere, `soft(2)` on the 120-shape grid parted from the code on 150 channels at
// 64x48, `tests/instances.rs`).
fn shadow_distance(p: vec3<f32>, least: f32) -> f32 {
    walk_least = least;
    let d = scene_distance(p);
    walk_least = 0.0;
    return d;
}

// Vec4 i of the union's data, as words.
fn union_words(i: u32) -> vec4<u32> {
    return bitcast<vec4<u32>>(data[frame.instances_at + i]);
}

// One trip of the walk of OP_INSTANCES at pc from point p; `kinds` is where the kinds'
// first instructions are listed in the pool. Returns the pc to go to (pc itself for the next
// node, or a kind's code), or NO_JUMP when the walk is over (its result in `walk_out`).
fn walk_trip(regs: ptr<function, array<vec4<f32>, MAX_REGISTERS>>, pc: u32, p: vec3<f32>, kinds: u32) -> u32 {
    var leaf = 0u;
    if walk_at != pc {
        walk_at = pc;
        walk_p = p;
        walk_best = 3.0e38;
        walk_nearest = 0u;
        walk_node = 0u;
        walk_after = 0u;
        leaf = walk_hint;
    }
    if leaf == 0u {
        // The root's skip link: the number of nodes.
        if walk_node >= union_words(0u).w {
            walk_at = NO_JUMP;
            var material = 0u;
            if walk_nearest != 0u {
                walk_hint = walk_nearest;
                material = union_words(walk_nearest + 1u).y;
            }
            walk_out = vec4<f32>(walk_best, f32(material), 0.0, 0.0);
            return NO_JUMP;
        }
        let node = union_words(2u * walk_node);
        let bounds = union_words(2u * walk_node + 1u);
        let half = bitcast<vec3<f32>>(bounds.xyz);
        let q = abs(walk_p - bitcast<vec3<f32>>(node.xyz)) - half;
        let bd = length(max(q, vec3<f32>(0.0))) + min(max(q.x, max(q.y, q.z)), 0.0);
        if bd >= walk_best {
            walk_node = node.w;
            return pc;
        }
        if bd > length(half) && bd >= walk_least {
            walk_best = bd;
            walk_node = node.w;
            return pc;
        }
        if bounds.w == 0u {
            walk_node = walk_node + 1u;
            return pc;
        }
        leaf = bounds.w;
        walk_after = node.w;
    }
    // The instance's local point, as shaders/instances.wgsl's `instance_distance`.
    let record = leaf - 1u;
    let turn = data[frame.instances_at + record];
    let centre = data[frame.instances_at + record + 1u];
    let v = walk_p - centre.xyz;
    let t = 2.0 * cross(turn.xyz, v);
    (*regs)[0] = vec4<f32>((v + turn.w * t + cross(turn.xyz, t)) / centre.w, 0.0);
    walk_leaf = leaf;
    walk_scale = centre.w;
    let kind = union_words(record + 2u).x;
    return u32(data[frame.consts_at + kinds + kind].x);
}

// OP_INSTANCE_DONE: the instance's distance `local` (in its own frame) counted, the walk's
// point back in register 0; returns the walk's pc.
fn walk_back(regs: ptr<function, array<vec4<f32>, MAX_REGISTERS>>, local: f32) -> u32 {
    let d = local * walk_scale;
    if d < walk_best {
        walk_best = d;
        walk_nearest = walk_leaf;
    }
    (*regs)[0] = vec4<f32>(walk_p, 0.0);
    walk_node = walk_after;
    return walk_at;
}

// OP_ARG: word `imm & 0xff` of the record being evaluated, `imm >> 8` words wide (a scalar
// splatted, as the interpreter keeps every scalar). Four words are read and the unused
// ones dropped (the record is padded to whole vec4s; an index past the data is clamped),
// with no loop: each loop reached costs lavapipe's budget a trip.
fn instance_arg(imm: u32) -> vec4<f32> {
    let w = 4u * (frame.instances_at + walk_leaf - 1u) + (imm & 0xffu);
    let last = 4u * arrayLength(&data) - 1u;
    let i = min(vec4<u32>(w) + vec4<u32>(0u, 1u, 2u, 3u), vec4<u32>(last));
    let words = vec4<f32>(data[i.x / 4u][i.x % 4u], data[i.y / 4u][i.y % 4u], data[i.z / 4u][i.z % 4u], data[i.w / 4u][i.w % 4u]);
    let width = imm >> 8u;
    let v = select(vec4<f32>(0.0), words, vec4<u32>(0u, 1u, 2u, 3u) < vec4<u32>(width));
    return select(v, vec4<f32>(v.x), width == 1u);
}
