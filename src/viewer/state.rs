//! The window's GPU state: the surface, the ball renderer and egui's renderer. One frame is
//! the scene image (the balls shaded by [`Renderer::encode`], the headless path, only when
//! the scene, the bake settings or the size changed) copied into the window, then the panel
//! on top; a surface that is outdated, lost, occluded or zero-sized skips the frame or is
//! rebuilt, never panics.

use std::sync::Arc;

use winit::window::Window;

use crate::error::{Error, Result};
use crate::gpu::readback::Readback;
use crate::gpu::{Gpu, Renderer, Target};
use crate::lut::BakeConfig;
use crate::scene::Scene;

/// What the panel drew this frame, in egui's terms.
pub struct Overlay {
    pub primitives: Vec<egui::ClippedPrimitive>,
    pub textures: egui::TexturesDelta,
    pub pixels_per_point: f32,
}

/// How a frame went.
pub enum Frame {
    /// Drawn and presented; with the window's pixels (RGBA8, the whole window) if asked.
    Shown(Option<Vec<u8>>),
    /// Nothing drawn: the window is minimised, occluded, or the surface timed out.
    Skipped,
    /// The surface was outdated or lost and has been rebuilt: draw again.
    Retry,
}

pub struct State {
    pub window: Arc<Window>,
    instance: wgpu::Instance,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    pub renderer: Renderer,
    egui: egui_wgpu::Renderer,
    /// The scene as last shaded, the size of the window (copied under the panel each
    /// frame), and what it holds.
    scene_image: Option<wgpu::Texture>,
    scene_key: Option<SceneKey>,
    scene_draws: u64,
    /// The surface said it no longer fits: reconfigure before the next frame.
    stale: bool,
}

