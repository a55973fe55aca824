//! The distance helpers' formulas in generic operations, as `shaders/prims/*.wgsl` spell
//! them, so that their derivatives follow from the rules (the value stays the helper call).
//! Branches become selects and the fractals' fixed loops are unrolled (an iteration past the
//! mandelbulb's escape keeps the orbit). Noise, an integer hash, has a gradient helper of its
//! own instead (`shaders/noise_gradient.wgsl`).

use super::Differ;
use crate::graph::NodeId;
use crate::ops::{Builtin, Helper, Op, Swizzle};
use crate::types::Ty;

impl Differ {
    fn n(&mut self, op: Op, a: &[NodeId]) -> NodeId {
        self.node(op, a)
    }

    fn b(&mut self, b: Builtin, a: &[NodeId]) -> NodeId {
        self.node(Op::Builtin(b), a)
    }

    fn f(&mut self, x: f32) -> NodeId {
        self.g.f32(x)
    }

    fn sw(&mut self, x: NodeId, idx: &[u8]) -> NodeId {
        self.node(Op::Swizzle(Swizzle::new(idx)), &[x])
    }

    /// `x.x`, `x.y`, `x.z`.
    fn c(&mut self, x: NodeId, i: u8) -> NodeId {
        self.sw(x, &[i])
    }

    fn vec(&mut self, comps: &[NodeId]) -> NodeId {
        self.node(Op::MakeVec, comps)
    }

    fn max3(&mut self, q: NodeId) -> NodeId {
        let (x, y, z) = (self.c(q, 0), self.c(q, 1), self.c(q, 2));
        let m = self.b(Builtin::Max, &[y, z]);
        self.b(Builtin::Max, &[x, m])
    }

    fn min3(&mut self, q: NodeId) -> NodeId {
        let (x, y, z) = (self.c(q, 0), self.c(q, 1), self.c(q, 2));
        let m = self.b(Builtin::Min, &[y, z]);
        self.b(Builtin::Min, &[x, m])
    }

    /// iq's box on the offset `q = |p| - b`: `length(max(q, 0)) + min(max3(q), 0)`.
    fn box_of_offset(&mut self, q: NodeId) -> NodeId {
        let ty = self.g.ty(q);
        let z = self.zero(ty);
        let out = self.b(Builtin::Max, &[q, z]);
        let out = self.b(Builtin::Length, &[out]);
        let inner = if ty == Ty::Vec2 {
            let (x, y) = (self.c(q, 0), self.c(q, 1));
            self.b(Builtin::Max, &[x, y])
        } else {
            self.max3(q)
        };
        let z1 = self.f(0.0);
        let inner = self.b(Builtin::Min, &[inner, z1]);
        self.n(Op::Add, &[out, inner])
    }

    /// A 2D cross-section distance `d2` extruded along z by `|z| - h` (the prisms).
    fn extrude(&mut self, d2: NodeId, p: NodeId, h: NodeId) -> NodeId {
        let z = self.c(p, 2);
        let az = self.b(Builtin::Abs, &[z]);
        let dz = self.n(Op::Sub, &[az, h]);
        let v = self.vec(&[d2, dz]);
        self.box_of_offset(v)
    }

    /// The distance from the segment from 0 to `e` of a point at `pa` from its start:
    /// `length(pa - e clamp(dot(pa, e) / max(dot(e, e), 1e-30), 0, 1))`.
    fn segment(&mut self, pa: NodeId, e: NodeId) -> NodeId {
        let num = self.b(Builtin::Dot, &[pa, e]);
        let den = self.b(Builtin::Dot, &[e, e]);
        let tiny = self.f(1e-30);
        let den = self.b(Builtin::Max, &[den, tiny]);
        let t = self.n(Op::Div, &[num, den]);
        let (zero, one) = (self.f(0.0), self.f(1.0));
        let t = self.b(Builtin::Clamp, &[t, zero, one]);
        let et = self.n(Op::Mul, &[e, t]);
        let v = self.n(Op::Sub, &[pa, et]);
        self.b(Builtin::Length, &[v])
    }

    /// `select(d, -d, cond)`.
    fn negate_if(&mut self, d: NodeId, cond: NodeId) -> NodeId {
        let nd = self.n(Op::Neg, &[d]);
        self.n(Op::Select, &[d, nd, cond])
    }

