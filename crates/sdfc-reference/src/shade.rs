//! Normals, Phong shading with shadows and ambient occlusion, fog and reflections: the
//! semantics of shaders/shading and the per-scene `shade`/`finish` of sdfc-wgsl's marcher, in
//! f64, with secondary rays started just off the surface and marched to the reference's
//! threshold.

use crate::march::{march, RayHit};
use crate::scene::{Material, SceneEval};
use crate::vec::{add, dot, f64s, length, mul, reflect, safe_normalize, scale, sub, V3};
use sdfc_ir::scene::{LightKind, RenderSettings, Scene, Shadows};

/// How far secondary rays start off the surface, relative to the point's scale: far above
/// f64 rounding there, far below any feature the GPU can resolve.
const OFFSET: f64 = 1e-7;

/// The unit gradient of the distance at `p`, seen from a ray along `rd`: central differences
/// with a step far below any feature and far above f64 rounding at `p`'s magnitude. Where
/// they cancel (a surface of zero thickness: the distance is |y| across it, and the two
/// one-sided differences are opposite) the gradient is taken a little way back along the
/// ray, on the side the ray comes from (1e3 steps back: a grazing ray must leave the step's
/// reach of the surface). Cancellation is judged against the one-sided differences, not
/// the step: a field divided by its Lipschitz bound has a gradient of a quarter or less, and
/// an absolute test took such surfaces for zero-thick ones, sampled a unit back at 1e5, and
/// had normals 22 degrees off.
pub fn normal(scene: &SceneEval, p: V3, rd: V3) -> V3 {
    let h = 1e-8 * scale(p);
    let (g, sides) = gradient(scene, p, h);
    if length(g) >= 0.1 * sides {
        return safe_normalize(g);
    }
    safe_normalize(gradient(scene, sub(p, mul(rd, 1e3 * h)), h).0)
}

/// Twice h times the central-difference gradient at `p`, and the length of the vector of
/// the one-sided differences' magnitudes summed per axis (the central one's when they agree).
fn gradient(scene: &SceneEval, p: V3, h: f64) -> (V3, f64) {
    let d = scene.distance(p);
    let mut g = [0.0; 3];
    let mut sides = [0.0; 3];
    for k in 0..3 {
        let mut a = p;
        let mut b = p;
        a[k] += h;
        b[k] -= h;
        let (forward, backward) = (scene.distance(a) - d, d - scene.distance(b));
        g[k] = forward + backward;
        sides[k] = forward.abs() + backward.abs();
    }
    (g, length(sides))
}

/// Shading of a whole scene: settings, lights, and the scene functions.
pub struct Shader<'a> {
    pub scene: &'a SceneEval<'a>,
    pub desc: &'a Scene,
}