impl State {
    /// Opens a device that can present to `window` (through `instance`).
    pub fn new(
        instance: wgpu::Instance,
        backends: wgpu::Backends,
        window: Arc<Window>,
    ) -> Result<State> {
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| Error::Gpu {
                message: format!("cannot create a surface for the window: {e}"),
            })?;
        let gpu = Gpu::open(&instance, backends, Some(&surface), wgpu::Features::empty())?;
        let size = window.inner_size();
        let config = surface_config(&surface, &gpu, size.width, size.height)?;
        if config.width > 0 && config.height > 0 {
            surface.configure(&gpu.device, &config);
        }
        let egui = egui_wgpu::Renderer::new(
            &gpu.device,
            config.format,
            egui_wgpu::RendererOptions {
                dithering: false,
                ..Default::default()
            },
        );
        Ok(State {
            window,
            instance,
            surface,
            config,
            renderer: Renderer::new(gpu),
            egui,
            scene_image: None,
            scene_key: None,
            scene_draws: 0,
            stale: false,
        })
    }

    /// The window's size in pixels as configured (zero while minimised).
    pub fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// Follows a window resize; a zero size (minimised) leaves the surface unconfigured
    /// until the window is restored.
    pub fn resize(&mut self, width: u32, height: u32) {
        let max = self.renderer.gpu().device.limits().max_texture_dimension_2d;
        self.config.width = width.min(max);
        self.config.height = height.min(max);
        if width > 0 && height > 0 {
            self.surface
                .configure(&self.renderer.gpu().device, &self.config);
        }
    }

    /// Recreates the surface after it was lost.
    fn rebuild_surface(&mut self) -> Result<()> {
        self.surface = self
            .instance
            .create_surface(self.window.clone())
            .map_err(|e| Error::Gpu {
                message: format!("cannot recreate the lost surface: {e}"),
            })?;
        let (w, h) = self.size();
        self.resize(w, h);
        Ok(())
    }

    /// Draws `scene` into the `scene_width` left columns of the window, the panel over the
    /// rest, and presents; `capture` also returns the window's pixels.
    pub fn draw(
        &mut self,
        scene: &Scene,
        scene_width: u32,
        overlay: &Overlay,
        capture: bool,
    ) -> Result<Frame> {
        let (width, height) = self.size();
        if width == 0 || height == 0 {
            return Ok(Frame::Skipped);
        }
        if std::mem::take(&mut self.stale) {
            self.resize(width, height);
        }
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(frame) => frame,
            wgpu::CurrentSurfaceTexture::Suboptimal(frame) => {
                // Drawn this time; reconfigured before the next one.
                self.stale = true;
                frame
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(Frame::Skipped)
            }
            wgpu::CurrentSurfaceTexture::Outdated => {
                self.resize(width, height);
                return Ok(Frame::Retry);
            }
            wgpu::CurrentSurfaceTexture::Lost => {
                self.rebuild_surface()?;
                return Ok(Frame::Retry);
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                return Err(Error::Gpu {
                    message: "acquiring the window's next image failed validation".into(),
                })
            }
        };
        self.renderer.gpu().check()?;
        let device = self.renderer.gpu().device.clone();
        let queue = self.renderer.gpu().queue.clone();
        for (id, deltas) in &overlay.textures.set {
            for delta in deltas {
                self.egui.update_texture(&device, &queue, *id, delta);
            }
        }
        let mut encoder = device.create_command_encoder(&Default::default());
        let scene_width = scene_width.clamp(1, width);
        self.update_scene(scene, scene_width, &mut encoder);
        self.compose(overlay, &frame.texture, &mut encoder);
        let readback = match capture {
            true => Some(self.capture(overlay, &frame.texture, &mut encoder)?),
            false => None,
        };
        queue.submit([encoder.finish()]);
        queue.present(frame);
        for id in &overlay.textures.free {
            self.egui.free_texture(id);
        }
        self.renderer.gpu().check()?;
        let image = match readback {
            Some(readback) => Some(to_rgba(readback.read(&device)?, self.config.format)),
            None => None,
        };
        Ok(Frame::Shown(image))
    }

    /// How many times the balls were shaded (frames that only redraw the panel reuse the
    /// last image of the scene).
    pub fn scene_draws(&self) -> u64 {
        self.scene_draws
    }

    /// Shades the scene into the window-sized scene image, unless it already holds this
    /// scene with these bake settings at this size.
    fn update_scene(
        &mut self,
        scene: &Scene,
        scene_width: u32,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let (width, height) = self.size();
        let key = SceneKey {
            scene: scene.clone(),
            bake: self.renderer.bake_config(),
            size: (scene_width, width, height),
        };
        let fits = self.scene_image.as_ref().is_some_and(|t| {
            (t.width(), t.height()) == (width, height) && t.format() == self.config.format
        });
        if !fits {
            self.scene_image = Some(self.renderer.gpu().device.create_texture(
                &wgpu::TextureDescriptor {
                    label: Some("scene image"),
                    size: extent(width, height),
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: self.config.format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                    view_formats: &[],
                },
            ));
            self.scene_key = None;
        }
        if self.scene_key.as_ref() == Some(&key) {
            return;
        }
        let texture = self.scene_image.as_ref().expect("created above");
        let view = texture.create_view(&Default::default());
        let target = Target {
            view: &view,
            format: self.config.format,
            width: scene_width,
            height,
        };
        self.renderer.encode(scene, target, encoder);
        // The tables may have been re-baked for this scene: key on the settings now held.
        self.scene_key = Some(SceneKey {
            bake: self.renderer.bake_config(),
            ..key
        });
        self.scene_draws += 1;
    }

    /// The scene image copied into `texture`, then the panel drawn over it.
    fn compose(
        &mut self,
        overlay: &Overlay,
        texture: &wgpu::Texture,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let (width, height) = self.size();
        let scene_image = self.scene_image.as_ref().expect("updated before composing");
        encoder.copy_texture_to_texture(
            scene_image.as_image_copy(),
            texture.as_image_copy(),
            extent(width, height),
        );
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [width, height],
            pixels_per_point: overlay.pixels_per_point,
        };
        let gpu = self.renderer.gpu();
        let extra = self.egui.update_buffers(
            &gpu.device,
            &gpu.queue,
            encoder,
            &overlay.primitives,
            &screen,
        );
        // egui paints no callbacks here, so there are no extra command buffers to submit.
        debug_assert!(extra.is_empty());
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.config.format),
            ..Default::default()
        });
        let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("panel"),
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
        self.egui
            .render(&mut pass.forget_lifetime(), &overlay.primitives, &screen);
    }

    /// Records the read of the window's image: straight from the surface texture where the
    /// surface allows copies, else from the same frame composed again into an offscreen
    /// texture (wgpu keeps it alive until the submitted copy is done).
    fn capture(
        &mut self,
        overlay: &Overlay,
        surface_texture: &wgpu::Texture,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<Readback> {
        let device = self.renderer.gpu().device.clone();
        let size = self.size();
        let readback = Readback::new(&device, self.config.format, size)?;
        if self.config.usage.contains(wgpu::TextureUsages::COPY_SRC) {
            readback.record(encoder, surface_texture);
            return Ok(readback);
        }
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("screenshot"),
            size: extent(size.0, size.1),
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: self.config.format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        self.compose(overlay, &texture, encoder);
        readback.record(encoder, &texture);
        Ok(readback)
    }
}

