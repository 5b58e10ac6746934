// accumulate.wgsl: the lobe's progressive image on the GPU (src/gpu/accumulate.rs). Each
// frame of `ibl_method = "lobe"` is drawn by the ball renderer into an `Rgba32Uint` frame
// (the bits of linear radiance, alpha 1: balls.wgsl under OUTPUT_BITS); fs_lobe_accumulate
// adds it to the running sums (the bits of f32 sums, alpha the count of frames: one sum
// texture read, the other written, swapped each frame), and fs_lobe_resolve writes their
// mean through the target's output (the display transform, or linear on a float target).
// Integer textures are read with textureLoad and written by any backend (GL renders to no
// 32-bit float format), so the sums are the same bits on Vulkan and on GL.

#define_import_path shadeballs::accumulate
#import shadeballs::screen::{VsOut, output_value, Colour}

// Group 2 of the accumulation's pipelines: this frame's radiance bits, and the sums so
// far (the bits of f32 rgb sums and, in alpha, the count of frames).
@group(2) @binding(0) var lobe_frame_bits: texture_2d<u32>;
@group(2) @binding(1) var lobe_sum_bits: texture_2d<u32>;

// The sums so far plus this frame's radiance (and 1 in alpha: the count).
@fragment
fn fs_lobe_accumulate(in: VsOut) -> @location(0) vec4<u32> {
    let p = vec2<i32>(in.position.xy);
    let frame = bitcast<vec4<f32>>(textureLoad(lobe_frame_bits, p, 0i));
    let sum = bitcast<vec4<f32>>(textureLoad(lobe_sum_bits, p, 0i));
    return bitcast<vec4<u32>>(sum + frame);
}

// The mean of the frames summed so far at the pixel, as the target takes it. The count is
// at least 1 wherever a frame was added (the resolve follows at least one accumulation).
@fragment
fn fs_lobe_resolve(in: VsOut) -> @location(0) Colour {
    let sum = bitcast<vec4<f32>>(textureLoad(lobe_sum_bits, vec2<i32>(in.position.xy), 0i));
    return output_value(sum.rgb / max(sum.w, 1.0));
}
