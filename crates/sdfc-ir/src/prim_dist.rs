//! The distance formulas of the primitives added after the first seven, in f64, spelled
//! as `shaders/prims/*.wgsl` spell them (same branches, same order of operations where it
//! matters). The evaluator calls them for every float type: a helper's point is never a
//! constant, so these never take part in f32 constant folding.

type V3 = [f64; 3];

fn len2(x: f64, y: f64) -> f64 {
    (x * x + y * y).sqrt()
}

fn len3(v: V3) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Exact distance of the box with half extents 0 at the origin shifted: iq's box formula on
/// an already folded offset vector `q = |p| - b`.
fn box_of_offset(q: V3) -> f64 {
    let outside = len3(q.map(|x| x.max(0.0)));
    outside + q[0].max(q[1]).max(q[2]).min(0.0)
}

/// Distance from `(x, y)` to the segment `a`-`b` in 2D (a zero-length segment is a point).
fn segment(x: f64, y: f64, a: [f64; 2], b: [f64; 2]) -> f64 {
    let (px, py) = (x - a[0], y - a[1]);
    let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
    let t = ((px * ex + py * ey) / (ex * ex + ey * ey).max(1e-30)).clamp(0.0, 1.0);
    len2(px - ex * t, py - ey * t)
}

/// The edges of a box of half extents `b`, bars of square cross-section `w`, flush with
/// its faces. Outside: the nearest of the three bar families (after folding, one bar each).
/// Inside, the bars overlap at the corners, where the nearest bar's depth underestimates:
/// the depth is the distance to the complement, whose pieces are the outside of the box and
/// three tunnels (two coordinates deeper than `w` below the faces).
pub fn box_frame(p: V3, b: V3, w: f64) -> f64 {
    let q = [0, 1, 2].map(|i| p[i].abs() - b[i]);
    let e = 0.5 * w;
    let r = q.map(|x| (x + e).abs() - e);
    let d = box_of_offset([q[0], r[1], r[2]])
        .min(box_of_offset([r[0], q[1], r[2]]))
        .min(box_of_offset([r[0], r[1], q[2]]));
    if d >= 0.0 {
        return d;
    }
    let m = q.map(|x| (w + x).max(0.0));
    let to_face = (-q[0]).min(-q[1]).min(-q[2]);
    let tunnel = len2(m[0], m[1]).min(len2(m[1], m[2])).min(len2(m[2], m[0]));
    -to_face.min(tunnel)
}

/// Torus arc in the xy plane: major radius `ra`, tube `rb`, the angles within the
/// half-angle (sine `s`, cosine `c`) of +y. Within the arc the nearest point of the centre
/// circle is the one above the point; beyond the arc's end it is the end point `ra (s, c)`.
/// (Written as two lengths rather than iq's `sqrt(|p|^2 + ra^2 - 2 ra k)`, which cancels
/// badly in f32 near the centre circle.)
pub fn capped_torus(p: V3, s: f64, c: f64, ra: f64, rb: f64) -> f64 {
    let x = p[0].abs();
    let d = if c * x > s * p[1] {
        len3([x - ra * s, p[1] - ra * c, p[2]])
    } else {
        len2(len2(x, p[1]) - ra, p[2])
    };
    d - rb
}

/// Frustum along y from `-h` (radius `r1`) to `h` (radius `r2`): in the half-plane
/// (radius, y) the distance to the trapezoid's bottom, top and slanted edges, negative inside.
pub fn capped_cone(p: V3, h: f64, r1: f64, r2: f64) -> f64 {
    let x = len2(p[0], p[2]);
    let y = p[1];
    let bottom = len2((x - r1).max(0.0), y + h);
    let top = len2((x - r2).max(0.0), y - h);
    let side = segment(x, y, [r1, -h], [r2, h]);
    let d = bottom.min(top).min(side);
    let inside = y.abs() <= h && x * (2.0 * h) <= r1 * (h - y) + r2 * (h + y);
    if inside {
        -d
    } else {
        d
    }
}

/// A lower bound of the distance to the ellipsoid with semi-axes `r`: the larger of two
/// 1-Lipschitz functions that are negative exactly inside, `(|p / r| - 1) min(r)` and
/// `|p| - max(r)` (the bounding sphere; it only helps outside).
pub fn ellipsoid(p: V3, r: V3) -> f64 {
    let r = r.map(|x| x.max(1e-6));
    let k = len3([p[0] / r[0], p[1] / r[1], p[2] / r[2]]);
    let d1 = (k - 1.0) * r[0].min(r[1]).min(r[2]);
    let d2 = len3(p) - r[0].max(r[1]).max(r[2]);
    d1.max(d2)
}