    /// The helper's distance in generic operations, or `None` for those differenced.
    pub(super) fn helper_expansion(&mut self, h: Helper, a: &[NodeId]) -> Option<NodeId> {
        let p = a[0];
        Some(match h {
            Helper::SdSphere => {
                let l = self.b(Builtin::Length, &[p]);
                self.n(Op::Sub, &[l, a[1]])
            }
            Helper::SdBox | Helper::SdRoundBox => {
                let ap = self.b(Builtin::Abs, &[p]);
                let q = self.n(Op::Sub, &[ap, a[1]]);
                let d = self.box_of_offset(q);
                if h == Helper::SdRoundBox {
                    self.n(Op::Sub, &[d, a[2]])
                } else {
                    d
                }
            }
            Helper::SdTorus => {
                let xz = self.sw(p, &[0, 2]);
                let l = self.b(Builtin::Length, &[xz]);
                let x = self.n(Op::Sub, &[l, a[1]]);
                let y = self.c(p, 1);
                let q = self.vec(&[x, y]);
                let l = self.b(Builtin::Length, &[q]);
                self.n(Op::Sub, &[l, a[2]])
            }
            Helper::SdCylinder => {
                let xz = self.sw(p, &[0, 2]);
                let l = self.b(Builtin::Length, &[xz]);
                let x = self.n(Op::Sub, &[l, a[1]]);
                let y = self.c(p, 1);
                let ay = self.b(Builtin::Abs, &[y]);
                let y = self.n(Op::Sub, &[ay, a[2]]);
                let d = self.vec(&[x, y]);
                self.box_of_offset(d)
            }
            Helper::SdCapsule => {
                let pa = self.n(Op::Sub, &[p, a[1]]);
                let ba = self.n(Op::Sub, &[a[2], a[1]]);
                let l = self.segment(pa, ba);
                self.n(Op::Sub, &[l, a[3]])
            }
            Helper::SdEllipsoid => {
                let lo = self.g.vec3([1e-6; 3]);
                let r = self.b(Builtin::Max, &[a[1], lo]);
                let pr = self.n(Op::Div, &[p, r]);
                let k = self.b(Builtin::Length, &[pr]);
                let one = self.f(1.0);
                let k = self.n(Op::Sub, &[k, one]);
                let rmin = self.min3(r);
                let d1 = self.n(Op::Mul, &[k, rmin]);
                let l = self.b(Builtin::Length, &[p]);
                let rmax = self.max3(r);
                let d2 = self.n(Op::Sub, &[l, rmax]);
                self.b(Builtin::Max, &[d1, d2])
            }
            Helper::SdOctahedron => {
                let s = a[1];
                let av = self.b(Builtin::Abs, &[p]);
                let (ax, ay, az) = (self.c(av, 0), self.c(av, 1), self.c(av, 2));
                let sum = self.n(Op::Add, &[ax, ay]);
                let sum = self.n(Op::Add, &[sum, az]);
                let m = self.n(Op::Sub, &[sum, s]);
                let k = self.f(0.577_350_26);
                let face = self.n(Op::Mul, &[m, k]);
                let three = self.f(3.0);
                let mut d = face;
                // The branches of the WGSL, innermost (z) first.
                for (axis, order) in [(2u8, [2u8, 0, 1]), (1, [1, 2, 0]), (0, [0, 1, 2])] {
                    let c = self.c(av, axis);
                    let c3 = self.n(Op::Mul, &[three, c]);
                    let cond = self.n(Op::Lt, &[c3, m]);
                    let q = self.sw(av, &order);
                    let edge = self.octahedron_edge(q, s);
                    d = self.n(Op::Select, &[d, edge, cond]);
                }
                d
            }
            Helper::SdHexPrism => {
                let (r, hh) = (a[1], a[2]);
                let nv = self.value(crate::value::Value::V2([-0.866_025_4, 0.5]));
                let xy = self.sw(p, &[0, 1]);
                let q = self.b(Builtin::Abs, &[xy]);
                let dn = self.b(Builtin::Dot, &[nv, q]);
                let z = self.f(0.0);
                let dn = self.b(Builtin::Min, &[dn, z]);
                let two = self.f(2.0);
                let dn = self.n(Op::Mul, &[two, dn]);
                let off = self.n(Op::Mul, &[dn, nv]);
                let q = self.n(Op::Sub, &[q, off]);
                let k = self.f(0.577_350_26);
                let hs = self.n(Op::Mul, &[r, k]);
                let nhs = self.n(Op::Neg, &[hs]);
                let (qx, qy) = (self.c(q, 0), self.c(q, 1));
                let cx = self.b(Builtin::Clamp, &[qx, nhs, hs]);
                let x = self.n(Op::Sub, &[qx, cx]);
                let y = self.n(Op::Sub, &[qy, r]);
                let v = self.vec(&[x, y]);
                let d2 = self.b(Builtin::Length, &[v]);
                let inside = self.n(Op::Lt, &[qy, r]);
                let d2 = self.negate_if(d2, inside);
                self.extrude(d2, p, hh)
            }
            Helper::SdTriPrism => {
                let (r, hh) = (a[1], a[2]);
                let px = self.c(p, 0);
                let x = self.b(Builtin::Abs, &[px]);
                let y = self.c(p, 1);
                let k = self.f(1.732_050_8);
                let c = self.n(Op::Mul, &[k, r]);
                let xc = self.n(Op::Sub, &[x, c]);
                let z = self.f(0.0);
                let bx = self.b(Builtin::Max, &[xc, z]);
                let yr = self.n(Op::Add, &[y, r]);
                let bv = self.vec(&[bx, yr]);
                let bottom = self.b(Builtin::Length, &[bv]);
                let pa = self.vec(&[xc, yr]);
                let nc = self.n(Op::Neg, &[c]);
                let three = self.f(3.0);
                let r3 = self.n(Op::Mul, &[three, r]);
                let e = self.vec(&[nc, r3]);
                let side = self.segment(pa, e);
                let d2 = self.b(Builtin::Min, &[bottom, side]);
                // Inside: y >= -r and 0.866 x + 0.5 y <= r (both, as nested selects).
                let nr = self.n(Op::Neg, &[r]);
                let above = self.n(Op::Ge, &[y, nr]);
                let (kx, ky) = (self.f(0.866_025_4), self.f(0.5));
                let sx = self.n(Op::Mul, &[kx, x]);
                let sy = self.n(Op::Mul, &[ky, y]);
                let s = self.n(Op::Add, &[sx, sy]);
                let below = self.n(Op::Le, &[s, r]);
                let nd = self.n(Op::Neg, &[d2]);
                let inner = self.n(Op::Select, &[d2, nd, below]);
                let d2 = self.n(Op::Select, &[d2, inner, above]);
                self.extrude(d2, p, hh)
            }
            Helper::SdBoxFrame => self.box_frame(p, a[1], a[2]),
            Helper::SdCappedTorus => {
                let (sc, ra, rb) = (a[1], a[2], a[3]);
                let px = self.c(p, 0);
                let ax = self.b(Builtin::Abs, &[px]);
                let (y, z) = (self.c(p, 1), self.c(p, 2));
                let q = self.vec(&[ax, y, z]);
                let (s, c) = (self.c(sc, 0), self.c(sc, 1));
                let cx = self.n(Op::Mul, &[c, ax]);
                let sy = self.n(Op::Mul, &[s, y]);
                let beyond = self.n(Op::Gt, &[cx, sy]);
                let (rs, rc) = (self.n(Op::Mul, &[ra, s]), self.n(Op::Mul, &[ra, c]));
                let zero = self.f(0.0);
                let end = self.vec(&[rs, rc, zero]);
                let to_end = self.n(Op::Sub, &[q, end]);
                let to_end = self.b(Builtin::Length, &[to_end]);
                let xy = self.sw(q, &[0, 1]);
                let l = self.b(Builtin::Length, &[xy]);
                let l = self.n(Op::Sub, &[l, ra]);
                let v = self.vec(&[l, z]);
                let ring = self.b(Builtin::Length, &[v]);
                let d = self.n(Op::Select, &[ring, to_end, beyond]);
                self.n(Op::Sub, &[d, rb])
            }
            Helper::SdCappedCone => self.capped_cone(p, a[1], a[2], a[3]),
            Helper::SdPyramid => self.pyramid(p, a[1]),
            Helper::SdMenger => {
                let n = self.iterations(a[1])?;
                self.menger(p, n)
            }
            Helper::SdSierpinski => {
                let n = self.iterations(a[1])?;
                self.sierpinski(p, n)
            }
            Helper::SdMandelbulb => {
                let n = self.iterations(a[2])?;
                self.mandelbulb(p, a[1], n, a[3])
            }
            Helper::SdMandelbulbInt => {
                let n = self.iterations(a[2])?;
                let power = self.g.as_scalar_const(a[1])?;
                self.mandelbulb_int(p, a[1], power as u32, n, a[3])?
            }
            // Noise has its gradient helper; rotations and that helper have rules (`rules.rs`).
            Helper::Noise
            | Helper::NoiseGradient
            | Helper::RotateX
            | Helper::RotateY
            | Helper::RotateZ => return None,
        })
    }

