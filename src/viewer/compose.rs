//! A window frame from two cached images, so that a frame redoes only what changed:
//!
//! - the *scene image*: the balls shaded by [`Renderer::encode`] (the headless path) into
//!   the scene area of a window-sized texture, the background's colour beyond it; shaded
//!   again only when the scene, the bake settings or the size change;
//! - the *frame image*: the scene image with the panel drawn over it by egui; the panel is
//!   drawn again only when egui's output changes or reaches over the scene area (a popup);
//!   otherwise a new scene image is copied into its scene area alone.
//!
//! The frame image is copied (or, where the surface forbids copies, drawn) into the window,
//! and screenshots are read from it.

use std::sync::Arc;

use crate::environment::EnvMap;
use crate::gpu::{Renderer, Target};
use crate::lut::BakeConfig;
use crate::scene::Scene;

/// Whether `t` is an image of `size` in `format`.
fn fits(t: &Option<wgpu::Texture>, size: (u32, u32), format: wgpu::TextureFormat) -> bool {
    t.as_ref()
        .is_some_and(|t| (t.width(), t.height()) == size && t.format() == format)
}

/// What the panel drew this frame, in egui's terms.
pub struct Overlay {
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
    bake: BakeConfig,
    size: (u32, u32, u32),
}

impl SceneKey {
    fn new(scene: &Scene, bake: BakeConfig, size: (u32, u32, u32)) -> Self {
        let mut scene = scene.clone();
        let map = scene.environment_map.take().map(|e| MapKey {
            map: e.map,
            rotation_deg: e.rotation_deg,
            intensity: e.intensity,
        });
        SceneKey {
            scene,
            map,
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
pub struct Layers {
    scene_image: Option<wgpu::Texture>,
    scene_key: Option<SceneKey>,
    frame_image: Option<wgpu::Texture>,
    /// Whether the frame image's panel is egui's latest output.
    panel_current: bool,
    /// How many times the balls were shaded, and the panel drawn.
    pub scene_draws: u64,
    pub panel_draws: u64,
}

impl Layers {
    /// Whether the next [`Layers::update`] at `size` in `format` draws the panel again:
    /// egui's output `changed`, reaches over the scene area (not `panel_only`), or the frame
    /// image does not hold the latest panel at that size.
    pub fn panel_due(
        &self,
        changed: bool,
        panel_only: bool,
        size: (u32, u32),
        format: wgpu::TextureFormat,
    ) -> bool {
        changed || !panel_only || !(self.panel_current && fits(&self.frame_image, size, format))
    }

    /// Records on `encoder` what brings the frame image up to date with `scene`, drawn in
    /// its `scene_width` left columns, and `overlay`; returns the frame image.
    #[allow(clippy::too_many_arguments)]
    pub fn update(
        &mut self,
        renderer: &mut Renderer,
        (egui, egui_labels): (&mut egui_wgpu::Renderer, &mut egui_wgpu::Renderer),
        format: wgpu::TextureFormat,
        (width, height): (u32, u32),
        scene: &Scene,
        scene_width: u32,
        overlay: &Overlay,
        encoder: &mut wgpu::CommandEncoder,
    ) -> crate::Result<&wgpu::Texture> {
        let size = (width, height);
        let redraw_panel = self.panel_due(overlay.changed, overlay.panel_only, size, format);
        if !fits(&self.scene_image, size, format) || !fits(&self.frame_image, size, format) {
            let device = &renderer.gpu().device;
            self.scene_image = Some(image(device, "scene image", format, width, height));
            self.frame_image = Some(image(device, "frame image", format, width, height));
            self.scene_key = None;
            self.panel_current = false;
        }
        let key = SceneKey::new(scene, renderer.bake_config(), (scene_width, width, height));
        // Truth balls accumulate: an unchanged scene is drawn again, each draw adding an
        // estimate a pixel, up to the cap.
        let accumulating = scene.has_truth()
            && renderer
                .truth_samples()
                .is_none_or(|n| n < crate::gpu::MAX_TRUTH_SPP);
        let scene_changed = self.scene_key.as_ref() != Some(&key) || accumulating;
        let (scene_image, frame_image) = (
            self.scene_image.as_ref().expect("created above"),
            self.frame_image.as_ref().expect("created above"),
        );
        if scene_changed {
            let view = scene_image.create_view(&Default::default());
            let target = Target {
                view: &view,
                format,
                width: scene_width,
                height,
            };
            renderer.encode(scene, target, encoder)?;
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
pub fn copy(
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
        view_formats: &[],
    })
}

fn extent(width: u32, height: u32) -> wgpu::Extent3d {
    wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: 1,
    }
}
