//! The pinhole camera, shared by the GPU and CPU renderers: both build the primary ray of a
//! pixel from the same [`CameraBasis`] with the same formula.

use glam::DVec3;

/// A perspective camera looking from `position` at `target`, `+y` up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: DVec3,
    pub target: DVec3,
    /// Vertical field of view in degrees, in `(0, 180)`.
    pub vfov_deg: f64,
}

/// The camera's frame for an image of a given aspect: the ray through pixel centre
/// `(px + 0.5, py + 0.5)` of a `w x h` image is
/// `normalize(forward + ndc_x right + ndc_y up)` with `ndc_x = 2 (px + 0.5) / w - 1` and
/// `ndc_y = 1 - 2 (py + 0.5) / h` (row 0 at the top).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraBasis {
    pub origin: DVec3,
    pub forward: DVec3,
    /// Unit right vector scaled by `tan(vfov / 2) * aspect`.
    pub right: DVec3,
    /// Unit up vector scaled by `tan(vfov / 2)`.
    pub up: DVec3,
}

impl Camera {
    /// The reference scene's camera (DESIGN.md section 4).
    pub fn reference() -> Self {
        Camera {
            position: DVec3::new(0.0, 80.0, 300.0),
            target: DVec3::ZERO,
            vfov_deg: 75.0,
        }
    }

    /// Why this camera cannot form a frame, if it cannot: target at the position, or
    /// looking straight up or down (the `+y` up vector gives no right vector).
    pub fn problem(&self) -> Option<&'static str> {
        let forward = self.target - self.position;
        if forward.length_squared() == 0.0 || !forward.is_finite() {
            return Some("camera target equals its position");
        }
        if forward.normalize().cross(DVec3::Y).length_squared() < 1e-12 {
            return Some("camera looks straight up or down (parallel to +y)");
        }
        if !(self.vfov_deg > 0.0 && self.vfov_deg < 180.0) {
            return Some("vfov_deg must be in (0, 180)");
        }
        None
    }

    /// The frame for an image `width / height`. The camera must be valid
    /// ([`Camera::problem`] is `None`; scenes are validated on load).
    pub fn basis(&self, width: u32, height: u32) -> CameraBasis {
        let forward = (self.target - self.position).normalize();
        let right = forward.cross(DVec3::Y).normalize();
        let up = right.cross(forward);
        let tan_half = (self.vfov_deg.to_radians() * 0.5).tan();
        let aspect = width as f64 / height.max(1) as f64;
        CameraBasis {
            origin: self.position,
            forward,
            right: right * tan_half * aspect,
            up: up * tan_half,
        }
    }
}

impl CameraBasis {
    /// The unit direction of the primary ray through the centre of pixel `(px, py)`.
    pub fn ray(&self, px: u32, py: u32, width: u32, height: u32) -> DVec3 {
        let ndc_x = 2.0 * (px as f64 + 0.5) / width as f64 - 1.0;
        let ndc_y = 1.0 - 2.0 * (py as f64 + 0.5) / height as f64;
        (self.forward + ndc_x * self.right + ndc_y * self.up).normalize()
    }
}
