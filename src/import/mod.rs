//! Materials from other tools (feature `gltf`; docs/interop.md, "glTF in"): a glTF 2.0
//! file (`.gltf`, or its binary form `.glb`) read as a [`Scene`](crate::scene::Scene) of
//! shading balls, one per sphere the file places, else one per material in a chart. The
//! module sits on the scene layer: it builds scenes and knows no renderer.

mod base64;
mod glb;
mod gltf;
mod json;

pub use gltf::load;
#[cfg(test)]
pub(crate) use gltf::parse;
pub use gltf::GltfMaterial;
pub(crate) use gltf::{external_files, Imported};

use std::path::Path;

/// Whether `path` names a glTF file (`.gltf` or `.glb`, any case): what `render --scene`
/// and `view --scene` read with [`load`] instead of as a TOML scene.
pub(crate) fn is_gltf(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}
