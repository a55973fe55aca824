// Culling per ray: one walk of the hierarchy with the ray lists the instances whose padded
// boxes it passes through, with the stretch of t inside each (sorted by entry). The march
// then takes each listed instance alone over its stretch (`shaders/march_instances.wgsl`).
// The list holds at most RAY_LIST entries, every one that enters before `ray_cut` (the
// nearest entry of those left out), and the march lists again from the first node left out
// (`ray_resume`). On lavapipe the lists drew the 300-shape grid 3.7x to 5.5x faster than its
// code (the same marcher on both sides), where the walk at every step ran at 0.43x from
// close by (docs/performance.md, "Culling per ray").
const RAY_LIST: u32 = 32u;
const NO_RESUME: u32 = 0xffffffffu;

// The ray's list: leaf words, entry and exit t.
var<private> ray_leaf: array<u32, 32>;
var<private> ray_in: array<f32, 32>;
var<private> ray_out: array<f32, 32>;
// The pixel angle; the list's length, the t it starts at and the entry of the first
// instance it leaves out (3e38: none); the t where the march ended.
var<private> ray_pixel: f32;
var<private> ray_n: u32;
var<private> ray_lo: f32;
var<private> ray_cut: f32;
var<private> ray_hit: f32;
// The first node a full list left out (`ray_start`'s walk resumes there), or NO_RESUME.
var<private> ray_resume: u32;
// The leaf word of what the march hit (`end_leaf`): an instance, or 0 for a mixed union's
// other children (or none).
var<private> ray_end_leaf: u32;

// How far from its stretch an instance is still evaluated at t: four surface thresholds
// (`march_threshold`), so that a stretch's ends never look like a surface (a bound below the
// threshold would).
fn ray_margin(t: f32) -> f32 {
    return 4.0 * march_threshold(t, ray_pixel) + 1e-4;
}

// The half size of a node's box (centre c, half size `half`) padded for rays from ro: a
// quarter of the surface threshold at the box's far side, `reach` times that side's t, and
// 1e-3 (`ray_start`; shadow rays' thresholds and cones grow with t, the march's `reach` is
// 0). The blocks' pass pads by the same (`shaders/instances_blocks.wgsl`), so that its
// candidates hold every box a camera ray lists.
fn ray_padded(c: vec3<f32>, half: vec3<f32>, ro: vec3<f32>, pixel: f32, reach: f32) -> vec3<f32> {
    let far = length(c - ro) + length(half);
    return half + 0.25 * march_threshold(far, pixel) + reach * far + 1e-3;
}

// Lists the instances whose boxes the ray from ro along rd passes through between t0 and
// t1, the RAY_LIST that it enters first. Each box is padded by a quarter of the threshold at
// its far side (and 1e-3): the marcher counts a ray that passes a surface within a tenth of
// the threshold as touching it (`march_end`, and a hundredth in `refine`), and such a ray
// goes through the padded box. (A ray farther from a box cannot meet its instance, and the
// march's bounds hold along the ray only, so it need not list it. 1.5 thresholds, as first
// written, made the lists of rays from afar long: the 5 000-shape grid from the suite's
// camera ran 2.2x slower on lavapipe, with no error fewer.) A node's padding covers its subtree's
// needs too (no point of the subtree is farther), so a subtree whose padded box the ray
// misses is passed over whole. The list takes the first RAY_LIST leaves of the walk, and
// the cut is the nearest entry of any box left out (a full list leaves every subtree out
// whole): before it every box the ray enters is listed. The walk starts at node `start` (0:
// the root), and `ray_resume` keeps the first node a full list left out, where the march
// lists again (`shaders/march_instances.wgsl`): the nodes before it in the walk's order are
// done. The hierarchy puts the child
// nearer the camera first, so a camera ray's walk meets its instances nearly in the order
// of entry, and the list is sorted once after the walk, where an insertion at each leaf had
// a loop inside the walk's (llvmpipe runs a loop's first trip even where no lane needs it:
// 1.06x faster from close by on the 300-shape grid, docs/performance.md).
fn ray_start(ro: vec3<f32>, rd: vec3<f32>, t0: f32, t1: f32, pixel: f32, reach: f32, start: u32) {
    ray_pixel = pixel;
    var resume = NO_RESUME;
    // A zero component makes its slab's bounds infinite: the ray is inside it or never.
    let inv = 1.0 / select(rd, vec3<f32>(1e-30), rd == vec3<f32>(0.0));
    var n = 0u;
    var cut = 3.0e38;
    let end = scene_data[0].w;
    var i = start;
    // A camera ray whose block's candidates were made (`shaders/instances_blocks.wgsl`)
    // takes them, each a leaf, in the walk's order, instead of the walk's nodes: one loop
    // either way, so that its body is inlined once. (Its list never fills: a block holds
    // fewer candidates than RAY_LIST. A second list of the same ray walks: the first call
    // clears `ray_primary`.)
    var from_block = ray_primary && ray_slot != NO_BLOCK;
    ray_primary = false;
    var e = 0u;
    var e_end = 0u;
    if from_block {
        e_end = u32(aov_out[ray_slot].x);
        from_block = e_end <= BLOCK_CANDIDATES;
    }
    loop {
        var node = i;
        if from_block {
            if e >= e_end {
                break;
            }
            node = block_candidate(ray_slot, e);
            e = e + 1u;
        } else if i >= end {
            break;
        }
        let a = scene_data[2u * node];
        let b = scene_data[2u * node + 1u];
        let c = bitcast<vec3<f32>>(a.xyz);
        let half = bitcast<vec3<f32>>(b.xyz);
        let h = ray_padded(c, half, ro, pixel, reach);
        let ta = (c - h - ro) * inv;
        let tb = (c + h - ro) * inv;
        let tn = min(ta, tb);
        let tf = max(ta, tb);
        let lo = max(max(max(tn.x, tn.y), tn.z), t0);
        let hi = min(min(min(tf.x, tf.y), tf.z), t1);
        if lo > hi {
            i = a.w;
            continue;
        }
        if n == RAY_LIST || lo >= cut {
            // (The list is full: a cut exists only once it is.)
            cut = min(cut, lo);
            resume = min(resume, node);
            i = a.w;
            continue;
        }
        if b.w == 0u {
            i = node + 1u;
            continue;
        }
        ray_in[n] = lo;
        ray_out[n] = hi;
        ray_leaf[n] = b.w;
        n = n + 1u;
        i = a.w;
    }
    ray_sort(n);
    ray_n = n;
    ray_lo = t0;
    ray_cut = cut;
    ray_resume = resume;
}

