// types.wgsl: the renderer's override constants and uniform layouts, shared by its entry
// points. Every struct here has a Rust twin of the same layout (src/gpu/uniforms.rs,
// src/gpu/environment.rs), checked member by member by src/gpu/tests/boundary.rs.

#define_import_path shadeballs::types
#import shadeballs::constants::LutParams

// MAX_BALLS and MAX_LIGHTS: the sizes of the balls storage buffer and the lights uniform
// array. SUN_POINTS: the lights a map's sun is shaded as (src/scene SunLight). TERM_*: a
// ball's multiple-scattering term (Ball.term; src/scene Model), each ball's own, so one
// pipeline draws every model (a branch per ball, coherent over its pixels); 0 without one.
// LAYERING_*: how a ball's dielectric base sits under its coating (Ball.layering; src/scene
// Layering). COAT_FORM_*: how a clear coat weights the ball under it (Ball.clearcoat_form;
// src/scene CoatForm). COATING_ROW_LEN: the values of a coating row (coating_rows,
// lut::coating). TONE_MAP_*, TRANSFER_*: the values of TONE_MAP and TRANSFER.
// generated from the Rust constants by src/gpu/tests/boundary.rs: do not edit
const MAX_BALLS: u32 = 4096u; // scene::MAX_BALLS
const MAX_LIGHTS: u32 = 16u; // scene::MAX_LIGHTS
const SUN_POINTS: u32 = 4u; // scene::SUN_POINTS
const TERM_KULLA_CONTY: u32 = 1u; // gpu::uniforms::TERM_CODES
const TERM_TURQUIN: u32 = 2u; // gpu::uniforms::TERM_CODES
const TERM_FDEZ_AGUERA: u32 = 3u; // gpu::uniforms::TERM_CODES
const LAYERING_CONSTANT: u32 = 0u; // gpu::uniforms::LAYERING_CODES
const LAYERING_GLTF: u32 = 1u; // gpu::uniforms::LAYERING_CODES
const LAYERING_VIEW_ONLY: u32 = 2u; // gpu::uniforms::LAYERING_CODES
const LAYERING_RECIPROCAL: u32 = 3u; // gpu::uniforms::LAYERING_CODES
const LAYERING_PHYSICAL: u32 = 4u; // gpu::uniforms::LAYERING_CODES
const COAT_FORM_PHYSICAL: u32 = 0u; // gpu::uniforms::COAT_FORM_CODES
const COAT_FORM_FILAMENT: u32 = 1u; // gpu::uniforms::COAT_FORM_CODES
const COAT_FORM_GLTF: u32 = 2u; // gpu::uniforms::COAT_FORM_CODES
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
// 1: the map's sun is SUN_POINTS lights after the scene's, for the balls that take it
// (vs_ball in screen.wgsl; src/environment/sun.rs); 0 (default): none (no sun, the lobe's
// samples, the Monte Carlo and the walk, which read the map itself).
override SUN_LIGHT: u32 = 0u;
// The environment map's part (src/gpu/plan.rs Variant::ibl): 0: no map (compiled out);
// 1: the map under the split sum; 2: the map by the lobe's samples.
override IBL: u32 = 0u;
// With IBL = 2: each strategy's samples a pixel a frame (lighting.wgsl shade_environment_mis): a pipeline-time count, never a loop bound read from a uniform
// (screen.wgsl loop_counts says why).
override IBL_SAMPLES: u32 = 1u;
// With IBL = 2: the cosine strategy's samples a pixel a frame (Scene::cosine_samples: all
// of IBL_SAMPLES, or half under a map whose light mostly stands above its mean).
override IBL_COSINE_SAMPLES: u32 = 1u;
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
// 1 (default): the clear coat's code (clearcoat.wgsl, coating.wgsl has_clearcoat) and the
// anisotropic lobe's (lighting.wgsl has_anisotropy), each a branch on the ball's own
// members; 0: compiled out, as no ball the pipeline draws has one (src/gpu/plan.rs
// Variant::clearcoat, Variant::anisotropy): lavapipe runs a branch on a varying whether
// or not a ball takes it.
override HAS_CLEARCOAT: u32 = 1u;
override HAS_ANISOTROPY: u32 = 1u;
// 1 (default): a metal base's code (lighting.wgsl shade_metal, model.wgsl metal_brdf) and a
// dielectric one's (coating.wgsl), each under a branch on the ball's metallic; 0: compiled
// out, as no ball the pipeline draws has metallic above 0 (HAS_METAL) or below 1
// (HAS_DIELECTRIC) (src/gpu/plan.rs Variant::metal, Variant::dielectric). An all-metal
// chart's pixels ran the dielectric's code under a mask on lavapipe.
override HAS_METAL: u32 = 1u;
override HAS_DIELECTRIC: u32 = 1u;

