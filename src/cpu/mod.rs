//! The CPU reference renderer: the model of `shaders/lighting.wgsl` and `balls.wgsl` per
//! pixel in f64 (the maths of `src/brdf`), with the same camera, the same exact spheres and
//! the same table reads (`Tables::lut_e`, the f32 arithmetic of the shader). It is the
//! truth the GPU image is tested against, and the fallback when there is no adapter.

pub mod montecarlo;
mod shade;
pub mod truth;

use glam::DVec3;
use rayon::prelude::*;

pub use montecarlo::{render_montecarlo, render_montecarlo_part, MonteCarloImage, Part};
pub use shade::{
    intersect_sphere, shade, shade_environment_map, CpuEnvironment, PointTerms, TableRead,
};
pub use truth::{
    render_radiance_with_truth, render_truth, BallMean, TruthImage, TruthProgress, TruthSettings,
};

use shade::{shade_with_terms, Forms};

use crate::display::{to_unorm8, tone_map};
use crate::lut::Tables;
use crate::scene::{Ball, CameraBasis, Scene, BOUNDS_PAD_PX, MAX_BALLS};

/// Linear radiance of every pixel, row-major, row 0 at the top; rows on rayon's pool.
pub fn render_radiance(scene: &Scene, tables: &Tables, width: u32, height: u32) -> Vec<DVec3> {
    render_radiance_with(scene, &TableRead::Lut(tables), width, height)
}

/// As [`render_radiance`] with a chosen source of E and E_avg.
///
/// Each pixel intersects only the balls whose screen-space bounds cover it (the bounds the
/// GPU's quads use, [`CameraBasis::sphere_bounds`], widened by the same
/// [`BOUNDS_PAD_PX`]), found through square screen bins of [`BIN_PX`] pixels: the cost
/// follows the pixels the balls cover, not their number. Candidates are tried in index
/// order, so the nearest hit and its tie-break (lowest index) are those of a loop over
/// every ball.
pub fn render_radiance_with(
    scene: &Scene,
    e: &TableRead<'_>,
    width: u32,
    height: u32,
) -> Vec<DVec3> {
    let basis = scene.camera.basis(width, height);
    let balls = &scene.balls[..scene.balls.len().min(MAX_BALLS)];
    let form = scene.preset.f_avg_form();
    let geometry = scene.effective_geometry();
    let bins = Bins::new(&basis, balls, width, height);
    let bins = &bins;
    // The map prepared as the GPU prepares it (E for its kernels from the 2-D table of the
    // scene's G, whatever `e` reads).
    let ibl = scene.environment_map.as_ref().map(|environment| {
        let tables = match e {
            TableRead::Lut(t) if t.config.geometry == geometry => (*t).clone(),
            _ => crate::lut::bake(&crate::lut::BakeConfig {
                geometry,
                ..Default::default()
            }),
        };
        (environment, CpuEnvironment::new(environment, &tables))
    });
    let ibl = &ibl;
    let background = scene.background_radiance();
    let shows_map = scene.background_shows_map();
    (0..height)
        .into_par_iter()
        .flat_map_iter(|py| {
            (0..width).map(move |px| {
                let d = basis.ray(px, py, width, height);
                let o = basis.origin;
                match (bins.nearest(balls, px, py, o, d), ibl) {
                    (None, Some((environment, map))) if shows_map => {
                        background + map.background(environment, d)
                    }
                    (None, _) => background,
                    (Some((t, k)), _) => {
                        let b = &balls[k];
                        let n = surface_normal(o + t * d - b.center, d);
                        let forms = Forms {
                            form,
                            geometry,
                            split: ibl.as_ref().map(|(_, map)| &map.split),
                        };
                        let (lo, terms) = shade_with_terms(scene, b, n, -d, e, &forms);
                        match ibl {
                            Some((_, map)) => {
                                lo + shade_environment_map(scene, b, n, -d, &terms, map)
                            }
                            None => lo,
                        }
                    }
                }
            })
        })
        .collect()
}

/// Side of the CPU renderer's screen bins, in pixels.
pub const BIN_PX: u32 = 16;

/// The balls that may cover each bin of the image: each ball's pixel rectangle (from its
/// padded bounds) and, per bin, the indices of the balls whose rectangle meets it, in
/// index order.
struct Bins {
    columns: usize,
    /// Per ball: first and last pixel column and row its bounds cover (inclusive).
    rects: Vec<[u32; 4]>,
    /// Per bin (row-major), the balls that meet it.
    members: Vec<Vec<u32>>,
}

