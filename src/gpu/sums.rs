//! The running sums the GPU's progressive images share (the truth balls', `truth.rs`; the
//! Monte Carlo's, `montecarlo.rs`; the lobe's, `accumulate.rs`): two sides of textures read
//! and written in turn (a float target of 32 bits is not blendable without a feature), a
//! bind group reading each side, the count of frames summed, the clear of the first frame,
//! the full-screen resolve, and the per-ball quads the passes draw. No pass imports another
//! pass or the renderer: what they share is here.

use std::sync::Arc;

use super::bindings::BallInstance;
use super::pipelines::DEPTH_FORMAT;
use super::plan::Variant;
use super::uniforms::GpuBall;
use crate::brdf::Geometry;
use crate::lut::MuAxis;
use crate::scene::{Scene, MAX_BALLS};

/// The truth's and the Monte Carlo's format: f32 sums (rgb) and the count of estimates
/// (alpha).
pub(crate) const SUM_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Pixels added around each ball's exact bounds without antialiasing: the shader's f32 ray
/// may hit a pixel whose centre the f64 silhouette just misses (the CPU renderer's bins use
/// the same). With antialiasing the pad is [`crate::scene::AA_BOUNDS_PAD_PX`]
/// ([`crate::scene::bounds_pad_px`]).
pub(crate) const QUAD_PAD_PX: f64 = crate::scene::BOUNDS_PAD_PX;

/// What the accumulation and resolve passes draw with: the device, the bind groups 0 and
/// 1, and the pipelines' compile-time choices.
pub(crate) struct Draw<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub group0: &'a wgpu::BindGroup,
    pub group1: &'a wgpu::BindGroup,
    pub geometry: Geometry,
    pub mu_axis: MuAxis,
    pub variant: Variant,
}

/// Whether two scenes give the same summed image but for its exposure and display
/// transform (the sums are linear radiance): equal but for the exposure, tone mapper and
/// transfer curve, with the same map (the same shared texels, turned and scaled alike), so
/// that no frame compares a map's texels.
pub(crate) fn same_scene(a: &Scene, b: &Scene) -> bool {
    let strip = |s: &Scene| Scene {
        environment_map: None,
        exposure: 1.0,
        tone_map: None,
        transfer: None,
        size: None,
        ..s.clone()
    };
    let maps = match (&a.environment_map, &b.environment_map) {
        (None, None) => true,
        (Some(x), Some(y)) => {
            Arc::ptr_eq(&x.map, &y.map)
                && x.rotation_deg == y.rotation_deg
                && x.intensity == y.intensity
        }
        _ => false,
    };
    maps && strip(a) == strip(b)
}

/// The quads of `members` (indices of `scene`'s balls) at `size`, each over its ball's
/// bounds padded by `pad` pixels, with the ball's members `balls[k]`; balls `hidden` (by
/// an identical earlier one), past `balls` or off screen are left out.
pub(crate) fn quads(
    scene: &Scene,
    (balls, hidden): (&[GpuBall], &[bool]),
    size: (u32, u32),
    pad: f64,
    members: impl IntoIterator<Item = usize>,
) -> Vec<BallInstance> {
    let (w, h) = size;
    let basis = scene.camera.basis(w, h);
    members
        .into_iter()
        .filter(|&k| k < balls.len() && !hidden[k])
        .filter_map(|k| {
            let b = &scene.balls[k];
            let rect = basis.sphere_bounds(b.center, b.radius, w, h, pad)?;
            Some(BallInstance {
                rect: rect.map(|v| v as f32),
                ball: balls[k],
            })
        })
        .collect()
}

/// A vertex buffer for up to [`MAX_BALLS`] quads.
pub(crate) fn quad_buffer(device: &wgpu::Device, label: &str) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: (std::mem::size_of::<BallInstance>() * MAX_BALLS) as u64,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A pass's pipeline layout: the renderer's groups 0 and 1 and the pass's own group 2.
pub(crate) fn pipeline_layout(
    device: &wgpu::Device,
    label: &str,
    [group0, group1, group2]: [&wgpu::BindGroupLayout; 3],
) -> wgpu::PipelineLayout {
    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(group0), Some(group1), Some(group2)],
        immediate_size: 0,
    })
}

