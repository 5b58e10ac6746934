//! The window's GPU state: the surface, the ball renderer and egui's renderer. A frame is
//! the frame image of [`Layers`] (the balls and the panel, each redone only when it
//! changed) copied into the window; a surface that is outdated, lost, occluded or
//! zero-sized skips the frame or is rebuilt, never panics.

use std::sync::Arc;

use winit::window::Window;

use crate::error::{Error, Result};
use crate::gpu::readback::Readback;
use crate::gpu::{Gpu, Renderer};
use crate::scene::Scene;

use super::blit::Blit;
use super::compare::Compare;
use super::compose::{self, lobe_open, Layers, Overlay, LOBE_SAMPLE_CAP};

/// How a frame went.
pub(crate) enum Frame {
    /// Drawn and presented; with the window's pixels (RGBA8, the whole window) if asked.
    Shown(Option<Vec<u8>>),
    /// Nothing drawn: the window is minimised or occluded (its restoring event redraws).
    Skipped,
    /// The surface was outdated or lost and has been rebuilt, or timed out: draw again.
    Retry,
}

pub(crate) struct State {
    pub window: Arc<Window>,
    instance: wgpu::Instance,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    pub renderer: Renderer,
    /// The renderer of a comparison's right side (made at its first frame), on the same
    /// device: its own plan and truth sums.
    second: Option<Renderer>,
    egui: egui_wgpu::Renderer,
    /// egui's renderer of the chart's labels (drawn into the scene image in the same frame
    /// as the panel: each needs its own buffers).
    egui_labels: egui_wgpu::Renderer,
    layers: Layers,
    /// The draw that puts the frame image into a surface that cannot be copied into.
    blit: Option<Blit>,
    /// The surface said it no longer fits: reconfigure before the next frame.
    stale: bool,
}

impl State {
    /// Opens a device that can present to `window` (through `instance`).
    pub(crate) fn new(
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
        let config = surface_config(&surface, &gpu, 0, 0)?;
        let blit = (!config.usage.contains(wgpu::TextureUsages::COPY_DST))
            .then(|| Blit::new(&gpu.device, config.format));
        let egui_renderer = || {
            egui_wgpu::Renderer::new(
                &gpu.device,
                config.format,
                egui_wgpu::RendererOptions {
                    dithering: false,
                    ..Default::default()
                },
            )
        };
        let (egui, egui_labels) = (egui_renderer(), egui_renderer());
        let size = window.inner_size();
        let mut state = State {
            window,
            instance,
            surface,
            config,
            renderer: viewer_renderer(Renderer::new(gpu)),
            second: None,
            egui,
            egui_labels,
            layers: Layers::default(),
            blit,
            stale: false,
        };
        state.resize(size.width, size.height);
        Ok(state)
    }

