#!/usr/bin/env python3
"""Rewrites the emitted WGSL of a generated grid scene (`sdfc_tests::grid_scene`) so that its
union is read from a storage buffer: bounding-volume hierarchies of its instances (one per
kind of shape, or one for all), each walked by one loop with skip links (no stack), with the
compiled culling's rules (a part is opened only where its box is nearer than the best
distance so far, and answers with its box's distance farther than its reach). The experiment
behind "Large unions as data" in docs/performance.md. Not part of the compiler; it knows
only the grid's three kinds of shape (it shares `table-experiment.py`'s parser) and fails
loudly on anything else.

    scripts/bvh-experiment.py GRID.wgsl OUT.wgsl OUT.bin [LEAF] [--subgroup | --mixed [--hint]]

LEAF (default 1) is the number of instances a leaf of a per-kind hierarchy evaluates,
straight-line: a leaf with fewer repeats its first instance, which changes neither the
minimum nor the material. `--subgroup` makes the per-kind walk coherent (it needs a device
with subgroups; naga validates it only with that capability), `--mixed` builds one hierarchy
for every kind, and `--hint` starts its walk at the instance nearest at the last call
(below). `compare_shader compare SCENE.sdf OUT.wgsl:OUT.bin WxH` renders it against the
scene's own shader.
"""
import importlib.util
import math
import os
import struct
import sys

_spec = importlib.util.spec_from_file_location(
    "table_experiment", os.path.join(os.path.dirname(__file__), "table-experiment.py")
)
tables = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(tables)

# Node boxes are padded so that f32 rounding cannot put an instance's surface outside them.
PAD = 1e-3

BINDING = """
// The scene as data (binding 3): per kind of shape, a hierarchy of boxes in depth-first
// order, two vec4 a node (centre, skip link; half size, 0 or 1 + the leaf's first instance),
// then the instances: a sphere (centre, radius); a box (centre, cos) then (sin, half size);
// a torus (centre, cos) then (sin, R, r, 0).
@group(0) @binding(3) var<storage, read> scene_data: array<vec4<u32>>;

struct Nearest {
    distance: f32,
    kind: u32,
}
"""

VISIT = """
// What a node contributes and where the walk goes next: `bound` is the node's box distance
// where it is beyond its reach (a lower bound of its subtree's field), else 3e38; `next` the
// node after it (its first child) where it is opened, else its skip link (past its
// subtree); `leaf`, for a leaf to evaluate, 1 + its first instance's vec4, else 0.
struct Visit {
    bound: f32,
    next: u32,
    leaf: u32,
}

fn visit(p: vec3<f32>, node: u32, best: f32) -> Visit {
    let a = scene_data[2u * node];
    let b = scene_data[2u * node + 1u];
    let half = bitcast<vec3<f32>>(b.xyz);
    let q = abs(p - bitcast<vec3<f32>>(a.xyz)) - half;
    let bd = length(max(q, vec3<f32>(0.0))) + min(max(q.x, max(q.y, q.z)), 0.0);
    if bd >= best {
        return Visit(3.0e38, a.w, 0u);
    }
    if bd > length(half) {
        return Visit(bd, a.w, 0u);
    }
    if b.w == 0u {
        return Visit(3.0e38, node + 1u, 0u);
    }
    return Visit(3.0e38, a.w, b.w);
}
"""

NEAREST = """
fn scene_nearest(p: vec3<f32>, with_kind: bool) -> Nearest {
    var d = 3.0e38;
    var kind = 0u;
{walks}
    return Nearest(d, kind);
}
"""

WALK = """    // {name}: nodes {first}..{end}.
    var i{k} = {first}u;
    loop {
        if i{k} >= {end}u {
            break;
        }
        let v = visit(p, i{k}, d);
        i{k} = v.next;
        d = min(d, v.bound);
        if v.leaf == 0u {
            continue;
        }
        let base = v.leaf - 1u;
{leaf}
    }
"""


