#!/usr/bin/env python3
"""Per-tile ray culling, an experiment on the `--instances` shader of a generated grid.

For each 8x8 tile of the image (one workgroup; `SDFC_TILE=WxH` for other blocks), the CPU lists the instances whose padded
boxes the tile's primary rays pass through, each with the interval of t in which any of
those rays is inside the box, sorted by entry. The primary march then evaluates only the
listed instances whose interval holds t (with a margin); every other listed instance
contributes its distance along the ray to its interval (a bound on how far the ray can
step before it could meet that instance), and unlisted instances none: no ray of the tile
comes near them. Normals, the material and everything else keep the walk over the whole
union. The shader's own lists, which each march makes on the device (`ray_start`,
docs/performance.md, "Culling per ray"), give way to the tile's. Not part of the compiler
(it writes the tile lists for one camera and one image size); docs/performance.md,
"Per-tile ray culling (an experiment)".

    sdfc compile SCENE.sdf --instances --data IN.bin -o IN.wgsl
    scripts/tile-experiment.py IN.wgsl IN.bin WxH OUT.wgsl OUT.bin
    compare_shader compare SCENE.sdf OUT.wgsl:OUT.bin WxH [IN.wgsl:IN.bin]

The scene must have one sample a pixel (`antialias: 1`) and its camera near the origin
(no camera-relative frame); the script fails loudly otherwise.
"""
import math
import os
import re
import struct
import sys

# The block of pixels that shares a list: SDFC_TILE=WxH (8x8 by default, a workgroup).
TILE_W, TILE_H = (int(v) for v in os.environ.get("SDFC_TILE", "8x8").split("x"))


def consts(wgsl):
    def vec(name):
        m = re.search(rf"const {name}: vec3<f32> = vec3<f32>\(([^)]*)\);", wgsl)
        if not m:
            sys.exit(f"no {name} in the shader")
        return [float(x) for x in m.group(1).split(",")]

    def scalar(name):
        m = re.search(rf"const {name}: \w+ = ([0-9.e+-]+)u?;", wgsl)
        if not m:
            sys.exit(f"no {name} in the shader")
        return float(m.group(1))

    return {
        "pos": vec("CAMERA_POSITION"),
        "fwd": vec("CAMERA_FORWARD"),
        "right": vec("CAMERA_RIGHT"),
        "up": vec("CAMERA_UP"),
        "tan": scalar("TAN_HALF_FOV"),
        "max": scalar("MAX_DISTANCE"),
        "aa": scalar("ANTIALIAS"),
    }


def f32(bits):
    return struct.unpack("<f", struct.pack("<I", bits))[0]


def ray(c, x, y, w, h):
    sx = 2.0 * x / w - 1.0
    sy = 1.0 - 2.0 * y / h
    aspect = w / h
    d = [c["fwd"][i] + sx * c["tan"] * aspect * c["right"][i] + sy * c["tan"] * c["up"][i] for i in range(3)]
    n = math.sqrt(sum(v * v for v in d))
    return [v / n for v in d]


