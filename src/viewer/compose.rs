//! A window frame from two cached images, so that a frame redoes only what changed:
//!
//! - the *scene image*: the balls shaded by [`Renderer::encode_progressive`] (the headless
//!   path's [`Renderer::encode`], or the lobe's image converging) into the scene area of a
//!   window-sized texture, the background's colour beyond it; shaded again only when the
//!   scene, the bake settings or the size change, or while truth balls accumulate or the
//!   lobe's image converges;
//! - the *frame image*: the scene image with the panel drawn over it by egui; the panel is
//!   drawn again only when egui's output changes or reaches over the scene area (a popup);
//!   otherwise a new scene image is copied into its scene area alone.
//!
//! With a comparison ([`Compare`]) the scene image is composed of two more images, the
//! comparison's two scenes drawn by two renderers (each keeps its own plan and truth
//! sums): the left one's columns left of the split and the right one's right of it (the
//! wipe), or their difference (`difference.rs`).
//!
//! The frame image is copied (or, where the surface forbids copies, drawn) into the window,
//! and screenshots are read from it.

use std::sync::Arc;

use crate::environment::EnvMap;
use crate::gpu::{Renderer, Target};
use crate::lut::BakeConfig;
use crate::scene::Scene;

use super::compare::{Compare, View};
use super::difference::Difference;

/// Most lobe samples a pixel the viewer sums while nothing changes (`ibl_method = "lobe"`):
/// past it, an unchanged scene is not drawn again and the idle viewer goes idle.
pub(crate) const LOBE_SAMPLE_CAP: u32 = 4096;

/// Whether `r`'s lobe image is under [`LOBE_SAMPLE_CAP`] (its latest scene uses the lobe):
/// the scene image is drawn again while it is.
pub(crate) fn lobe_open(r: &Renderer) -> bool {
    r.lobe_samples().is_some_and(|n| n < LOBE_SAMPLE_CAP)
}

/// Whether `t` is an image of `size` in `format`.
fn fits(t: &Option<wgpu::Texture>, size: (u32, u32), format: wgpu::TextureFormat) -> bool {
    t.as_ref()
        .is_some_and(|t| (t.width(), t.height()) == size && t.format() == format)
}

/// What the panel drew this frame, in egui's terms.
pub(crate) struct Overlay {
    /// The chart's labels, drawn into the scene image over the balls (its own renderer).
    pub labels: Vec<egui::ClippedPrimitive>,
    /// The panel (and any popup).
    pub primitives: Vec<egui::ClippedPrimitive>,
    pub textures: egui::TexturesDelta,
    pub pixels_per_point: f32,
    /// Whether egui's shapes differ from the previous frame's.
    pub changed: bool,
    /// Whether everything egui drew lies right of the scene area.
    pub panel_only: bool,
}

/// What the scene image holds: a scene, drawn with these bake settings, `scene width`
/// columns of a `width x height` window.
#[derive(PartialEq)]
struct SceneKey {
    /// The scene without its environment map (in `map`).
    scene: Scene,
    map: Option<MapKey>,
    compare: Option<Compare>,
    bake: BakeConfig,
    size: (u32, u32, u32),
}

impl SceneKey {
    fn new(
        scene: &Scene,
        compare: Option<Compare>,
        bake: BakeConfig,
        size: (u32, u32, u32),
    ) -> Self {
        let mut scene = scene.clone();
        let map = scene.environment_map.take().map(|e| MapKey {
            map: e.map,
            rotation_deg: e.rotation_deg,
            intensity: e.intensity,
        });
        SceneKey {
            scene,
            map,
            compare,
            bake,
            size,
        }
    }
}

/// An environment map as drawn: the same map is the same `Arc` (comparing the texels every
/// frame would cost milliseconds for a large map). The key holds the `Arc`, so its address
/// is not reused while compared.
struct MapKey {
    map: Arc<EnvMap>,
    rotation_deg: f64,
    intensity: f64,
}

impl PartialEq for MapKey {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.map, &other.map)
            && self.rotation_deg == other.rotation_deg
            && self.intensity == other.intensity
    }
}

#[derive(Default)]
pub(crate) struct Layers {
    scene_image: Option<wgpu::Texture>,
    scene_key: Option<SceneKey>,
    frame_image: Option<wgpu::Texture>,
    /// A comparison's two scenes, drawn whole (window-sized, made at its first frame).
    sides: Option<(wgpu::Texture, wgpu::Texture)>,
    /// The difference view's pass (made at its first frame).
    difference: Option<Difference>,
    /// Whether the frame image's panel is egui's latest output.
    panel_current: bool,
    /// How many times the balls were shaded, and the panel drawn.
    pub scene_draws: u64,
    pub panel_draws: u64,
}

