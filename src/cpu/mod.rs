//! The CPU reference renderer: the model of `shaders/lighting.wgsl` and `balls.wgsl` per
//! pixel in f64 (the maths of `src/brdf`), with the same camera, the same exact spheres and
//! the same table reads (`Tables::lut_e`, the f32 arithmetic of the shader). It is the
//! truth the GPU image is tested against, and the fallback when there is no adapter.

pub(crate) mod clearcoat;
pub(crate) mod coating;
mod forms;
mod light;
mod model;
pub mod montecarlo;
mod shade;
pub(crate) mod truth;

use glam::DVec3;
use rayon::prelude::*;

pub use light::CpuEnvironment;
pub use montecarlo::render_montecarlo;
pub use montecarlo::render_montecarlo_part;
pub use montecarlo::MonteCarloImage;
pub use montecarlo::Part;
pub use shade::intersect_sphere;
pub use shade::shade;
pub use truth::render_truth;
pub use truth::TruthProgress;
pub use truth::TruthSettings;
pub(crate) use truth::{render_radiance_with_truth, TruthImage};
// What the anisotropic term's measurement (scene::tests::anisotropy) forms a point's map
// part from.
#[cfg(test)]
pub(crate) use light::{f_add_rgb, loss, loss_avg};
#[cfg(test)]
pub(crate) use model::anisotropic_frame;
#[cfg(test)]
pub(crate) use shade::{shade_environment_map, PointTerms};

use forms::{Forms, LobeSamples};
use shade::shade_point;

use crate::display::{to_rgba8_pixel, DisplayTransform};
use crate::lut::TableSet;
use crate::prepared::Prepared;
use crate::scene::{bounds_pad_px, Ball, CameraBasis, Scene, AA_EDGE_PX, MAX_BALLS};

/// Linear radiance of every pixel, row-major, row 0 at the top; rows on rayon's pool. E
/// and E_avg are read from the tables `prepared` for `scene` as the shader reads them, each
/// ball's coating is the one prepared.
///
/// Each pixel intersects only the balls whose screen-space bounds cover it (the bounds the
/// GPU's quads use, `CameraBasis::sphere_bounds`, widened by the same
/// `crate::scene::BOUNDS_PAD_PX`, or `crate::scene::AA_BOUNDS_PAD_PX` with antialiasing), found through square screen bins of `BIN_PX` pixels: the cost
/// follows the pixels the balls cover, not their number. Candidates are tried in index
/// order, so the nearest hit and its tie-break (lowest index) are those of a loop over
/// every ball.
pub fn render_radiance(scene: &Scene, prepared: &Prepared, width: u32, height: u32) -> Vec<DVec3> {
    let mut frames = render_radiance_at_lobe_frames(scene, prepared, width, height, &[0]);
    frames.pop().expect("one frame asked for")
}

