// lut.wgsl: reading the tables, exactly the f32 arithmetic of Tables::lut_loss /
// lut_loss_avg / lut_e / lut_e_avg, Layout::r_coord, MuAxis::coord and lut_texel_span in
// src/lut (manual bilinear over textureLoad: no filtering feature needed, so it runs the
// same on Vulkan and GL). The tables hold the missing energy 1 - E ("loss"):
// - e_table: 1 - E(mu, roughness) as 2x2 blocks, Rgba32Float, mu_size x r_size: texel
//   (i, j) holds texels (i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1) of the table
//   (src/gpu/upload.rs loss_quads), so a bilinear read is one load;
// - e_avg_table: R32Float, r_size x 2: row 0 holds 1 - E_avg per roughness row, row 1 each
//   row's roughness (for the power-law read).
// Every function takes the tables and their LutParams as arguments (GpuTables in
// src/gpu/upload.rs makes both), so a host program's shader can call them.
//
// No control flow here depends on LutParams, only select: a lavapipe workaround, explained
// once at loop_counts in screen.wgsl (a uniform value that decides an if is inlined and the
// pipeline compiled again at every bind).

#define_import_path shadeballs::lut
#import shadeballs::constants::{LutParams, LOSS_AVG_MIN, MU_AXIS_SQRT, MU_AXIS_WARPED}
#import shadeballs::constants::E_AVG_READ_POWER_LAW
#import shadeballs::brdf::roughness_clamped

struct LutSpan {
    i0: u32,
    i1: u32,
    // Weight of texel i1.
    f: f32,
}

// The two texels and the weight of the second for a read at coordinate x on an axis of n
// texels: p = clamp(x scale + bias, 0, n - 1) (src/lut layout.rs, texel-centre convention);
// (0, 0, 0) on an axis of one texel. For n >= 2 the max(.., 0) is exact (p >= 0), so the
// values are those of the branch in src/lut lut_texel_span.
fn lut_texel_span(x: f32, n: u32, scale: f32, bias: f32) -> LutSpan {
    let single = n <= 1u;
    let last = f32(max(n, 1u) - 1u);
    let p = clamp(x * scale + bias, 0.0, last);
    let i0 = max(min(floor(p), last - 1.0), 0.0);
    let i = u32(i0);
    return LutSpan(i, i + select(1u, 0u, single), p - i0);
}

// The table coordinate of mu for a read at alpha on the mu axis `axis` (MU_AXIS_*;
// MuAxis::coord); alpha >= 4e-4 (the roughness clamp), so the warp's division is finite.
// A constant axis (the renderer's pipelines pass one) folds the selects away.
fn mu_coord(mu_in: f32, alpha: f32, axis: u32) -> f32 {
    let mu = clamp(mu_in, 0.0, 1.0);
    let warped = mu * (1.0 + alpha) / (mu + alpha);
    return select(select(mu, sqrt(mu), axis == MU_AXIS_SQRT), warped, axis == MU_AXIS_WARPED);
}

// The roughness axis coordinate (Layout::r_coord): the clamped roughness mapped from
// [r_min, 1] to [0, 1].
fn r_coord(roughness: f32, p: LutParams) -> f32 {
    return clamp((roughness_clamped(roughness) - p.r_min) / (1.0 - p.r_min), 0.0, 1.0);
}

// Texels (i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1) of the table in one load (the 2x2
// blocks above): a bilinear read costs one fetch instead of four (docs/benchmarks.md, "The
// term's cost").
fn loss_quad(e_table: texture_2d<f32>, i: u32, j: u32) -> vec4<f32> {
    return textureLoad(e_table, vec2<u32>(i, j), 0);
}

// Bilinear read of 1 - E(mu, roughness) (Tables::lut_loss).
fn lut_loss(e_table: texture_2d<f32>, p: LutParams, mu: f32, roughness: f32) -> f32 {
    let r = roughness_clamped(roughness);
    let x = mu_coord(mu, r * r, p.mu_axis);
    let sx = lut_texel_span(x, p.mu_size, p.mu_scale, p.mu_bias);
    let sy = lut_texel_span(r_coord(roughness, p), p.r_size, p.r_scale, p.r_bias);
    // (t00, t10, t01, t11): the span's i1 and j1 are i0 + 1 and j0 + 1, or i0 and j0 on an
    // axis of one texel, where the block repeats its texel.
    let q = loss_quad(e_table, sx.i0, sy.i0);
    let top = q.x + (q.y - q.x) * sx.f;
    let bottom = q.z + (q.w - q.z) * sx.f;
    return top + (bottom - top) * sy.f;
}

// lut_loss with the roughness half of the read done once per ball (Tables::lut_row):
// row = (first row index, weight of the next row, alpha). The same value as
// lut_loss(e_table, p, mu, roughness) (Tables::lut_loss_row).
fn lut_loss_row(e_table: texture_2d<f32>, p: LutParams, mu: f32, row: vec3<f32>) -> f32 {
    let x = mu_coord(mu, row.z, p.mu_axis);
    let sx = lut_texel_span(x, p.mu_size, p.mu_scale, p.mu_bias);
    let q = loss_quad(e_table, sx.i0, u32(row.x));
    let top = q.x + (q.y - q.x) * sx.f;
    let bottom = q.z + (q.w - q.z) * sx.f;
    return top + (bottom - top) * row.y;
}