# The coherent walk (`--subgroup`): every lane of a subgroup visits the same nodes, opening a
# node where any lane needs it, so that the node index and the loads are uniform; a lane that
# does not need a subtree is muted until the walk leaves it, so its field is the divergent
# walk's.
COHERENT_WALK = """    // {name}: nodes {first}..{end}.
    var i{k} = {first}u;
    var mute{k} = {first}u;
    loop {
        if i{k} >= {end}u {
            break;
        }
        let a = scene_data[2u * i{k}];
        let b = scene_data[2u * i{k} + 1u];
        let half = bitcast<vec3<f32>>(b.xyz);
        let q = abs(p - bitcast<vec3<f32>>(a.xyz)) - half;
        let bd = length(max(q, vec3<f32>(0.0))) + min(max(q.x, max(q.y, q.z)), 0.0);
        let live = i{k} >= mute{k};
        let far = live && bd < d && bd > length(half);
        let open = live && bd < d && !far;
        d = select(d, bd, far);
        mute{k} = select(mute{k}, a.w, live && !open);
        if !subgroupAny(open) {
            i{k} = a.w;
            continue;
        }
        if b.w == 0u {
            i{k} = i{k} + 1u;
            continue;
        }
        let base = b.w - 1u;
{leaf}
        i{k} = a.w;
    }
"""


def parse(src):
    start, end = src.index(tables.FIRST_GROUP), src.index(tables.AFTER_SCENE)
    kinds = {"spheres": [], "boxes": [], "tori": []}
    lets = 0
    nums = lambda s: [float(x) for x in s.split(", ")]
    for line in src[start:end].splitlines():
        if tables.re.match(r"\s*let d\d+ = sd_", line):
            lets += 1
        if m := tables.SPHERE.match(line):
            kinds["spheres"].append(nums(tables.centre(m)) + [float(m[2])])
        elif m := tables.BOX.match(line):
            half = nums(m[4])
            half = half * 3 if len(half) == 1 else half
            kinds["boxes"].append(nums(tables.centre(m)) + [float(m[2]), float(m[3])] + half)
        elif m := tables.TORUS.match(line):
            kinds["tori"].append(
                nums(tables.centre(m)) + [float(m[2]), float(m[3]), float(m[4]), float(m[5])]
            )
    found = sum(len(v) for v in kinds.values())
    if found != lets or found == 0:
        sys.exit(f"{lets} shapes, {found} of them of the grid's three kinds")
    return src[:start], kinds, src[end:]


def bounds(kind, e):
    """An instance's box (centre, half size), conservative whatever its turn."""
    c = e[:3]
    if kind == "spheres":
        h = [e[3]] * 3
    elif kind == "boxes":
        # Turned about y: x and z within the box's half diagonal in xz.
        r = math.hypot(e[5], e[7])
        h = [r, e[6], r]
    else:
        h = [e[5] + e[6]] * 3
    return c, h


def build(boxes, leaf_size):
    """Over the instances' `boxes`: nodes in depth-first order (centre, half, skip, the leaf's
    first place in `order` or None) and `order`, the instances' indices leaf by leaf, each
    leaf padded to `leaf_size` by repeating its first."""
    nodes, order = [], []

    def boxof(idx):
        lo = [min(boxes[i][0][a] - boxes[i][1][a] for i in idx) for a in range(3)]
        hi = [max(boxes[i][0][a] + boxes[i][1][a] for i in idx) for a in range(3)]
        c = [(l + h) / 2 for l, h in zip(lo, hi)]
        h = [(h - l) / 2 * (1 + PAD) + PAD for l, h in zip(lo, hi)]
        return c, h

    def rec(idx):
        me = len(nodes)
        c, h = boxof(idx)
        nodes.append([c, h, None, None])
        if len(idx) <= leaf_size:
            nodes[me][3] = len(order)
            order.extend(idx + [idx[0]] * (leaf_size - len(idx)))
        else:
            # A median split along the longest axis of the centres.
            cs = [boxes[i][0] for i in idx]
            axis = max(range(3), key=lambda a: max(x[a] for x in cs) - min(x[a] for x in cs))
            idx = sorted(idx, key=lambda i: boxes[i][0][axis])
            mid = len(idx) // 2
            rec(idx[:mid])
            rec(idx[mid:])
        nodes[me][2] = len(nodes)

    rec(list(range(len(boxes))))
    return nodes, order