/// [`render_radiance`] at each of `lobe_frames` of the lobe's samples (`ibl_method =
/// "lobe"`: frame `f` takes the sample indices `f N .. (f + 1) N` of each pixel's sequence,
/// as `gpu::Renderer::set_lobe_frame`), an image each, the map prepared once for them all
/// (its prefiltered layers take a second or more); the same image as [`render_radiance`]
/// under the split sum.
pub(crate) fn render_radiance_at_lobe_frames(
    scene: &Scene,
    prepared: &Prepared,
    width: u32,
    height: u32,
    lobe_frames: &[u32],
) -> Vec<Vec<DVec3>> {
    let e = prepared.tables();
    let basis = scene.camera.basis(width, height);
    let balls = &scene.balls[..scene.balls.len().min(MAX_BALLS)];
    let form = scene.preset.f_avg_form();
    let geometry = scene.effective_geometry();
    let bins = Bins::new(&basis, balls, width, height, bounds_pad_px(scene.antialias));
    let bins = &bins;
    // The map prepared as the GPU prepares it (E for its kernels from the 2-D table of the
    // scene's G, whatever `e` reads).
    let ibl = scene.environment_map.as_ref().map(|environment| {
        let tables = match e {
            TableSet::Full(t) if t.config.geometry == geometry => (**t).clone(),
            _ => crate::lut::bake(&crate::lut::BakeConfig {
                geometry,
                ..Default::default()
            }),
        };
        let lobe = scene.ibl_method == crate::environment::IblMethod::Lobe;
        (
            environment,
            CpuEnvironment::reused(environment, &tables, lobe),
        )
    });
    let ibl = &ibl;
    // The map's sun as a light for the balls that take it (`Scene::sun_light`): they are
    // lit by the scene's lights and the sun's, and read the map without it.
    let sun = scene.sun_light();
    let sun_scene = sun.map(|s| {
        let mut lit = scene.clone();
        lit.lights.extend(s.lights);
        lit
    });
    let sun_scene = &sun_scene;
    let background = scene.background_radiance();
    let shows_map = scene.background_shows_map();
    // What a ray in unit direction d that hits no ball sees (`background_radiance`).
    let background_along = move |d: DVec3| match ibl {
        Some((environment, map)) if shows_map => background + map.background(environment, d),
        _ => background,
    };
    // Radiance leaving ball k, hit at distance t along the ray (o, d), towards the eye, at
    // frame `lobe_frame` of the lobe's samples.
    let shade_hit = move |o: DVec3, d: DVec3, t: f64, k: usize, pixel: (u32, u32), lobe_frame| {
        let b = &balls[k];
        let n = surface_normal(o + t * d - b.center, d);
        let takes_sun = sun.is_some_and(|s| s.takes(b));
        let forms = Forms {
            form,
            geometry,
            map: ibl.as_ref().map(|(_, map)| map.for_ball(takes_sun)),
            lobe: LobeSamples::of(scene, pixel, lobe_frame),
            coat: None,
        };
        let coats = (prepared.coat(k), prepared.clearcoat(k));
        let lit = match sun_scene {
            Some(lit) if takes_sun => lit,
            _ => scene,
        };
        shade_point(lit, (b, coats), n, -d, e, &forms)
    };
    let o = basis.origin;
    let size = (width, height);
    let basis = &basis;
    lobe_frames
        .iter()
        .map(|&lobe_frame| {
            (0..height)
                .into_par_iter()
                .flat_map_iter(|py| {
                    (0..width).map(move |px| {
                        match bins.view(basis, balls, size, scene.antialias, (px, py)) {
                            PixelView::Miss(d) => background_along(d),
                            PixelView::Ball(view) => {
                                let (t, k) = (view.footprint.t, view.k);
                                let lo = shade_hit(o, view.hit, t, k, (px, py), lobe_frame);
                                view.mix(lo, || background_along(view.miss))
                            }
                        }
                    })
                })
                .collect()
        })
        .collect()
}

/// What one pixel sees, as the GPU's per-ball draws and their depth test keep it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum PixelView {
    /// No ball: the background along the unit direction of the pixel's centre ray.
    Miss(DVec3),
    /// A ball covers some of the pixel.
    Ball(BallView),
}

/// The ball a pixel sees: its [`Footprint`] with the rays' unit directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BallView {
    /// Index of the ball.
    pub k: usize,
    /// What the pixel sees of it (`footprint.t` along `hit`).
    pub footprint: Footprint,
    /// Unit direction of the ray the ball is shaded along.
    pub hit: DVec3,
    /// Unit direction of the ray the background is seen along (the rest of the pixel).
    pub miss: DVec3,
}

impl BallView {
    /// The pixel's radiance from the ball's `lo` and the background's
    /// ([`footprint_radiance`]).
    pub(crate) fn mix(&self, lo: DVec3, background: impl FnOnce() -> DVec3) -> DVec3 {
        footprint_radiance(&self.footprint, lo, background)
    }
}