    /// A fractal's constant iteration count (the compiler checks its range), at most 64.
    fn iterations(&self, x: NodeId) -> Option<u32> {
        let n = self.g.as_scalar_const(x)?;
        (0.0..=64.0).contains(&n).then_some(n as u32)
    }

    /// `select(a, b, c1 && c2)`.
    fn select_both(&mut self, a: NodeId, b: NodeId, c1: NodeId, c2: NodeId) -> NodeId {
        let inner = self.n(Op::Select, &[a, b, c2]);
        self.n(Op::Select, &[a, inner, c1])
    }

    fn box_frame(&mut self, p: NodeId, b: NodeId, w: NodeId) -> NodeId {
        let ap = self.b(Builtin::Abs, &[p]);
        let q = self.n(Op::Sub, &[ap, b]);
        let half = self.f(0.5);
        let e = self.n(Op::Mul, &[half, w]);
        let qe = self.n(Op::Add, &[q, e]);
        let r = self.b(Builtin::Abs, &[qe]);
        let r = self.n(Op::Sub, &[r, e]);
        let (qx, qy, qz) = (self.c(q, 0), self.c(q, 1), self.c(q, 2));
        let (rx, ry, rz) = (self.c(r, 0), self.c(r, 1), self.c(r, 2));
        let bars: Vec<NodeId> = [[qx, ry, rz], [rx, qy, rz], [rx, ry, qz]]
            .iter()
            .map(|c| {
                let v = self.vec(c);
                self.box_of_offset(v)
            })
            .collect();
        let d = self.b(Builtin::Min, &[bars[0], bars[1]]);
        let d = self.b(Builtin::Min, &[d, bars[2]]);
        let qw = self.n(Op::Add, &[q, w]);
        let z3 = self.zero(Ty::Vec3);
        let m = self.b(Builtin::Max, &[qw, z3]);
        let nq = self.n(Op::Neg, &[q]);
        let to_face = self.min3(nq);
        let lens: Vec<NodeId> = [[0u8, 1], [1, 2], [2, 0]]
            .iter()
            .map(|s| {
                let v = self.sw(m, s);
                self.b(Builtin::Length, &[v])
            })
            .collect();
        let tunnel = self.b(Builtin::Min, &[lens[0], lens[1]]);
        let tunnel = self.b(Builtin::Min, &[tunnel, lens[2]]);
        let inner = self.b(Builtin::Min, &[to_face, tunnel]);
        let inner = self.n(Op::Neg, &[inner]);
        let zero = self.f(0.0);
        let outside = self.n(Op::Ge, &[d, zero]);
        self.n(Op::Select, &[inner, d, outside])
    }