// A row of lut_loss_row packed in one u32 (src/lut lut_row_pack: the first row in the high
// 16 bits, the next row's weight in 1/65535 in the low 16), at `roughness` (alpha: its
// clamped square). src/lut lut_row_unpack.
fn lut_row_unpack(packed: u32, roughness: f32) -> vec3<f32> {
    let r = roughness_clamped(roughness);
    return vec3<f32>(f32(packed >> 16u), f32(packed & 0xffffu) / 65535.0, r * r);
}

// E as the shader reads it (Tables::lut_e).
fn lut_e(e_table: texture_2d<f32>, p: LutParams, mu: f32, roughness: f32) -> f32 {
    return 1.0 - lut_loss(e_table, p, mu, roughness);
}

// Read of 1 - E_avg(roughness) between the two nearest rows, linear or as the power law
// through them (`a (r / r_a)^p` meeting `b` at `r_b`: linear in ln(1 - E_avg) against ln r),
// as p.e_avg_read says (Tables::lut_loss_avg, EAvgRead).
fn lut_loss_avg(e_avg_table: texture_2d<f32>, p: LutParams, roughness: f32) -> f32 {
    let sy = lut_texel_span(r_coord(roughness, p), p.r_size, p.r_scale, p.r_bias);
    let a = textureLoad(e_avg_table, vec2<u32>(sy.i0, 0u), 0).r;
    let b = textureLoad(e_avg_table, vec2<u32>(sy.i1, 0u), 0).r;
    let linear = a + (b - a) * sy.f;
    // Both rows have roughness >= ROUGHNESS_MIN > 0 (clamped reads). On an axis of one row
    // ra = rb: the weight is 0 / 0, and the select below takes `linear` (= a) instead.
    let ra = textureLoad(e_avg_table, vec2<u32>(sy.i0, 1u), 0).r;
    let rb = textureLoad(e_avg_table, vec2<u32>(sy.i1, 1u), 0).r;
    let w = ln_f32(roughness_clamped(roughness) / ra) / ln_f32(rb / ra);
    let la = ln_f32(max(a, LOSS_AVG_MIN));
    let lb = ln_f32(max(b, LOSS_AVG_MIN));
    let power_law = exp_f32(la + (lb - la) * w);
    return select(linear, power_law, p.e_avg_read == E_AVG_READ_POWER_LAW && sy.i1 != sy.i0);
}

// ln and exp to within ~2 ulp of f32, for the power-law E_avg read, so that the read is the
// same on every GPU as Rust's f32 ln/exp (WGSL leaves the built-ins' accuracy to the
// implementation).
// ln 2 split so that n * LN2_HI is exact for |n| < 256 (Cody & Waite 1980).
const LN2_HI: f32 = 0.693145751953125;
const LN2_LO: f32 = 1.4286067653e-6;
const SQRT_HALF: f32 = 0.70710678118;

// ln x for x > 0 normal: x = m 2^e, m in [sqrt(1/2), sqrt(2)), ln m = 2 atanh(s),
// s = (m - 1) / (m + 1), |s| <= 0.172, by its series to s^9 (next term < 2e-9 relative).
fn ln_f32(x: f32) -> f32 {
    let parts = frexp(x);
    var m = parts.fract;
    var e = f32(parts.exp);
    if m < SQRT_HALF {
        m = m * 2.0;
        e = e - 1.0;
    }
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    let series = 1.0 + s2 * (1.0 / 3.0 + s2 * (1.0 / 5.0 + s2 * (1.0 / 7.0 + s2 * (1.0 / 9.0))));
    return e * LN2_HI + (e * LN2_LO + 2.0 * s * series);
}

// exp y for y in f32's normal range: y = n ln 2 + r, |r| <= ln 2 / 2, exp r by Taylor to
// r^8 (next term < 3e-10 relative).
fn exp_f32(y: f32) -> f32 {
    let n = round(y / (LN2_HI + LN2_LO));
    let r = (y - n * LN2_HI) - n * LN2_LO;
    var p = 1.0 / 40320.0;
    p = 1.0 / 5040.0 + r * p;
    p = 1.0 / 720.0 + r * p;
    p = 1.0 / 120.0 + r * p;
    p = 1.0 / 24.0 + r * p;
    p = 1.0 / 6.0 + r * p;
    p = 0.5 + r * p;
    p = 1.0 + r * p;
    p = 1.0 + r * p;
    return ldexp(p, i32(n));
}

// E_avg as the shader reads it (Tables::lut_e_avg).
fn lut_e_avg(e_avg_table: texture_2d<f32>, p: LutParams, roughness: f32) -> f32 {
    return 1.0 - lut_loss_avg(e_avg_table, p, roughness);
}
