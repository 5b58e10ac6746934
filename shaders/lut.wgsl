// lut.wgsl: reading the tables, exactly the f32 arithmetic of Tables::lut_loss /
// lut_loss_avg / lut_e / lut_e_avg, Layout::r_coord, MuAxis::coord and lut_texel_span in
// src/lut (manual bilinear over textureLoad: no filtering feature needed, so it runs the
// same on Vulkan and GL). The tables hold the missing energy 1 - E ("loss").

struct LutSpan {
    i0: u32,
    i1: u32,
    // Weight of texel i1.
    f: f32,
}

// The two texels and the weight of the second for a read at coordinate x on an axis of n
// texels: p = clamp(x scale + bias, 0, n - 1) (src/lut layout.rs, texel-centre convention).
fn lut_texel_span(x: f32, n: u32, scale: f32, bias: f32) -> LutSpan {
    if n <= 1u {
        return LutSpan(0u, 0u, 0.0);
    }
    let last = f32(n - 1u);
    let p = clamp(x * scale + bias, 0.0, last);
    let i0 = min(floor(p), last - 1.0);
    let i = u32(i0);
    return LutSpan(i, i + 1u, p - i0);
}

// The table coordinate of mu for a read at alpha (MuAxis::coord).
fn mu_coord(mu_in: f32, alpha: f32) -> f32 {
    let mu = clamp(mu_in, 0.0, 1.0);
    let axis = globals.lut_dims.z;
    if axis == MU_AXIS_SQRT {
        return sqrt(mu);
    }
    if axis == MU_AXIS_WARPED {
        return mu * (1.0 + alpha) / (mu + alpha);
    }
    return mu;
}

// The roughness axis coordinate (Layout::r_coord): the clamped roughness mapped from
// [r_min, 1] to [0, 1].
fn r_coord(roughness: f32) -> f32 {
    let r_min = globals.lut_r.x;
    return clamp((roughness_clamped(roughness) - r_min) / (1.0 - r_min), 0.0, 1.0);
}

fn loss_texel(i: u32, j: u32) -> f32 {
    return textureLoad(e_table, vec2<u32>(i, j), 0).r;
}

// Bilinear read of 1 - E(mu, roughness) (Tables::lut_loss).
fn lut_loss(mu: f32, roughness: f32) -> f32 {
    let r = roughness_clamped(roughness);
    let x = mu_coord(mu, r * r);
    let sx = lut_texel_span(x, globals.lut_dims.x, globals.lut.x, globals.lut.y);
    let sy = lut_texel_span(r_coord(roughness), globals.lut_dims.y, globals.lut.z, globals.lut.w);
    let t00 = loss_texel(sx.i0, sy.i0);
    let t10 = loss_texel(sx.i1, sy.i0);
    let t01 = loss_texel(sx.i0, sy.i1);
    let t11 = loss_texel(sx.i1, sy.i1);
    let top = t00 + (t10 - t00) * sx.f;
    let bottom = t01 + (t11 - t01) * sx.f;
    return top + (bottom - top) * sy.f;
}

// E as the shader reads it (Tables::lut_e).
fn lut_e(mu: f32, roughness: f32) -> f32 {
    return 1.0 - lut_loss(mu, roughness);
}

// Read of 1 - E_avg(roughness) between the two nearest rows, linear or geometric as the
// layout says (Tables::lut_loss_avg, EAvgRead).
fn lut_loss_avg(roughness: f32) -> f32 {
    let sy = lut_texel_span(r_coord(roughness), globals.lut_dims.y, globals.lut.z, globals.lut.w);
    let a = textureLoad(e_avg_table, vec2<u32>(sy.i0, 0u), 0).r;
    let b = textureLoad(e_avg_table, vec2<u32>(sy.i1, 0u), 0).r;
    if globals.lut_dims.w == E_AVG_READ_GEOMETRIC {
        let la = log(max(a, LOSS_AVG_MIN));
        let lb = log(max(b, LOSS_AVG_MIN));
        return exp(la + (lb - la) * sy.f);
    }
    return a + (b - a) * sy.f;
}

// E_avg as the shader reads it (Tables::lut_e_avg).
fn lut_e_avg(roughness: f32) -> f32 {
    return 1.0 - lut_loss_avg(roughness);
}
