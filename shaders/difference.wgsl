// The viewer's difference view: |a - b| of two scene images' displayed values (their
// bytes, read through non-sRGB views), the largest channel's, times a scale, in a colour
// ramp from black (no difference) through purple, red and orange to pale yellow (the scale's
// full step or more). `src/viewer/difference.rs` holds the CPU mirror of `difference_colour`
// (the colour bar's colours) and of the whole pixel (the tests').

#define_import_path shadeballs::difference

struct DifferenceParams {
    // |a - b| is multiplied by this before the ramp (1 at its top).
    scale: f32,
    pad0: f32,
    pad1: f32,
    pad2: f32,
}

@group(0) @binding(0) var image_a: texture_2d<f32>;
@group(0) @binding(1) var image_b: texture_2d<f32>;
@group(0) @binding(2) var<uniform> params: DifferenceParams;

// The ramp's colour at t (clamped to [0, 1]): display values, linear between five stops.
fn difference_colour(t: f32) -> vec3<f32> {
    var stops = array<vec3<f32>, 5>(
        vec3<f32>(0.0, 0.0, 0.0),
        vec3<f32>(0.30, 0.05, 0.55),
        vec3<f32>(0.80, 0.15, 0.35),
        vec3<f32>(1.0, 0.55, 0.05),
        vec3<f32>(1.0, 1.0, 0.75),
    );
    let x = clamp(t, 0.0, 1.0) * 4.0;
    let i = min(u32(x), 3u);
    return mix(stops[i], stops[i + 1u], x - f32(i));
}

@vertex
fn difference_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    // (-1, -1), (3, -1), (-1, 3): covers the viewport.
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u)) * 2.0 - 1.0;
    return vec4<f32>(xy, 0.0, 1.0);
}

@fragment
fn difference_fs(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    let d = abs(textureLoad(image_a, p, 0).rgb - textureLoad(image_b, p, 0).rgb);
    let t = max(d.r, max(d.g, d.b)) * params.scale;
    return vec4<f32>(difference_colour(t), 1.0);
}