    /// The window's size in pixels as configured (zero while minimised).
    pub(crate) fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// Follows a window resize; a zero size (minimised) leaves the surface unconfigured
    /// until the window is restored.
    pub(crate) fn resize(&mut self, width: u32, height: u32) {
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

    /// Draws `scene` (or its comparison) into the `scene_width` left columns of the window,
    /// the panel over the rest, and presents; `capture` also returns the window's pixels.
    /// egui's texture changes are applied whether or not the frame is shown: egui sends
    /// each only once.
    pub(crate) fn draw(
        &mut self,
        scene: (&Scene, Option<&Compare>),
        scene_width: u32,
        overlay: &Overlay,
        capture: bool,
    ) -> Result<Frame> {
        let (device, queue) = (&self.renderer.gpu().device, &self.renderer.gpu().queue);
        for (id, deltas) in &overlay.textures.set {
            for delta in deltas {
                self.egui.update_texture(device, queue, *id, delta);
                self.egui_labels.update_texture(device, queue, *id, delta);
            }
        }
        let frame = self.draw_frame(scene, scene_width, overlay, capture);
        for id in &overlay.textures.free {
            self.egui.free_texture(id);
            self.egui_labels.free_texture(id);
        }
        frame
    }

    fn draw_frame(
        &mut self,
        scene: (&Scene, Option<&Compare>),
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
            wgpu::CurrentSurfaceTexture::Occluded => return Ok(Frame::Skipped),
            wgpu::CurrentSurfaceTexture::Timeout => return Ok(Frame::Retry),
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
        let mut encoder = device.create_command_encoder(&Default::default());
        if scene.1.is_some() {
            self.second_renderer();
        }
        let frame_image = self.layers.update(
            (&mut self.renderer, self.second.as_mut()),
            (&mut self.egui, &mut self.egui_labels),
            self.config.format,
            (width, height),
            scene,
            scene_width.clamp(1, width),
            overlay,
            &mut encoder,
        )?;
        match &self.blit {
            None => compose::copy(&mut encoder, frame_image, &frame.texture, (width, height)),
            Some(blit) => {
                let view = frame.texture.create_view(&Default::default());
                blit.encode(&device, &mut encoder, frame_image, &view);
            }
        }
        let readback = match capture {
            true => {
                let readback = Readback::new(&device, self.config.format, (width, height))?;
                readback.record(&mut encoder, frame_image);
                Some(readback)
            }
            false => None,
        };
        queue.submit([encoder.finish()]);
        queue.present(frame);
        self.renderer.gpu().check()?;
        let image = match readback {
            Some(readback) => Some(to_rgba(readback.read(&device)?, self.config.format)),
            None => None,
        };
        Ok(Frame::Shown(image))
    }

    /// Whether the next frame draws the panel again ([`Layers::panel_due`] at the window's
    /// size): only then does it need egui's output tessellated.
    pub(crate) fn panel_due(&self, changed: bool, panel_only: bool) -> bool {
        self.layers
            .panel_due(changed, panel_only, self.size(), self.config.format)
    }

    /// The renderer of a comparison's right side, made if it is not yet.
    pub(crate) fn second_renderer(&mut self) -> &mut Renderer {
        let gpu = self.renderer.gpu().share();
        let bake = self.renderer.bake_config();
        let second = self
            .second
            .get_or_insert_with(|| viewer_renderer(Renderer::new(gpu)));
        second.set_bake_config(bake);
        second
    }

    /// Whether truth balls of `scene` (or of either side of its comparison) are still
    /// accumulating: each draw of the unchanged scene adds an estimate a pixel, up to the
    /// headless cap.
    pub(crate) fn truth_accumulating(&self, scene: &Scene, compare: Option<&Compare>) -> bool {
        let open = |r: Option<&Renderer>, s: &Scene| {
            s.has_truth()
                && r.is_none_or(|r| {
                    r.truth_samples()
                        .is_none_or(|n| n < crate::gpu::MAX_TRUTH_SPP)
                })
        };
        match compare {
            None => open(Some(&self.renderer), scene),
            Some(c) => {
                let (a, b) = c.scenes(scene);
                open(Some(&self.renderer), &a) || open(self.second.as_ref(), &b)
            }
        }
    }

    /// Whether the lobe's image of the latest scene drawn (or of either side of the
    /// comparison `compare`) is still converging: each draw of the unchanged scene adds
    /// `ibl_samples` samples a pixel, up to [`LOBE_SAMPLE_CAP`].
    pub(crate) fn lobe_converging(&self, compare: Option<&Compare>) -> bool {
        lobe_open(&self.renderer)
            || (compare.is_some() && self.second.as_ref().is_some_and(lobe_open))
    }

    /// The comparison `c`'s numbers a ball ([`super::compare::numbers`]), measured from
    /// its two side images as the latest frame drew them in a scene area `scene_width`
    /// wide; `None` before a comparison was drawn.
    pub(crate) fn ball_numbers(
        &self,
        scene: &Scene,
        c: &Compare,
        scene_width: u32,
    ) -> Result<Option<Vec<super::compare::BallNumbers>>> {
        let Some((a, b)) = self.layers.sides() else {
            return Ok(None);
        };
        let (device, queue) = (&self.renderer.gpu().device, &self.renderer.gpu().queue);
        let height = self.size().1.min(a.height());
        let halves = c.halves(scene_width.min(a.width()));
        let sizes = [(halves[0].1, height), (halves[1].1, height)];
        let mut encoder = device.create_command_encoder(&Default::default());
        let mut readbacks = Vec::new();
        for (t, size) in [(a, sizes[0]), (b, sizes[1])] {
            let readback = Readback::new(device, t.format(), size)?;
            readback.record(&mut encoder, t);
            readbacks.push(readback);
        }
        queue.submit([encoder.finish()]);
        let mut images = Vec::new();
        for readback in readbacks {
            images.push(to_rgba(readback.read(device)?, self.config.format));
        }
        let images = (&images[0][..], &images[1][..]);
        Ok(Some(super::compare::numbers(c, scene, images, sizes)))
    }

    /// How many times the balls were shaded, and the panel drawn (frames that change
    /// only one of them reuse the other).
    pub(crate) fn draws(&self) -> (u64, u64) {
        (self.layers.scene_draws, self.layers.panel_draws)
    }
}

/// `renderer` with the viewer's cap on the lobe's samples.
fn viewer_renderer(mut renderer: Renderer) -> Renderer {
    renderer.set_lobe_sample_cap(Some(LOBE_SAMPLE_CAP));
    renderer
}

/// The surface's configuration: an 8-bit format, one without an sRGB suffix where the
/// surface offers one (the shader writes display values itself, as into the headless
/// renderer's `Rgba8Unorm`), else an sRGB one (the renderer then writes linear values that
/// the hardware encodes to the same bytes, and the panel's egui does likewise), copies
/// allowed where the surface offers them (for screenshots), vsync.
fn surface_config(
    surface: &wgpu::Surface<'_>,
    gpu: &Gpu,
    width: u32,
    height: u32,
) -> Result<wgpu::SurfaceConfiguration> {
    // The viewer opens its own device (`Gpu::open`), so the adapter is there.
    let adapter = gpu.adapter.as_ref().ok_or_else(|| Error::Gpu {
        message: "the viewer needs the adapter it opened".into(),
    })?;
    let caps = surface.get_capabilities(adapter);
    let format = surface_format(&caps.formats).ok_or_else(|| Error::Gpu {
        message: format!(
            "the window's surface offers no 8-bit RGBA or BGRA format (it offers {:?})",
            caps.formats
        ),
    })?;
    // The frame image is copied in where the surface allows it, else drawn ([`Blit`]).
    let usage =
        wgpu::TextureUsages::RENDER_ATTACHMENT | (caps.usages & wgpu::TextureUsages::COPY_DST);
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

/// The surface format the viewer draws into, of those `offered`: 8-bit RGBA or BGRA,
/// without an sRGB suffix where one is offered, else with it.
pub(crate) fn surface_format(offered: &[wgpu::TextureFormat]) -> Option<wgpu::TextureFormat> {
    use wgpu::TextureFormat as F;
    let pick = |wanted: [F; 2]| offered.iter().copied().find(|f| wanted.contains(f));
    pick([F::Bgra8Unorm, F::Rgba8Unorm]).or_else(|| pick([F::Bgra8UnormSrgb, F::Rgba8UnormSrgb]))
}

/// The window's pixels as RGBA8 (the surface may be BGRA).
fn to_rgba(mut pixels: Vec<u8>, format: wgpu::TextureFormat) -> Vec<u8> {
    if matches!(
        format,
        wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
    ) {
        for px in pixels.chunks_exact_mut(4) {
            px.swap(0, 2);
        }
    }
    pixels
}
