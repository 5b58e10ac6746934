//! Recording a frame: the pipelines per shader variant, each ball's quad over its
//! screen-space bounds, the background as the render pass's clear.

use super::renderer::{is_linear, pipeline_key, PipelineKey, Renderer, Target};
use super::resources::BallInstance;
use super::{shaders, uniforms};
use crate::scene::Scene;

impl Renderer {
    /// The pipeline of `key`, created on first use: the variant's override constants, the
    /// per-ball entry points with their instance buffer, or the full-screen ones.
    pub(super) fn pipeline(&mut self, key: PipelineKey) -> &wgpu::RenderPipeline {
        let (format, geometry, form, mu_axis, per_ball, variant) = key;
        let device = &self.gpu.device;
        let (module, layout) = (&self.module, &self.pipeline_layout);
        self.pipelines.entry(key).or_insert_with(|| {
            let linear = is_linear(format);
            let constants = shaders::overrides_for(geometry, form, linear, mu_axis, variant);
            let options = wgpu::PipelineCompilationOptions {
                constants: &constants,
                ..Default::default()
            };
            let (vs, fs, buffers): (_, _, &[Option<wgpu::VertexBufferLayout>]) = if per_ball {
                (
                    shaders::VS_BALL,
                    shaders::FS_BALL,
                    &[Some(BallInstance::LAYOUT)],
                )
            } else {
                (shaders::VS_MAIN, shaders::FS_MAIN, &[])
            };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("balls"),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some(vs),
                    compilation_options: options.clone(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: None,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some(fs),
                    compilation_options: options,
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        })
    }

    /// Records the draw of `scene` into `target` on `encoder` (plans the scene, bakes what
    /// its plan needs and is not cached, uploads uniforms and quads now).
    pub fn encode(
        &mut self,
        scene: &Scene,
        target: Target<'_>,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let plan = self.plan_for(scene).clone();
        let bound = self.bound.as_ref().expect("ensure_tables binds");
        let read = bound.read.clone();
        let bind = bound.bind.clone();
        let queue = &self.gpu.queue;
        let (w, h) = (target.width, target.height);
        let globals = uniforms::globals(scene, &read, w, h);
        queue.write_buffer(&self.resources.globals, 0, bytemuck::bytes_of(&globals));
        let balls = uniforms::balls(scene, &read);
        if !balls.is_empty() {
            queue.write_buffer(&self.resources.balls, 0, bytemuck::cast_slice(&balls));
        }
        let lights = uniforms::lights(scene);
        if !lights.is_empty() {
            queue.write_buffer(&self.resources.lights, 0, bytemuck::cast_slice(&lights));
        }
        // Per variant: its pipeline and the range of its quads in the instance buffer.
        let mut draws = Vec::new();
        let mut quads: Vec<BallInstance> = Vec::new();
        let basis = scene.camera.basis(w, h);
        for (variant, members) in &plan.draws {
            let start = quads.len() as u32;
            if plan.per_ball {
                quads.extend(members.iter().filter_map(|&k| {
                    let b = &scene.balls[k];
                    let rect = basis.sphere_bounds(b.center, b.radius, w, h, QUAD_PAD_PX)?;
                    Some(BallInstance {
                        rect: rect.map(|v| v as f32),
                        ball: k as u32,
                    })
                }));
            }
            let key = pipeline_key(&plan, scene, target.format, *variant);
            draws.push((self.pipeline(key).clone(), start..quads.len() as u32));
        }
        if !quads.is_empty() {
            let queue = &self.gpu.queue;
            queue.write_buffer(&self.resources.instances, 0, bytemuck::cast_slice(&quads));
        }
        let clear = if plan.per_ball {
            background(scene, target.format)
        } else {
            wgpu::Color::BLACK
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
            ..Default::default()
        });
        // The image's rectangle: the whole target headless, the scene area in a window.
        pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
        pass.set_scissor_rect(0, 0, w, h);
        pass.set_bind_group(0, &bind, &[]);
        let stride = std::mem::size_of::<BallInstance>() as u64;
        for (pipeline, range) in draws {
            pass.set_pipeline(&pipeline);
            if plan.per_ball {
                if range.is_empty() {
                    continue;
                }
                let bytes = range.start as u64 * stride..range.end as u64 * stride;
                pass.set_vertex_buffer(0, self.resources.instances.slice(bytes));
                pass.draw(0..6, 0..range.len() as u32);
            } else {
                pass.draw(0..3, 0..1);
            }
        }
    }
}

/// Pixels added around each ball's exact bounds: the shader's f32 ray may hit a pixel
/// whose centre the f64 silhouette just misses.
pub const QUAD_PAD_PX: f64 = 2.0;

/// The clear colour: what the shader would give a pixel that hits no ball (the
/// environment, linear on a float target, else through `tone_map`, the CPU renderer's f64
/// mirror of the shader's).
fn background(scene: &Scene, format: wgpu::TextureFormat) -> wgpu::Color {
    let env = scene.environment;
    let value = |c: f64| {
        if is_linear(format) {
            c as f32 as f64
        } else {
            crate::display::tone_map(c, scene.exposure)
        }
    };
    wgpu::Color {
        r: value(env.x),
        g: value(env.y),
        b: value(env.z),
        a: 1.0,
    }
}