    fn capped_cone(&mut self, p: NodeId, h: NodeId, r1: NodeId, r2: NodeId) -> NodeId {
        let xz = self.sw(p, &[0, 2]);
        let x = self.b(Builtin::Length, &[xz]);
        let y = self.c(p, 1);
        let zero = self.f(0.0);
        let yh = self.n(Op::Add, &[y, h]);
        let ymh = self.n(Op::Sub, &[y, h]);
        let x1 = self.n(Op::Sub, &[x, r1]);
        let x2 = self.n(Op::Sub, &[x, r2]);
        let mx1 = self.b(Builtin::Max, &[x1, zero]);
        let mx2 = self.b(Builtin::Max, &[x2, zero]);
        let bv = self.vec(&[mx1, yh]);
        let bottom = self.b(Builtin::Length, &[bv]);
        let tv = self.vec(&[mx2, ymh]);
        let top = self.b(Builtin::Length, &[tv]);
        let pa = self.vec(&[x1, yh]);
        let dr = self.n(Op::Sub, &[r2, r1]);
        let two = self.f(2.0);
        let h2 = self.n(Op::Mul, &[two, h]);
        let e = self.vec(&[dr, h2]);
        let side = self.segment(pa, e);
        let d = self.b(Builtin::Min, &[bottom, top]);
        let d = self.b(Builtin::Min, &[d, side]);
        let ay = self.b(Builtin::Abs, &[y]);
        let c1 = self.n(Op::Le, &[ay, h]);
        let lhs = self.n(Op::Mul, &[x, h2]);
        let hmy = self.n(Op::Sub, &[h, y]);
        let hpy = self.n(Op::Add, &[h, y]);
        let a1 = self.n(Op::Mul, &[r1, hmy]);
        let a2 = self.n(Op::Mul, &[r2, hpy]);
        let rhs = self.n(Op::Add, &[a1, a2]);
        let c2 = self.n(Op::Le, &[lhs, rhs]);
        let nd = self.n(Op::Neg, &[d]);
        self.select_both(d, nd, c1, c2)
    }