def slab(ro, inv, centre, half, pad):
    t0, t1 = 0.0, math.inf
    for a in range(3):
        lo = centre[a] - half[a] - pad
        hi = centre[a] + half[a] + pad
        if inv[a] == math.inf or inv[a] == -math.inf:
            if ro[a] < lo or ro[a] > hi:
                return None
            continue
        ta = (lo - ro[a]) * inv[a]
        tb = (hi - ro[a]) * inv[a]
        t0 = max(t0, min(ta, tb))
        t1 = min(t1, max(ta, tb))
    return (t0, t1) if t0 <= t1 else None


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    wgsl = open(sys.argv[1]).read()
    data = open(sys.argv[2], "rb").read()
    w, h = (int(v) for v in sys.argv[3].lower().split("x"))
    c = consts(wgsl)
    if c["aa"] != 1:
        sys.exit("the experiment lists primary rays at pixel centres: antialias must be 1")
    words = struct.unpack(f"<{len(data) // 4}I", data)
    vec4s = len(words) // 4
    end = words[3]
    nodes = []
    for i in range(end):
        a = words[8 * i : 8 * i + 4]
        b = words[8 * i + 4 : 8 * i + 8]
        nodes.append(([f32(v) for v in a[:3]], a[3], [f32(v) for v in b[:3]], b[3]))
    pixel = 2.0 * c["tan"] / h
    ro = c["pos"]
    # Per tile: leaf word -> [t in, t out].
    tiles_x, tiles_y = (w + TILE_W - 1) // TILE_W, (h + TILE_H - 1) // TILE_H
    lists = [dict() for _ in range(tiles_x * tiles_y)]
    for y in range(h):
        for x in range(w):
            rd = ray(c, x + 0.5, y + 0.5, w, h)
            inv = [1.0 / v if v != 0.0 else math.inf for v in rd]
            tile = lists[(y // TILE_H) * tiles_x + x // TILE_W]
            i = 0
            while i < end:
                centre, skip, half, leaf = nodes[i]
                # Padded by two pixels' footprint at the box's far side, so that a ray the
                # marcher would count as grazing a surface (within half a pixel) lists it.
                far = math.dist(ro, centre) + math.sqrt(sum(v * v for v in half))
                hit = slab(ro, inv, centre, half, 2.0 * pixel * far + 1e-3)
                if hit is None or hit[0] > c["max"]:
                    i = skip
                    continue
                if leaf == 0:
                    i += 1
                    continue
                span = tile.setdefault(leaf, [math.inf, -math.inf])
                span[0] = min(span[0], hit[0])
                span[1] = max(span[1], min(hit[1], c["max"]))
                i = skip
    table = vec4s
    entries = table + len(lists)
    out = list(words)
    heads, body = [], []
    counts = []
    for tile in lists:
        ordered = sorted(tile.items(), key=lambda kv: kv[1][0])
        heads += [entries + len(body) // 4, len(ordered), 0, 0]
        counts.append(len(ordered))
        # The fourth word: the largest t out of this entry and those before it.
        most = -math.inf
        bits = lambda v: struct.unpack("<I", struct.pack("<f", v))[0]
        for leaf, (t0, t1) in ordered:
            most = max(most, t1)
            body += [leaf, bits(t0), bits(t1), bits(most)]
    out += heads + body
    open(sys.argv[5], "wb").write(struct.pack(f"<{len(out)}I", *out))
    busy = [n for n in counts if n]
    print(
        f"{len(lists)} tiles, {len(busy)} with instances: {sum(busy) / max(len(busy), 1):.1f} a tile "
        f"on average, {max(counts)} at most",
        file=sys.stderr,
    )

    part = f"""
// Per-tile ray culling (scripts/tile-experiment.py): the instances near this workgroup's
// primary rays, from the tile table at vec4 {table} of the data.
const TILES_X: u32 = {tiles_x}u;
var<private> tile_first: u32;
var<private> tile_count: u32;

// A bound on how far the ray can step from t: listed instances whose interval holds t
// (within m) give their distance, the others their distance along the ray to their
// interval; unlisted instances are never near a ray of the tile.
//
// Entries whose interval and every earlier one's ended before t (the fourth word: the
// largest t out so far) are passed over from where the last call of this ray began (back
// to the tile's first where t went back); together they bound the step by t minus that end.
var<private> tile_k0: u32;
var<private> tile_t0: f32;

fn tile_distance(p: vec3<f32>, t: f32, m: f32) -> f32 {{
    var d = 3.0e38;
    let end = tile_first + tile_count;
    if t < tile_t0 {{
        tile_k0 = tile_first;
    }}
    var k0 = tile_k0;
    loop {{
        if k0 >= end || bitcast<f32>(scene_data[k0].w) + m >= t {{
            break;
        }}
        k0 = k0 + 1u;
    }}
    tile_k0 = k0;
    tile_t0 = t;
    if k0 > tile_first {{
        d = t - bitcast<f32>(scene_data[k0 - 1u].w);
    }}
    for (var k = k0; k < end; k = k + 1u) {{
        let e = scene_data[k];
        let t_in = bitcast<f32>(e.y);
        if t_in - t >= d {{
            break;
        }}
        let t_out = bitcast<f32>(e.z);
        if t < t_in - m {{
            d = min(d, t_in - t);
        }} else if t > t_out + m {{
            d = min(d, t - t_out);
        }} else {{
            d = min(d, instance_distance(p, e.x));
        }}
    }}
    return d;
}}
"""
    part += """
// With the normals (SDFC_TILE_SHADING=1): the hit's t, and its margin, for `tile_nearest`.
var<private> tile_t: f32;
var<private> tile_m: f32;

// The nearest listed instance at a point near the hit: those whose interval holds the hit's t
// (within the margin). Boxes are padded by two pixels' footprint, far more than the normal's
// step, so every instance within that step of the hit is among them.
fn tile_nearest(p: vec3<f32>) -> Nearest {
    var d = 3.0e38;
    var leaf = 0u;
    let end = tile_first + tile_count;
    for (var k = tile_first; k < end; k = k + 1u) {
        let e = scene_data[k];
        if bitcast<f32>(e.y) - tile_m > tile_t {
            break;
        }
        if tile_t > bitcast<f32>(e.z) + tile_m {
            continue;
        }
        let di = instance_distance(p, e.x);
        if di < d {
            d = di;
            leaf = e.x;
        }
    }
    return Nearest(d, leaf);
}
"""

    def sub(old, new, count=1):
        nonlocal wgsl
        if wgsl.count(old) != count:
            sys.exit(f"expected {count} of {old!r} in the shader")
        wgsl = wgsl.replace(old, new)

    # The shader's own per-ray lists (`shaders/instances_rays.wgsl`) give way to the tile's.
    sub("fn scene_distance(p: vec3<f32>) -> f32 {", part + "\nfn scene_distance(p: vec3<f32>) -> f32 {")
    sub("    ray_start(ro, rd, span.x, span.y, pixel);\n", "")
    sub(
        "            let d = march_distance(ro + rd * t, t);\n",
        "            let d = tile_distance(ro + rd * t, t, 4.0 * surface_epsilon(t, pixel) + 1e-4);\n",
    )
    sub(
        "        d = march_distance(ro + rd * t, t);\n",
        "        d = tile_distance(ro + rd * t, t, 4.0 * eps + 1e-4);\n",
    )
    sub(
        "    load_frame();\n",
        f"    load_frame();\n    let tile = scene_data[{table}u + (gid.y / {TILE_H}u) * TILES_X + gid.x / {TILE_W}u];\n"
        "    tile_first = tile.x;\n    tile_count = tile.y;\n    tile_k0 = tile.x;\n    tile_t0 = -3.0e38;\n",
    )
    if os.environ.get("SDFC_TILE_SHADING") == "1":
        sub(
            "        n = n + k[i] * normal_distance(p + k[i] * h);\n",
            "        n = n + k[i] * tile_nearest(p + k[i] * h).distance;\n",
        )
        sub(
            "    let leaf = ray_nearest(p, 3.0e38).leaf;\n",
            "    let leaf = tile_nearest(p).leaf;\n",
        )
        sub(
            "    ray_hit = hit.t;\n",
            "    ray_hit = hit.t;\n    tile_t = hit.t;\n"
            "    tile_m = 4.0 * surface_epsilon(hit.t, pixel) + 1e-4;\n",
        )
    else:
        # The walk for the normal and the material, as before the shader's own lists.
        sub(
            "        n = n + k[i] * normal_distance(p + k[i] * h);\n",
            "        n = n + k[i] * scene_distance(p + k[i] * h);\n",
        )
        sub(
            "    let leaf = ray_nearest(p, 3.0e38).leaf;\n",
            "    let leaf = scene_nearest(p, 3.0e38).leaf;\n",
        )
    open(sys.argv[4], "w").write(wgsl)


if __name__ == "__main__":
    main()