impl Shader<'_> {
    fn render(&self) -> &RenderSettings {
        &self.desc.render
    }

    fn max_distance(&self) -> f64 {
        self.render().max_distance as f64
    }

    /// shaders/shading/shadow_hard.wgsl: 0 if the segment meets a surface, else 1.
    fn shadow_hard(&self, ro: V3, rd: V3, tmax: f64) -> f64 {
        let r = march(self.scene, ro, rd, tmax);
        if r.hit && r.t < tmax {
            0.0
        } else {
            1.0
        }
    }

    /// shaders/shading/shadow_soft.wgsl: the narrowest free cone, sampled far more densely.
    fn shadow_soft(&self, ro: V3, rd: V3, tmax: f64, k: f64) -> f64 {
        let mut light: f64 = 1.0;
        let mut t = 0.0;
        let floor = 1e-9 * scale(ro);
        for _ in 0..crate::march::MAX_STEPS {
            if t >= tmax {
                break;
            }
            let h = self.scene.distance(add(ro, mul(rd, t)));
            if h.is_nan() {
                break;
            }
            light = light.min(k * h / t.max(floor));
            if light <= 0.0 {
                return 0.0;
            }
            t += h.max(1e-7 * t + floor);
        }
        light.clamp(0.0, 1.0)
    }

    fn shadow(&self, ro: V3, rd: V3, tmax: f64) -> f64 {
        match self.render().shadows {
            Shadows::None => 1.0,
            Shadows::Hard => self.shadow_hard(ro, rd, tmax),
            Shadows::Soft(k) => self.shadow_soft(ro, rd, tmax, k as f64),
        }
    }

    /// shaders/shading/ambient_occlusion.wgsl.
    fn ambient_occlusion(&self, p: V3, n: V3) -> f64 {
        let Some(ao) = self.render().ao else {
            return 1.0;
        };
        let (mut occlusion, mut most) = (0.0, 0.0);
        // Weights falloff^(i - top), the largest 1 (falloff^i overflowed for a falloff
        // above 1 and many samples).
        let falloff = ao.falloff as f64;
        let top = if falloff > 1.0 { ao.samples } else { 1 } as f64;
        for i in 1..=ao.samples {
            let h = ao.step as f64 * i as f64;
            let d = self.scene.distance(add(p, mul(n, h)));
            let weight = falloff.powf(i as f64 - top);
            occlusion += weight * (h - d).clamp(0.0, h);
            most += weight * h;
        }
        if most <= 0.0 {
            return 1.0;
        }
        (1.0 - ao.strength as f64 * occlusion / most).clamp(0.0, 1.0)
    }

    /// The emitted `shade`: ambient (times AO), then diffuse and specular per light, each
    /// times its shadow.
    pub fn shade(&self, p: V3, n: V3, rd: V3, m: &Material) -> V3 {
        let base = [m.albedo[0], m.albedo[1], m.albedo[2]];
        let mut c = mul(base, m.phong[0] * self.ambient_occlusion(p, n));
        let origin = add(p, mul(n, OFFSET * scale(p)));
        for light in &self.desc.lights {
            let (l, tmax) = match &light.kind {
                LightKind::Directional { direction } => {
                    (mul(f64s(*direction), -1.0), self.max_distance())
                }
                LightKind::Point { position } => {
                    let to_light = sub(f64s(*position), p);
                    (safe_normalize(to_light), length(to_light))
                }
            };
            let diffuse = dot(n, l).max(0.0);
            let lit = if diffuse > 0.0 {
                self.shadow(origin, l, tmax)
            } else {
                0.0
            };
            let r = reflect(mul(l, -1.0), n);
            let specular = if diffuse > 0.0 {
                dot(r, mul(rd, -1.0)).max(1e-6).powf(m.phong[3])
            } else {
                0.0
            };
            let radiance = mul(f64s(light.color), light.intensity as f64);
            let term = add(mul(base, m.phong[1] * diffuse), [m.phong[2] * specular; 3]);
            let lit = if self.render().shadows == Shadows::None {
                1.0
            } else {
                lit
            };
            for k in 0..3 {
                c[k] += lit * radiance[k] * term[k];
            }
        }
        c
    }

    /// The emitted `finish`: exponential fog over distance t.
    fn finish(&self, c: V3, t: f64) -> V3 {
        match &self.render().fog {
            None => c,
            Some(f) => {
                let w = (-(f.density as f64) * t).exp();
                let fc = f64s(f.color);
                [0, 1, 2].map(|k| fc[k] + (c[k] - fc[k]) * w)
            }
        }
    }

    /// shaders/shading/radiance_{plain,reflections}.wgsl: the colour the ray brings back.
    pub fn radiance(&self, ro: V3, rd: V3, first: RayHit) -> V3 {
        let background = f64s(self.render().background);
        let bounces = self.render().reflections;
        let mut color = [0.0; 3];
        let mut weight = 1.0;
        let (mut origin, mut dir, mut hit) = (ro, rd, first);
        for bounce in 0..=bounces {
            if bounce > 0 {
                hit = march(self.scene, origin, dir, self.max_distance());
            }
            if !hit.hit {
                return add(color, mul(background, weight));
            }
            let p = add(origin, mul(dir, hit.t));
            let n = normal(self.scene, p, dir);
            let m = self.scene.material(p);
            let local = self.finish(self.shade(p, n, dir, &m), hit.t);
            let r = m.albedo[3].clamp(0.0, 1.0);
            if bounce == bounces || r <= 0.0 {
                return add(color, mul(local, weight));
            }
            color = add(color, mul(local, weight * (1.0 - r)));
            weight *= r;
            dir = reflect(dir, n);
            origin = add(p, mul(n, OFFSET * scale(p)));
        }
        color
    }
}