    fn pyramid(&mut self, p: NodeId, h: NodeId) -> NodeId {
        let (px, pz) = (self.c(p, 0), self.c(p, 2));
        let (ax, az) = (self.b(Builtin::Abs, &[px]), self.b(Builtin::Abs, &[pz]));
        let x = self.b(Builtin::Max, &[ax, az]);
        let z = self.b(Builtin::Min, &[ax, az]);
        let y = self.c(p, 1);
        let (half, quarter, zero) = (self.f(0.5), self.f(0.25), self.f(0.0));
        let hh = self.n(Op::Mul, &[h, h]);
        let sv = self.n(Op::Add, &[quarter, hh]);
        let sv = self.b(Builtin::Sqrt, &[sv]);
        let u = z;
        let xm = self.n(Op::Sub, &[x, half]);
        let mhalf = self.f(-0.5);
        let v1 = self.n(Op::Mul, &[mhalf, xm]);
        let v2 = self.n(Op::Mul, &[h, y]);
        let v = self.n(Op::Add, &[v1, v2]);
        let v = self.n(Op::Div, &[v, sv]);
        let w1 = self.n(Op::Mul, &[h, xm]);
        let w2 = self.n(Op::Mul, &[half, y]);
        let w = self.n(Op::Add, &[w1, w2]);
        let w = self.n(Op::Div, &[w, sv]);
        // Inside: below both the base plane and the face.
        let nw = self.n(Op::Neg, &[w]);
        let inner = self.b(Builtin::Min, &[y, nw]);
        let inner = self.n(Op::Neg, &[inner]);
        let c_up = self.n(Op::Ge, &[y, zero]);
        let c_face = self.n(Op::Le, &[w, zero]);
        let bx = self.b(Builtin::Max, &[xm, zero]);
        let zm = self.n(Op::Sub, &[z, half]);
        let bz = self.b(Builtin::Max, &[zm, zero]);
        let bv = self.vec(&[bx, y, bz]);
        let base = self.b(Builtin::Length, &[bv]);
        let um = self.n(Op::Sub, &[u, half]);
        let pa = self.vec(&[um, v]);
        let e = self.vec(&[mhalf, sv]);
        let mu = self.b(Builtin::Max, &[um, zero]);
        let t1 = self.vec(&[mu, v]);
        let t1 = self.b(Builtin::Length, &[t1]);
        // (The WGSL divides by dot(e, e) unguarded: e is never zero there.)
        let t2 = self.segment(pa, e);
        let t = self.b(Builtin::Min, &[t1, t2]);
        // Over the face's interior (v >= 0 and u sv + v / 2 <= sv / 2) the edge term is 0.
        let c_v = self.n(Op::Ge, &[v, zero]);
        let usv = self.n(Op::Mul, &[u, sv]);
        let hv = self.n(Op::Mul, &[half, v]);
        let lhs = self.n(Op::Add, &[usv, hv]);
        let rhs = self.n(Op::Mul, &[half, sv]);
        let c_in = self.n(Op::Le, &[lhs, rhs]);
        let t = self.select_both(t, zero, c_v, c_in);
        let tw = self.vec(&[t, w]);
        let tw = self.b(Builtin::Length, &[tw]);
        let out = self.b(Builtin::Min, &[base, tw]);
        self.select_both(out, inner, c_up, c_face)
    }

