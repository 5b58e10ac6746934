//! The pinhole camera, shared by the GPU and CPU renderers: both build the primary ray of a
//! pixel from the same [`CameraBasis`] with the same formula.

use glam::DVec3;

/// A perspective camera looking from `position` at `target`, `+y` up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The eye, in world units.
    pub position: DVec3,
    /// The point looked at (centred in the image).
    pub target: DVec3,
    /// Vertical field of view in degrees, in `(0, 180)`.
    pub vfov_deg: f64,
    /// The narrowest aspect (width / height) at which `vfov_deg` holds: a narrower image
    /// keeps the horizontal field of view an image of this aspect has and widens the
    /// vertical one, so that what fits across the frame at this aspect fits at any
    /// (`Camera::tan_half_vfov`). `None`: `vfov_deg` holds at every aspect (a narrow
    /// image crops the sides). A chart's scenes set it; the homework's keep `None`.
    pub min_aspect: Option<f64>,
}

/// The camera's frame for an image of a given aspect: the ray through pixel centre
/// `(px + 0.5, py + 0.5)` of a `w x h` image is
/// `normalize(forward + ndc_x right + ndc_y up)` with `ndc_x = 2 (px + 0.5) / w - 1` and
/// `ndc_y = 1 - 2 (py + 0.5) / h` (row 0 at the top).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraBasis {
    /// The eye: the camera's position, where every primary ray starts.
    pub origin: DVec3,
    /// Unit vector from the eye towards the target.
    pub forward: DVec3,
    /// Unit right vector scaled by `tan(vfov / 2) * aspect`.
    pub right: DVec3,
    /// Unit up vector scaled by `tan(vfov / 2)`.
    pub up: DVec3,
}

impl Camera {
    /// The reference scene's camera (docs/design/reference-scene.md, "The balls, the light
    /// and the camera").
    pub fn reference() -> Self {
        Camera {
            position: DVec3::new(0.0, 80.0, 300.0),
            target: DVec3::ZERO,
            vfov_deg: 75.0,
            min_aspect: None,
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
        if let Some(a) = self.min_aspect {
            if !(a.is_finite() && (MIN_ASPECT_RANGE.0..=MIN_ASPECT_RANGE.1).contains(&a)) {
                return Some("min_aspect must be in [0.1, 10]");
            }
        }
        None
    }

    /// Why the GPU cannot draw this camera's `width x height` image as the CPU does, if it
    /// cannot (issue 38, 4): a pixel spans less than [`MIN_GPU_PIXEL_ANGLE`], finer than
    /// the f32 directions of the shader's rays resolve (its f32 unit vectors are 6e-8
    /// apart), so its balls would be drawn in blocks of pixels. The camera must be valid.
    pub(crate) fn gpu_problem(&self, width: u32, height: u32) -> Option<String> {
        let angle = self.basis(width, height).pixel_angle(width, height);
        if angle >= MIN_GPU_PIXEL_ANGLE {
            return None;
        }
        let side = f64::from(width.max(height));
        let vfov = 2.0 * (MIN_GPU_PIXEL_ANGLE * side / 2.0).atan().to_degrees();
        Some(format!(
            "a pixel of the {width}x{height} image spans {angle:.2e} rad (vfov_deg {}), \
             finer than the GPU's f32 rays resolve ({MIN_GPU_PIXEL_ANGLE:.1e} rad): use \
             vfov_deg of at least about {vfov:.2e}, or --backend cpu",
            crate::scene::short_number(self.vfov_deg)
        ))
    }

    /// The frame for an image `width / height`. The camera must be valid
    /// ([`Camera::problem`] is `None`; scenes are validated on load).
    pub fn basis(&self, width: u32, height: u32) -> CameraBasis {
        let forward = (self.target - self.position).normalize();
        let right = forward.cross(DVec3::Y).normalize();
        let up = right.cross(forward);
        let aspect = width as f64 / height.max(1) as f64;
        let tan_half = self.tan_half_vfov(aspect);
        CameraBasis {
            origin: self.position,
            forward,
            right: right * tan_half * aspect,
            up: up * tan_half,
        }
    }
}

/// The least angle, in radians (tangent units), that a pixel may span on the GPU: 16 steps
/// of f32 at 1 (`f32::EPSILON`), so that the shader's f32 ray directions place a silhouette
/// within 1/16 of a pixel of the CPU's f64 ones ([`Camera::gpu_problem`]). At 720 rows that
/// is a vfov of 0.08 degrees; at 16384, 1.8 degrees.
pub(crate) const MIN_GPU_PIXEL_ANGLE: f64 = 16.0 * f32::EPSILON as f64;
/// The range a camera's [`Camera::min_aspect`] may take (10:1 either way).
pub(crate) const MIN_ASPECT_RANGE: (f64, f64) = (0.1, 10.0);

impl Camera {
    /// `tan(vfov / 2)` of an image of `aspect` (width / height): `vfov_deg`'s, or, for an
    /// image narrower than [`Camera::min_aspect`], the larger one that keeps that aspect's
    /// horizontal field of view (`tan(hfov / 2) = tan(vfov / 2) * min_aspect`).
    pub(crate) fn tan_half_vfov(&self, aspect: f64) -> f64 {
        let tan_half = (self.vfov_deg.to_radians() * 0.5).tan();
        match self.min_aspect {
            Some(min) if aspect > 0.0 && aspect < min => tan_half * min / aspect,
            _ => tan_half,
        }
    }

