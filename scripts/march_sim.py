"""Step counts of sdfc's marchers on examples/terrain.sdf without a device.

A scalar f64 port of the terrain's distance (shaders/noise.wgsl, the fbm and heightfield
of the compiled scene, its ray-aware divisor) and of the marchers as they stand on
2026-12-04: shaders/march_plain.wgsl, shaders/march_relaxed.wgsl and `refine` in
shaders/hit.wgsl (without the 2.4e-7 t threshold floor, which never binds here), with the
two step budgets of 2026-12-07 (`march_spent`). Checked
against lavapipe's steps AOV: 64x48 plain 34.01 / relaxed 28.73 steps per pixel against
34.0 / 28.8 on the device; 128x96 35.77 / 29.53 against 35.8 / 29.5. Step counts are
exact on any device, so rules for relaxation can be tried here in seconds; confirm a
winner on the device (`sdfc render --compare`), and keep this file in step with the
shaders if it is to stay useful.

    python3 scripts/march_sim.py 64 48     # plain against relaxed, by depth band
"""
import math, sys

M32 = 0xffffffff
def hash3(x, y, z):
    h = ((x & M32) * 73856093 ^ (y & M32) * 19349663 ^ (z & M32) * 83492791) & M32
    h ^= h >> 16
    h = (h * 0x7feb352d) & M32
    h ^= h >> 15
    h = (h * 0x846ca68b) & M32
    h ^= h >> 16
    return h

def grad(x, y, z, fx, fy, fz):
    h = hash3(x, y, z) & 15
    u = fx if h < 8 else fy
    v = fy if h < 4 else (fx if (h == 12 or h == 14) else fz)
    return (u if (h & 1) == 0 else -u) + (v if (h & 2) == 0 else -v)

def fade(t):
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)

def mix(a, b, w):
    return a + (b - a) * w

def noise(px, py, pz):
    fx0, fy0, fz0 = math.floor(px), math.floor(py), math.floor(pz)
    ix, iy, iz = int(fx0), int(fy0), int(fz0)
    fx, fy, fz = px - fx0, py - fy0, pz - fz0
    wx, wy, wz = fade(fx), fade(fy), fade(fz)
    x0 = mix(grad(ix, iy, iz, fx, fy, fz), grad(ix + 1, iy, iz, fx - 1, fy, fz), wx)
    x1 = mix(grad(ix, iy + 1, iz, fx, fy - 1, fz), grad(ix + 1, iy + 1, iz, fx - 1, fy - 1, fz), wx)
    x2 = mix(grad(ix, iy, iz + 1, fx, fy, fz - 1), grad(ix + 1, iy, iz + 1, fx - 1, fy, fz - 1), wx)
    x3 = mix(grad(ix, iy + 1, iz + 1, fx, fy - 1, fz - 1), grad(ix + 1, iy + 1, iz + 1, fx - 1, fy - 1, fz - 1), wx)
    return max(-1.0, min(1.0, mix(mix(x0, x1, wy), mix(x2, x3, wy), wz)))

def height(x, z):
    qx, qz = x * 0.35, z * 0.35
    s = 0.0
    a = 1.0
    f = 1.0
    for _ in range(6):
        s += noise(qx * f, 0.0, qz * f) * a
        a *= 0.5
        f *= 2.0
    return 1.5 * (s / 1.96875)

LIP = 1.9723084
class Scene:
    def __init__(self, mode="iso"):
        self.mode = mode
        self.evals = 0
    def dist(self, p, rd):
        self.evals += 1
        x, y, z = p
        g = y - height(x, z)
        if self.mode == "iso":
            l0 = min(LIP, max(13.6 * abs(rd[0]) + abs(rd[1]) + 13.6 * abs(rd[2]), 0.125))
        else:  # directional heightfield bound: |rd.y| + 1.7 |rd_xz|
            l0 = min(LIP, abs(rd[1]) + 1.7 * math.hypot(rd[0], rd[2]))
        d0 = g / l0
        d1 = max(d0, y - 1.5)
        d2 = y + 0.3
        return min(d1, d2)

CAM = (0.0, 2.5, 6.0)
FWD = (0.0, -0.34425464, -0.93887633)
RIGHT = (1.0, -0.0, 0.0)
UP = (0.0, 0.93887633, -0.34425464)
TAN = math.tan(math.radians(25))
MAX_STEPS = 400
MAX_DISTANCE = 60.0

