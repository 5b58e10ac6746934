//! The truth, pictured (`render --backend truth`): every ball shaded with the random walk
//! of Heitz et al. 2016 on its microsurface ([`crate::walk`]), the exact multiple scattering
//! the real-time models approximate (docs/truth.md, "The truth, pictured").
//!
//! The camera, the primary rays and the sphere hits are those of the other CPU renderers,
//! so a truth image compares pixel for pixel with theirs. Per covered pixel:
//!
//! - **Single scattering, exactly, once.** The lights: `f_micro` (Schlick F, GGX D,
//!   height-correlated Smith G, the walk's own) plus the Lambertian base of a dielectric,
//!   times `L mu_i`. The uniform environment: its radiance times the single-scattering
//!   albedo with Schlick F by deterministic quadrature (`walk::single`, tabulated over `mu`
//!   per distinct ball) plus the base's albedo.
//! - **Multiple scattering, by the walk.** Each estimate traces one path entering along
//!   the view direction (reciprocity: the BRDF is symmetric) and keeps only what its
//!   second and later events give: next-event estimates towards every light
//!   (`f(v, l) mu_l`) and the escaping mass times the radiance arriving from the escape
//!   direction (the uniform environment and the map).
//! - **The map's single scattering** by the Monte Carlo backend's estimator of the
//!   single-scattering model (three strategies, balance heuristic), one draw each per
//!   estimate.
//!
//! Progressive: passes of estimates per pixel, each pixel seeding its generator from
//! `(seed, pixel, pass)`, so the image depends on neither the number of threads nor when
//! the render stops, only on the passes done. It stops at `spp` estimates or when every
//! ball's mean radiance has a relative standard error below the target.
//!
//! A dielectric's walk is its specular layer (`F0` about 0.04); its Lambertian base is the
//! models' (`diffuse (1 - F_avg) / pi`), so the truth differs from them only in the
//! specular layer's multiple scattering.

use std::collections::HashMap;
use std::time::Instant;

use glam::DVec3;
use rayon::prelude::*;

use super::montecarlo::{Lighting, MonteCarloImage, ShadingPoint, LUMINANCE, MAX_SPP};
use super::{surface_normal, Bins};
use crate::brdf::{Geometry, DIV_EPSILON};
use crate::error::{Error, Result};
use crate::lut::TableSet;
use crate::prepared::{with_substrates, Prepared};
use crate::sampling::Frame;
use crate::scene::{bounds_pad_px, Ball, CameraBasis, Model, Scene, MAX_BALLS};
use crate::walk::clearcoat::Layered;
use crate::walk::coating::Coating;
use crate::walk::microsurface::Microsurface;
use crate::walk::single::{single_albedo, Rules};
use crate::walk::{trace, Reflectance, Rng, Schlick};

/// Smallest relative standard error `--stderr` accepts (0.01 %): below it a render of the
/// reference scene would need more than [`MAX_SPP`] estimates a pixel.
pub(crate) const MIN_STDERR: f64 = 1e-4;

/// Nodes of the tabulated single-scattering albedo over `mu` (uniform, linear
/// interpolation: within 1e-4 of the quadrature between nodes at the roughness clamp).
const SINGLE_NODES: usize = 129;

/// What a truth render does and when it stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TruthSettings {
    /// Most estimates per covered pixel (`1..=MAX_SPP`).
    pub spp: u32,
    /// Stop once every ball's mean radiance has a relative standard error below this
    /// (`None`: run all `spp`).
    pub stderr: Option<f64>,
    /// The seed of every pixel's generators.
    pub seed: u64,
    /// Scattering events a path may have (`u32::MAX`: unlimited; 1 leaves single
    /// scattering only, a check of the renderer).
    pub max_order: u32,
    /// Every ball by the walk (`--backend truth`), or only those whose model is
    /// [`Model::Truth`] (the others' pixels are left uncovered, for
    /// `render_radiance_with_truth` to fill).
    pub every_ball: bool,
}