/// A 2-D texture of `format` and `size` with `usage`.
pub(crate) fn texture(
    device: &wgpu::Device,
    label: &str,
    format: wgpu::TextureFormat,
    (width, height): (u32, u32),
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// The shape of a pair of sums: its label, the format and count of the targets a side
/// holds, the size, whether they are read back (`COPY_SRC`), and whether the passes into
/// them test depth.
pub(crate) struct SumsSpec {
    pub label: &'static str,
    pub format: wgpu::TextureFormat,
    pub targets: usize,
    pub size: (u32, u32),
    pub copy_src: bool,
    pub depth: bool,
}

/// Two sides of `targets` textures (the latest sums and the next), a bind group reading
/// each side, an optional depth target, and the frames summed.
pub(crate) struct Sums {
    label: &'static str,
    size: (u32, u32),
    /// Kept alive with their views (and read back by the Monte Carlo).
    textures: [Vec<wgpu::Texture>; 2],
    views: [Vec<wgpu::TextureView>; 2],
    groups: [wgpu::BindGroup; 2],
    depth: Option<wgpu::TextureView>,
    /// The side holding the latest sums.
    latest: usize,
    /// Frames summed so far.
    frames: u32,
}

impl Sums {
    /// The sums of `spec`, each side's bind group (of `layout`) binding `leading` from
    /// binding 0, then the side's views, then `trailing`.
    pub(crate) fn new(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        spec: SumsSpec,
        leading: &[wgpu::BindingResource<'_>],
        trailing: &[wgpu::BindingResource<'_>],
    ) -> Self {
        let mut usage =
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        if spec.copy_src {
            usage |= wgpu::TextureUsages::COPY_SRC;
        }
        let side = || -> Vec<wgpu::Texture> {
            (0..spec.targets)
                .map(|_| texture(device, spec.label, spec.format, spec.size, usage))
                .collect()
        };
        let textures = [side(), side()];
        let views = textures.each_ref().map(|side| {
            side.iter()
                .map(|t| t.create_view(&Default::default()))
                .collect::<Vec<_>>()
        });
        let groups = views.each_ref().map(|side| {
            let resources = leading
                .iter()
                .cloned()
                .chain(side.iter().map(wgpu::BindingResource::TextureView))
                .chain(trailing.iter().cloned());
            let entries: Vec<wgpu::BindGroupEntry> = resources
                .enumerate()
                .map(|(binding, resource)| wgpu::BindGroupEntry {
                    binding: binding as u32,
                    resource,
                })
                .collect();
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(spec.label),
                layout,
                entries: &entries,
            })
        });
        let depth = spec.depth.then(|| {
            let usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
            texture(device, spec.label, DEPTH_FORMAT, spec.size, usage)
                .create_view(&Default::default())
        });
        Sums {
            label: spec.label,
            size: spec.size,
            textures,
            views,
            groups,
            depth,
            latest: 0,
            frames: 0,
        }
    }

    /// The size summed.
    pub(crate) fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Frames summed so far.
    pub(crate) fn frames(&self) -> u32 {
        self.frames
    }

    /// Starts the sums again from zero at the next frame.
    pub(crate) fn reset(&mut self) {
        self.frames = 0;
    }

    /// The bind group reading the latest sums.
    pub(crate) fn group(&self) -> &wgpu::BindGroup {
        &self.groups[self.latest]
    }

    /// The textures holding the latest sums.
    pub(crate) fn latest_textures(&self) -> &[wgpu::Texture] {
        &self.textures[self.latest]
    }

    /// Records a clear of the latest sums to zero where no frame is summed yet (the first
    /// frame reads zero sums).
    pub(crate) fn clear_if_empty(&self, encoder: &mut wgpu::CommandEncoder) {
        if self.frames == 0 {
            let zero = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
            let attachments = attachments(&self.views[self.latest], zero);
            encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(self.label),
                color_attachments: &attachments,
                ..Default::default()
            });
        }
    }

    /// A render pass into the next sums, its targets starting with `load` (the depth
    /// target, if any, cleared), with the latest sums' bind group as group 2 and `draw`'s
    /// groups 0 and 1. [`Sums::advance`] after it makes them the latest.
    pub(crate) fn next_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        draw: (&wgpu::BindGroup, &wgpu::BindGroup),
        load: wgpu::LoadOp<wgpu::Color>,
    ) -> wgpu::RenderPass<'e> {
        let attachments = attachments(&self.views[1 - self.latest], load);
        let depth = self
            .depth
            .as_ref()
            .map(|view| wgpu::RenderPassDepthStencilAttachment {
                view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(self.label),
            color_attachments: &attachments,
            depth_stencil_attachment: depth,
            ..Default::default()
        });
        pass.set_bind_group(0, draw.0, &[]);
        pass.set_bind_group(1, draw.1, &[]);
        pass.set_bind_group(2, self.group(), &[]);
        pass
    }

    /// Makes the sums [`Sums::next_pass`] wrote the latest, one more frame.
    pub(crate) fn advance(&mut self) {
        self.latest = 1 - self.latest;
        self.frames = self.frames.saturating_add(1);
    }

    /// Records the full-screen `pipeline` reading the latest sums into `view`, starting
    /// with `load`, over the `size` rectangle at its top-left corner (within the sums').
    pub(crate) fn resolve(
        &self,
        draw: &Draw<'_>,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::RenderPipeline,
        (view, load): (&wgpu::TextureView, wgpu::LoadOp<wgpu::Color>),
        size: (u32, u32),
    ) {
        let attachment = [Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load,
                store: wgpu::StoreOp::Store,
            },
        })];
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(self.label),
            color_attachments: &attachment,
            ..Default::default()
        });
        let (w, h) = (self.size.0.min(size.0), self.size.1.min(size.1));
        pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
        pass.set_scissor_rect(0, 0, w, h);
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, draw.group0, &[]);
        pass.set_bind_group(1, draw.group1, &[]);
        pass.set_bind_group(2, self.group(), &[]);
        pass.draw(0..3, 0..1);
    }
}

/// Colour attachments of `views`, each starting with `load` and stored.
fn attachments(
    views: &[wgpu::TextureView],
    load: wgpu::LoadOp<wgpu::Color>,
) -> Vec<Option<wgpu::RenderPassColorAttachment<'_>>> {
    views
        .iter()
        .map(|view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load,
                    store: wgpu::StoreOp::Store,
                },
            })
        })
        .collect()
}
