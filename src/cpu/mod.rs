//! The CPU reference renderer: the model of `shaders/lighting.wgsl` and `balls.wgsl` per
//! pixel in f64 (the maths of `src/brdf`), with the same camera, the same exact spheres and
//! the same table reads (`Tables::lut_e`, the f32 arithmetic of the shader). It is the
//! truth the GPU image is tested against, and the fallback when there is no adapter.

mod shade;

use glam::DVec3;
use rayon::prelude::*;

pub use shade::{intersect_sphere, shade, TableRead};

use crate::display::{to_unorm8, tone_map};
use crate::lut::Tables;
use crate::scene::{Scene, MAX_BALLS};

/// Linear radiance of every pixel, row-major, row 0 at the top; rows on rayon's pool.
pub fn render_radiance(scene: &Scene, tables: &Tables, width: u32, height: u32) -> Vec<DVec3> {
    render_radiance_with(scene, &TableRead::Lut(tables), width, height)
}

/// As [`render_radiance`] with a chosen source of E and E_avg.
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
    (0..height)
        .into_par_iter()
        .flat_map_iter(|py| {
            (0..width).map(move |px| {
                let d = basis.ray(px, py, width, height);
                let o = basis.origin;
                let mut best: Option<(f64, usize)> = None;
                for (k, b) in balls.iter().enumerate() {
                    let t = intersect_sphere(o, d, b.center, b.radius);
                    if t > 0.0 && best.is_none_or(|(bt, _)| t < bt) {
                        best = Some((t, k));
                    }
                }
                match best {
                    None => scene.environment,
                    Some((t, k)) => {
                        let b = &balls[k];
                        let n = surface_normal(o + t * d - b.center, d);
                        shade(scene, b, n, -d, e, form, geometry)
                    }
                }
            })
        })
        .collect()
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
