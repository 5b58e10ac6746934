// The viewer's copy of its frame image into a window whose surface cannot be copied into
// (GL): a full-screen triangle whose fragments load the texel under them, unfiltered, so
// that the window gets the frame image's exact bytes.

#define_import_path shadeballs::blit

@group(0) @binding(0) var frame_image: texture_2d<f32>;

@vertex
fn blit_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    // (-1, -1), (3, -1), (-1, 3): covers the viewport.
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u)) * 2.0 - 1.0;
    return vec4<f32>(xy, 0.0, 1.0);
}

@fragment
fn blit_fs(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(frame_image, vec2<i32>(position.xy), 0);
}