/// What a pixel sees of one ball (`Footprint` in `footprint.wgsl`): the distance of the hit it
/// is shaded at (not `> 0`: the ball covers none of the pixel), the image positions (pixels)
/// of the ray the ball is shaded along and of the ray the background is seen along, and
/// the fraction of the pixel the ball covers (1: the centre ray alone).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Footprint {
    /// Distance along the shading ray.
    pub t: f64,
    /// Image position of the ray the ball is shaded along.
    pub hit: (f64, f64),
    /// Image position of the ray the background is seen along.
    pub miss: (f64, f64),
    /// Fraction of the pixel the ball covers.
    pub coverage: f64,
}

/// `ray_distance` of `balls.wgsl`: the distance of the primary ray in unit direction `d`
/// through image position `q` (pixels) of a `size` image from point `c`, and its
/// derivatives along x and y per pixel (y down), analytic: with `D` the unnormalised
/// direction, `dd = (dD - d (d . dD)) / |D|` (`dD = 2 right / w` or `-2 up / h`), and the
/// perpendicular `P = oc - (oc . d) d` moves by `dP = -(oc . dd) d - (oc . d) dd`, its
/// length by `P . dP / |P|`.
pub(crate) fn ray_distance(
    basis: &CameraBasis,
    size: (u32, u32),
    q: (f64, f64),
    d: DVec3,
    c: DVec3,
) -> (f64, f64, f64) {
    let (w, h) = (size.0 as f64, size.1 as f64);
    let oc = basis.origin - c;
    let b = oc.dot(d);
    let p = oc - b * d;
    let len = p.length();
    let ndc_x = 2.0 * q.0 / w - 1.0;
    let ndc_y = 1.0 - 2.0 * q.1 / h;
    let inv = 1.0 / (basis.forward + ndc_x * basis.right + ndc_y * basis.up).length();
    let moved = |dd_raw: DVec3| {
        let dd = (dd_raw - d * d.dot(dd_raw)) * inv;
        let dp = -oc.dot(dd) * d - b * dd;
        p.dot(dp) / len.max(crate::brdf::DIV_EPSILON)
    };
    (
        len,
        moved(2.0 * basis.right / w),
        moved(-2.0 * basis.up / h),
    )
}

/// `box_coverage` of `footprint.wgsl`: the area of the unit pixel square centred on the origin
/// where `n . q <= s` (`n` a unit vector or 0), the integral of the square's chord across
/// `n` (a trapezoid; Gupta and Sproull, "Filtering edges for gray-scale displays",
/// SIGGRAPH 1981, for a box filter).
pub(crate) fn box_coverage(s: f64, n: (f64, f64)) -> f64 {
    let eps = crate::brdf::DIV_EPSILON;
    let (a, b) = (n.0.abs().max(n.1.abs()), n.0.abs().min(n.1.abs()));
    let (h, k) = (0.5 * (a + b), 0.5 * (a - b));
    let corner = 1.0 / (2.0 * a * b).max(eps);
    let area = if s <= -h || s >= h {
        if s > 0.0 {
            1.0
        } else {
            0.0
        }
    } else if s < -k {
        (s + h) * (s + h) * corner
    } else if s > k {
        1.0 - (h - s) * (h - s) * corner
    } else {
        0.5 + s / a.max(eps)
    };
    area.clamp(0.0, 1.0)
}

/// `straddles_silhouette` of `footprint.wgsl`: whether the footprint of a pixel whose centre
/// ray passes `distance` from the centre of the sphere `(c, r)` may straddle its
/// silhouette: within [`AA_EDGE_PX`] footprints of `r`, a footprint being `|o - c|` times
/// [`CameraBasis::pixel_angle`] (what the distance moves at most per pixel). A ball whose
/// radius is under half a footprint (about a pixel: the footprint bounds two pixels' angle)
/// has no silhouette to linearise across the pixel (the covered part's centroid can miss
/// it, leaving a knife edge, `n.v = 0`, that f32 and f64 shade apart): it is shaded along
/// the centre ray, as without antialiasing (issue 28, finding 6).
pub(crate) fn straddles_silhouette(
    basis: &CameraBasis,
    size: (u32, u32),
    distance: f64,
    c: DVec3,
    r: f64,
) -> bool {
    let footprint = (basis.origin - c).length() * basis.pixel_angle(size.0, size.1);
    r >= 0.5 * footprint && (distance - r).abs() <= AA_EDGE_PX * footprint
}