    fn menger(&mut self, p: NodeId, n: u32) -> NodeId {
        let two = self.f(2.0);
        let q = self.n(Op::Mul, &[two, p]);
        let aq = self.b(Builtin::Abs, &[q]);
        let one3 = self.konst_like(1.0, Ty::Vec3);
        let o = self.n(Op::Sub, &[aq, one3]);
        let mut d = self.box_of_offset(o);
        let third = self.konst_like(1.0 / 3.0, Ty::Vec2);
        let mut s = 1.0f32;
        for _ in 0..n {
            let sc = self.f(s);
            let t = self.n(Op::Mul, &[q, sc]);
            let t = self.n(Op::Add, &[t, one3]);
            let half = self.f(0.5);
            let th = self.n(Op::Mul, &[t, half]);
            let fl = self.b(Builtin::Floor, &[th]);
            let fl2 = self.n(Op::Mul, &[two, fl]);
            let m = self.n(Op::Sub, &[t, fl2]);
            let m = self.n(Op::Sub, &[m, one3]);
            let a = self.b(Builtin::Abs, &[m]);
            let bars: Vec<NodeId> = [[0u8, 1], [1, 2], [2, 0]]
                .iter()
                .map(|sw| {
                    let uv = self.sw(a, sw);
                    let b = self.n(Op::Sub, &[uv, third]);
                    self.box_of_offset(b)
                })
                .collect();
            let holes = self.b(Builtin::Min, &[bars[0], bars[1]]);
            let holes = self.b(Builtin::Min, &[holes, bars[2]]);
            let hs = self.n(Op::Div, &[holes, sc]);
            let hs = self.n(Op::Neg, &[hs]);
            d = self.b(Builtin::Max, &[d, hs]);
            s *= 3.0;
        }
        let half = self.f(0.5);
        self.n(Op::Mul, &[half, d])
    }

    fn sierpinski(&mut self, p: NodeId, n: u32) -> NodeId {
        let two = self.f(2.0);
        let mut z = self.n(Op::Mul, &[two, p]);
        let mut scale = 2.0f32;
        let corner = |d: &mut Differ, c: [f32; 3]| d.g.vec3(c);
        for _ in 0..n {
            let (x, y, w) = (self.c(z, 0), self.c(z, 1), self.c(z, 2));
            let (nx, ny, nw) = (
                self.n(Op::Neg, &[x]),
                self.n(Op::Neg, &[y]),
                self.n(Op::Neg, &[w]),
            );
            let xy = self.n(Op::Add, &[x, y]);
            let mut best = self.n(Op::Add, &[xy, w]);
            let mut v = corner(self, [1.0, 1.0, 1.0]);
            let cands = [
                ([nx, ny, w], [-1.0, -1.0, 1.0]),
                ([nx, y, nw], [-1.0, 1.0, -1.0]),
                ([x, ny, nw], [1.0, -1.0, -1.0]),
            ];
            for (terms, c) in cands {
                let s = self.n(Op::Add, &[terms[0], terms[1]]);
                let s = self.n(Op::Add, &[s, terms[2]]);
                let better = self.n(Op::Gt, &[s, best]);
                best = self.n(Op::Select, &[best, s, better]);
                let cv = corner(self, c);
                v = self.n(Op::Select, &[v, cv, better]);
            }
            let z2 = self.n(Op::Mul, &[two, z]);
            z = self.n(Op::Sub, &[z2, v]);
            scale *= 2.0;
        }
        let (x, y, w) = (self.c(z, 0), self.c(z, 1), self.c(z, 2));
        let (nx, ny, nw) = (
            self.n(Op::Neg, &[x]),
            self.n(Op::Neg, &[y]),
            self.n(Op::Neg, &[w]),
        );
        let planes: Vec<NodeId> = [[nx, ny, nw], [x, y, nw], [x, ny, w], [nx, y, w]]
            .iter()
            .map(|t| {
                let s = self.n(Op::Add, &[t[0], t[1]]);
                self.n(Op::Add, &[s, t[2]])
            })
            .collect();
        let m1 = self.b(Builtin::Max, &[planes[0], planes[1]]);
        let m2 = self.b(Builtin::Max, &[planes[2], planes[3]]);
        let m = self.b(Builtin::Max, &[m1, m2]);
        let one = self.f(1.0);
        let m = self.n(Op::Sub, &[m, one]);
        let k = self.f(0.577_350_26 / scale);
        self.n(Op::Mul, &[m, k])
    }