/// The octahedron `|x| + |y| + |z| <= s`. Inside, the depth below the face plane; outside,
/// the distance to the face triangle's interior (plane distance), or to the edge across
/// which the point's projection leaves the triangle.
pub fn octahedron(p: V3, s: f64) -> f64 {
    let a = p.map(f64::abs);
    let m = a[0] + a[1] + a[2] - s;
    let q = if 3.0 * a[0] < m {
        a
    } else if 3.0 * a[1] < m {
        [a[1], a[2], a[0]]
    } else if 3.0 * a[2] < m {
        [a[2], a[0], a[1]]
    } else {
        return m * (1.0 / 3f64.sqrt());
    };
    let k = (0.5 * (q[2] - q[1] + s)).clamp(0.0, s);
    len3([q[0], q[1] - s + k, q[2] - k])
}

/// Combines a 2D signed distance in the cross-section with the distance along the axis
/// (`|z| - half_length`): exact for a prism.
fn extrude(d2: f64, dz: f64) -> f64 {
    d2.max(dz).min(0.0) + len2(d2.max(0.0), dz.max(0.0))
}

/// Hexagonal prism along z: inradius `r` (flat faces at y = +-r), half length `h`.
pub fn hex_prism(p: V3, r: f64, h: f64) -> f64 {
    let (nx, ny) = (-0.5 * 3f64.sqrt(), 0.5);
    let (mut x, mut y) = (p[0].abs(), p[1].abs());
    // Reflect the 0-60 degree wedge onto the 60-120 one, whose nearest side is the top one.
    let t = (nx * x + ny * y).min(0.0);
    x -= 2.0 * t * nx;
    y -= 2.0 * t * ny;
    let half_side = r / 3f64.sqrt();
    let d = len2(x - x.clamp(-half_side, half_side), y - r);
    let d2 = if y < r { -d } else { d };
    extrude(d2, p[2].abs() - h)
}

/// Triangular prism along z: an equilateral triangle of inradius `r` pointing to +y with
/// its centroid on the axis (vertices (0, 2r) and (+-sqrt(3) r, -r)), half length `h`.
pub fn tri_prism(p: V3, r: f64, h: f64) -> f64 {
    let x = p[0].abs();
    let y = p[1];
    let c = 3f64.sqrt() * r;
    let bottom = len2((x - c).max(0.0), y + r);
    let side = segment(x, y, [c, -r], [0.0, 2.0 * r]);
    let d = bottom.min(side);
    let inside = y >= -r && 0.5 * 3f64.sqrt() * x + 0.5 * y <= r;
    extrude(if inside { -d } else { d }, p[2].abs() - h)
}

/// Pyramid with the base [-0.5, 0.5]^2 on y = 0 and apex (0, h, 0). Folded so that
/// x >= z >= 0, the nearest faces are the base and the +x side. Outside: the nearer of the
/// two face polygons (the side face measured in its own plane coordinates). Inside: the
/// depth below the nearer of the base and that face's plane.
pub fn pyramid(p: V3, h: f64) -> f64 {
    let (mut x, mut z) = (p[0].abs(), p[2].abs());
    if z > x {
        std::mem::swap(&mut x, &mut z);
    }
    let y = p[1];
    let sv = (0.25 + h * h).sqrt();
    // Plane coordinates of the +x face: u along its base edge, v up the face, w its normal.
    let u = z;
    let v = (-0.5 * (x - 0.5) + h * y) / sv;
    let w = (h * (x - 0.5) + 0.5 * y) / sv;
    if y >= 0.0 && w <= 0.0 {
        return -y.min(-w);
    }
    let base = len3([(x - 0.5).max(0.0), y, (z - 0.5).max(0.0)]);
    let in_face = v >= 0.0 && u * sv + 0.5 * v <= 0.5 * sv;
    let t = if in_face {
        0.0
    } else {
        len2((u - 0.5).max(0.0), v).min(segment(u, v, [0.5, 0.0], [0.0, sv]))
    };
    base.min(len2(t, w))
}

/// Mandelbulb of power `n` (pole along y), `iters` iterations, bailout radius 2: the
/// estimate `0.5 r ln r / dr`. The set lies within radius `bound`; beyond `1.25 bound` the
/// distance to that sphere is returned without iterating. (Not beyond `bound` itself: the
/// sphere's distance is 0 on the sphere, and the marcher would stop there, on the sphere.)
pub fn mandelbulb(p: V3, n: f64, iters: f64, bound: f64) -> f64 {
    let lp = len3(p);
    if lp > 1.25 * bound {
        return lp - bound;
    }
    let mut z = p;
    let mut dr = 1.0;
    let mut r = lp;
    let mut i = 0.0;
    while i < iters && r <= 2.0 {
        let rs = r.max(1e-20);
        let theta = (z[1] / rs).clamp(-1.0, 1.0).acos() * n;
        let phi = z[2].atan2(z[0]) * n;
        dr = n * rs.powf(n - 1.0) * dr + 1.0;
        let zr = rs.powf(n);
        z = [
            zr * theta.sin() * phi.cos() + p[0],
            zr * theta.cos() + p[1],
            zr * theta.sin() * phi.sin() + p[2],
        ];
        r = len3(z);
        i += 1.0;
    }
    let r = r.max(1e-20);
    0.5 * r.ln() * r / dr
}

