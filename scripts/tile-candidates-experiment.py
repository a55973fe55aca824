#!/usr/bin/env python3
"""Each ray's list from its tile's candidates, an experiment on the `--instances` shader.

For each block of pixels (8x8 by default, `SDFC_TILE=WxH`), the CPU lists the instances
whose padded boxes (the padding `ray_start` gives them) meet the frustum of the block's four
corner rays, in the hierarchy's order, as a pass of the device could before the frame (the
padding of `epsilon: pixel`, the default, without `march_threshold`'s floor of 2.4e-7 t,
which only matters far from the origin: other scenes may lose boxes). Each
ray then makes its own list, as `ray_start` does, from its block's candidates instead of a
walk of the whole hierarchy; the march, the normal and the material are unchanged. (The
frustum test is conservative, so every box a ray passes is among its block's candidates and
the pictures are the same.) One camera and one image size: not part of the compiler;
docs/performance.md, "Next: each ray's list from its tile's candidates".

    sdfc compile SCENE.sdf --instances --data IN.bin -o IN.wgsl
    scripts/tile-candidates-experiment.py IN.wgsl IN.bin WxH OUT.wgsl OUT.bin
    compare_shader compare SCENE.sdf OUT.wgsl:OUT.bin WxH IN.wgsl:IN.bin
"""
import importlib.util
import math
import os
import struct
import sys

# The camera's constants, the rays and the data's words, as the per-tile experiment reads them.
_spec = importlib.util.spec_from_file_location(
    "tile_experiment", os.path.join(os.path.dirname(os.path.abspath(__file__)), "tile-experiment.py")
)
te = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(te)

TILE_W, TILE_H = (int(v) for v in os.environ.get("SDFC_TILE", "8x8").split("x"))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def candidates(c, nodes, x0, y0, x1, y1, w, h):
    """The leaves' node indices whose padded boxes meet the block's frustum."""
    corners = [te.ray(c, x, y, w, h) for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]
    middle = te.ray(c, (x0 + x1) / 2, (y0 + y1) / 2, w, h)
    planes = []
    for k in range(4):
        n = cross(corners[k], corners[(k + 1) % 4])
        planes.append(n if dot(n, middle) >= 0 else [-v for v in n])
    pixel = 2.0 * c["tan"] / h
    ro = c["pos"]
    out = []
    i = 0
    while i < len(nodes):
        centre, skip, half, leaf = nodes[i]
        # `ray_start`'s padding with `epsilon: pixel`: a quarter of the threshold at the box's
        # far side, and 1e-3.
        far = math.dist(ro, centre) + math.sqrt(sum(v * v for v in half))
        padded = [v + 0.25 * 0.5 * pixel * far + 1e-3 for v in half]
        rel = [centre[a] - ro[a] for a in range(3)]
        if not all(dot(n, rel) + sum(abs(n[a]) * padded[a] for a in range(3)) >= 0 for n in planes):
            i = skip
        elif leaf == 0:
            i += 1
        else:
            out.append(i)
            i = skip
    return out


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    wgsl = open(sys.argv[1]).read()
    data = open(sys.argv[2], "rb").read()
    w, h = (int(v) for v in sys.argv[3].lower().split("x"))
    c = te.consts(wgsl)
    words = list(struct.unpack(f"<{len(data) // 4}I", data))
    nodes = []
    for i in range(words[3]):
        a, b = words[8 * i : 8 * i + 4], words[8 * i + 4 : 8 * i + 8]
        nodes.append(([te.f32(v) for v in a[:3]], a[3], [te.f32(v) for v in b[:3]], b[3]))
    tiles_x, tiles_y = (w + TILE_W - 1) // TILE_W, (h + TILE_H - 1) // TILE_H
    lists = [
        candidates(c, nodes, x * TILE_W, y * TILE_H, min((x + 1) * TILE_W, w), min((y + 1) * TILE_H, h), w, h)
        for y in range(tiles_y)
        for x in range(tiles_x)
    ]
    table = len(words) // 4
    base = (table + len(lists)) * 4
    heads, body = [], []
    for l in lists:
        heads += [base + len(body), len(l), 0, 0]
        body += l
    out = words + heads + body
    while len(out) % 4:
        out.append(0)
    open(sys.argv[5], "wb").write(struct.pack(f"<{len(out)}I", *out))
    busy = [len(l) for l in lists if l]
    print(
        f"{len(lists)} tiles, {len(busy)} with candidates: {sum(busy) / max(len(busy), 1):.1f} a "
        f"tile on average, {max(busy, default=0)} at most",
        file=sys.stderr,
    )

    def sub(old, new):
        nonlocal wgsl
        if wgsl.count(old) != 1:
            sys.exit(f"expected one {old!r} in the shader")
        wgsl = wgsl.replace(old, new)

    # `ray_start`'s walk becomes a loop over the block's candidates, each a leaf: a box the
    # ray misses, or one left out of a full list, is passed over like a leaf of the walk.
    sub(
        """    let end = scene_data[0].w;
    var i = 0u;
    loop {
        if i >= end {
            break;
        }
        let a = scene_data[2u * i];""",
        f"""    let tile = scene_data[{table}u + (ray_gid.y / {TILE_H}u) * {tiles_x}u + ray_gid.x / {TILE_W}u];
    var e = tile.x;
    loop {{
        if e >= tile.x + tile.y {{
            break;
        }}
        let i = scene_data[e / 4u][e & 3u];
        e = e + 1u;
        let a = scene_data[2u * i];""",
    )
    sub("        if lo > hi {\n            i = a.w;\n            continue;", "        if lo > hi {\n            continue;")
    sub("            cut = min(cut, lo);\n            i = a.w;\n            continue;", "            cut = min(cut, lo);\n            continue;")
    sub("        if b.w == 0u {\n            i = i + 1u;\n            continue;\n        }\n", "")
    sub("        n = n + 1u;\n        i = a.w;\n", "        n = n + 1u;\n")
    sub("var<private> ray_pixel: f32;", "var<private> ray_pixel: f32;\nvar<private> ray_gid: vec2<u32>;")
    sub("    load_frame();\n", "    load_frame();\n    ray_gid = gid;\n")
    open(sys.argv[4], "w").write(wgsl)


if __name__ == "__main__":
    main()
