#!/usr/bin/env python3
"""Culling by a uniform grid of cells, an experiment on the `--instances` shader of a union.

The union's root box, padded by a margin M, is cut into cubic cells; each cell lists the
instances whose boxes, padded by M, overlap it. The march's distance at a point in a cell is
the least of its listed instances' distances and, along the ray, M more than the ray's
distance to the cell's faces (both ways): every instance not listed is further than M from
the cell, so the ray cannot meet one before it has left the cell by M. No per-ray list, no
walk of the hierarchy for a camera ray: a step costs a cell's lookup and its few
instances. The normal's and the material's samples take the instances of their own cell
(every instance within M of a point is listed there). Shadows and ambient occlusion keep
the walk. Not part of the compiler; docs/performance.md, "Tried and not kept (stop 43)".

    sdfc compile SCENE.sdf --instances --data IN.bin -o IN.wgsl
    scripts/grid-experiment.py IN.wgsl IN.bin OUT.wgsl OUT.bin
    compare_shader compare SCENE.sdf OUT.wgsl:OUT.bin WxH [IN.wgsl:IN.bin]

SDFC_GRID_CELLS: about how many cells per instance (1 by default); SDFC_GRID_MARGIN: M as
a share of a cell's side (0.25 by default).
"""
import math
import os
import struct
import sys


def f32(bits):
    return struct.unpack("<f", struct.pack("<I", bits))[0]


def bits(v):
    return struct.unpack("<I", struct.pack("<f", v))[0]


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    wgsl = open(sys.argv[1]).read()
    data = open(sys.argv[2], "rb").read()
    words = list(struct.unpack(f"<{len(data) // 4}I", data))
    end = words[3]
    leaves = []
    for i in range(end):
        a = words[8 * i : 8 * i + 4]
        b = words[8 * i + 4 : 8 * i + 8]
        if b[3] != 0:
            leaves.append(([f32(v) for v in a[:3]], [f32(v) for v in b[:3]], b[3]))
    root_c = [f32(v) for v in words[0:3]]
    root_h = [f32(v) for v in words[4:7]]
    per = float(os.environ.get("SDFC_GRID_CELLS", "1"))
    share = float(os.environ.get("SDFC_GRID_MARGIN", "0.25"))
    size = [2.0 * h for h in root_h]
    volume = max(size[0], 1e-6) * max(size[1], 1e-6) * max(size[2], 1e-6)
    side = (volume / (per * len(leaves))) ** (1.0 / 3.0)
    margin = share * side
    lo = [root_c[a] - root_h[a] - margin for a in range(3)]
    dims = [max(1, math.ceil((size[a] + 2.0 * margin) / side)) for a in range(3)]
    cells = [[] for _ in range(dims[0] * dims[1] * dims[2])]
    for centre, half, leaf in leaves:
        rng = []
        for a in range(3):
            c0 = math.floor((centre[a] - half[a] - margin - lo[a]) / side)
            c1 = math.floor((centre[a] + half[a] + margin - lo[a]) / side)
            rng.append(range(max(c0, 0), min(c1, dims[a] - 1) + 1))
        for z in rng[2]:
            for y in rng[1]:
                for x in rng[0]:
                    cells[(z * dims[1] + y) * dims[0] + x].append(leaf)
    g = len(words) // 4
    cell_base = (g + 3) * 4
    entries = []
    cell_words = []
    for cell in cells:
        if len(cell) > 255:
            sys.exit("a cell holds more than 255 instances")
        cell_words.append((len(entries) << 8) | len(cell))
        entries += cell
    while len(cell_words) % 4:
        cell_words.append(0)
    entry_base = cell_base + len(cell_words)
    header = [bits(lo[0]), bits(lo[1]), bits(lo[2]), bits(side)]
    header += [dims[0], dims[1], dims[2], entry_base]
    header += [bits(margin), bits(1.0 / side), cell_base, 0]
    out = words + header + cell_words + entries
    while len(out) % 4:
        out.append(0)
    open(sys.argv[4], "wb").write(struct.pack(f"<{len(out)}I", *out))
    busy = [len(c) for c in cells if c]
    print(
        f"{len(leaves)} instances, {dims[0]}x{dims[1]}x{dims[2]} cells of {side:.3f}, margin "
        f"{margin:.3f}: {len(busy)} hold instances, {sum(busy) / max(len(busy), 1):.2f} each on "
        f"average, {max(busy, default=0)} at most",
        file=sys.stderr,
    )

    part = f"""
// Culling by a grid of cells (scripts/grid-experiment.py), its header at vec4 {g}.
var<private> grid_ro: vec3<f32>;
var<private> grid_inv: vec3<f32>;

fn grid_start(ro: vec3<f32>, rd: vec3<f32>) {{
    grid_ro = ro;
    grid_inv = 1.0 / select(rd, vec3<f32>(1e-30), rd == vec3<f32>(0.0));
}}

// The instances listed in p's cell: the nearest's distance and leaf word; along the ray
// (at t), no more than M beyond the ray's distance to the cell's faces, either way.
fn grid_walk(p: vec3<f32>, t: f32, along: bool) -> Nearest {{
    let h0 = scene_data[{g}u];
    let h1 = scene_data[{g + 1}u];
    let h2 = scene_data[{g + 2}u];
    let lo = bitcast<vec3<f32>>(h0.xyz);
    let side = bitcast<f32>(h0.w);
    let margin = bitcast<f32>(h2.x);
    let inv_side = bitcast<f32>(h2.y);
    let cf = clamp(floor((p - lo) * inv_side), vec3<f32>(0.0), vec3<f32>(h1.xyz - 1u));
    let c = vec3<u32>(cf);
    var d = 3.0e38;
    if along {{
        let clo = lo + cf * side;
        let ta = (clo - grid_ro) * grid_inv;
        let tb = (clo + side - grid_ro) * grid_inv;
        let t_in = max(max(min(ta.x, tb.x), min(ta.y, tb.y)), min(ta.z, tb.z));
        let t_out = min(min(max(ta.x, tb.x), max(ta.y, tb.y)), max(ta.z, tb.z));
        d = max(min(t_out - t, t - t_in), 0.0) + margin;
    }}
    let ci = (c.z * h1.y + c.y) * h1.x + c.x;
    let cw = scene_data[h2.z / 4u + ci / 4u][ci & 3u];
    let first = h1.w + (cw >> 8u);
    let last = first + (cw & 255u);
    var nearest = 0u;
    for (var e = first; e < last; e = e + 1u) {{
        let leaf = scene_data[e / 4u][e & 3u];
        let di = instance_distance(p, leaf);
        if di < d {{
            d = di;
            nearest = leaf;
        }}
    }}
    return Nearest(d, nearest);
}}
"""

    def sub(old, new, count=1):
        nonlocal wgsl
        if wgsl.count(old) != count:
            sys.exit(f"expected {count} of {old!r} in the shader")
        wgsl = wgsl.replace(old, new)

    sub("fn scene_distance(p: vec3<f32>) -> f32 {", part + "\nfn scene_distance(p: vec3<f32>) -> f32 {")
    sub("    ray_start(ro, rd, span.x, span.y, pixel);\n", "    grid_start(ro, rd);\n")
    sub("    return ray_distance(p, t, 3.0e38);\n", "    return grid_walk(p, t, true).distance;\n")
    sub("    return ray_nearest(p, 3.0e38);\n", "    return grid_walk(p, ray_hit, false);\n")
    open(sys.argv[3], "w").write(wgsl)


if __name__ == "__main__":
    main()