impl Layers {
    /// A comparison's two side images as last drawn (`None` before the first comparison).
    pub(crate) fn sides(&self) -> Option<(&wgpu::Texture, &wgpu::Texture)> {
        self.sides.as_ref().map(|(a, b)| (a, b))
    }

    /// Whether the next [`Layers::update`] at `size` in `format` draws the panel again:
    /// egui's output `changed`, reaches over the scene area (not `panel_only`), or the frame
    /// image does not hold the latest panel at that size.
    pub(crate) fn panel_due(
        &self,
        changed: bool,
        panel_only: bool,
        size: (u32, u32),
        format: wgpu::TextureFormat,
    ) -> bool {
        changed || !panel_only || !(self.panel_current && fits(&self.frame_image, size, format))
    }

    /// Records on `encoder` what brings the frame image up to date with `scene` (or the
    /// comparison of it, drawn with `renderers.1` for its right side), drawn in its
    /// `scene_width` left columns, and `overlay`; returns the frame image.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn update(
        &mut self,
        renderers: (&mut Renderer, Option<&mut Renderer>),
        (egui, egui_labels): (&mut egui_wgpu::Renderer, &mut egui_wgpu::Renderer),
        format: wgpu::TextureFormat,
        (width, height): (u32, u32),
        (scene, compare): (&Scene, Option<&Compare>),
        scene_width: u32,
        overlay: &Overlay,
        encoder: &mut wgpu::CommandEncoder,
    ) -> crate::Result<&wgpu::Texture> {
        let (renderer, second) = renderers;
        let size = (width, height);
        let redraw_panel = self.panel_due(overlay.changed, overlay.panel_only, size, format);
        if !fits(&self.scene_image, size, format) || !fits(&self.frame_image, size, format) {
            let device = &renderer.gpu().device;
            self.scene_image = Some(image(device, "scene image", format, width, height));
            self.frame_image = Some(image(device, "frame image", format, width, height));
            self.sides = None;
            self.scene_key = None;
            self.panel_current = false;
        }
        let compare = compare.zip(second);
        let key = SceneKey::new(
            scene,
            compare.as_ref().map(|(c, _)| **c),
            renderer.bake_config(),
            (scene_width, width, height),
        );
        // Truth balls accumulate, and the lobe's image converges: an unchanged scene is
        // drawn again, each draw adding an estimate (the truth's) or `ibl_samples` samples
        // (the lobe's) a pixel, up to the caps.
        let accumulating = |r: &Renderer, s: &Scene| {
            let truth = s.has_truth()
                && r.truth_samples()
                    .is_none_or(|n| n < crate::gpu::MAX_TRUTH_SPP);
            truth || lobe_open(r)
        };
        let scene_changed = self.scene_key.as_ref() != Some(&key)
            || match &compare {
                None => accumulating(renderer, scene),
                Some((c, second)) => {
                    let (a, b) = c.scenes(scene);
                    accumulating(renderer, &a) || accumulating(second, &b)
                }
            };
        if scene_changed {
            let scene_image = self.scene_image.as_ref().expect("created above");
            match compare {
                None => {
                    let view = scene_image.create_view(&Default::default());
                    let target = Target {
                        view: &view,
                        format,
                        width: scene_width,
                        height,
                    };
                    renderer.encode_progressive(scene, target, encoder)?;
                }
                Some((c, second)) => {
                    let sides = (&mut *renderer, second);
                    self.shade_compared(sides, scene, c, (scene_width, height), encoder)?;
                }
            }
            let scene_image = self.scene_image.as_ref().expect("created above");
            if !overlay.labels.is_empty() {
                let labels = (&overlay.labels[..], overlay.pixels_per_point);
                draw_egui(renderer, egui_labels, labels, scene_image, size, encoder);
            }
            // The tables may have been re-baked for this scene: key on the settings held now.
            self.scene_key = Some(SceneKey {
                bake: renderer.bake_config(),
                ..key
            });
            self.scene_draws += 1;
        }
        let (scene_image, frame_image) = (
            self.scene_image.as_ref().expect("created above"),
            self.frame_image.as_ref().expect("created above"),
        );
        if redraw_panel {
            copy(encoder, scene_image, frame_image, (width, height));
            let panel = (&overlay.primitives[..], overlay.pixels_per_point);
            draw_egui(renderer, egui, panel, frame_image, size, encoder);
            self.panel_current = overlay.panel_only;
            self.panel_draws += 1;
        } else if scene_changed {
            copy(encoder, scene_image, frame_image, (scene_width, height));
        }
        Ok(frame_image)
    }

    /// Records the comparison `c` of `scene` into the scene image's `width x height`
    /// scene area: its left scene drawn by the first renderer, its right one by the second,
    /// each into an image of its own, then the wipe's columns of each copied, or their
    /// difference drawn.
    fn shade_compared(
        &mut self,
        (renderer, second): (&mut Renderer, &mut Renderer),
        scene: &Scene,
        c: &Compare,
        (width, height): (u32, u32),
        encoder: &mut wgpu::CommandEncoder,
    ) -> crate::Result<()> {
        let scene_image = self.scene_image.as_ref().expect("made by update");
        let (format, full) = (
            scene_image.format(),
            (scene_image.width(), scene_image.height()),
        );
        let device = renderer.gpu().device.clone();
        let (a, b) = self.sides.get_or_insert_with(|| {
            let side = |label| image(&device, label, format, full.0, full.1);
            (side("left side"), side("right side"))
        });
        let (left, right) = c.scenes(scene);
        let halves = c.halves(width);
        let sides = [(&mut *renderer, &left, &*a), (second, &right, &*b)];
        for ((r, s, t), (_, side_width)) in sides.into_iter().zip(halves) {
            let view = t.create_view(&Default::default());
            let target = Target {
                view: &view,
                format,
                width: side_width,
                height,
            };
            r.encode_progressive(s, target, encoder)?;
        }
        match c.view {
            View::Wipe => {
                let split = c.split_px(width);
                copy_columns(encoder, a, scene_image, 0..split, 0, height);
                copy_columns(encoder, b, scene_image, split..width, split, height);
            }
            View::SideBySide => {
                for (t, (x0, w)) in [(&*a, halves[0]), (&*b, halves[1])] {
                    copy_columns(encoder, t, scene_image, 0..w.min(width - x0), x0, height);
                }
            }
            View::Difference { scale } => {
                let pass = self
                    .difference
                    .get_or_insert_with(|| Difference::new(&device, format));
                let gpu = renderer.gpu();
                let queue = (&gpu.device, &gpu.queue);
                pass.encode(queue, encoder, (a, b), scene_image, (width, height), scale);
            }
        }
        Ok(())
    }
}