impl Default for TruthSettings {
    fn default() -> Self {
        TruthSettings {
            spp: 64,
            stderr: None,
            seed: 0,
            max_order: u32::MAX,
            every_ball: true,
        }
    }
}

/// Where a progressive truth render stands after a pass.
#[derive(Clone, Debug, PartialEq)]
pub struct TruthProgress {
    /// Estimates per covered pixel so far.
    pub spp: u32,
    /// The most any ball's mean radiance has of relative standard error (`None` before a
    /// variance is known, under 2 estimates).
    pub worst_stderr: Option<f64>,
    /// Seconds since the render started.
    pub seconds: f64,
}

/// A truth image: the Monte Carlo image of every pixel, and per ball the mean radiance of
/// its pixels with that mean's standard error.
#[derive(Clone, Debug, PartialEq)]
pub struct TruthImage {
    /// Mean radiance and its standard error per pixel.
    pub image: MonteCarloImage,
    /// Per ball (scene order): the mean over its pixels and its standard error, per channel.
    pub balls: Vec<BallMean>,
    /// Progress after each pass (the curve of error against time).
    pub passes: Vec<TruthProgress>,
}

/// The mean radiance over a ball's pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BallMean {
    /// Pixels of the ball (nearest hit).
    pub pixels: u64,
    /// Mean radiance over them.
    pub mean: DVec3,
    /// Standard error of that mean, per channel: `sqrt(sum s_p^2) / pixels`, `s_p` the
    /// standard error of pixel `p`'s mean.
    pub std_error: DVec3,
}

impl BallMean {
    /// `Y(std_error) / Y(mean)` (Rec. 709 luminance); 0 for a black ball with no noise,
    /// `None` for a ball no pixel sees.
    pub(crate) fn relative_std_error(&self) -> Option<f64> {
        if self.pixels == 0 {
            return None;
        }
        let (m, s) = (self.mean.dot(LUMINANCE), self.std_error.dot(LUMINANCE));
        Some(if m > DIV_EPSILON { s / m } else { s })
    }
}

/// A covered pixel's fixed part and its running sums.
struct Pixel {
    index: usize,
    px: u32,
    py: u32,
    ball: usize,
    n: DVec3,
    v: DVec3,
    /// The single scattering of the lights and the uniform environment.
    fixed: DVec3,
    sum: DVec3,
    sum_sq: DVec3,
}