/// `ball_footprint` of `footprint.wgsl`: the footprint of image position `frag` (a pixel's
/// centre) of a `size` image on the sphere `(c, r)`, `antialias` as the scene's. Near the
/// silhouette ([`straddles_silhouette`]), the silhouette linearised at the centre (the
/// level set `r` of [`ray_distance`] and its gradient per pixel) gives the covered fraction
/// ([`box_coverage`]) and the centroids of the covered and uncovered parts along its
/// normal: the rays the ball and the background are seen along. A pixel covered whole
/// keeps the centre ray alone.
pub(crate) fn ball_footprint(
    basis: &CameraBasis,
    size: (u32, u32),
    antialias: bool,
    frag: (f64, f64),
    c: DVec3,
    r: f64,
) -> Footprint {
    let eps = crate::brdf::DIV_EPSILON;
    let o = basis.origin;
    let d = basis.ray_at(frag.0, frag.1, size.0, size.1);
    let centre = Footprint {
        t: intersect_sphere(o, d, c, r),
        hit: frag,
        miss: frag,
        coverage: 1.0,
    };
    if !antialias {
        return centre;
    }
    let oc = o - c;
    if !straddles_silhouette(basis, size, (oc - oc.dot(d) * d).length(), c, r) {
        return centre;
    }
    let (distance, gx, gy) = ray_distance(basis, size, frag, d, c);
    let len = (gx * gx + gy * gy).sqrt();
    let n = (gx / len.max(eps), gy / len.max(eps));
    let s = (r - distance) / len.max(eps);
    let coverage = box_coverage(s, n);
    if coverage >= 1.0 {
        return centre;
    }
    let h = 0.5 * (n.0.abs() + n.1.abs());
    let edge = s.clamp(-h, h);
    let along = |u: f64| (frag.0 + n.0 * u, frag.1 + n.1 * u);
    let hit = along(0.5 * (edge - h));
    let dh = basis.ray_at(hit.0, hit.1, size.0, size.1);
    let mut t = intersect_sphere(o, dh, c, r);
    if t.is_nan() || t <= 0.0 {
        // The centroid of the covered part is inside the silhouette; where rounding says
        // otherwise, the ray's closest approach to the centre.
        t = (c - o).dot(dh);
    }
    Footprint {
        t: if coverage > 0.0 { t } else { -1.0 },
        hit,
        miss: along(0.5 * (edge + h)),
        coverage,
    }
}

/// `footprint_radiance` of `balls.wgsl`: the ball's radiance `lo` (shaded along the ray
/// through `f.hit`) mixed with the background's (along the ray through `f.miss`, asked
/// only where the ball does not cover the whole pixel) by the coverage, in linear radiance.
pub(crate) fn footprint_radiance(
    f: &Footprint,
    lo: DVec3,
    background: impl FnOnce() -> DVec3,
) -> DVec3 {
    if f.coverage < 1.0 {
        // WGSL's mix(a, b, t) = a (1 - t) + b t.
        background() * (1.0 - f.coverage) + lo * f.coverage
    } else {
        lo
    }
}

