//! The CPU/GPU boundary's Rust side as data: every struct the shaders read from a uniform
//! or storage buffer, by its WGSL name, with the size and member offsets of its Rust twin
//! (`size_of`, `offset_of`). tests/suite/boundary.rs compares them with naga's layout of
//! the composed programs, member by member.

use std::mem::{offset_of, size_of};

use super::environment::{EnvUniform, PrefilterParams};
use super::uniforms::{Globals, GpuBall, GpuLight};
use crate::lut::LutParams;

/// A Rust struct's layout under the name of its WGSL twin.
#[derive(Clone, Copy, Debug)]
pub struct StructLayout {
    /// The WGSL struct's name.
    pub wgsl: &'static str,
    /// The Rust type's name.
    pub rust: &'static str,
    /// `size_of` the Rust type.
    pub size: usize,
    /// Each field's name and `offset_of`, in declaration order.
    pub members: &'static [(&'static str, usize)],
}

/// The layout of `$ty` as the WGSL struct `$wgsl`, fields listed in declaration order.
macro_rules! layout {
    ($wgsl:literal, $ty:ty { $($field:ident),* $(,)? }) => {
        StructLayout {
            wgsl: $wgsl,
            rust: stringify!($ty),
            size: size_of::<$ty>(),
            members: &[$((stringify!($field), offset_of!($ty, $field))),*],
        }
    };
}

/// Every struct of the boundary.
pub const STRUCTS: [StructLayout; 6] = [
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
    layout!(
        "Ball",
        GpuBall {
            center_radius,
            f0_roughness,
            diffuse,
            ms,
            f_add_ms_norm,
            lut_row,
            term,
        }
    ),
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
            padding0,
            padding1,
            padding2,
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
];
