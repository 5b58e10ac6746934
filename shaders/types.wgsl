// types.wgsl: the renderer's override constants and uniform layouts, shared by its entry
// points. Every struct here has a Rust twin of the same layout (src/gpu/uniforms.rs,
// src/gpu/environment.rs), checked member by member by tests/suite/boundary.rs.

#define_import_path shadeballs::types
#import shadeballs::constants::LutParams

// MAX_BALLS and MAX_LIGHTS: the sizes of the balls storage buffer and the lights uniform
// array. TERM_*: a ball's multiple-scattering term (Ball.term; src/scene Model), each
// ball's own, so one pipeline draws every model (a branch per ball, coherent over its
// pixels); 0 without one. LAYERING_*: how a ball's dielectric base sits under its coating
// (Ball.layering; src/scene Layering). COATING_ROW_LEN: the values of a coating row
// (coating_rows, lut::coating). TONE_MAP_*, TRANSFER_*: the values of TONE_MAP and TRANSFER.
// generated from the Rust constants by tests/suite/boundary.rs: do not edit
const MAX_BALLS: u32 = 4096u; // scene::MAX_BALLS
const MAX_LIGHTS: u32 = 16u; // scene::MAX_LIGHTS
const TERM_KULLA_CONTY: u32 = 1u; // gpu::uniforms::TERM_CODES
const TERM_TURQUIN: u32 = 2u; // gpu::uniforms::TERM_CODES
const TERM_FDEZ_AGUERA: u32 = 3u; // gpu::uniforms::TERM_CODES
const LAYERING_CONSTANT: u32 = 0u; // gpu::uniforms::LAYERING_CODES
const LAYERING_GLTF: u32 = 1u; // gpu::uniforms::LAYERING_CODES
const LAYERING_VIEW_ONLY: u32 = 2u; // gpu::uniforms::LAYERING_CODES
const LAYERING_RECIPROCAL: u32 = 3u; // gpu::uniforms::LAYERING_CODES
const LAYERING_PHYSICAL: u32 = 4u; // gpu::uniforms::LAYERING_CODES
const COATING_ROW_LEN: u32 = 48u; // lut::COATING_ROW_LEN
const TONE_MAP_REINHARD: u32 = 0u; // display::ToneMap::code
const TONE_MAP_ACES: u32 = 1u; // display::ToneMap::code
const TONE_MAP_AGX: u32 = 2u; // display::ToneMap::code
const TONE_MAP_KHRONOS_NEUTRAL: u32 = 3u; // display::ToneMap::code
const TONE_MAP_NONE: u32 = 4u; // display::ToneMap::code
const TRANSFER_SRGB: u32 = 0u; // display::Transfer::code
const TRANSFER_GAMMA_2_2: u32 = 1u; // display::Transfer::code
// end of the generated constants

// Pipeline-time choices (PipelineCompilationOptions::constants), folded by the compiler:
// no uniform branches on them.
override GEOMETRY: u32;
// The mu axis of the tables the pipeline reads (MU_AXIS_*): a pipeline-time choice
// (lut_params in lighting.wgsl).
override MU_AXIS: u32;
// 1: write linear radiance (float target, for EXR); 0: tone-mapped display value.
override OUTPUT_LINEAR: u32;
// The display transform of a display target (src/display.rs; the scene's, Scene::display):
// the tone mapper (TONE_MAP_*) and the transfer curve (TRANSFER_*); SRGB_TARGET = 1 on a
// `*Srgb` format, whose hardware encodes: the shader then writes the display value decoded
// to linear (target_value in screen.wgsl). Ignored when OUTPUT_LINEAR = 1.
override TONE_MAP: u32 = 0u;
override TRANSFER: u32 = 0u;
override SRGB_TARGET: u32 = 0u;
// The multiple-scattering term (src/gpu/plan.rs TermMode): 0: compiled out (no E read
// for it), the same image as every flag off; 1 (default): a branch on each ball's flag (one
// pipeline for every ball); 2: compiled in for every ball the pipeline draws (the planned
// renderer draws the balls with the term with it, those without with 0).
override MS_TERM: u32 = 1u;
// 1 (default): the uniform environment's part of the shading; 0: compiled out (the scene
// has none). Likewise the directional lights' loop.
override HAS_ENVIRONMENT: u32 = 1u;
override HAS_LIGHTS: u32 = 1u;
// The environment map's part (src/gpu/plan.rs Variant::ibl): 0: no map (compiled out);
// 1: the map under the split sum; 2: the map by the lobe's samples.
override IBL: u32 = 0u;
// With IBL = 2: the lobe's samples a pixel a frame (lighting.wgsl shade_environment_lobe): a pipeline-time count, never a loop bound read from a uniform
// (screen.wgsl loop_counts says why).
override IBL_SAMPLES: u32 = 1u;
// 1 (default): antialiased silhouettes (balls.wgsl ball_footprint: a pixel the silhouette
// crosses mixes the ball and the background by the fraction it covers); 0: one ray through
// each pixel's centre, the image of before (src/scene Scene::antialias).
override AA: u32 = 1u;
// 1 (default): the split sum reads its prefiltered layers along the dominant direction
// (environment.wgsl specular_direction, at its callers in lighting.wgsl and
// coating.wgsl); 0: along the mirror direction itself (a
// measurement's switch, src/gpu/plan.rs DrawOptions::dominant_direction).
override DOMINANT_DIRECTION: u32 = 1u;
// 0 (default): each ball's term is its own (Ball.term, a flat varying); TERM_*: every ball
// the pipeline draws has this term (src/gpu/plan.rs Variant::ball_term), a pipeline-time
// choice, so that no other term's branch is run (lavapipe runs both sides of a branch on
// a varying, the Kulla-Conty term's two reads of the convolved layers included).
override BALL_TERM: u32 = 0u;