// Sorts the list's first n entries by entry (stable): a camera ray's are nearly in order
// already, so the inner loop seldom shifts.
fn ray_sort(n: u32) {
    for (var j = 1u; j < n; j = j + 1u) {
        let lo = ray_in[j];
        let hi = ray_out[j];
        let leaf = ray_leaf[j];
        var k = j;
        loop {
            if k == 0u || ray_in[k - 1u] <= lo {
                break;
            }
            ray_in[k] = ray_in[k - 1u];
            ray_out[k] = ray_out[k - 1u];
            ray_leaf[k] = ray_leaf[k - 1u];
            k = k - 1u;
        }
        ray_in[k] = lo;
        ray_out[k] = hi;
        ray_leaf[k] = leaf;
    }
}

// The union's distance at p, t along the ray (the march's end, `ray_hit`), from the ray's
// list; no more than `below` (a distance already known, a mixed union's other children's),
// with the leaf word of the instance that gave it (0 if none is nearer): the central and
// forward normals' samples, and ambient occlusion's
// (`shaders/shading/ambient_occlusion_list.wgsl`, its own list along the normal). Only the
// listed instances whose stretch holds t (within `ray_margin`) are evaluated: every
// instance within the normal's step of the end is among them (the boxes' padding is far
// larger than the step). From a margin before the cut on, or where the march listed the ray
// more than once (`ray_lo` is then past every t), the walk over the whole hierarchy
// answers. Where no listed stretch holds t, it answers too
// unless `occlusion` (then nothing listed is near, and `below` stands; at the march's end a
// pass by an edge was counted as touching it, within the threshold but outside the
// padding). The walk takes no box's distance for its subtree's (`walk_node`'s `least`):
// ambient occlusion needs the distance itself up to its sample's height, and near the
// march's end a box that far is passed over anyway.
//
// One loop serves the list and the walk, so that it holds one call of instance_distance,
// not two: drivers inline every call, and on lavapipe a loop's first trip and an `if`'s
// body run under masks where no lane needs them (docs/performance.md, "One loop for the
// list and the walk").
fn ray_nearest(p: vec3<f32>, t: f32, below: f32, occlusion: bool) -> Nearest {
    let m = ray_margin(t);
    var walk = t < ray_lo || t > ray_cut - m;
    var d = below;
    var k = 0u;
    var hint = select(0u, scene_hint, walk);
    // Whether a listed stretch holds t (if none does, the walk answers).
    var held = false;
    let end = scene_data[0].w;
    var i = 0u;
    var nearest = 0u;
    loop {
        var leaf = hint;
        if hint != 0u {
            hint = 0u;
        } else if walk {
            if i >= end {
                break;
            }
            let w = walk_node(p, i, d, 3.0e38);
            i = w.next;
            d = w.distance;
            leaf = w.leaf;
            if leaf == 0u {
                continue;
            }
        } else {
            if k >= ray_n || ray_in[k] - m > t {
                if held || occlusion {
                    break;
                }
                walk = true;
                hint = scene_hint;
                continue;
            }
            leaf = ray_leaf[k];
            let outside = t < ray_in[k] - m || t > ray_out[k] + m;
            k = k + 1u;
            if outside {
                continue;
            }
            held = true;
        }
        let di = instance_distance(p, leaf);
        if di < d {
            d = di;
            nearest = leaf;
        }
    }
    if walk && nearest != 0u {
        scene_hint = nearest;
    }
    return Nearest(d, nearest);
}
