//! A frame's preparation: the scene planned, its tables and map bound, the uniforms and the
//! balls uploaded ([`Frame`]), what the ball pass, the truth's and the lobe's sums and the
//! Monte Carlo draw with.

use super::Renderer;
use crate::error::Result;
use crate::gpu::context::Gpu;
use crate::gpu::environment::EnvUniform;
use crate::gpu::plan::Plan;
use crate::gpu::sums::Draw;
use crate::gpu::uniforms::{self, GpuBall};
use crate::scene::Scene;

impl Renderer {
    /// Plans `scene`, binds its tables and map, and uploads the uniforms of a `w x h`
    /// frame at the lobe frame set ([`Renderer::set_lobe_frame`]).
    pub(super) fn prepare_frame(&mut self, scene: &Scene, w: u32, h: u32) -> Result<Frame> {
        self.prepare_frame_at(scene, (w, h), self.lobe_frame)
    }

    /// [`Renderer::prepare_frame`] at frame `lobe_frame` of the lobe's samples.
    pub(super) fn prepare_frame_at(
        &mut self,
        scene: &Scene,
        (w, h): (u32, u32),
        lobe_frame: u32,
    ) -> Result<Frame> {
        let env_group = self
            .environment
            .bind_group(&self.gpu, scene, self.bake_config)?;
        let plan = self.plan_for(scene).clone();
        let bound = self.tables.bound().expect("plan_for binds");
        let tables = bound.tables.clone();
        let bind = bound.bind.clone();
        let queue = &self.gpu.queue;
        let globals = uniforms::globals(scene, &tables, w, h);
        queue.write_buffer(&self.bindings.globals, 0, bytemuck::bytes_of(&globals));
        // The quads carry their ball (the balls' storage buffer is no longer read).
        let balls = uniforms::balls(scene, &self.prepared);
        let rows = self.prepared.coating_rows().flat();
        queue.write_buffer(&self.bindings.coating_rows, 0, bytemuck::cast_slice(&rows));
        let env_uniform = EnvUniform::of(scene).at_lobe_frame(scene, lobe_frame);
        queue.write_buffer(
            &self.environment.uniform,
            0,
            bytemuck::bytes_of(&env_uniform),
        );
        let lights = uniforms::lights(scene);
        if !lights.is_empty() {
            queue.write_buffer(&self.bindings.lights, 0, bytemuck::cast_slice(&lights));
        }
        let hidden = hidden_duplicates(&balls);
        Ok(Frame {
            plan,
            size: (w, h),
            group0: bind,
            group1: env_group,
            balls,
            hidden,
            env_uniform,
        })
    }
}

/// What a frame draws with: the plan, the image's size, bind groups 0 and 1, the balls
/// (with those hidden by an identical earlier one) and the map's uniform.
pub(super) struct Frame {
    pub(super) plan: Plan,
    pub(super) size: (u32, u32),
    pub(super) group0: wgpu::BindGroup,
    pub(super) group1: wgpu::BindGroup,
    pub(super) balls: Vec<GpuBall>,
    /// [`hidden_duplicates`] of `balls`.
    pub(super) hidden: Vec<bool>,
    pub(super) env_uniform: EnvUniform,
}

impl Frame {
    /// The accumulation passes' device, groups and compile-time choices for this frame.
    pub(super) fn draw<'a>(&'a self, gpu: &'a Gpu) -> Draw<'a> {
        Draw {
            device: &gpu.device,
            queue: &gpu.queue,
            group0: &self.group0,
            group1: &self.group1,
            geometry: self.plan.geometry,
            mu_axis: self.plan.bake.layout.mu_axis,
            variant: self.plan.truth_variant,
        }
    }
}

/// Which balls are hidden by an earlier one of the same centre and radius (as the shader
/// sees them, in f32): such a pair ties at every pixel, where the nearest hit is the lower
/// index's (`cpu::render_radiance`); the depth test would
/// keep whichever quad is drawn first, so the later ball is not drawn at all.
fn hidden_duplicates(balls: &[GpuBall]) -> Vec<bool> {
    let mut seen = std::collections::HashSet::with_capacity(balls.len());
    balls
        .iter()
        // + 0.0 makes -0 and +0 one key.
        .map(|b| {
            let [x, y, z] = b.center;
            !seen.insert([x, y, z, b.radius].map(|v| (v + 0.0).to_bits()))
        })
        .collect()
}
