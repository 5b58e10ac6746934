//! The balls' pass: the map behind the balls, then each planned draw's quads with its
//! pipeline (`balls.wgsl`), into any target; the truth balls' resolve after it.

use super::frame::Frame;
use super::{Renderer, Target};
use crate::error::Result;
use crate::gpu::bindings::BallInstance;
use crate::gpu::pipelines::{is_bits, is_linear, pipeline_key};
use crate::gpu::sums;
use crate::scene::Scene;

impl Renderer {
    /// Records the draw of `scene` into `target` on `encoder` (plans the scene, bakes what
    /// its plan needs and is not cached, uploads uniforms and quads now): the balls' pass,
    /// then the truth balls' accumulation and resolve. Fails, recording nothing, where the
    /// scene's map is new and its mip chain would not fit in memory.
    pub fn encode(
        &mut self,
        scene: &Scene,
        target: Target<'_>,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<()> {
        let frame = self.prepare_frame(scene, target.width, target.height)?;
        self.encode_balls(scene, &frame, target, encoder);
        if !frame.plan.truth.is_empty() && self.truth_frame(scene, &frame, encoder) {
            let draw = frame.draw(&self.gpu);
            self.truth
                .resolve(&draw, encoder, target.view, target.format, frame.size);
        }
        Ok(())
    }

    /// Records the balls' pass of `frame` into `target`: each variant's quads with its
    /// pipeline, then the map behind the balls (a full-screen draw at the far plane, where
    /// no ball is).
    pub(super) fn encode_balls(
        &mut self,
        scene: &Scene,
        frame: &Frame,
        target: Target<'_>,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let (quads, ranges) = ball_quads(scene, frame);
        let (background_pipeline, draws) = self.ball_pipelines(frame, target.format, ranges);
        if !quads.is_empty() {
            let queue = &self.gpu.queue;
            queue.write_buffer(&self.bindings.instances, 0, bytemuck::cast_slice(&quads));
        }
        let clear = background(scene, target.format);
        // The per-ball draw's depth target, the size of the whole colour attachment.
        let depth = {
            let texture = target.view.texture();
            let size = (texture.width(), texture.height());
            self.depth.view(&self.gpu.device, size)
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("balls"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target.view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(clear),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        // The image's rectangle: the whole target headless, the scene area in a window.
        let (w, h) = frame.size;
        pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
        pass.set_scissor_rect(0, 0, w, h);
        pass.set_bind_group(0, &frame.group0, &[]);
        pass.set_bind_group(1, &frame.group1, &[]);
        let stride = std::mem::size_of::<BallInstance>() as u64;
        for (pipeline, range) in draws {
            if range.is_empty() {
                continue;
            }
            pass.set_pipeline(&pipeline);
            let bytes = range.start as u64 * stride..range.end as u64 * stride;
            pass.set_vertex_buffer(0, self.bindings.instances.slice(bytes));
            pass.draw(0..4, 0..range.len() as u32);
        }
        // The map behind the balls last, at the far plane: the depth test skips every pixel
        // a ball wrote (a third of the showcase's frame), where it would be overdrawn.
        if let Some(pipeline) = background_pipeline {
            pass.set_pipeline(&pipeline);
            pass.draw(0..3, 0..1);
        }
    }

    /// The pipelines of `frame`'s balls' pass into `format`: the map's background draw
    /// (where the background shows it), and each planned draw's pipeline with its range
    /// of quads.
    fn ball_pipelines(
        &mut self,
        frame: &Frame,
        format: wgpu::TextureFormat,
        ranges: Vec<std::ops::Range<u32>>,
    ) -> (
        Option<wgpu::RenderPipeline>,
        Vec<(wgpu::RenderPipeline, std::ops::Range<u32>)>,
    ) {
        let plan = &frame.plan;
        let device = &self.gpu.device;
        let shows_map = frame.env_uniform.shows_map == 1.0;
        // A scene of truth balls alone has no per-ball draw: its background is drawn with
        // the truth's variant (same map and display), not left the clear colour.
        let first = plan.draws.first().map(|(v, _)| v);
        let first = first.or((!plan.truth.is_empty()).then_some(&plan.truth_variant));
        let background = match first {
            Some(variant) if shows_map => Some(
                self.pipelines
                    .background(
                        device,
                        format,
                        *variant,
                        plan.geometry,
                        plan.bake.layout.mu_axis,
                    )
                    .clone(),
            ),
            _ => None,
        };
        let draws = plan
            .draws
            .iter()
            .zip(ranges)
            .map(|((variant, _), range)| {
                let key = pipeline_key(plan, format, *variant);
                (self.pipelines.get(device, key).clone(), range)
            })
            .collect();
        (background, draws)
    }
}

/// The per-ball quads of `frame`, grouped by the plan's draws, and each draw's range of
/// them.
fn ball_quads(scene: &Scene, frame: &Frame) -> (Vec<BallInstance>, Vec<std::ops::Range<u32>>) {
    let pad = crate::scene::bounds_pad_px(scene.antialias);
    let mut quads: Vec<BallInstance> = Vec::new();
    let mut ranges = Vec::with_capacity(frame.plan.draws.len());
    for (_, members) in &frame.plan.draws {
        let start = quads.len() as u32;
        let balls = (&frame.balls[..], &frame.hidden[..]);
        let members = members.iter().copied();
        quads.extend(sums::quads(scene, balls, frame.size, pad, members));
        ranges.push(start..quads.len() as u32);
    }
    (quads, ranges)
}

/// The clear colour: what the shader would give a pixel that hits no ball (the
/// environment, linear on a float target, its f32 bits on an `Rgba32Uint` one, else
/// through the display transform, decoded to linear on an sRGB target). wgpu clears an integer target with each component
/// `as u32` (Vulkan and GL alike), which keeps a u32 held in an f64 exactly.
pub(super) fn background(scene: &Scene, format: wgpu::TextureFormat) -> wgpu::Color {
    let env = scene.background_radiance();
    if is_bits(format) {
        let bits = |c: f64| (c as f32).to_bits() as f64;
        return wgpu::Color {
            r: bits(env.x),
            g: bits(env.y),
            b: bits(env.z),
            a: bits(1.0),
        };
    }
    let value = if is_linear(format) {
        env.as_vec3().as_dvec3()
    } else {
        // wgpu clears an sRGB target with a linear colour, which the hardware encodes.
        crate::display::target_value(env, scene.exposure, scene.display(), format.is_srgb())
    };
    wgpu::Color {
        r: value.x,
        g: value.y,
        b: value.z,
        a: 1.0,
    }
}
