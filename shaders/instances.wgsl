// The scene's union as data (binding 3, `sdfc render --instances`), vec4s of 32-bit words
// (floats as their bits): a hierarchy of boxes in depth-first order, two vec4 a node (centre
// and skip link, the node past its subtree; half size, and 0 or, for a leaf, 1 + the index of
// its instance's record), then the records: a unit quaternion; centre and scale; kind,
// material and the primitive's arguments, flat, in as many vec4 as they need. An instance is
// its kind's distance with its arguments at turn(q, p - centre) / scale, times scale. (Whole
// vec4 loads: on lavapipe four scalar loads cost about four times one vec4 load.)
@group(0) @binding(3) var<storage, read> scene_data: array<vec4<u32>>;

// The leaf word of the instance nearest at this invocation's last call, or 0. Consecutive
// calls (ambient occlusion's samples, the normals' where the list does not answer) are at
// nearby points, so evaluating it first starts the walk from a tight best distance. The value does not depend on it (see scene_nearest).
var<private> scene_hint: u32;

// The union's distance, and the leaf word of the instance that gave it (0 if none did).
struct Nearest {
    distance: f32,
    leaf: u32,
}

// One instance's distance, from its leaf word.
fn instance_distance(p: vec3<f32>, leaf: u32) -> f32 {
    let r = leaf - 1u;
    let q = bitcast<vec4<f32>>(scene_data[r]);
    let c = bitcast<vec4<f32>>(scene_data[r + 1u]);
    let v = p - c.xyz;
    // v turned by the quaternion q: v + q.w t + q.xyz x t, with t = 2 q.xyz x v.
    let t = 2.0 * cross(q.xyz, v);
    let local = (v + q.w * t + cross(q.xyz, t)) / c.w;
    return instance_kind(local, r) * c.w;
}

// One node of the walk (`scene_nearest`, `ray_nearest`): where it goes next, the leaf word of
// the instance to evaluate there (0: none), and the best distance so far.
struct Walked {
    next: u32,
    leaf: u32,
    distance: f32,
}

// The walk at node i, at p, with the best distance so far d: a node whose box is no nearer
// than d is passed over with its subtree; beyond its box's reach (its half diagonal), and no
// nearer than `least`, the subtree answers with the box's distance, a lower bound of its
// field (what a march needs, far from the shapes: `least` 0; ambient occlusion needs the
// distance itself, up to its sample's height: 3e38; a soft shadow, wherever it could lower
// the light); a leaf gives its instance; an inner node goes down to its first child.
fn walk_node(p: vec3<f32>, i: u32, d: f32, least: f32) -> Walked {
    let a = scene_data[2u * i];
    let b = scene_data[2u * i + 1u];
    let half = bitcast<vec3<f32>>(b.xyz);
    let q = abs(p - bitcast<vec3<f32>>(a.xyz)) - half;
    let bd = length(max(q, vec3<f32>(0.0))) + min(max(q.x, max(q.y, q.z)), 0.0);
    if bd >= d {
        return Walked(a.w, 0u, d);
    }
    if bd > length(half) && bd >= least {
        return Walked(a.w, 0u, bd);
    }
    if b.w == 0u {
        return Walked(i + 1u, 0u, d);
    }
    return Walked(a.w, b.w, d);
}

// One loop over the hierarchy (`walk_node`), with no stack. The result does not depend on
// the order of the walk (or on the hint): every instance contributes its distance, or the
// box distance of the node it lies under where the point is beyond that node's reach and
// that distance is no less than `least` (`walk_node`), and a skipped subtree contributes at
// least the best distance when it was skipped, which is never below the end result. Near
// every surface that is the union's exact distance. `below` is a distance the caller already
// has (a mixed union's other children's, else 3e38): the walk starts from it, and the leaf
// word is 0 where no instance is nearer.
// (`ray_nearest` walks the same way, without bounds, where a ray's list does not answer.)
fn scene_nearest(p: vec3<f32>, below: f32, least: f32) -> Nearest {
    var d = below;
    var nearest = 0u;
    // The root's skip link: the number of nodes.
    let end = scene_data[0].w;
    var i = 0u;
    // The hint is the loop's first leaf, so that the loop holds the only call of
    // instance_distance: drivers inline every call, and Mesa's build of the 300-shape grid's
    // pipeline took 0.73 s with a call for the hint before the loop, 0.58 s without.
    var hint = scene_hint;
    loop {
        var leaf = hint;
        if hint != 0u {
            hint = 0u;
        } else {
            if i >= end {
                break;
            }
            let w = walk_node(p, i, d, least);
            i = w.next;
            d = w.distance;
            leaf = w.leaf;
            if leaf == 0u {
                continue;
            }
        }
        let di = instance_distance(p, leaf);
        if di < d {
            d = di;
            nearest = leaf;
        }
    }
    if nearest != 0u {
        scene_hint = nearest;
    }
    return Nearest(d, nearest);
}