/// Renders every ball of `scene` with the random walk at `width x height`. `progress` is
/// called after each pass; returning false stops the render there (the image holds the
/// passes done).
///
/// Errors when `spp` is outside `1..=MAX_SPP`, `stderr` outside `[MIN_STDERR, 1]`, or
/// `max_order` is 0.
pub fn render_truth(
    scene: &Scene,
    prepared: &Prepared,
    width: u32,
    height: u32,
    settings: TruthSettings,
    mut progress: impl FnMut(&TruthProgress) -> bool,
) -> Result<TruthImage> {
    settings.check()?;
    scene.check_clearcoat_truth_lights(settings.every_ball)?;
    // The walk goes through the substrate the base reading implies.
    let substrates = with_substrates(scene, prepared);
    let e = prepared.tables();
    let scene = &substrates;
    let started = Instant::now();
    let basis = scene.camera.basis(width, height);
    let balls = &scene.balls[..scene.balls.len().min(MAX_BALLS)];
    // One ray through each pixel's centre, whatever `scene.antialias` says (the image says
    // so: `MonteCarloImage::antialias`).
    let bins = Bins::new(&basis, balls, width, height, bounds_pad_px(false));
    // The map's single scattering: the Monte Carlo estimator of the single-scattering
    // model under the map alone.
    let map_scene = Scene {
        lights: Vec::new(),
        environment: DVec3::ZERO,
        ..scene.clone()
    };
    let map_lighting = scene
        .environment_map
        .is_some()
        .then(|| Lighting::new(&map_scene));
    let (mean, covered, mut pixels) = walked_pixels(
        scene,
        e,
        (&basis, &bins),
        (width, height),
        settings.every_ball,
    );

    let mut done = 0u32;
    let mut passes = Vec::new();
    let mut ball_means = vec![BallMean::default(); balls.len()];
    while done < settings.spp {
        // Passes double (1, 1, 2, 4, ...) up to 16 estimates, so a stopping test comes
        // often early and rarely costs much late.
        let batch = done.clamp(1, 16).min(settings.spp - done);
        let pass = done;
        let map = map_lighting.as_ref();
        pixels.par_iter_mut().for_each(|p| {
            // A pixel facing away estimates zero: its sums stay zero.
            let Some(walk) = PixelWalk::new(scene, &balls[p.ball], p, e, map.is_some()) else {
                return;
            };
            for k in 0..batch {
                let mut rng = Rng::new(&[
                    settings.seed,
                    u64::from(p.px),
                    u64::from(p.py),
                    u64::from(pass + k),
                ]);
                let x = walk.estimate(scene, e, map, settings.max_order, &mut rng);
                p.sum += x;
                p.sum_sq += x * x;
            }
        });
        done += batch;
        ball_means = means(&pixels, balls.len(), done);
        // None with no ball pixels (issue 38, 9: it read "0.000 %" and met any target).
        let worst_stderr = ball_means
            .iter()
            .filter_map(BallMean::relative_std_error)
            .reduce(f64::max)
            .filter(|_| done >= 2);
        let state = TruthProgress {
            spp: done,
            worst_stderr,
            seconds: started.elapsed().as_secs_f64(),
        };
        let go_on = progress(&state);
        passes.push(state);
        // Without a ball pixel the image is exact (the background alone): two estimates,
        // whose standard errors are zero, and no more.
        let nothing_to_walk = pixels.is_empty() && done >= 2;
        let converged = nothing_to_walk
            || matches!(
                (settings.stderr, worst_stderr),
                (Some(target), Some(worst)) if worst <= target
            );
        if !go_on || converged {
            break;
        }
    }

    let image = walked_image((width, height), done, mean, covered, &pixels);
    Ok(TruthImage {
        image,
        balls: ball_means,
        passes,
    })
}

/// The truth's image after `done` estimates a pixel: the walked `pixels`' means (their fixed
/// part plus their estimates' mean) and standard errors over `mean`, which holds the rest.
fn walked_image(
    (width, height): (u32, u32),
    done: u32,
    mut mean: Vec<DVec3>,
    covered: Vec<bool>,
    pixels: &[Pixel],
) -> MonteCarloImage {
    let n = f64::from(done.max(1));
    let mut std_error = vec![DVec3::ZERO; mean.len()];
    for p in pixels {
        mean[p.index] = p.fixed + p.sum / n;
        std_error[p.index] = pixel_std_error(p, done);
    }
    MonteCarloImage {
        width,
        height,
        spp: done,
        mean,
        std_error,
        covered,
        // One ray through each pixel's centre (`render_truth`).
        antialias: false,
    }
}

impl TruthSettings {
    /// Errors when `spp` is outside `1..=MAX_SPP`, `stderr` outside `[MIN_STDERR, 1]`, or
    /// `max_order` is 0.
    fn check(&self) -> Result<()> {
        let invalid = |what, message: String| Err(Error::Invalid { what, message });
        if !(1..=MAX_SPP).contains(&self.spp) {
            return invalid(
                "samples per pixel",
                format!("{}: must be in 1..={MAX_SPP}", self.spp),
            );
        }
        if let Some(s) = self.stderr {
            if !(MIN_STDERR..=1.0).contains(&s) {
                return invalid(
                    "standard error",
                    format!("{s}: must be in {MIN_STDERR}..=1 (a fraction: 0.005 is 0.5 %)"),
                );
            }
        }
        if self.max_order == 0 {
            return invalid(
                "scattering order",
                "0: a path needs at least one event".into(),
            );
        }
        Ok(())
    }
}