/// The mandelbulb of a whole power `n`, as `shaders/prims/sd_mandelbulb_int.wgsl` computes
/// it: the same estimate as [`mandelbulb`], with the angles' multiples and `r^n` raised by
/// repeated squaring of complex numbers instead of trigonometry.
pub fn mandelbulb_int(p: V3, n: u32, iters: f64, bound: f64) -> f64 {
    let lp = len3(p);
    if lp > 1.25 * bound {
        return lp - bound;
    }
    let cmul = |a: [f64; 2], b: [f64; 2]| [a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0]];
    let mut z = p;
    let mut dr = 1.0;
    let mut r = lp;
    let mut i = 0.0;
    while i < iters && r <= 2.0 {
        let rs = r.max(1e-20);
        let rho = len2(z[0], z[2]);
        let mut theta = [(z[1] / rs).clamp(-1.0, 1.0), rho / rs];
        let mut phi = if rho > 0.0 {
            [z[0] / rho, z[2] / rho]
        } else {
            [1.0, 0.0]
        };
        let mut radius = rs;
        let (mut theta_n, mut phi_n, mut radius_n) = ([1.0, 0.0], [1.0, 0.0], 1.0);
        let mut e = n;
        while e > 0 {
            if e & 1 == 1 {
                theta_n = cmul(theta_n, theta);
                phi_n = cmul(phi_n, phi);
                radius_n *= radius;
            }
            theta = cmul(theta, theta);
            phi = cmul(phi, phi);
            radius *= radius;
            e >>= 1;
        }
        dr = n as f64 * (radius_n / rs) * dr + 1.0;
        z = [
            radius_n * theta_n[1] * phi_n[0] + p[0],
            radius_n * theta_n[0] + p[1],
            radius_n * theta_n[1] * phi_n[1] + p[2],
        ];
        r = len3(z);
        i += 1.0;
    }
    let r = r.max(1e-20);
    0.5 * r.ln() * r / dr
}

/// Menger sponge in [-0.5, 0.5]^3 (worked in the doubled frame [-1, 1]^3): the box, minus
/// at each level the cross of square bars of half width 1/3 in every cell, folded into the
/// cell by a mirrored repetition. The max of exact distances: a bound with the exact sign.
pub fn menger(p: V3, iters: f64) -> f64 {
    let q = p.map(|x| 2.0 * x);
    let mut d = box_of_offset(q.map(|x| x.abs() - 1.0));
    let mut s = 1.0;
    let mut i = 0.0;
    while i < iters {
        let a = q.map(|x| {
            let t = x * s + 1.0;
            (t - 2.0 * (t * 0.5).floor() - 1.0).abs()
        });
        let third = 1.0 / 3.0;
        let bar = |u: f64, v: f64| {
            let (bu, bv) = (u - third, v - third);
            len2(bu.max(0.0), bv.max(0.0)) + bu.max(bv).min(0.0)
        };
        let cross = bar(a[0], a[1]).min(bar(a[1], a[2])).min(bar(a[2], a[0]));
        d = d.max(-cross / s);
        s *= 3.0;
        i += 1.0;
    }
    0.5 * d
}

/// Sierpinski tetrahedron on alternate corners of [-0.5, 0.5]^3 (doubled frame: vertices
/// (1,1,1), (-1,-1,1), (-1,1,-1), (1,-1,-1)). Each level moves to the half-size copy at the
/// vertex nearest the point (the copies are mirror images across the planes between them,
/// so that copy is the nearest); at the end the tetrahedron's face planes bound the distance.
pub fn sierpinski(p: V3, iters: f64) -> f64 {
    let mut z = p.map(|x| 2.0 * x);
    let mut scale = 2.0;
    let mut i = 0.0;
    while i < iters {
        let dots = [
            z[0] + z[1] + z[2],
            -z[0] - z[1] + z[2],
            -z[0] + z[1] - z[2],
            z[0] - z[1] - z[2],
        ];
        let mut v = [1.0, 1.0, 1.0];
        let mut best = dots[0];
        if dots[1] > best {
            best = dots[1];
            v = [-1.0, -1.0, 1.0];
        }
        if dots[2] > best {
            best = dots[2];
            v = [-1.0, 1.0, -1.0];
        }
        if dots[3] > best {
            v = [1.0, -1.0, -1.0];
        }
        z = [0, 1, 2].map(|k| 2.0 * z[k] - v[k]);
        scale *= 2.0;
        i += 1.0;
    }
    let planes = (-z[0] - z[1] - z[2])
        .max(z[0] + z[1] - z[2])
        .max(z[0] - z[1] + z[2])
        .max(-z[0] + z[1] + z[2]);
    (planes - 1.0) / 3f64.sqrt() / scale
}