/// Side of the CPU renderer's screen bins, in pixels.
pub(crate) const BIN_PX: u32 = 16;

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
    fn new(basis: &CameraBasis, balls: &[Ball], width: u32, height: u32, pad_px: f64) -> Self {
        let columns = width.div_ceil(BIN_PX) as usize;
        let rows = height.div_ceil(BIN_PX) as usize;
        let mut members = vec![Vec::new(); columns * rows];
        let mut rects = Vec::with_capacity(balls.len());
        for (k, b) in balls.iter().enumerate() {
            if members.is_empty() {
                break; // An empty image.
            }
            let Some(ndc) = basis.sphere_bounds(b.center, b.radius, width, height, pad_px) else {
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

    /// What pixel `(px, py)` of a `size` image sees. Without antialiasing, the nearest
    /// ball along the centre ray ([`Bins::nearest`]). With it, as the per-ball draw's depth
    /// test keeps: the footprint ([`ball_footprint`]) of the nearest shading distance, the
    /// lowest index on a tie (`radiance_at`).
    fn view(
        &self,
        basis: &CameraBasis,
        balls: &[Ball],
        size: (u32, u32),
        antialias: bool,
        (px, py): (u32, u32),
    ) -> PixelView {
        let (width, height) = size;
        let o = basis.origin;
        if !antialias {
            let d = basis.ray(px, py, width, height);
            return match self.nearest(balls, px, py, o, d) {
                None => PixelView::Miss(d),
                Some((t, k)) => {
                    let frag = (px as f64 + 0.5, py as f64 + 0.5);
                    PixelView::Ball(BallView {
                        k,
                        footprint: Footprint {
                            t,
                            hit: frag,
                            miss: frag,
                            coverage: 1.0,
                        },
                        hit: d,
                        miss: d,
                    })
                }
            };
        }
        let frag = (px as f64 + 0.5, py as f64 + 0.5);
        let mut best: Option<(Footprint, usize)> = None;
        for k in self.candidates(px, py) {
            let b = &balls[k];
            let f = ball_footprint(basis, size, true, frag, b.center, b.radius);
            if f.t > 0.0 && best.as_ref().is_none_or(|(bf, _)| f.t < bf.t) {
                best = Some((f, k));
            }
        }
        let ray = |(x, y): (f64, f64)| basis.ray_at(x, y, width, height);
        match best {
            None => PixelView::Miss(basis.ray(px, py, width, height)),
            Some((f, k)) => PixelView::Ball(BallView {
                k,
                footprint: f,
                hit: ray(f.hit),
                miss: ray(f.miss),
            }),
        }
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

/// `surface_normal` of `screen.wgsl`: the unit normal along `p` (hit point minus centre), or
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

/// RGBA8 of `radiance` (alpha 255) through the homework's display transform (Reinhard,
/// gamma 1/2.2: `DisplayTransform::HOMEWORK`); [`to_display_rgba8`] takes any.
pub fn to_rgba8(radiance: &[DVec3], exposure: f64) -> Vec<u8> {
    to_display_rgba8(radiance, exposure, DisplayTransform::HOMEWORK)
}

/// RGBA8 of `radiance` (alpha 255) through the display transform `display` under
/// `exposure` (`crate::display::display_value`, as the GPU's `target_value` into an
/// `Rgba8Unorm` target).
pub fn to_display_rgba8(radiance: &[DVec3], exposure: f64, display: DisplayTransform) -> Vec<u8> {
    radiance
        .iter()
        .flat_map(|&c| to_rgba8_pixel(c, exposure, display))
        .collect()
}

/// Linear RGBA f32 of `radiance` (alpha 1).
pub fn to_rgba_f32(radiance: &[DVec3]) -> Vec<f32> {
    radiance
        .iter()
        .flat_map(|c| [c.x as f32, c.y as f32, c.z as f32, 1.0])
        .collect()
}

/// The nearest ball the ray from `o` along unit `d` hits, and its distance (f64; of two at
/// one distance, the lower index, as the renderers draw them): what [`ball_index_map`]
/// gives each pixel, for callers that need the hit too.
pub fn nearest_ball(scene: &Scene, o: DVec3, d: DVec3) -> Option<(f64, usize)> {
    scene
        .balls
        .iter()
        .enumerate()
        .map(|(i, b)| (intersect_sphere(o, d, b.center, b.radius), i))
        .filter(|(t, _)| *t > 0.0)
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// Per pixel (row-major, row 0 at the top), the ball whose sphere the centre ray hits
/// first (`None`: background): which ball each pixel of a Monte Carlo image belongs to.
pub fn ball_index_map(scene: &Scene, width: u32, height: u32) -> Vec<Option<usize>> {
    let basis = scene.camera.basis(width, height);
    (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| {
            let d = basis.ray(x, y, width, height);
            nearest_ball(scene, basis.origin, d).map(|(_, i)| i)
        })
        .collect()
}