    /// The mandelbulb's estimate with its loop unrolled: an iteration that the WGSL's loop
    /// would not run (the orbit escaped, `r > 2`) keeps z, dr and r as they were.
    fn mandelbulb(&mut self, p: NodeId, pw: NodeId, iterations: u32, bound: NodeId) -> NodeId {
        let lp = self.b(Builtin::Length, &[p]);
        let (mut z, mut r) = (p, lp);
        let mut dr = self.f(1.0);
        let (one, two, tiny) = (self.f(1.0), self.f(2.0), self.f(1e-20));
        let minus_one = self.f(-1.0);
        let pw1 = self.n(Op::Sub, &[pw, one]);
        for _ in 0..iterations {
            let active = self.n(Op::Le, &[r, two]);
            let rs = self.b(Builtin::Max, &[r, tiny]);
            let zy = self.c(z, 1);
            let cy = self.n(Op::Div, &[zy, rs]);
            let cy = self.b(Builtin::Clamp, &[cy, minus_one, one]);
            let theta = self.b(Builtin::Acos, &[cy]);
            let theta = self.n(Op::Mul, &[theta, pw]);
            let (zz, zx) = (self.c(z, 2), self.c(z, 0));
            let phi = self.b(Builtin::Atan2, &[zz, zx]);
            let phi = self.n(Op::Mul, &[phi, pw]);
            let rp1 = self.b(Builtin::Pow, &[rs, pw1]);
            let ndr = self.n(Op::Mul, &[pw, rp1]);
            let ndr = self.n(Op::Mul, &[ndr, dr]);
            let ndr = self.n(Op::Add, &[ndr, one]);
            let zr = self.b(Builtin::Pow, &[rs, pw]);
            let (st, ct) = (
                self.b(Builtin::Sin, &[theta]),
                self.b(Builtin::Cos, &[theta]),
            );
            let (sp, cp) = (self.b(Builtin::Sin, &[phi]), self.b(Builtin::Cos, &[phi]));
            (z, dr, r) =
                self.mandelbulb_advance(p, zr, [ct, st], [cp, sp], ndr, active, (z, dr, r));
        }
        self.mandelbulb_estimate(lp, r, dr, bound)
    }

    /// The end of one orbit step: `z = zr (sin t cos f, cos t, sin t sin f) + p` from the
    /// multiplied angles' (cosine, sine) pairs `t` and `f`, its length, and the new `dr`;
    /// an orbit that had escaped (`active` false) keeps `(z, dr, r)` as they were.
    #[allow(clippy::too_many_arguments)]
    fn mandelbulb_advance(
        &mut self,
        p: NodeId,
        zr: NodeId,
        t: [NodeId; 2],
        f: [NodeId; 2],
        ndr: NodeId,
        active: NodeId,
        (z, dr, r): (NodeId, NodeId, NodeId),
    ) -> (NodeId, NodeId, NodeId) {
        let x = self.n(Op::Mul, &[t[1], f[0]]);
        let w = self.n(Op::Mul, &[t[1], f[1]]);
        let dir = self.vec(&[x, t[0], w]);
        let nz = self.n(Op::Mul, &[zr, dir]);
        let nz = self.n(Op::Add, &[nz, p]);
        let nr = self.b(Builtin::Length, &[nz]);
        (
            self.n(Op::Select, &[z, nz, active]),
            self.n(Op::Select, &[dr, ndr, active]),
            self.n(Op::Select, &[r, nr, active]),
        )
    }