/// What the scene image holds: a scene, drawn with these bake settings, `scene width`
/// columns of a `width x height` window.
#[derive(PartialEq)]
struct SceneKey {
    scene: Scene,
    bake: BakeConfig,
    size: (u32, u32, u32),
}

fn extent(width: u32, height: u32) -> wgpu::Extent3d {
    wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: 1,
    }
}

/// The surface's configuration: a format without an sRGB suffix (the shader writes display
/// values itself, as into the headless renderer's `Rgba8Unorm`), copies allowed where the
/// surface offers them (for screenshots), vsync.
fn surface_config(
    surface: &wgpu::Surface<'_>,
    gpu: &Gpu,
    width: u32,
    height: u32,
) -> Result<wgpu::SurfaceConfiguration> {
    let caps = surface.get_capabilities(&gpu.adapter);
    let format = caps
        .formats
        .iter()
        .copied()
        .find(|f| {
            matches!(
                f,
                wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Rgba8Unorm
            )
        })
        .ok_or_else(|| Error::Gpu {
            message: format!(
                "the window's surface offers no 8-bit non-sRGB format (it offers {:?})",
                caps.formats
            ),
        })?;
    // The scene image is copied in each frame.
    if !caps.usages.contains(wgpu::TextureUsages::COPY_DST) {
        return Err(Error::Gpu {
            message: "the window's surface cannot be copied into".into(),
        });
    }
    let mut usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_DST;
    if caps.usages.contains(wgpu::TextureUsages::COPY_SRC) {
        usage |= wgpu::TextureUsages::COPY_SRC;
    }
    Ok(wgpu::SurfaceConfiguration {
        usage,
        format,
        width,
        height,
        present_mode: wgpu::PresentMode::AutoVsync,
        desired_maximum_frame_latency: 2,
        alpha_mode: caps
            .alpha_modes
            .first()
            .copied()
            .unwrap_or(wgpu::CompositeAlphaMode::Auto),
        view_formats: Vec::new(),
        color_space: wgpu::SurfaceColorSpace::Auto,
    })
}

/// The window's pixels as RGBA8 (the surface may be BGRA).
fn to_rgba(mut pixels: Vec<u8>, format: wgpu::TextureFormat) -> Vec<u8> {
    if format == wgpu::TextureFormat::Bgra8Unorm {
        for px in pixels.chunks_exact_mut(4) {
            px.swap(0, 2);
        }
    }
    pixels
}
