//! The WGSL modules, concatenated as the pipelines do, parse and validate with naga (no
//! GPU needed), and mirror the Rust functions name for name.
use shadeballs::gpu::shaders;

fn validate(name: &str, source: &str) {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name} does not parse:\n{}", e.emit_to_string(source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name} does not validate:\n{}", e.emit_to_string(source)));
}

#[test]
fn modules_parse_and_validate() {
    validate("balls module", &shaders::balls_source());
    validate("probe module", &shaders::probe_source());
    validate("viewer blit", include_str!("../../shaders/blit.wgsl"));
}

#[test]
fn wgsl_mirrors_the_rust_function_names() {
    let all = shaders::balls_source();
    let names = [
        "d_ggx",
        "g1_schlick",
        "g_schlick",
        "lambda_smith",
        "g1_smith",
        "g_smith",
        "g_smith_correlated",
        "f_schlick",
        "f_avg_schlick",
        "f_avg_games202",
        "f_ms",
        "f_add_accurate",
        "f_add_games202",
        "f_add_denominator",
        "f_add_preset",
        "alpha_from_roughness",
        "roughness_clamped",
        "f_micro",
        "fresnel_dielectric",
        "f0_from_ior",
        "f_base_constant",
        "f_base_gltf",
        "f_base_view_only",
        "f_base_reciprocal",
        "coating_inside_reflectance",
        "f_base_physical",
        "substrate_albedo",
        "lut_texel_span",
        "lut_e",
        "lut_e_avg",
        "lut_loss",
        "lut_loss_avg",
    ];
    for name in names {
        assert!(
            all.contains(&format!("fn {name}(")),
            "no `fn {name}(` in the WGSL"
        );
    }
}

#[test]
fn brdf_functions_cite_their_source() {
    let brdf = shaders::COMMON
        .iter()
        .find(|(n, _)| *n == "brdf.wgsl")
        .unwrap()
        .1;
    for (name, source) in [
        ("d_ggx", "Walter et al. 2007"),
        ("g1_schlick", "Schlick 1994"),
        ("lambda_smith", "Heitz 2014"),
        ("g1_smith", "Walter et al. 2007"),
        ("g_smith_correlated", "Heitz 2014"),
        ("f_schlick", "Schlick 1994"),
        ("f_avg_games202", "Gulbrandsen 2014"),
        ("f_ms", "Kulla & Conty 2017"),
        ("f_add_accurate", "Kulla & Conty 2017"),
        ("fresnel_dielectric", "Walter et al. 2007"),
        ("f_base_gltf", "glTF 2.0"),
        ("f_base_view_only", "Principled v2"),
        ("f_base_reciprocal", "OpenPBR"),
    ] {
        let at = brdf.find(&format!("fn {name}(")).unwrap();
        let comment = &brdf[brdf[..at].rfind("\n\n").unwrap_or(0)..at];
        assert!(comment.contains(source), "{name} does not cite {source}");
    }
}