/// Each pixel of a `size` image of `scene` along the ray through its centre (`basis`, the
/// balls found through `bins`): the background where no ball is hit (in the returned mean
/// image), else a pixel to walk (every ball's, or only the truth balls' unless
/// `every_ball`) with its fixed part (exact single scattering), and which pixels those are.
fn walked_pixels(
    scene: &Scene,
    e: &TableSet,
    (basis, bins): (&CameraBasis, &Bins),
    (width, height): (u32, u32),
    every_ball: bool,
) -> (Vec<DVec3>, Vec<bool>, Vec<Pixel>) {
    let balls = &scene.balls[..scene.balls.len().min(MAX_BALLS)];
    let background = Lighting::new(scene);
    let singles = SingleAlbedos::new(scene, balls);
    let mut mean = vec![DVec3::ZERO; (width * height) as usize];
    let mut covered = vec![false; mean.len()];
    let mut pixels: Vec<Pixel> = Vec::new();
    for py in 0..height {
        for px in 0..width {
            let index = (py * width + px) as usize;
            let d = basis.ray(px, py, width, height);
            let o = basis.origin;
            match bins.nearest(balls, px, py, o, d) {
                None => mean[index] = background.background(d),
                Some((_, k)) if !every_ball && balls[k].model != Model::Truth => {}
                Some((t, k)) => {
                    let b = &balls[k];
                    let n = surface_normal(o + t * d - b.center, d);
                    // The ball's emission is added at the first hit: no part of the walk.
                    let fixed = single_fixed(scene, b, n, -d, e, &singles) + b.material.emission;
                    covered[index] = true;
                    pixels.push(Pixel {
                        index,
                        px,
                        py,
                        ball: k,
                        n,
                        v: -d,
                        fixed,
                        sum: DVec3::ZERO,
                        sum_sq: DVec3::ZERO,
                    });
                }
            }
        }
    }
    (mean, covered, pixels)
}

/// The standard error of a pixel's mean after `n` estimates (0 under 2).
fn pixel_std_error(p: &Pixel, n: u32) -> DVec3 {
    if n < 2 {
        return DVec3::ZERO;
    }
    let n = f64::from(n);
    let m = p.sum / n;
    let var = ((p.sum_sq - n * m * m) / (n - 1.0)).max(DVec3::ZERO);
    (var / n).powf(0.5)
}

/// Each ball's mean over its pixels and the standard error of that mean.
fn means(pixels: &[Pixel], count: usize, n: u32) -> Vec<BallMean> {
    let mut sums = vec![(0u64, DVec3::ZERO, DVec3::ZERO); count];
    for p in pixels {
        let s = pixel_std_error(p, n);
        let entry = &mut sums[p.ball];
        entry.0 += 1;
        entry.1 += p.fixed + p.sum / f64::from(n.max(1));
        entry.2 += s * s;
    }
    sums.into_iter()
        .map(|(pixels, sum, var)| {
            let k = pixels.max(1) as f64;
            BallMean {
                pixels,
                mean: sum / k,
                std_error: var.powf(0.5) / k,
            }
        })
        .collect()
}

/// The single-scattering albedo with Schlick F and the walk's G, tabulated over `mu` per
/// distinct (roughness, F0) of the scene's balls (only under a uniform environment).
struct SingleAlbedos {
    tables: HashMap<[u64; 4], Vec<DVec3>>,
}

impl SingleAlbedos {
    fn key(b: &Ball) -> [u64; 4] {
        let f0 = b.material.f0;
        [b.roughness, f0.x, f0.y, f0.z].map(f64::to_bits)
    }