# The mixed walk (`--mixed`): one hierarchy over every instance, leaves of one, the kind in a
# leaf word's top bits and a switch on it; each instance two vec4 (a sphere's second unused).
MIXED = """
// One instance's distance, from its leaf word (kind in the top four bits, 1 + its first vec4
// below).
fn instance(p: vec3<f32>, leaf: u32) -> f32 {
    let base = (leaf & 0x0fffffffu) - 1u;
    let a = bitcast<vec4<f32>>(scene_data[base]);
    let b = bitcast<vec4<f32>>(scene_data[base + 1u]);
    switch leaf >> 28u {
        case 0u: {
            return sd_sphere(p - a.xyz, a.w);
        }
        case 1u: {
            return sd_box(rotate_y(p - a.xyz, a.w, b.x), b.yzw);
        }
        default: {
            return sd_torus(rotate_x(p - a.xyz, a.w, b.x), b.y, b.z);
        }
    }
}
{hint_decl}
fn scene_nearest(p: vec3<f32>, with_kind: bool) -> Nearest {
    var d = 3.0e38;
    var kind = 0u;
    var nearest = 0u;
{hint_start}
    var i = 0u;
    loop {
        if i >= {end}u {
            break;
        }
        let v = visit(p, i, d);
        i = v.next;
        d = min(d, v.bound);
        if v.leaf == 0u {
            continue;
        }
        let di = instance(p, v.leaf);
        if di < d {
            nearest = v.leaf;
        }
        d = min(d, di);
    }
{hint_end}
    if with_kind {
        kind = nearest >> 28u;
    }
    return Nearest(d, kind);
}
"""

# `--hint`: the instance nearest at the invocation's last call is evaluated first, so that
# the walk starts from a tight best distance (the value is the same: a skipped part is never
# nearer than the final distance).
HINT_DECL = """
// The leaf word of the instance nearest at this invocation's last call, or 0.
var<private> hint: u32;
"""
HINT_START = """    if hint != 0u {
        d = instance(p, hint);
        nearest = hint;
    }"""
HINT_END = """    if nearest != 0u {
        hint = nearest;
    }"""


def main_mixed(head, kinds, tail, out_path, bin_path, hint):
    items = [(k, e) for k, name in enumerate(kinds) for e in kinds[name]]
    names = list(kinds)
    nodes, order = build([bounds(names[k], e) for k, e in items], 1)
    words, inst = [], []
    base = 2 * len(nodes)
    for c, h, skip, first in nodes:
        leaf = 0
        if first is not None:
            leaf = (items[order[first]][0] << 28) | (1 + base + 2 * first)
        words += u32s_of_floats(c) + [skip] + u32s_of_floats(h) + [leaf]
    for i in order:
        e = items[i][1]
        inst += u32s_of_floats(e + [0.0] * (8 - len(e)))
    nearest = (
        MIXED.replace("{end}", str(len(nodes)))
        .replace("{hint_decl}", HINT_DECL if hint else "")
        .replace("{hint_start}", HINT_START if hint else "")
        .replace("{hint_end}", HINT_END if hint else "")
    )
    scene = BINDING + VISIT + nearest
    write(head, scene, tail, words + inst, out_path, bin_path)
    print(f"{out_path}: {len(items)} instances, {len(nodes)} nodes, mixed; {bin_path}")


