#!/usr/bin/env python3
"""Rewrites the emitted WGSL of a generated grid scene (`sdfc_tests::grid_scene`) so that its
union is three `var<private>` tables of shape parameters walked by loops, instead of one
block of code per shape: the experiment behind "Large unions as tables" in
docs/performance.md. Not part of the compiler (only `sdfc-wgsl` spells the product's WGSL);
it knows only the grid's three kinds of shape and fails loudly on anything else.

    scripts/table-experiment.py GRID.wgsl OUT.wgsl
"""
import re
import sys

# A shape's point: `p - vec3<f32>(centre)`, or `p` for a shape at the origin.
POINT = r"(?:p - vec3<f32>\(([^)]*)\)|p)"
SPHERE = re.compile(r"\s*let d\d+ = sd_sphere\(" + POINT + r", ([^)]*)\);$")
BOX = re.compile(
    r"\s*let d\d+ = sd_box\(rotate_y\(" + POINT + r", ([^,]*), ([^)]*)\), "
    r"vec3<f32>\(([^)]*)\)\);$"
)
TORUS = re.compile(
    r"\s*let d\d+ = sd_torus\(rotate_x\(" + POINT + r", ([^,]*), ([^)]*)\), "
    r"([^,]*), ([^)]*)\);$"
)
FIRST_GROUP = "// The distance (and, when asked, the material) of one group"
AFTER_SCENE = "// Camera (spec section 8)"

SCENE = """
// The scene's shapes as tables: a sphere is (centre, radius); a box (centre, cos) then
// (sin, half size); a torus (centre, cos) then (sin, R, r, 0).
struct Nearest {
    distance: f32,
    kind: u32,
}

fn scene_nearest(p: vec3<f32>, with_kind: bool) -> Nearest {
    var d = 3.0e38;
    var kind = 0u;
    for (var i = 0u; i < {spheres}u; i++) {
        let e = SPHERES[i];
        let di = sd_sphere(p - e.xyz, e.w);
        if with_kind && di < d { kind = 0u; }
        d = min(d, di);
    }
    for (var i = 0u; i < {boxes}u; i++) {
        let a = BOXES[2u * i];
        let b = BOXES[2u * i + 1u];
        let di = sd_box(rotate_y(p - a.xyz, a.w, b.x), b.yzw);
        if with_kind && di < d { kind = 1u; }
        d = min(d, di);
    }
    for (var i = 0u; i < {tori}u; i++) {
        let a = TORI[2u * i];
        let b = TORI[2u * i + 1u];
        let di = sd_torus(rotate_x(p - a.xyz, a.w, b.x), b.y, b.z);
        if with_kind && di < d { kind = 2u; }
        d = min(d, di);
    }
    return Nearest(d, kind);
}

// The signed distance from p to the scene.
fn scene_distance(p: vec3<f32>) -> f32 {
    return scene_nearest(p, false).distance;
}

// The grid's materials: spheres red, boxes green, tori blue.
fn scene_material(p: vec3<f32>) -> SceneMaterial {
    let k = scene_nearest(p, true).kind;
    let albedo = select(select(MATERIAL_BLUE_ALBEDO, MATERIAL_GREEN_ALBEDO, k == 1u), MATERIAL_RED_ALBEDO, k == 0u);
    let phong = select(MATERIAL_DEFAULT_PHONG, MATERIAL_GREEN_PHONG, k == 1u);
    return SceneMaterial(albedo, phong);
}

"""


def centre(m):
    return m[1] or "0.0, 0.0, 0.0"


def table(name, rows):
    body = "".join(f"    {row},\n" for row in rows)
    count = sum(row.count("vec4<f32>(") for row in rows)
    return f"var<private> {name}: array<vec4<f32>, {count}> = array<vec4<f32>, {count}>(\n{body});\n"


def main(src_path, out_path):
    src = open(src_path).read()
    start, end = src.index(FIRST_GROUP), src.index(AFTER_SCENE)
    spheres, boxes, tori, lets = [], [], [], 0
    for line in src[start:end].splitlines():
        if re.match(r"\s*let d\d+ = sd_", line):
            lets += 1
        if m := SPHERE.match(line):
            spheres.append(f"vec4<f32>({centre(m)}, {m[2]})")
        elif m := BOX.match(line):
            half = m[4].split(", ")
            half = half * 3 if len(half) == 1 else half
            boxes.append(f"vec4<f32>({centre(m)}, {m[2]}), vec4<f32>({m[3]}, {', '.join(half)})")
        elif m := TORUS.match(line):
            tori.append(f"vec4<f32>({centre(m)}, {m[2]}), vec4<f32>({m[3]}, {m[4]}, {m[5]}, 0.0)")
    found = len(spheres) + len(boxes) + len(tori)
    if found != lets or found == 0:
        sys.exit(f"{src_path}: {lets} shapes, {found} of them of the grid's three kinds")
    scene = (
        SCENE.replace("{spheres}", str(len(spheres)))
        .replace("{boxes}", str(len(boxes)))
        .replace("{tori}", str(len(tori)))
    )
    tables = table("SPHERES", spheres) + table("BOXES", boxes) + table("TORI", tori)
    open(out_path, "w").write(src[:start] + tables + scene + src[end:])
    print(f"{out_path}: {len(spheres)} spheres, {len(boxes)} boxes, {len(tori)} tori")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
