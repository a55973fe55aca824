//! The camera rays of spec section 8, in f64 from the scene's camera.

use crate::vec::{add, cross, f64s, mul, safe_normalize, sub, V3};
use sdfc_ir::scene::Camera as SceneCamera;

#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub position: V3,
    pub forward: V3,
    pub right: V3,
    pub up: V3,
    pub tan_half_fov: f64,
}

impl Camera {
    pub fn of(c: &SceneCamera) -> Camera {
        let position = f64s(c.position);
        let forward = safe_normalize(sub(f64s(c.target), position));
        let right = safe_normalize(cross(forward, f64s(c.up)));
        let up = cross(right, forward);
        Camera {
            position,
            forward,
            right,
            up,
            tan_half_fov: (c.fov as f64 * 0.5).tan(),
        }
    }

    /// The unit ray through image position (`x`, `y`) in pixels from the top left corner of a
    /// `w` x `h` image (pixel centres at half-integers).
    pub fn ray(&self, x: f64, y: f64, w: f64, h: f64) -> V3 {
        let sx = 2.0 * x / w - 1.0;
        let sy = 1.0 - 2.0 * y / h;
        let aspect = w / h;
        safe_normalize(add(
            add(
                self.forward,
                mul(self.right, sx * self.tan_half_fov * aspect),
            ),
            mul(self.up, sy * self.tan_half_fov),
        ))
    }
}