def write(head, scene, tail, words, out_path, bin_path):
    """The shader (the scene's distance and material functions after `scene`, as the table
    experiment writes them) and its data."""
    tail_start = tables.SCENE.index("// The signed distance from p to the scene.")
    open(out_path, "w").write(head + scene + tables.SCENE[tail_start:] + tail)
    open(bin_path, "wb").write(struct.pack(f"<{len(words)}I", *words))


def u32s_of_floats(xs):
    return [struct.unpack("<I", struct.pack("<f", x))[0] for x in xs]


def main(src_path, out_path, bin_path, leaf_size, coherent):
    head, kinds, tail = parse(open(src_path).read())
    words, walks = [], []
    node_offset = 0
    built = {}
    for k, v in kinds.items():
        if v:
            nodes, order = build([bounds(k, e) for e in v], leaf_size)
            built[k] = (nodes, [v[i] for i in order])
    total_nodes = sum(len(n) for n, _ in built.values())
    # All nodes first (node i at vec4s 2i, 2i + 1), then the instances.
    inst_words = []
    inst_base = 2 * total_nodes
    for k, (name, (nodes, insts)) in enumerate(built.items()):
        per = {"spheres": 1, "boxes": 2, "tori": 2}[name]
        base = inst_base + len(inst_words) // 4
        for c, h, skip, first in nodes:
            words += u32s_of_floats(c) + [node_offset + skip]
            words += u32s_of_floats(h) + [0 if first is None else 1 + base + per * first]
        for e in insts:
            vals = e if name == "spheres" else e + [0.0] * (8 - len(e))
            inst_words += u32s_of_floats(vals)
        leaf = []
        for j in range(leaf_size):
            if name == "spheres":
                leaf.append(
                    f"        let e{j} = bitcast<vec4<f32>>(scene_data[base + {j}u]);\n"
                    f"        let d{j} = sd_sphere(p - e{j}.xyz, e{j}.w);"
                )
            else:
                a, b = f"a{j}", f"b{j}"
                load = (
                    f"        let {a} = bitcast<vec4<f32>>(scene_data[base + {2 * j}u]);\n"
                    f"        let {b} = bitcast<vec4<f32>>(scene_data[base + {2 * j + 1}u]);\n"
                )
                if name == "boxes":
                    call = f"sd_box(rotate_y(p - {a}.xyz, {a}.w, {b}.x), {b}.yzw)"
                else:
                    call = f"sd_torus(rotate_x(p - {a}.xyz, {a}.w, {b}.x), {b}.y, {b}.z)"
                leaf.append(load + f"        let d{j} = {call};")
            if coherent:
                leaf.append(f"        let m{j} = select(3.0e38, d{j}, open);")
            else:
                leaf.append(f"        let m{j} = d{j};")
            leaf.append(
                f"        if with_kind && m{j} < d {{\n            kind = {k}u;\n        }}\n"
                f"        d = min(d, m{j});"
            )
        walks.append(
            (COHERENT_WALK if coherent else WALK).replace("{name}", name)
            .replace("{k}", str(k))
            .replace("{first}", str(node_offset))
            .replace("{end}", str(node_offset + len(nodes)))
            .replace("{leaf}", "\n".join(leaf))
        )
        node_offset += len(nodes)
    words += inst_words
    scene = BINDING + ("" if coherent else VISIT) + NEAREST.replace("{walks}", "".join(walks))
    write(head, scene, tail, words, out_path, bin_path)
    counts = ", ".join(f"{len(v)} {k}" for k, v in kinds.items())
    print(
        f"{out_path}: {counts}; {total_nodes} nodes, leaves of {leaf_size}; "
        f"{bin_path}: {4 * len(words)} bytes"
    )


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) not in (3, 4):
        sys.exit(__doc__)
    if "--mixed" in sys.argv:
        head, kinds, tail = parse(open(args[0]).read())
        main_mixed(head, kinds, tail, args[1], args[2], "--hint" in sys.argv)
    else:
        leaf = int(args[3]) if len(args) == 4 else 1
        main(args[0], args[1], args[2], leaf, "--subgroup" in sys.argv)