impl Bins {
    fn new(basis: &CameraBasis, balls: &[Ball], width: u32, height: u32) -> Self {
        let columns = width.div_ceil(BIN_PX) as usize;
        let rows = height.div_ceil(BIN_PX) as usize;
        let mut members = vec![Vec::new(); columns * rows];
        let mut rects = Vec::with_capacity(balls.len());
        for (k, b) in balls.iter().enumerate() {
            if members.is_empty() {
                break; // An empty image.
            }
            let Some(ndc) = basis.sphere_bounds(b.center, b.radius, width, height, BOUNDS_PAD_PX)
            else {
                // Off screen or behind the eye: no pixel sees it.
                rects.push([1, 0, 1, 0]);
                continue;
            };
            let rect = pixel_rect(ndc, width, height);
            rects.push(rect);
            let [x0, x1, y0, y1] = rect.map(|v| (v / BIN_PX) as usize);
            for row in y0..=y1 {
                for col in x0..=x1 {
                    members[row * columns + col].push(k as u32);
                }
            }
        }
        Bins {
            columns,
            rects,
            members,
        }
    }

    /// The nearest of the balls covering pixel `(px, py)` along its ray from `o` in unit
    /// direction `d`: (distance, index), the lowest index on a tie.
    fn nearest(
        &self,
        balls: &[Ball],
        px: u32,
        py: u32,
        o: DVec3,
        d: DVec3,
    ) -> Option<(f64, usize)> {
        let mut best: Option<(f64, usize)> = None;
        for k in self.candidates(px, py) {
            let b = &balls[k];
            let t = intersect_sphere(o, d, b.center, b.radius);
            if t > 0.0 && best.is_none_or(|(bt, _)| t < bt) {
                best = Some((t, k));
            }
        }
        best
    }

    /// The balls whose bounds cover pixel `(px, py)`, in index order.
    fn candidates(&self, px: u32, py: u32) -> impl Iterator<Item = usize> + '_ {
        let bin = (py / BIN_PX) as usize * self.columns + (px / BIN_PX) as usize;
        self.members[bin]
            .iter()
            .map(|&k| k as usize)
            .filter(move |&k| {
                let [x0, x1, y0, y1] = self.rects[k];
                (x0..=x1).contains(&px) && (y0..=y1).contains(&py)
            })
    }
}

/// The pixels whose centres NDC bounds `[x0, y0, x1, y1]` (y up) hold, widened by one pixel
/// each side against rounding: `[first column, last column, first row, last row]` within
/// the image (row 0 at the top). Pixel centre `px + 0.5` is at NDC `2 (px + 0.5) / w - 1`.
fn pixel_rect(ndc: [f64; 4], width: u32, height: u32) -> [u32; 4] {
    let [x0, y0, x1, y1] = ndc;
    let (w, h) = (width as f64, height as f64);
    let clamp = |v: f64, n: u32| v.clamp(0.0, (n - 1) as f64) as u32;
    [
        clamp(((x0 + 1.0) * 0.5 * w - 0.5).floor() - 1.0, width),
        clamp(((x1 + 1.0) * 0.5 * w - 0.5).ceil() + 1.0, width),
        clamp(((1.0 - y1) * 0.5 * h - 0.5).floor() - 1.0, height),
        clamp(((1.0 - y0) * 0.5 * h - 0.5).ceil() + 1.0, height),
    ]
}

/// `surface_normal` of `balls.wgsl`: the unit normal along `p` (hit point minus centre), or
/// facing the eye (`-d`) when `|p| <= DIV_EPSILON`, where `normalize` would give NaN (a
/// ball far smaller than its distance from the camera, its hit point lost in rounding).
pub fn surface_normal(p: DVec3, d: DVec3) -> DVec3 {
    let eps = crate::brdf::DIV_EPSILON;
    if p.length_squared() > eps * eps {
        p.normalize()
    } else {
        -d
    }
}

/// Tone-mapped RGBA8 of `radiance` (alpha 255).
pub fn to_rgba8(radiance: &[DVec3], exposure: f64) -> Vec<u8> {
    radiance
        .iter()
        .flat_map(|c| {
            let m = |v| to_unorm8(tone_map(v, exposure));
            [m(c.x), m(c.y), m(c.z), 255]
        })
        .collect()
}

/// Linear RGBA f32 of `radiance` (alpha 1).
pub fn to_rgba_f32(radiance: &[DVec3]) -> Vec<f32> {
    radiance
        .iter()
        .flat_map(|c| [c.x as f32, c.y as f32, c.z as f32, 1.0])
        .collect()
}