// Which of a value's three shares the ball's term (TERM_*; src/gpu/uniforms.rs term_code)
// takes: 1 Turquin's, 2 Fdez-Aguera's, 0 Kulla-Conty's. The one choice among the terms:
// every shader chooses through it (by_term, by_term_f32). Each share is formed by the
// caller; a pipeline-time term (BALL_TERM) folds the others away.
fn term_share(term: u32) -> u32 {
    if term == TERM_TURQUIN {
        return 1u;
    }
    if term == TERM_FDEZ_AGUERA {
        return 2u;
    }
    return 0u;
}

// The share of `term_share(term)` among Kulla-Conty's, Turquin's and Fdez-Aguera's.
fn by_term(term: u32, kulla_conty: vec3<f32>, turquin: vec3<f32>, fdez_aguera: vec3<f32>) -> vec3<f32> {
    let share = term_share(term);
    return select(select(kulla_conty, fdez_aguera, share == 2u), turquin, share == 1u);
}

// by_term of scalars.
fn by_term_f32(term: u32, kulla_conty: f32, turquin: f32, fdez_aguera: f32) -> f32 {
    let share = term_share(term);
    return select(select(kulla_conty, fdez_aguera, share == 2u), turquin, share == 1u);
}

// Mirrors src/gpu/uniforms.rs Globals (every member a vec4 for one std140 layout).
struct Globals {
    cam_origin: vec4<f32>,
    cam_forward: vec4<f32>,
    // Right and up scaled by tan(vfov / 2) (times aspect for right): src/scene CameraBasis.
    cam_right: vec4<f32>,
    cam_up: vec4<f32>,
    // rgb: environment radiance (also the background); w: exposure.
    environment: vec4<f32>,
    // width, height (pixels), the roughness from which a ball takes the map's sun as a light
    // (SUN_LIGHT; vs_ball), unused.
    size: vec4<f32>,
    // ball count, light count, unused, unused.
    counts: vec4<u32>,
    // How the bound tables are read (Layout::lut_params; the ball pipelines take the mu
    // axis from MU_AXIS instead, lut_params in lighting.wgsl).
    lut: LutParams,
}

// The ball (src/gpu/uniforms.rs GpuBall, whose member list BALL_MEMBERS this block is
// generated from: gpu::ball): `Ball` by its members' names, and how a quad carries it from
// its instance (BallIn, the vertex attributes) to the fragment stage (BallOut, flat
// varyings, each a run of members packed by 16-byte row), ball_of unpacking it.
// generated from gpu::uniforms::BALL_MEMBERS by src/gpu/tests/boundary.rs: do not edit
struct Ball {
    center: vec3<f32>,
    radius: f32,
    f0: vec3<f32>,
    roughness: f32,
    diffuse: vec3<f32>,
    ms: f32,
    f_add: vec3<f32>,
    ms_norm: f32,
    lut_row: vec3<f32>,
    term: u32,
    metallic: f32,
    eta: f32,
    coat_f_add: f32,
    coat_f_avg: f32,
    e_spec_avg: f32,
    coating_row: u32,
    layering: u32,
    fresnel: u32,
    anisotropy_alpha_t: f32,
    anisotropy_alpha_b: f32,
    anisotropy_cos: f32,
    anisotropy_sin: f32,
    clearcoat_lut_row: vec3<f32>,
    clearcoat: f32,
    clearcoat_base_avg: vec3<f32>,
    clearcoat_roughness: f32,
    clearcoat_eta: f32,
    clearcoat_f_add: f32,
    clearcoat_ms_norm: f32,
    clearcoat_e_avg: f32,
    clearcoat_row: u32,
    clearcoat_form: u32,
    clearcoat_base_row: u32,
    clearcoat_escape: u32,
    emission: vec3<f32>,
    clearcoat_base_roughness: f32,
}

// The ball's members as a quad's instance attributes (BallInstance::LAYOUT).
struct BallIn {
    @location(0) rect: vec4<f32>,
    @location(1) ball_0: vec4<f32>,
    @location(2) ball_1: vec4<f32>,
    @location(3) ball_2: vec4<f32>,
    @location(4) ball_3: vec4<f32>,
    @location(5) ball_4: vec3<f32>,
    @location(6) ball_5: u32,
    @location(7) ball_6: vec4<f32>,
    @location(8) ball_7: f32,
    @location(9) ball_8: vec3<u32>,
    @location(10) ball_9: vec4<f32>,
    @location(11) ball_10: vec4<f32>,
    @location(12) ball_11: vec4<f32>,
    @location(13) ball_12: vec4<f32>,
    @location(14) ball_13: vec4<u32>,
    @location(15) ball_14: vec4<f32>,
}