    fn new(scene: &Scene, balls: &[Ball]) -> Self {
        let mut keys: Vec<([u64; 4], Ball)> = Vec::new();
        if scene.environment != DVec3::ZERO {
            for b in balls {
                let key = Self::key(b);
                if !keys.iter().any(|(k, _)| *k == key) {
                    keys.push((key, *b));
                }
            }
        }
        let rules = Rules::default();
        let tables = keys
            .into_par_iter()
            .map(|(key, b)| {
                let channels = b.material.f0.to_array().map(Schlick);
                let table = (0..SINGLE_NODES)
                    .map(|i| {
                        let mu = i as f64 / (SINGLE_NODES - 1) as f64;
                        let a = single_albedo(
                            &rules,
                            mu,
                            b.roughness,
                            &channels,
                            &[Geometry::SmithCorrelated],
                        );
                        DVec3::from_slice(&a[0])
                    })
                    .collect();
                (key, table)
            })
            .collect();
        SingleAlbedos { tables }
    }

    /// The albedo of ball `b` at `mu` (linear between nodes).
    fn at(&self, b: &Ball, mu: f64) -> DVec3 {
        let Some(t) = self.tables.get(&Self::key(b)) else {
            return DVec3::ZERO;
        };
        let x = mu.clamp(0.0, 1.0) * (SINGLE_NODES - 1) as f64;
        let i = (x as usize).min(SINGLE_NODES - 2);
        let f = x - i as f64;
        t[i] * (1.0 - f) + t[i + 1] * f
    }
}

/// The metal's single-scattering model at a point (no term, the walk's G; the coating is
/// walked whole).
fn single_point(scene: &Scene, b: &Ball, n: DVec3, v: DVec3, e: &TableSet) -> ShadingPoint {
    let metal = Ball {
        model: Model::None,
        material: crate::scene::Material::metal(b.material.f0)
            .with_anisotropy(b.material.anisotropy, b.material.anisotropy_rotation),
        ..*b
    };
    let mut point = ShadingPoint::new(scene, &metal, n, v, e);
    point.geometry = Geometry::SmithCorrelated;
    point
}

/// The exact single scattering of the lights and the uniform environment at a point: the
/// metal's, weighted by its share (the coating's is in its walk).
fn single_fixed(
    scene: &Scene,
    b: &Ball,
    n: DVec3,
    v: DVec3,
    e: &TableSet,
    singles: &SingleAlbedos,
) -> DVec3 {
    // A clear coat's ball is walked whole (`PixelWalk::estimate_clearcoat`).
    if !b.material.has_metal() || b.material.clearcoat.is_on() {
        return DVec3::ZERO;
    }
    let point = single_point(scene, b, n, v, e);
    let mut lo = DVec3::ZERO;
    for light in &scene.lights {
        let mu_i = n.dot(light.direction);
        if mu_i > 0.0 && point.mu_o > 0.0 {
            lo += super::montecarlo::model_brdf(&point, light.direction, e) * light.radiance * mu_i;
        }
    }
    // An anisotropic lobe's is walked (its first escapes: `PixelWalk::estimate_metal`).
    if scene.environment != DVec3::ZERO && point.mu_o > 0.0 && !b.material.is_anisotropic() {
        lo += scene.environment * singles.at(b, point.mu_o);
    }
    b.material.metallic * lo
}

/// What a pixel's estimates share, formed once per pixel and pass rather than per
/// estimate: its frame, microsurface and Fresnel channels, the lights above its horizon in
/// the local frame with Lambda of their direction, and (under a map) its
/// single-scattering shading point.
struct PixelWalk {
    frame: Frame,
    surface: Microsurface,
    channels: [Schlick; 3],
    v_local: DVec3,
    lights: [(DVec3, DVec3, f64); crate::scene::MAX_LIGHTS],
    count: usize,
    point: Option<ShadingPoint>,
    metallic: f64,
    /// Whether the metal's lobe is anisotropic.
    anisotropic: bool,
    /// The dielectric part: its walk, its base's albedo, the lights' local directions.
    coating: Option<(Coating, [f64; 3], [DVec3; crate::scene::MAX_LIGHTS])>,
    /// A clear coat's ball: the whole material's walk under its coat.
    clearcoat: Option<Layered>,
}

