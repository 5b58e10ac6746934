//! Mouse orbit and zoom: the camera turns about its target on a sphere, never reaching the
//! poles (where the `+y` up vector gives no frame, [`Camera::problem`]).

use glam::DVec3;

use crate::scene::Camera;

/// Radians of turn per pixel of mouse drag.
pub(crate) const RADIANS_PER_PIXEL: f64 = 0.006;
/// Highest elevation of the camera above (or below) its target, in degrees.
pub(crate) const MAX_PITCH_DEG: f64 = 85.0;
/// Zoom factor per scroll line (distance multiplied by this for each line towards the scene).
pub(crate) const ZOOM_PER_LINE: f64 = 0.9;
/// Distance limits as multiples of the starting distance.
pub(crate) const ZOOM_RANGE: (f64, f64) = (0.05, 20.0);

/// The camera turned by `yaw` radians about `+y` through the target and raised by `pitch`
/// radians, its distance kept.
pub(crate) fn orbit(camera: &Camera, yaw: f64, pitch: f64) -> Camera {
    let offset = camera.position - camera.target;
    let distance = offset.length();
    let current_yaw = offset.x.atan2(offset.z);
    let current_pitch = (offset.y / distance).clamp(-1.0, 1.0).asin();
    let limit = MAX_PITCH_DEG.to_radians();
    let (y, p) = (
        current_yaw + yaw,
        (current_pitch + pitch).clamp(-limit, limit),
    );
    let direction = DVec3::new(p.cos() * y.sin(), p.sin(), p.cos() * y.cos());
    Camera {
        position: camera.target + direction * distance,
        ..*camera
    }
}

/// The camera moved along its line of sight by `ZOOM_PER_LINE ^ lines`, its distance kept
/// within [`ZOOM_RANGE`] of `home_distance`.
pub(crate) fn zoom(camera: &Camera, lines: f64, home_distance: f64) -> Camera {
    let offset = camera.position - camera.target;
    let distance = offset.length() * ZOOM_PER_LINE.powf(lines);
    let distance = distance.clamp(home_distance * ZOOM_RANGE.0, home_distance * ZOOM_RANGE.1);
    Camera {
        position: camera.target + offset.normalize() * distance,
        ..*camera
    }
}
