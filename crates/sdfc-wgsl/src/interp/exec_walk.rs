//! The CPU twin of `shaders/interpreter/instances.wgsl`, in f32: the walk of a union read as
//! data, one node per step, as `exec::run` drives it.

use super::encode::Bytecode;

/// A walk's state, as the shader's private variables hold it.
#[derive(Default)]
pub(super) struct Walk {
    /// The pc of the walk in progress.
    at: Option<u32>,
    p: [f32; 3],
    node: u32,
    after: u32,
    best: f32,
    nearest: u32,
    leaf: u32,
    scale: f32,
    hint: u32,
}

/// What one trip of the walk does next.
pub(super) enum Trip {
    /// Go to this pc (the walk again, or a kind's code, register 0 set).
    Jump(u32),
    /// The walk is over: (distance, material index, 0, 0).
    Over([f32; 4]),
}

fn words(code: &Bytecode, i: u32) -> Result<[u32; 4], String> {
    code.instances
        .get(i as usize)
        .copied()
        .ok_or_else(|| format!("union data {i} out of range"))
}

fn floats(w: [u32; 4]) -> [f32; 4] {
    w.map(f32::from_bits)
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn length(v: [f32; 3]) -> f32 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

impl Walk {
    /// One trip of `instances` at `pc` from point `p`, its kinds' starts at pool index
    /// `kinds`.
    pub(super) fn trip(
        &mut self,
        code: &Bytecode,
        pc: u32,
        p: [f32; 3],
        kinds: u32,
        point: &mut [f32; 4],
    ) -> Result<Trip, String> {
        let mut leaf = 0;
        if self.at != Some(pc) {
            *self = Walk {
                at: Some(pc),
                p,
                best: 3.0e38,
                hint: self.hint,
                ..Walk::default()
            };
            leaf = self.hint;
        }
        if leaf == 0 {
            if self.node >= words(code, 0)?[3] {
                self.at = None;
                let mut material = 0;
                if self.nearest != 0 {
                    self.hint = self.nearest;
                    material = words(code, self.nearest + 1)?[1];
                }
                return Ok(Trip::Over([self.best, material as f32, 0.0, 0.0]));
            }
            let node = words(code, 2 * self.node)?;
            let bx = words(code, 2 * self.node + 1)?;
            let (c, half) = (floats(node), floats(bx));
            let q: [f32; 3] = std::array::from_fn(|k| (self.p[k] - c[k]).abs() - half[k]);
            let outside = length(q.map(|x| x.max(0.0)));
            let bd = outside + q[0].max(q[1].max(q[2])).min(0.0);
            if bd >= self.best {
                self.node = node[3];
                return Ok(Trip::Jump(pc));
            }
            if bd > length([half[0], half[1], half[2]]) {
                self.best = bd;
                self.node = node[3];
                return Ok(Trip::Jump(pc));
            }
            if bx[3] == 0 {
                self.node += 1;
                return Ok(Trip::Jump(pc));
            }
            leaf = bx[3];
            self.after = node[3];
        }
        let record = leaf - 1;
        let q = floats(words(code, record)?);
        let c = floats(words(code, record + 1)?);
        let v: [f32; 3] = std::array::from_fn(|k| self.p[k] - c[k]);
        let t = cross([q[0], q[1], q[2]], v).map(|x| 2.0 * x);
        let u = cross([q[0], q[1], q[2]], t);
        *point = [0, 1, 2, 3].map(|k| {
            if k < 3 {
                (v[k] + q[3] * t[k] + u[k]) / c[3]
            } else {
                0.0
            }
        });
        self.leaf = leaf;
        self.scale = c[3];
        let kind = words(code, record + 2)?[0];
        let start = code
            .consts
            .get((kinds + kind) as usize)
            .ok_or("a kind without code")?[0];
        Ok(Trip::Jump(start as u32))
    }

    /// `instance_done` with the kind's distance `local`: back to the walk's pc.
    pub(super) fn back(&mut self, local: f32, point: &mut [f32; 4]) -> Result<u32, String> {
        let d = local * self.scale;
        if d < self.best {
            self.best = d;
            self.nearest = self.leaf;
        }
        *point = [self.p[0], self.p[1], self.p[2], 0.0];
        self.node = self.after;
        self.at.ok_or_else(|| "instance_done outside a walk".into())
    }

    /// `arg`: word `imm & 0xff` of the record being evaluated, `imm >> 8` words wide.
    pub(super) fn arg(&self, code: &Bytecode, imm: u32) -> Result<[f32; 4], String> {
        let w = 4 * (self.leaf.checked_sub(1).ok_or("arg outside a kind")?) + (imm & 0xff);
        let width = imm >> 8;
        let mut v = [0.0; 4];
        for (k, x) in v.iter_mut().enumerate().take(width as usize) {
            let i = w + k as u32;
            *x = f32::from_bits(words(code, i / 4)?[(i % 4) as usize]);
        }
        Ok(if width == 1 { [v[0]; 4] } else { v })
    }
}