// A quad's fragment: its ball as flat varyings (a fragment shades only its own
// ball, so it reads no per-ball buffer: a flat varying is a broadcast).
struct BallOut {
    @builtin(position) position: vec4<f32>,
    @location(0) @interpolate(flat) counts: vec2<u32>,
    @location(1) @interpolate(flat) ball_0: vec4<f32>,
    @location(2) @interpolate(flat) ball_1: vec4<f32>,
    @location(3) @interpolate(flat) ball_2: vec4<f32>,
    @location(4) @interpolate(flat) ball_3: vec4<f32>,
    @location(5) @interpolate(flat) ball_4: vec3<f32>,
    @location(6) @interpolate(flat) ball_5: u32,
    @location(7) @interpolate(flat) ball_6: vec4<f32>,
    @location(8) @interpolate(flat) ball_7: f32,
    @location(9) @interpolate(flat) ball_8: vec3<u32>,
    @location(10) @interpolate(flat) ball_9: vec4<f32>,
    @location(11) @interpolate(flat) ball_10: vec4<f32>,
    @location(12) @interpolate(flat) ball_11: vec4<f32>,
    @location(13) @interpolate(flat) ball_12: vec4<f32>,
    @location(14) @interpolate(flat) ball_13: vec4<u32>,
    @location(15) @interpolate(flat) ball_14: vec4<f32>,
}

fn ball_out(in: BallIn, position: vec4<f32>, counts: vec2<u32>) -> BallOut {
    var out: BallOut;
    out.position = position;
    out.counts = counts;
    out.ball_0 = in.ball_0;
    out.ball_1 = in.ball_1;
    out.ball_2 = in.ball_2;
    out.ball_3 = in.ball_3;
    out.ball_4 = in.ball_4;
    out.ball_5 = in.ball_5;
    out.ball_6 = in.ball_6;
    out.ball_7 = in.ball_7;
    out.ball_8 = in.ball_8;
    out.ball_9 = in.ball_9;
    out.ball_10 = in.ball_10;
    out.ball_11 = in.ball_11;
    out.ball_12 = in.ball_12;
    out.ball_13 = in.ball_13;
    out.ball_14 = in.ball_14;
    return out;
}

fn ball_of(in: BallOut) -> Ball {
    var b: Ball;
    b.center = in.ball_0.xyz;
    b.radius = in.ball_0.w;
    b.f0 = in.ball_1.xyz;
    b.roughness = in.ball_1.w;
    b.diffuse = in.ball_2.xyz;
    b.ms = in.ball_2.w;
    b.f_add = in.ball_3.xyz;
    b.ms_norm = in.ball_3.w;
    b.lut_row = in.ball_4;
    b.term = in.ball_5;
    b.metallic = in.ball_6.x;
    b.eta = in.ball_6.y;
    b.coat_f_add = in.ball_6.z;
    b.coat_f_avg = in.ball_6.w;
    b.e_spec_avg = in.ball_7;
    b.coating_row = in.ball_8.x;
    b.layering = in.ball_8.y;
    b.fresnel = in.ball_8.z;
    b.anisotropy_alpha_t = in.ball_9.x;
    b.anisotropy_alpha_b = in.ball_9.y;
    b.anisotropy_cos = in.ball_9.z;
    b.anisotropy_sin = in.ball_9.w;
    b.clearcoat_lut_row = in.ball_10.xyz;
    b.clearcoat = in.ball_10.w;
    b.clearcoat_base_avg = in.ball_11.xyz;
    b.clearcoat_roughness = in.ball_11.w;
    b.clearcoat_eta = in.ball_12.x;
    b.clearcoat_f_add = in.ball_12.y;
    b.clearcoat_ms_norm = in.ball_12.z;
    b.clearcoat_e_avg = in.ball_12.w;
    b.clearcoat_row = in.ball_13.x;
    b.clearcoat_form = in.ball_13.y;
    b.clearcoat_base_row = in.ball_13.z;
    b.clearcoat_escape = in.ball_13.w;
    b.emission = in.ball_14.xyz;
    b.clearcoat_base_roughness = in.ball_14.w;
    b.term = select(b.term, BALL_TERM, BALL_TERM != 0u);
    return b;
}
// end of the generated ball

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
    // xyz: unit direction towards the light; w: unused.
    direction: vec4<f32>,
    // rgb: radiance.
    radiance: vec4<f32>,
}