    /// How many times smaller than at `height` pixels the chart stands in a `width x
    /// height` image: 1, or `min_aspect / aspect` where [`Camera::min_aspect`] widens the
    /// field of view. The labels' font follows it ([`crate::labels::layout`]).
    pub(crate) fn zoom_out(&self, width: u32, height: u32) -> f64 {
        let aspect = width as f64 / height.max(1) as f64;
        let plain = (self.vfov_deg.to_radians() * 0.5).tan();
        self.tan_half_vfov(aspect) / plain
    }
}

/// Pixels added around each ball's exact bounds by both renderers (the GPU's quads,
/// the CPU's screen bins): the shader's f32 ray may hit a pixel whose centre the f64
/// silhouette just misses. Its rounding moves a silhouette by far less than a pixel
/// (about 1e-7 of the field of view against a pixel's 1e-3), so half a pixel is ample; a
/// wider pad costs frame time where balls are small (2 pixels: 4,096 balls 1.3x slower
/// than with 0.5 on lavapipe, the discarded fragments of each quad's border).
pub(crate) const BOUNDS_PAD_PX: f64 = 0.5;

/// Pixels added around each ball's exact bounds when silhouettes are antialiased
/// ([`crate::scene::Scene::antialias`]): a pixel whose centre misses the ball by up to half
/// its diagonal (0.71 px) is still partly covered, so the bounds grow by 0.75 pixel over
/// [`BOUNDS_PAD_PX`] (each extra pixel of pad costs frame time: docs/benchmarks.md,
/// "Antialiasing").
pub(crate) const AA_BOUNDS_PAD_PX: f64 = BOUNDS_PAD_PX + 0.75;

/// How near a silhouette, in pixel footprints ([`CameraBasis::pixel_angle`] times the
/// distance from the eye), a pixel's centre ray must pass for the pixel to be partly
/// covered (`AA_EDGE_PX` in `footprint.wgsl`): half a pixel's diagonal (0.71) and a margin for
/// the f32 rounding of the shader against this f64 test.
pub(crate) const AA_EDGE_PX: f64 = 1.0;

/// The pad of each ball's bounds for a scene drawn with (`true`) or without antialiasing.
pub fn bounds_pad_px(antialias: bool) -> f64 {
    if antialias {
        AA_BOUNDS_PAD_PX
    } else {
        BOUNDS_PAD_PX
    }
}

/// The relative margin by which `cz^2 - r^2` must be positive (the sphere wholly in front
/// of the eye's plane, `cz` its centre's depth) for [`CameraBasis::sphere_bounds`] to bound
/// it tighter than the screen; it keeps the bounds' division by `cz^2 - r^2` away from 0.
const IN_FRONT_MARGIN: f64 = 1e-9;

impl CameraBasis {
    /// The unit direction of the primary ray through the centre of pixel `(px, py)`.
    pub fn ray(&self, px: u32, py: u32, width: u32, height: u32) -> DVec3 {
        self.ray_at(px as f64 + 0.5, py as f64 + 0.5, width, height)
    }

