//! The one test binary (each extra binary links wgpu again). Modules by layer.

mod bad_input;
mod bounds;
mod clearcoat;
mod cli;
mod cli_bake;
mod cli_fuzz;
mod cli_render;
mod docs;
mod emission;
mod environment;
mod example;
mod extreme_scenes;
mod fuzz;
mod gltf_import;
mod golden;
mod gpu_faults;
mod hostile;
mod hostile_round4;
mod interop;
mod ktx2;
mod labels;
mod layers;
mod montecarlo;
// The GPU and image helpers, shared with the lab's tests and the crate's own.
#[allow(dead_code)]
mod pixels;
mod probe;
mod props;
mod readme_library;
mod readme_pictures;
mod scene_gen;
mod showcase;
mod tone_map;
mod truth_progress;
mod truth_render;
mod viewer;
