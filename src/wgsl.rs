//! The crate's WGSL for other programs' shaders.
//!
//! [`KULLA_CONTY`] is a WGSL library with no bindings and no override constants: the BRDF
//! terms (`d_ggx`, `geometry_g`, `f_schlick`, `f_micro`, `f_ms`, `f_add_preset`, ...: the
//! f32 twins of [`crate::brdf`], name for name) and the table reads (`lut_loss`, `lut_e`,
//! `lut_loss_avg`, `lut_e_avg`: the f32 twins of [`crate::lut::Tables`]' reads), each taking
//! the table textures and their [`crate::lut::LutParams`] as arguments. naga has no
//! `#include`: put the library before your own shader text.
//!
//! ```
//! let source = format!(
//!     "{}\n{}",
//!     shadeballs::wgsl::KULLA_CONTY,
//!     r#"
//! @group(0) @binding(0) var<uniform> params: LutParams;
//! @group(0) @binding(1) var e_table: texture_2d<f32>;
//! @group(0) @binding(2) var e_avg_table: texture_2d<f32>;
//!
//! @fragment
//! fn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
//!     let mu = p.x / 256.0;
//!     let e = lut_e(e_table, params, mu, 0.5);
//!     let e_avg = lut_e_avg(e_avg_table, params, 0.5);
//!     return vec4<f32>(e, e_avg, 0.0, 1.0);
//! }
//! "#
//! );
//! // The text wgpu's `create_shader_module` takes; naga (wgpu's shader compiler) accepts it.
//! let module = naga::front::wgsl::parse_str(&source).expect("parses");
//! naga::valid::Validator::new(Default::default(), naga::valid::Capabilities::all())
//!     .validate(&module)
//!     .expect("validates");
//! ```

/// The WGSL library: `constants.wgsl` (the constants and `struct LutParams`), `brdf.wgsl`
/// (the BRDF terms) and `lut.wgsl` (the table reads), concatenated.
pub const KULLA_CONTY: &str = concat!(
    include_str!("../shaders/constants.wgsl"),
    "\n",
    include_str!("../shaders/brdf.wgsl"),
    "\n",
    include_str!("../shaders/lut.wgsl"),
);