def ray(x, y, W, H):
    sx = 2.0 * (x + 0.5) / W - 1.0
    sy = 1.0 - 2.0 * (y + 0.5) / H
    a = W / H
    v = [FWD[i] + sx * TAN * a * RIGHT[i] + sy * TAN * UP[i] for i in range(3)]
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)

def at(ro, rd, t):
    return (ro[0] + rd[0] * t, ro[1] + rd[1] * t, ro[2] + rd[2] * t)

def eps_of(t, pixel):
    return 0.5 * pixel * t

class Stats:
    def __init__(self):
        self.refine = 0
        self.failed = 0

def refine(S, ro, rd, t0, d0, steps0, eps, st):
    steps = steps0
    if d0 <= 0.0 and t0 <= 0.0:
        return (0.0, steps, True)
    ta, da, tb, db = t0, d0, t0, d0
    bracketed = d0 <= 0.0
    side = 0
    t, d, tp, dp = t0, d0, t0, d0
    reach = t0 + d0
    dmin = d0
    cap = 256.0
    for i in range(20):
        near = abs(d) <= 1e-7 * max(t, 1.0)
        if near and (i == 0 or abs(d * (t - tp)) <= 1e-6 * t * abs(d - dp)):
            return (t, steps, True)
        nxt = t + d
        secant_step = False
        if bracketed and da > 0.0 and tb > ta:
            nxt = tb - db * (tb - ta) / (db - da)
            if not (nxt > ta and nxt < tb):
                nxt = 0.5 * (ta + tb)
        elif (not bracketed) and i > 0:
            slope = d - dp
            if slope >= 0.0 and dmin > 0.01 * eps:
                return (max(reach, t), steps, False)
            secant = t - d * (t - tp) / slope if slope != 0 else float("inf")
            if slope < 0.0 and secant > nxt:
                nxt = min(secant, t + cap * d)
                secant_step = nxt > t + d
        tq, dq = tp, dp
        tp, dp = t, d
        t = max(nxt, 0.0)
        d = S.dist(at(ro, rd, t), rd)
        steps += 1
        st.refine += 1
        if secant_step and t - abs(d) > tp + dp + eps and abs(d) > 0.1 * dp:
            cap = 0.25 * (t - tp) / dp
            t, d, tp, dp = tp, dp, tq, dq
            continue
        cap = min(4.0 * cap, 256.0)
        if d > 0.0:
            if t - d <= reach:
                reach = max(reach, t + d)
            dmin = min(dmin, d)
            if (not bracketed) or t > ta:
                if side == 1:
                    db = 0.5 * db
                ta, da, side = t, d, 1
        else:
            if (not bracketed) or t < tb:
                if side == -1:
                    da = 0.5 * da
                tb, db, side = t, d, -1
            if (not bracketed) and d0 > 0.0:
                ta, da = tp, dp
            bracketed = True
    if (not bracketed) and dmin > 0.01 * eps:
        return (max(reach, t), steps, False)
    return (t, steps, True)

def march_spent(steps, passed):
    # Two budgets since 2026-12-07 (shaders/hit.wgsl): the march's own samples, and those of
    # refinements that passed by.
    return steps - passed >= MAX_STEPS or passed >= MAX_STEPS

def march_end(t, steps, passed, passing):
    return (t, steps, passing and march_spent(steps, passed) and t <= MAX_DISTANCE)

def march_plain(S, ro, rd, pixel, st, span=(0.0, MAX_DISTANCE)):
    t = span[0]; steps = 0; passed = 0; passing = False; close = False
    last = 0.0; jump = 0.0; leap = False
    while True:
        if march_spent(steps, passed) or t > span[1]:
            break
        d = S.dist(at(ro, rd, t), rd); steps += 1
        if jump > 0.0 and d + last < jump:
            t = t - jump + last; jump = 0.0; leap = False; continue
        jump = 0.0
        eps = eps_of(t, pixel)
        if passing and d <= eps and d > last:
            last = d
            jump = 1.9 * d if leap else 0.0
            close = d <= 0.1 * eps
            t = t + (jump if leap else d)
            continue
        if d <= eps:
            rt, rs, rh = refine(S, ro, rd, t, d, steps, eps, st)
            if rh:
                return (rt, rs, rt <= MAX_DISTANCE)
            passed += rs - steps
            steps = rs; t = rt; passing = True; last = 0.0; close = True; leap = True
            continue
        passing = False
        t = t + d
    return march_end(t, steps, passed, passing and close)

