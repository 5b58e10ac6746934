//! The CPU/GPU boundary's Rust side as data: every struct the shaders read from a uniform
//! or storage buffer, by its WGSL name, with the size, member offsets and member types of
//! its Rust twin (`size_of`, `offset_of`, [`WgslType`]). src/gpu/tests/boundary.rs compares
//! them with naga's layout of the composed programs, member by member.

use std::mem::{offset_of, size_of};

use super::bindings::BallInstance;
use super::environment::{EnvUniform, PrefilterParams};
use super::montecarlo::McParams;
use super::uniforms::{Globals, GpuBall, GpuLight, BALL_MEMBERS};
use crate::environment::prefilter::BrightTexel;
use crate::lut::LutParams;

/// A Rust struct's layout under the name of its WGSL twin.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StructLayout {
    /// The WGSL struct's name.
    pub wgsl: &'static str,
    /// The Rust type's name.
    pub rust: &'static str,
    /// `size_of` the Rust type.
    pub size: usize,
    /// Each field's name, `offset_of` and WGSL type ([`WgslType`]), in declaration order.
    pub members: &'static [(&'static str, usize, &'static str)],
}

/// The WGSL type a Rust field stands for in a buffer.
pub(crate) trait WgslType {
    /// The type as WGSL writes it (`f32`, `vec4<u32>`, a struct's name).
    const WGSL: &'static str;
}

macro_rules! wgsl_type {
    ($($rust:ty => $wgsl:literal),* $(,)?) => {
        $(impl WgslType for $rust {
            const WGSL: &'static str = $wgsl;
        })*
    };
}

wgsl_type! {
    f32 => "f32",
    u32 => "u32",
    [f32; 2] => "vec2<f32>",
    [f32; 3] => "vec3<f32>",
    [f32; 4] => "vec4<f32>",
    [u32; 2] => "vec2<u32>",
    [u32; 4] => "vec4<u32>",
    LutParams => "LutParams",
}

/// The WGSL type of the field `field` picks out of an `S` (a closure `|s| &s.name`).
const fn wgsl_of<S, T: WgslType>(_field: fn(&S) -> &T) -> &'static str {
    T::WGSL
}

/// The layout of `$ty` as the WGSL struct `$wgsl`, fields listed in declaration order.
macro_rules! layout {
    ($wgsl:literal, $ty:ty { $($field:ident),* $(,)? }) => {
        StructLayout {
            wgsl: $wgsl,
            rust: stringify!($ty),
            size: size_of::<$ty>(),
            members: &[$((
                stringify!($field),
                offset_of!($ty, $field),
                wgsl_of(|s: &$ty| &s.$field),
            )),*],
        }
    };
}

/// The WGSL [`BALL_MEMBERS`] generate (`gpu::ball`), line by line: what `types.wgsl`
/// holds between the ball's markers (src/gpu/tests/boundary.rs).
pub(crate) fn ball_wgsl() -> Vec<String> {
    super::ball::wgsl(BALL_MEMBERS)
}

/// The vertex attributes of a ball's quad (`BallInstance::LAYOUT`, generated from
/// [`BALL_MEMBERS`]): what `vs_ball`'s input must declare, location for location.
pub(crate) fn ball_attributes() -> &'static [wgpu::VertexAttribute] {
    BallInstance::LAYOUT.attributes
}

/// [`BALL_MEMBERS`] as [`StructLayout::members`].
const BALL_LAYOUT: [(&str, usize, &str); BALL_MEMBERS.len()] = {
    let mut out = [("", 0, ""); BALL_MEMBERS.len()];
    let mut k = 0;
    while k < out.len() {
        let m = BALL_MEMBERS[k];
        out[k] = (m.name, m.offset, m.ty.wgsl());
        k += 1;
    }
    out
};

/// Every struct of the boundary.
pub(crate) const STRUCTS: [StructLayout; 8] = [
    layout!(
        "Globals",
        Globals {
            cam_origin,
            cam_forward,
            cam_right,
            cam_up,
            environment,
            size,
            counts,
            lut,
        }
    ),
    StructLayout {
        wgsl: "Ball",
        rust: "GpuBall",
        size: size_of::<GpuBall>(),
        members: &BALL_LAYOUT,
    },
    layout!(
        "Light",
        GpuLight {
            direction,
            radiance
        }
    ),
    layout!(
        "EnvUniform",
        EnvUniform {
            rotation,
            intensity,
            shows_map,
            background,
            lobe,
        }
    ),
    layout!(
        "LutParams",
        LutParams {
            mu_scale,
            mu_bias,
            r_scale,
            r_bias,
            mu_size,
            r_size,
            mu_axis,
            e_avg_read,
            r_min,
            padding_a,
            padding_b,
            padding_c,
        }
    ),
    layout!(
        "PrefilterParams",
        PrefilterParams {
            size,
            source,
            layer,
            limits,
        }
    ),
    layout!("BrightTexel", BrightTexel { direction, power }),
    layout!(
        "McParams",
        McParams {
            seed,
            pass_index,
            lit,
            map_size,
            strategies,
            shape,
            part,
            padding,
        }
    ),
];
