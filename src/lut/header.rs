//! The tables as source code for another engine (`shadeballs bake --out tables.h` or
//! `tables.glsl`; docs/interop.md, "The tables in another engine"): the stored losses
//! `1 - E` and `1 - E_avg` (what the shader reads, after the layout's storage rounding) as
//! C or GLSL float arrays, with their layout and the `LutParams` that address them in a
//! comment. Every value is written with the shortest digits that read back to the same f32.

use super::Tables;

/// Which language the arrays are written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Language {
    /// A C (and C++) header: `static const float` arrays and `#define`s.
    C,
    /// GLSL (4.30 / ES 3.00 and later): `const float` arrays with array constructors.
    Glsl,
}

/// An f32 written so that C and GLSL read it back exactly: Rust's shortest round-trip
/// digits, with a decimal point or an exponent (a float literal, not an integer).
fn literal(x: f32, language: Language) -> String {
    let mut s = format!("{x:?}");
    if !s.contains(['.', 'e', 'E']) {
        s.push_str(".0");
    }
    if language == Language::C {
        s.push('f');
    }
    s
}

/// The layout comment both languages share.
fn layout_comment(tables: &Tables) -> String {
    let layout = tables.layout();
    let p = layout.lut_params();
    format!(
        "shadeballs tables, baked with {config:?}\n\
         \n\
         SHADEBALLS_LOSS: 1 - E(mu, roughness), {mu} x {r} values, row-major: row j\n\
         (roughness) holds {mu} values of mu; value [j * {mu} + i] is texel (i, j) of the\n\
         {mu} x {r} E texture the crate's shader reads (lut_loss in lut.wgsl, the\n\
         exported shader's lut_loss). SHADEBALLS_LOSS_AVG: 1 - E_avg(roughness), {r}\n\
         values, texel (j, 0) of the {r} x 2 E_avg texture; SHADEBALLS_ROW_ROUGHNESS: each\n\
         row's roughness, {r} values, its texel (j, 1) (the power-law E_avg read uses it).\n\
         The crate's shader reads E as 2x2 blocks: texel (i, j) of its Rgba32Float E\n\
         texture holds the loss at (i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1), clamped\n\
         at the last column and row (gpu::upload::loss_quads).\n\
         Layout: {kind} (mu axis {mu_axis:?}, E_avg read {e_avg:?}), stored as {storage}.\n\
         Texel i of an axis of n texels sits where x * scale + bias = i. The LutParams\n\
         uniform that addresses them:\n\
         mu_scale = {ms:?}, mu_bias = {mb:?}, r_scale = {rs:?}, r_bias = {rb:?},\n\
         mu_size = {mu}, r_size = {r}, mu_axis = {ma}, e_avg_read = {ea}, r_min = {rm:?}.",
        config = tables.config,
        mu = layout.mu_size,
        r = layout.r_size,
        kind = layout.kind,
        mu_axis = layout.mu_axis,
        e_avg = layout.e_avg_read,
        storage = layout.storage,
        ms = p.mu_scale,
        mb = p.mu_bias,
        rs = p.r_scale,
        rb = p.r_bias,
        ma = p.mu_axis,
        ea = p.e_avg_read,
        rm = p.r_min,
    )
}

/// `values` as the body of an array initialiser, eight a line.
fn values(values: &[f32], language: Language) -> String {
    values
        .chunks(8)
        .map(|row| {
            let row: Vec<String> = row.iter().map(|&x| literal(x, language)).collect();
            format!("    {}", row.join(", "))
        })
        .collect::<Vec<_>>()
        .join(",\n")
}

/// The tables' source in `language`.
pub(crate) fn source(tables: &Tables, language: Language) -> String {
    let layout = tables.layout();
    let (mu, r) = (layout.mu_size, layout.r_size);
    let n = tables.stored_loss.len();
    let comment = layout_comment(tables);
    let roughness: Vec<f32> = (0..r).map(|j| layout.row_roughness(j)).collect();
    match language {
        Language::C => {
            let comment: String = comment.lines().map(|l| format!(" * {l}\n")).collect();
            format!(
                "/*\n{comment} */\n#ifndef SHADEBALLS_TABLES_H\n#define SHADEBALLS_TABLES_H\n\n\
                 #define SHADEBALLS_MU_SIZE {mu}\n#define SHADEBALLS_R_SIZE {r}\n\n\
                 static const float SHADEBALLS_LOSS[{n}] = {{\n{}\n}};\n\n\
                 static const float SHADEBALLS_LOSS_AVG[{r}] = {{\n{}\n}};\n\n\
                 static const float SHADEBALLS_ROW_ROUGHNESS[{r}] = {{\n{}\n}};\n\n\
                 #endif\n",
                values(&tables.stored_loss, language),
                values(&tables.stored_loss_avg, language),
                values(&roughness, language),
            )
        }
        Language::Glsl => {
            let comment: String = comment.lines().map(|l| format!("// {l}\n")).collect();
            format!(
                "{comment}\nconst int SHADEBALLS_MU_SIZE = {mu};\nconst int SHADEBALLS_R_SIZE = {r};\n\n\
                 const float SHADEBALLS_LOSS[{n}] = float[{n}](\n{}\n);\n\n\
                 const float SHADEBALLS_LOSS_AVG[{r}] = float[{r}](\n{}\n);\n\n\
                 const float SHADEBALLS_ROW_ROUGHNESS[{r}] = float[{r}](\n{}\n);\n",
                values(&tables.stored_loss, language),
                values(&tables.stored_loss_avg, language),
                values(&roughness, language),
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_read_back_to_the_same_f32() {
        for x in [0.0f32, 1.0, 0.1, 1e-7, 3.4e38, 0.123_456_79] {
            for language in [Language::C, Language::Glsl] {
                let s = literal(x, language);
                let back: f32 = s.trim_end_matches('f').parse().unwrap();
                assert_eq!(back, x, "{s}");
                assert!(s.contains(['.', 'e']), "{s}");
            }
        }
    }
}