/// Copies the columns `columns` of the top `height` rows of `from` into `to`, the first
/// at column `to_x` (nothing for an empty range).
fn copy_columns(
    encoder: &mut wgpu::CommandEncoder,
    from: &wgpu::Texture,
    to: &wgpu::Texture,
    columns: std::ops::Range<u32>,
    to_x: u32,
    height: u32,
) {
    if columns.is_empty() || height == 0 {
        return;
    }
    let at = |t, x| wgpu::TexelCopyTextureInfo {
        origin: wgpu::Origin3d { x, y: 0, z: 0 },
        ..wgpu::Texture::as_image_copy(t)
    };
    encoder.copy_texture_to_texture(
        at(from, columns.start),
        at(to, to_x),
        extent(columns.len() as u32, height),
    );
}

/// egui's `primitives` at `pixels_per_point` over `texture`. Each list drawn in one
/// frame needs its own `egui` renderer: its buffers are written when recorded, not when
/// the pass runs.
fn draw_egui(
    renderer: &Renderer,
    egui: &mut egui_wgpu::Renderer,
    (primitives, pixels_per_point): (&[egui::ClippedPrimitive], f32),
    texture: &wgpu::Texture,
    (width, height): (u32, u32),
    encoder: &mut wgpu::CommandEncoder,
) {
    let screen = egui_wgpu::ScreenDescriptor {
        size_in_pixels: [width, height],
        pixels_per_point,
    };
    let gpu = renderer.gpu();
    let extra = egui.update_buffers(&gpu.device, &gpu.queue, encoder, primitives, &screen);
    // egui paints no callbacks here, so there are no extra command buffers to submit.
    debug_assert!(extra.is_empty());
    let view = texture.create_view(&Default::default());
    let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("egui"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: &view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            },
        })],
        ..Default::default()
    });
    egui.render(&mut pass.forget_lifetime(), primitives, &screen);
}

/// Copies the top-left `width x height` of `from` into `to`.
pub(crate) fn copy(
    encoder: &mut wgpu::CommandEncoder,
    from: &wgpu::Texture,
    to: &wgpu::Texture,
    (width, height): (u32, u32),
) {
    encoder.copy_texture_to_texture(
        from.as_image_copy(),
        to.as_image_copy(),
        extent(width, height),
    );
}

fn image(
    device: &wgpu::Device,
    label: &str,
    format: wgpu::TextureFormat,
    width: u32,
    height: u32,
) -> wgpu::Texture {
    let bytes_view = [format.remove_srgb_suffix()];
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: extent(width, height),
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST
            | wgpu::TextureUsages::TEXTURE_BINDING,
        // The difference pass reads and writes the bytes themselves (`difference.rs`).
        view_formats: if format.is_srgb() { &bytes_view } else { &[] },
    })
}

fn extent(width: u32, height: u32) -> wgpu::Extent3d {
    wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: 1,
    }
}
