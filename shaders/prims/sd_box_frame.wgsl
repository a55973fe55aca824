// The edges of a box of half extents b: square bars of side w flush with its faces (exact).
// Outside, the nearest of the three bar families; inside, where the bars overlap at the
// corners, the depth is the distance to the complement: the box's outside or one of the
// three tunnels (two coordinates deeper than w below the faces).
fn sd_box_frame_bar(q: vec3<f32>) -> f32 {
    return length(max(q, vec3<f32>(0.0))) + min(max(q.x, max(q.y, q.z)), 0.0);
}

fn sd_box_frame(p: vec3<f32>, b: vec3<f32>, w: f32) -> f32 {
    let q = abs(p) - b;
    let e = 0.5 * w;
    let r = abs(q + vec3<f32>(e)) - vec3<f32>(e);
    let d = min(min(sd_box_frame_bar(vec3<f32>(q.x, r.y, r.z)), sd_box_frame_bar(vec3<f32>(r.x, q.y, r.z))), sd_box_frame_bar(vec3<f32>(r.x, r.y, q.z)));
    if d >= 0.0 {
        return d;
    }
    let m = max(q + vec3<f32>(w), vec3<f32>(0.0));
    let to_face = min(-q.x, min(-q.y, -q.z));
    let tunnel = min(min(length(m.xy), length(m.yz)), length(m.zx));
    return -min(to_face, tunnel);
}