    /// The unit direction of the primary ray through image position `(x, y)` in pixels
    /// (pixel centres at `+ 0.5`; `primary_ray` in `screen.wgsl`).
    pub(crate) fn ray_at(&self, x: f64, y: f64, width: u32, height: u32) -> DVec3 {
        let ndc_x = 2.0 * x / width as f64 - 1.0;
        let ndc_y = 1.0 - 2.0 * y / height as f64;
        (self.forward + ndc_x * self.right + ndc_y * self.up).normalize()
    }

    /// An upper bound on the angle between the primary rays of two pixels side by side, in
    /// radians: `|d(forward + ndc_x right + ndc_y up)|` over a pixel is `2 |right| / w` (or
    /// `2 |up| / h`), and the unnormalised direction is at least 1 long (forward is a unit
    /// vector orthogonal to right and up), so the unit direction turns by at most that
    /// much. The distance of the ray from a point `s` away from the eye moves by at most
    /// `s` times it a pixel (the tests' measure of pixels from a silhouette).
    pub(crate) fn pixel_angle(&self, width: u32, height: u32) -> f64 {
        let x = 2.0 * self.right.length() / width.max(1) as f64;
        let y = 2.0 * self.up.length() / height.max(1) as f64;
        x.max(y)
    }

    /// The screen-space bounds of the sphere `(center, radius)` as NDC `[x0, y0, x1, y1]`
    /// (x right, y up, clipped to `[-1, 1]`), widened by `pad_px` pixels of a `w x h` image;
    /// `None` when the sphere is entirely off screen or behind the eye. The whole screen
    /// when the sphere is not entirely in front of the eye (the camera inside or beside it).
    ///
    /// Exact for a pinhole: the range of `x / z` over a sphere of centre `(cx, cz)` (camera
    /// frame) ends at the planes `x = t z` tangent to it, where the centre's distance to the
    /// plane is the radius: `(cx - t cz)^2 = r^2 (1 + t^2)`, whose two roots are
    /// `(cx cz +- r sqrt(cx^2 + cz^2 - r^2)) / (cz^2 - r^2)`; likewise in y.
    pub fn sphere_bounds(
        &self,
        center: DVec3,
        radius: f64,
        w: u32,
        h: u32,
        pad_px: f64,
    ) -> Option<[f64; 4]> {
        let full = [-1.0, -1.0, 1.0, 1.0];
        let (sx, sy) = (self.right.length(), self.up.length());
        let p = center - self.origin;
        let cz = p.dot(self.forward);
        // Entirely behind the eye: no primary ray (direction . forward > 0) reaches it.
        if cz <= -radius {
            return None;
        }
        let a = cz * cz - radius * radius;
        // In front with a margin (relative to the distance; it also keeps the division by
        // `a` below finite): otherwise the whole screen.
        if cz <= radius || a <= IN_FRONT_MARGIN * cz * cz || sx <= 0.0 || sy <= 0.0 {
            return Some(full);
        }
        let range = |c: f64, scale: f64, px: u32| {
            let root = radius * (c * c + a).sqrt();
            let pad = 2.0 * pad_px / px.max(1) as f64;
            let lo = (c * cz - root) / a / scale - pad;
            let hi = (c * cz + root) / a / scale + pad;
            (lo.max(-1.0), hi.min(1.0))
        };
        let (x0, x1) = range(p.dot(self.right) / sx, sx, w);
        let (y0, y1) = range(p.dot(self.up) / sy, sy, h);
        if !(x0 < x1 && y0 < y1) {
            return None;
        }
        Some([x0, y0, x1, y1])
    }
}
