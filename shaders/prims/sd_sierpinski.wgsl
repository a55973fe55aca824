// Sierpinski tetrahedron on alternate corners of [-0.5, 0.5]^3 (doubled frame: vertices
// (1,1,1), (-1,-1,1), (-1,1,-1), (1,-1,-1)). Each level moves to the half-size copy at the
// vertex nearest the point (the copies mirror each other across the planes between them, so
// that copy is the nearest); at the end the face planes bound the distance (exact sign).
fn sd_sierpinski(p: vec3<f32>, iterations: f32) -> f32 {
    var o = SierpinskiLevel(2.0 * p, 2.0);
    let count = u32(iterations);
    for (var i = 0u; i < count; i = i + 1u) {
        o = sierpinski_step(o);
    }
    return sierpinski_estimate(o);
}

// The point between levels (doubled frame) and the level's scale.
struct SierpinskiLevel {
    z: vec3<f32>,
    scale: f32,
}

// One level: a function of its own, so that the interpreter can run one per trip of its
// loop (see sd_mandelbulb).
fn sierpinski_step(o: SierpinskiLevel) -> SierpinskiLevel {
    let z = o.z;
    var v = vec3<f32>(1.0, 1.0, 1.0);
    var best = z.x + z.y + z.z;
    let d1 = -z.x - z.y + z.z;
    if d1 > best {
        best = d1;
        v = vec3<f32>(-1.0, -1.0, 1.0);
    }
    let d2 = -z.x + z.y - z.z;
    if d2 > best {
        best = d2;
        v = vec3<f32>(-1.0, 1.0, -1.0);
    }
    let d3 = z.x - z.y - z.z;
    if d3 > best {
        v = vec3<f32>(1.0, -1.0, -1.0);
    }
    return SierpinskiLevel(2.0 * z - v, o.scale * 2.0);
}

fn sierpinski_estimate(o: SierpinskiLevel) -> f32 {
    let z = o.z;
    let planes = max(max(-z.x - z.y - z.z, z.x + z.y - z.z), max(z.x - z.y + z.z, -z.x + z.y + z.z));
    return (planes - 1.0) * 0.57735026918962576 / o.scale;
}