impl PixelWalk {
    /// `None` where the pixel faces away (`n.v <= 0`): it has nothing to estimate.
    fn new(scene: &Scene, b: &Ball, p: &Pixel, e: &TableSet, map: bool) -> Option<Self> {
        if p.n.dot(p.v) <= 0.0 {
            return None;
        }
        // An anisotropic metal walks its stretched surface in the ball's tangent frame
        // (docs/design/anisotropy.md); its coating stays isotropic.
        let (frame, surface) = match super::model::anisotropic_frame(b, p.n) {
            Some((frame, (t, bt))) => (frame, Microsurface::anisotropic(t, bt)),
            None => (Frame::new(p.n), Microsurface::new(b.roughness)),
        };
        let mut lights = [(DVec3::ZERO, DVec3::ZERO, 0.0); crate::scene::MAX_LIGHTS];
        let mut count = 0;
        for light in &scene.lights {
            let l = frame.to_local(light.direction);
            if l.z > 0.0 {
                lights[count] = (l, light.radiance, surface.lambda(l));
                count += 1;
            }
        }
        Some(PixelWalk {
            v_local: frame.to_local(p.v),
            frame,
            surface,
            channels: b.material.f0.to_array().map(Schlick),
            lights,
            count,
            point: (map && b.material.has_metal()).then(|| single_point(scene, b, p.n, p.v, e)),
            metallic: b.material.metallic,
            anisotropic: b.material.is_anisotropic(),
            clearcoat: b.material.clearcoat.is_on().then(|| layered(b, surface)),
            coating: b.material.has_dielectric().then(|| {
                let coating = Coating::new(b.shading_roughness(), b.material.ior);
                (coating, b.material.diffuse.to_array(), lights.map(|l| l.0))
            }),
        })
    }

    /// One walk through the coating from the view: its light towards each light
    /// (`Coating::estimate`, every order) and its exit's share of the environment.
    fn estimate_coating(&self, scene: &Scene, rng: &mut Rng) -> DVec3 {
        let Some((coating, base, directions)) = &self.coating else {
            return DVec3::ZERO;
        };
        let count = self.count;
        let mut towards = [[0.0; crate::walk::MAX_CHANNELS]; crate::scene::MAX_LIGHTS];
        let env = scene.environment;
        let map_env = scene.environment_map.as_ref();
        let mut escaped = DVec3::ZERO;
        coating.estimate(
            self.v_local,
            base,
            &directions[..count],
            rng,
            &mut towards[..count],
            |_, dir, w| {
                let world = self.frame.to_world(dir);
                let arriving = env + map_env.map_or(DVec3::ZERO, |m| m.radiance(world));
                escaped += DVec3::from_slice(&w[..3]) * arriving;
            },
        );
        let mut x = escaped;
        for (t, &(_, radiance, _)) in towards.iter().zip(&self.lights[..count]) {
            x += DVec3::new(t[0], t[1], t[2]) * radiance;
        }
        x
    }

    /// One estimate of what the fixed part leaves out: the walk's second and later events
    /// towards the lights and out to the environment, and the map's single scattering.
    fn estimate(
        &self,
        scene: &Scene,
        e: &TableSet,
        map: Option<&Lighting<'_>>,
        max_order: u32,
        rng: &mut Rng,
    ) -> DVec3 {
        if let Some(layered) = &self.clearcoat {
            return self.estimate_clearcoat(scene, layered, rng);
        }
        let coating = self.estimate_coating(scene, rng);
        if self.metallic <= 0.0 {
            return coating;
        }
        let metal = self.estimate_metal(scene, e, map, max_order, rng);
        self.metallic * metal + (1.0 - self.metallic) * coating
    }