    /// The whole-power mandelbulb as `sd_mandelbulb_int` computes it: the angles' multiples
    /// and `r^power` by repeated squaring, unrolled (the identity factor it starts from left
    /// out: multiplying by 1 + 0i changes nothing).
    fn mandelbulb_int(
        &mut self,
        p: NodeId,
        pw: NodeId,
        power: u32,
        iterations: u32,
        bound: NodeId,
    ) -> Option<NodeId> {
        let lp = self.b(Builtin::Length, &[p]);
        let (mut z, mut r) = (p, lp);
        let mut dr = self.f(1.0);
        let (zero, one, two, tiny) = (self.f(0.0), self.f(1.0), self.f(2.0), self.f(1e-20));
        let minus_one = self.f(-1.0);
        for _ in 0..iterations {
            let active = self.n(Op::Le, &[r, two]);
            let rs = self.b(Builtin::Max, &[r, tiny]);
            let (zx, zy, zz) = (self.c(z, 0), self.c(z, 1), self.c(z, 2));
            let xz = self.vec(&[zx, zz]);
            let rho = self.b(Builtin::Length, &[xz]);
            let ct = self.n(Op::Div, &[zy, rs]);
            let ct = self.b(Builtin::Clamp, &[ct, minus_one, one]);
            let st = self.n(Op::Div, &[rho, rs]);
            let off_axis = self.n(Op::Gt, &[rho, zero]);
            let cp = self.n(Op::Div, &[zx, rho]);
            let cp = self.n(Op::Select, &[one, cp, off_axis]);
            let sp = self.n(Op::Div, &[zz, rho]);
            let sp = self.n(Op::Select, &[zero, sp, off_axis]);
            let mut base = ([ct, st], [cp, sp], rs);
            let mut acc: Option<([NodeId; 2], [NodeId; 2], NodeId)> = None;
            let mut e = power;
            while e > 0 {
                if e & 1 == 1 {
                    acc = Some(match acc {
                        None => base,
                        Some((t, f, q)) => (
                            self.cmul(t, base.0),
                            self.cmul(f, base.1),
                            self.n(Op::Mul, &[q, base.2]),
                        ),
                    });
                }
                e >>= 1;
                if e > 0 {
                    base = (
                        self.cmul(base.0, base.0),
                        self.cmul(base.1, base.1),
                        self.n(Op::Mul, &[base.2, base.2]),
                    );
                }
            }
            // None for power 0 only, which the lowering never lets through (2 to 16).
            let (theta_n, phi_n, radius_n) = acc?;
            let rp1 = self.n(Op::Div, &[radius_n, rs]);
            let ndr = self.n(Op::Mul, &[pw, rp1]);
            let ndr = self.n(Op::Mul, &[ndr, dr]);
            let ndr = self.n(Op::Add, &[ndr, one]);
            (z, dr, r) =
                self.mandelbulb_advance(p, radius_n, theta_n, phi_n, ndr, active, (z, dr, r));
        }
        Some(self.mandelbulb_estimate(lp, r, dr, bound))
    }

    /// The product of the complex numbers `a` and `b` (real, imaginary).
    fn cmul(&mut self, a: [NodeId; 2], b: [NodeId; 2]) -> [NodeId; 2] {
        let re1 = self.n(Op::Mul, &[a[0], b[0]]);
        let re2 = self.n(Op::Mul, &[a[1], b[1]]);
        let im1 = self.n(Op::Mul, &[a[0], b[1]]);
        let im2 = self.n(Op::Mul, &[a[1], b[0]]);
        [self.n(Op::Sub, &[re1, re2]), self.n(Op::Add, &[im1, im2])]
    }

    /// The mandelbulb's estimate `0.5 ln r r / dr` from the orbit's end, or the distance to
    /// its bounding sphere where p is beyond 1.25 times its radius.
    fn mandelbulb_estimate(&mut self, lp: NodeId, r: NodeId, dr: NodeId, bound: NodeId) -> NodeId {
        let tiny = self.f(1e-20);
        let rf = self.b(Builtin::Max, &[r, tiny]);
        let l = self.b(Builtin::Log, &[rf]);
        let half = self.f(0.5);
        let e = self.n(Op::Mul, &[half, l]);
        let e = self.n(Op::Mul, &[e, rf]);
        let e = self.n(Op::Div, &[e, dr]);
        let k = self.f(1.25);
        let far = self.n(Op::Mul, &[k, bound]);
        let outside = self.n(Op::Gt, &[lp, far]);
        let sphere = self.n(Op::Sub, &[lp, bound]);
        self.n(Op::Select, &[e, sphere, outside])
    }

    /// The octahedron's distance to the edge for the permuted |p| `q`.
    fn octahedron_edge(&mut self, q: NodeId, s: NodeId) -> NodeId {
        let (x, y, z) = (self.c(q, 0), self.c(q, 1), self.c(q, 2));
        let zy = self.n(Op::Sub, &[z, y]);
        let zys = self.n(Op::Add, &[zy, s]);
        let half = self.f(0.5);
        let k = self.n(Op::Mul, &[half, zys]);
        let zero = self.f(0.0);
        let k = self.b(Builtin::Clamp, &[k, zero, s]);
        let ys = self.n(Op::Sub, &[y, s]);
        let ys = self.n(Op::Add, &[ys, k]);
        let zk = self.n(Op::Sub, &[z, k]);
        let v = self.vec(&[x, ys, zk]);
        self.b(Builtin::Length, &[v])
    }
}