def march_relaxed(S, ro, rd, pixel, st, R=1.6, rule=None, span=(0.0, MAX_DISTANCE)):
    t = span[0]; steps = 0; passed = 0; prev_radius = 0.0; step = 0.0
    passing = False; close = False; leap = False; retry = False
    while True:
        if march_spent(steps, passed) or t > span[1]:
            break
        d = S.dist(at(ro, rd, t), rd); steps += 1
        radius = abs(d)
        overshot = step > prev_radius and radius + prev_radius < step
        if overshot:
            st.failed += 1
            step = prev_radius - step
            retry = True; leap = False
        else:
            eps = eps_of(t, pixel)
            if passing and d <= eps and d > prev_radius:
                step = (1.9 if leap else 1.0) * d
                close = d <= 0.1 * eps
                prev_radius = radius
                t = t + step
                continue
            if d <= eps:
                rt, rs, rh = refine(S, ro, rd, t, d, steps, eps, st)
                if rh:
                    return (rt, rs, rt <= MAX_DISTANCE)
                passed += rs - steps
                steps = rs; t = rt; prev_radius = 0.0; step = 0.0
                passing = True; close = True; leap = True
                continue
            passing = False
            w = 1.0 if retry else R
            retry = False
            if w > 1.0 and step > 0.0:
                slope = min(1.0, max(0.0, (prev_radius - radius) / step))
                if rule is None:
                    w = min(R, max(1.0, 0.95 * 2.0 / (1.0 + slope)))
                else:
                    w = rule(R, slope, d, eps, t)
            step = d * w
            if t + step > span[1]:
                step = d
        prev_radius = radius
        t = t + step
    return march_end(t, steps, passed, passing and close)

def run(W, H, marcher, mode="iso", **kw):
    S = Scene(mode)
    pixel = 2.0 * TAN / H
    st = Stats()
    tot = 0
    rows = []
    for y in range(H):
        row = []
        for x in range(W):
            rd = ray(x, y, W, H)
            t, steps, hit = marcher(S, CAM, rd, pixel, st, **kw)
            tot += steps
            row.append((t if hit else float("inf"), steps))
        rows.append(row)
    n = W * H
    return dict(mean=tot / n, refine=st.refine / n, failed=st.failed / n, rows=rows)

def bands(W, H, R=1.6, rule=None):
    """Mean steps (march, refinement, failed relaxed steps) per depth band of the plain hit."""
    S = Scene()
    pixel = 2.0 * TAN / H
    agg = {}
    for y in range(H):
        for x in range(W):
            rd = ray(x, y, W, H)
            s1, s2 = Stats(), Stats()
            t1, n1, h1 = march_plain(S, CAM, rd, pixel, s1)
            _, n2, _ = march_relaxed(S, CAM, rd, pixel, s2, R=R, rule=rule)
            k = "miss" if not h1 else "t<5" if t1 < 5 else "t5-10" if t1 < 10 else "t10-20" if t1 < 20 else "t>20"
            a = agg.setdefault(k, [0] * 6)
            for i, v in enumerate([1, n1, s1.refine, n2, s2.refine, s2.failed]):
                a[i] += v
    for k, a in agg.items():
        n = a[0]
        print(f"{k:7s} {n:5d} px  plain {a[1]/n:6.2f} (refine {a[2]/n:5.2f})  "
              f"relaxed {a[3]/n:6.2f} (refine {a[4]/n:5.2f}, failed {a[5]/n:4.2f})")


if __name__ == "__main__":
    W, H = int(sys.argv[1]), int(sys.argv[2])
    a = run(W, H, march_plain)
    b = run(W, H, march_relaxed)
    print(f"plain {a['mean']:.2f} (refine {a['refine']:.2f})  relaxed {b['mean']:.2f} "
          f"(refine {b['refine']:.2f}, failed {b['failed']:.2f})  "
          f"saving {100*(1-b['mean']/a['mean']):.1f}%")
    bands(W, H)