    /// One path through a clear coat's ball from the view ([`Layered::sample`]): its exit's
    /// share of the uniform environment and the map (the render refuses lights with a clear
    /// coat: `Scene::check_clearcoat_truth_lights`).
    fn estimate_clearcoat(&self, scene: &Scene, layered: &Layered, rng: &mut Rng) -> DVec3 {
        let Some((dir, w)) = layered.sample(self.v_local, rng) else {
            return DVec3::ZERO;
        };
        let world = self.frame.to_world(dir);
        let map = scene.environment_map.as_ref();
        let arriving = scene.environment + map.map_or(DVec3::ZERO, |m| m.radiance(world));
        DVec3::from_array(w) * arriving
    }

    /// The metal's part of [`PixelWalk::estimate`].
    fn estimate_metal(
        &self,
        scene: &Scene,
        e: &TableSet,
        map: Option<&Lighting<'_>>,
        max_order: u32,
        rng: &mut Rng,
    ) -> DVec3 {
        let mut x = DVec3::ZERO;
        let mut escaped = DVec3::ZERO;
        if let (Some(map), Some(point)) = (map, &self.point) {
            x += map.estimate(point, e, 1, rng).0;
        }
        let (frame, surface, channels) = (&self.frame, &self.surface, &self.channels);
        let lights = &self.lights[..self.count];
        let env = scene.environment;
        let map_env = scene.environment_map.as_ref();
        let lit_above = env != DVec3::ZERO || map_env.is_some();
        trace(
            surface,
            self.v_local,
            channels,
            max_order,
            rng,
            |order, dir, mass, w| {
                if order >= 2 && lit_above {
                    let world = frame.to_world(dir);
                    let arriving = env + map_env.map_or(DVec3::ZERO, |m| m.radiance(world));
                    escaped += mass * DVec3::from_slice(w) * arriving;
                } else if order == 1 && self.anisotropic {
                    // The uniform environment's single scattering, which `single_fixed`
                    // tabulates over mu only for an isotropic lobe.
                    escaped += mass * DVec3::from_slice(w) * env;
                }
            },
            |order, wi_k, c, carry, w| {
                if order < 2 {
                    return;
                }
                for &(l, radiance, lambda) in lights {
                    let (phase, cos) = surface.phase(wi_k, l);
                    if phase <= 0.0 {
                        continue;
                    }
                    let base = carry * phase * c.powf(lambda);
                    let f = DVec3::from_array(channels.map(|f| f.eval(cos)));
                    x += base * DVec3::from_slice(w) * f * radiance;
                }
            },
        );
        x + escaped
    }
}

/// Ball `b`'s material under its clear coat, for the walk: its metal on `metal` (the
/// pixel's microsurface, stretched where the lobe is anisotropic, as the bare ball's), its
/// plastic's coating at the shading roughness (isotropic, as the bare ball's).
fn layered(b: &Ball, metal: Microsurface) -> Layered {
    let m = &b.material;
    Layered {
        coat: Coating::new(m.clearcoat.roughness, m.clearcoat.ior),
        weight: m.clearcoat.weight,
        metallic: m.metallic,
        metal,
        f0: m.f0.to_array(),
        plastic: Coating::new(b.shading_roughness(), m.ior),
        rho: m.diffuse.to_array(),
    }
}

/// The CPU reference renderer's image of a scene with truth balls: every other ball as
/// [`super::render_radiance`] shades it, the truth balls by the walk with `settings`
/// (`every_ball` is ignored).
pub(crate) fn render_radiance_with_truth(
    scene: &Scene,
    prepared: &Prepared,
    width: u32,
    height: u32,
    settings: TruthSettings,
) -> Result<Vec<DVec3>> {
    let mut radiance = super::render_radiance(scene, prepared, width, height);
    if scene.has_truth() {
        let settings = TruthSettings {
            every_ball: false,
            ..settings
        };
        let truth = render_truth(scene, prepared, width, height, settings, |_| true)?;
        for ((r, t), covered) in radiance
            .iter_mut()
            .zip(&truth.image.mean)
            .zip(&truth.image.covered)
        {
            if *covered {
                *r = *t;
            }
        }
    }
    Ok(radiance)
}