// Mirrors src/gpu/uniforms.rs Globals (every member a vec4 for one std140 layout).
struct Globals {
    cam_origin: vec4<f32>,
    cam_forward: vec4<f32>,
    // Right and up scaled by tan(vfov / 2) (times aspect for right): src/scene CameraBasis.
    cam_right: vec4<f32>,
    cam_up: vec4<f32>,
    // rgb: environment radiance (also the background); w: exposure.
    environment: vec4<f32>,
    // width, height (pixels), unused, unused.
    size: vec4<f32>,
    // ball count, light count, unused, unused.
    counts: vec4<u32>,
    // How the bound tables are read (Layout::lut_params; the ball pipelines take the mu
    // axis from MU_AXIS instead, lut_params in lighting.wgsl).
    lut: LutParams,
}

struct Ball {
    // xyz: centre; w: radius.
    center_radius: vec4<f32>,
    // xyz: the metal's linear F0; w: roughness (raw; the BRDF functions clamp it).
    f0_roughness: vec4<f32>,
    // The dielectric's linear base colour (0 for a metal): the albedo a viewer sees or
    // the substrate's, as the layering form reads it.
    diffuse: vec3<f32>,
    // The multiple-scattering term's weight: 1 with it, 0 without.
    ms: f32,
    // Constant over the ball, formed on the CPU (src/gpu/uniforms.rs balls): xyz: the
    // metal's f_add of the preset (f_add_accurate or f_add_games202 of E_avg); w: f_ms_norm
    // of 1 - E_avg at the ball's roughness as read: lut_loss_avg of the 2-D table, or its
    // own row's.
    f_add_ms_norm: vec4<f32>,
    // The roughness half of an E read at the ball's roughness (Tables::lut_row;
    // lut_loss_row in lut.wgsl): first row index, weight of the next row, alpha.
    lut_row: vec3<f32>,
    // The ball's term (TERM_*; 0 without one).
    term: u32,
    // The coating (src/scene CoatingConstants): x: metallic, the metal's share; y: the
    // coating's index eta; z: its f_add (0 without the term); w: its average Fresnel.
    coating: vec4<f32>,
    // The average of the coating's specular albedo with the ball's term, E_spec_avg.
    e_spec_avg: f32,
    // The ball's row in coating_rows (0 for an all-metal ball, which reads none).
    coating_row: u32,
    // The layering form (LAYERING_*).
    layering: u32,
    // The coating's Fresnel (FRESNEL_*; the preset's).
    fresnel: u32,
}

// Mirrors src/gpu/environment.rs EnvUniform.
struct EnvUniform {
    // cos and sin of -rotation_deg (env_to_map).
    rotation: vec2<f32>,
    // The map's intensity.
    intensity: f32,
    // The weight of the map in the background: 1 where it shows the map, 0 elsewhere.
    shows_map: f32,
    // rgb: the background's fixed radiance.
    background: vec4<f32>,
    // The lobe's samples: x: this frame's first sample index; y: unused; zw: the map's
    // base level size (texels).
    lobe: vec4<f32>,
}

struct Light {
    // xyz: unit direction towards the light.
    direction: vec4<f32>,
    // rgb: radiance.
    radiance: vec4<f32>,
}
