//! One source for the CPU/GPU boundary. The WGSL constants shared with Rust are generated
//! from the Rust constants: each file's block between the markers below must be what
//! [`blocks`] writes (`SHADEBALLS_BLESS=1 cargo test --release --lib -- boundary::` rewrites
//! the blocks). Every struct a program reads from a uniform or storage buffer has a Rust
//! twin whose `size_of`, `offset_of` and member types equal naga's layout, member by
//! member.
use std::collections::BTreeMap;

use crate::brdf::{self, DielectricFresnel, FAvgForm, Geometry};
use crate::display::{self, ToneMap, Transfer};
use crate::environment::{lobe, prefilter};
use crate::gpu::boundary::{self, StructLayout, STRUCTS};
use crate::gpu::shaders;
use crate::gpu::uniforms::{COAT_FORM_CODES, LAYERING_CODES, TERM_CODES};
use crate::lut::{self, EAvgRead, MuAxis};
use crate::wgsl::PROGRAMS;

const BEGIN: &str =
    "// generated from the Rust constants by src/gpu/tests/boundary.rs: do not edit";
const END: &str = "// end of the generated constants";
/// The markers of the ball's block in `types.wgsl` (`boundary::ball_wgsl`).
const BALL_BEGIN: &str =
    "// generated from gpu::uniforms::BALL_MEMBERS by src/gpu/tests/boundary.rs: do not edit";
const BALL_END: &str = "// end of the generated ball";

/// A WGSL constant's name, type and value, and the Rust item it comes from.
struct Constant {
    name: String,
    ty: &'static str,
    value: String,
    from: String,
}

fn float(name: &str, value: f64, from: &str) -> Constant {
    Constant {
        name: name.to_string(),
        ty: "f32",
        // `{:?}` keeps a decimal point or an exponent (an abstract float literal) and is
        // the shortest text that reads back as the same f64, hence the same f32.
        value: format!("{value:?}"),
        from: from.to_string(),
    }
}

fn uint(name: String, value: u64, from: String) -> Constant {
    Constant {
        name,
        ty: "u32",
        value: format!("{value}u"),
        from,
    }
}

/// `NAME` of a kebab-case name (`smith-correlated` -> `SMITH_CORRELATED`, `gamma-2.2` ->
/// `GAMMA_2_2`).
fn upper(name: &str) -> String {
    name.to_uppercase().replace(['-', '.'], "_")
}

/// The constants of `constants.wgsl`.
fn library_constants() -> Vec<Constant> {
    let mut c = vec![
        float("DIV_EPSILON", brdf::DIV_EPSILON, "brdf::DIV_EPSILON"),
        float("ROUGHNESS_MIN", brdf::ROUGHNESS_MIN, "brdf::ROUGHNESS_MIN"),
    ];
    let [r, g, b] = brdf::GAMES202_EDGE_TINT;
    c.push(Constant {
        name: "GAMES202_EDGE_TINT".into(),
        ty: "vec3<f32>",
        value: format!("vec3<f32>({r:?}, {g:?}, {b:?})"),
        from: "brdf::GAMES202_EDGE_TINT".into(),
    });
    for g in Geometry::ALL {
        let name = format!("GEOMETRY_{}", upper(g.name()));
        let from = format!("gpu::shaders::geometry_id(Geometry::{g:?})");
        c.push(uint(name, shaders::geometry_id(g) as u64, from));
    }
    for (name, form) in [
        ("ACCURATE", FAvgForm::Accurate),
        ("GAMES202", FAvgForm::Games202),
    ] {
        let from = format!("gpu::shaders::f_add_form_id(FAvgForm::{form:?})");
        c.push(uint(
            format!("F_ADD_{name}"),
            shaders::f_add_form_id(form) as u64,
            from,
        ));
    }
    for (name, form) in [
        ("EXACT", DielectricFresnel::Exact),
        ("SCHLICK", DielectricFresnel::Schlick),
    ] {
        let from = format!("gpu::shaders::fresnel_id(DielectricFresnel::{form:?})");
        c.push(uint(
            format!("FRESNEL_{name}"),
            shaders::fresnel_id(form) as u64,
            from,
        ));
    }
    for a in MuAxis::ALL {
        let from = format!("MuAxis::{a:?}.id()");
        c.push(uint(
            format!("MU_AXIS_{}", upper(a.name())),
            a.id() as u64,
            from,
        ));
    }
    for e in EAvgRead::ALL {
        let from = format!("EAvgRead::{e:?}.id()");
        c.push(uint(
            format!("E_AVG_READ_{}", upper(e.name())),
            e.id() as u64,
            from,
        ));
    }
    c.push(Constant {
        name: "LOSS_AVG_MIN".into(),
        ty: "f32",
        // An f32 on the Rust side: its own shortest text.
        value: format!("{:?}", lut::LOSS_AVG_MIN),
        from: "lut::LOSS_AVG_MIN".into(),
    });
    c
}

/// The constants of `types.wgsl`.
fn renderer_constants() -> Vec<Constant> {
    let scene = crate::scene::MAX_BALLS as u64;
    let lights = crate::scene::MAX_LIGHTS as u64;
    let mut c = vec![
        uint("MAX_BALLS".into(), scene, "scene::MAX_BALLS".into()),
        uint("MAX_LIGHTS".into(), lights, "scene::MAX_LIGHTS".into()),
        uint(
            "SUN_POINTS".into(),
            crate::scene::SUN_POINTS as u64,
            "scene::SUN_POINTS".into(),
        ),
    ];
    for (code, term) in TERM_CODES {
        let name = format!("TERM_{}", upper(term.name()));
        c.push(uint(name, code as u64, "gpu::uniforms::TERM_CODES".into()));
    }
    for (code, form) in LAYERING_CODES {
        let name = format!("LAYERING_{}", upper(form.name()));
        c.push(uint(
            name,
            code as u64,
            "gpu::uniforms::LAYERING_CODES".into(),
        ));
    }
    for (code, form) in COAT_FORM_CODES {
        let name = format!("COAT_FORM_{}", upper(form.name()));
        c.push(uint(
            name,
            code as u64,
            "gpu::uniforms::COAT_FORM_CODES".into(),
        ));
    }
    c.push(uint(
        "COATING_ROW_LEN".into(),
        lut::COATING_ROW_LEN as u64,
        "lut::COATING_ROW_LEN".into(),
    ));
    for t in ToneMap::ALL {
        let name = format!("TONE_MAP_{}", upper(t.name()));
        c.push(uint(name, t.code() as u64, "display::ToneMap::code".into()));
    }
    for t in Transfer::ALL {
        let name = format!("TRANSFER_{}", upper(t.name()));
        c.push(uint(
            name,
            t.code() as u64,
            "display::Transfer::code".into(),
        ));
    }
    c
}

/// The constants of `screen.wgsl`: the display transform's (src/display.rs).
fn display_constants() -> Vec<Constant> {
    vec![
        float(
            "MAX_DISPLAY_RADIANCE",
            display::MAX_DISPLAY_RADIANCE,
            "display::MAX_DISPLAY_RADIANCE",
        ),
        float(
            "DISPLAY_EPSILON",
            display::DISPLAY_EPSILON,
            "display::DISPLAY_EPSILON",
        ),
        float("AGX_MIN_EV", display::AGX_MIN_EV, "display::AGX_MIN_EV"),
        float("AGX_MAX_EV", display::AGX_MAX_EV, "display::AGX_MAX_EV"),
        float(
            "AGX_LOG_FLOOR",
            display::AGX_LOG_FLOOR,
            "display::AGX_LOG_FLOOR",
        ),
    ]
}

/// The constants of `environment.wgsl`.
fn environment_constants() -> Vec<Constant> {
    let sobol_masks = lobe::SOBOL_MASKS.iter().enumerate().map(|(k, &mask)| {
        uint(
            format!("SOBOL_MASK_{k}"),
            mask as u64,
            format!("environment::lobe::SOBOL_MASKS[{k}]"),
        )
    });
    let mut constants = vec![
        uint(
            "SPECULAR_LEVELS".into(),
            prefilter::SPECULAR_LEVELS as u64,
            "environment::prefilter::SPECULAR_LEVELS".into(),
        ),
        uint(
            "CONVOLVED_LEVELS".into(),
            prefilter::CONVOLVED_LEVELS as u64,
            "environment::prefilter::CONVOLVED_LEVELS".into(),
        ),
        uint(
            "SPLIT_SUM_SIZE".into(),
            lut::SPLIT_SUM_SIZE as u64,
            "lut::SPLIT_SUM_SIZE".into(),
        ),
    ];
    constants.extend(sobol_masks);
    constants.extend([
        float(
            "LOBE_LOD_BIAS",
            lobe::LOBE_LOD_BIAS,
            "environment::lobe::LOBE_LOD_BIAS",
        ),
        float(
            "LOBE_SIN_MIN",
            prefilter::POLE_SIN_MIN,
            "environment::prefilter::POLE_SIN_MIN",
        ),
    ]);
    constants
}

/// The constants of `prefilter.wgsl`.
fn prefilter_constants() -> Vec<Constant> {
    let from = |name: &str| format!("environment::prefilter::{name}");
    vec![
        uint(
            "KERNEL_SIZE".into(),
            prefilter::KERNEL_SIZE as u64,
            from("KERNEL_SIZE"),
        ),
        float(
            "FIS_LOD_BIAS",
            prefilter::FIS_LOD_BIAS,
            &from("FIS_LOD_BIAS"),
        ),
        float(
            "WEIGHT_EPSILON",
            prefilter::WEIGHT_EPSILON,
            &from("WEIGHT_EPSILON"),
        ),
        float(
            "POLE_SIN_MIN",
            prefilter::POLE_SIN_MIN,
            &from("POLE_SIN_MIN"),
        ),
        uint(
            "BRIGHT_MAX".into(),
            prefilter::BRIGHT_MAX as u64,
            from("BRIGHT_MAX"),
        ),
    ]
}

/// Each file with a generated block, and the block's lines.
fn blocks() -> Vec<(&'static str, Vec<String>)> {
    let lines = |c: Vec<Constant>| -> Vec<String> {
        c.iter()
            .map(|c| format!("const {}: {} = {}; // {}", c.name, c.ty, c.value, c.from))
            .collect()
    };
    vec![
        ("constants.wgsl", lines(library_constants())),
        ("types.wgsl", lines(renderer_constants())),
        ("screen.wgsl", lines(display_constants())),
        ("environment.wgsl", lines(environment_constants())),
        ("prefilter.wgsl", lines(prefilter_constants())),
        (
            "footprint.wgsl",
            lines(vec![float(
                "AA_EDGE_PX",
                crate::scene::AA_EDGE_PX,
                "scene::AA_EDGE_PX",
            )]),
        ),
        (
            "walk.wgsl",
            lines(vec![float(
                "WALK_RR_BELOW",
                crate::walk::RR_BELOW,
                "walk::RR_BELOW",
            )]),
        ),
    ]
}

/// `text` with its generated block replaced by `block`, or why it has no single block.
fn with_block(text: &str, block: &[String]) -> Result<String, String> {
    with_marked(text, (BEGIN, END), block)
}

/// `text` with the block between the markers `open` and `close` replaced by `block`.
fn with_marked(
    text: &str,
    (open, close): (&str, &str),
    block: &[String],
) -> Result<String, String> {
    let begin = text.find(open).ok_or("no begin marker")?;
    if text[begin + open.len()..].contains(open) {
        return Err("two begin markers".into());
    }
    let end = begin + text[begin..].find(close).ok_or("no end marker")?;
    let mut out = text[..begin + open.len()].to_string();
    out.push('\n');
    for line in block {
        out.push_str(line);
        out.push('\n');
    }
    out.push_str(&text[end..]);
    Ok(out)
}

#[test]
fn the_shared_wgsl_constants_are_generated_from_the_rust_constants() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let bless = std::env::var_os("SHADEBALLS_BLESS").is_some();
    let mut stale = Vec::new();
    for (file, block) in blocks() {
        let path = dir.join(file);
        let text = std::fs::read_to_string(&path).expect("the shader file reads");
        let expected = with_block(&text, &block).unwrap_or_else(|e| panic!("{file}: {e}"));
        if expected != text {
            if bless {
                std::fs::write(&path, &expected).expect("the shader file writes");
            } else {
                stale.push(file);
            }
        }
        // A generated constant is declared only in its block.
        for line in &block {
            let decl = &line[..line.find(':').unwrap_or(line.len()) + 1];
            assert_eq!(
                expected.matches(decl).count(),
                1,
                "{file}: `{decl}` outside the generated block"
            );
        }
    }
    assert!(
        stale.is_empty(),
        "generated WGSL constants differ from the Rust constants in {stale:?} \
         (SHADEBALLS_BLESS=1 cargo test --release --lib -- boundary:: rewrites them)"
    );
}

/// Every struct type `ty` holds, itself included (through arrays and members).
fn structs_in(
    module: &naga::Module,
    ty: naga::Handle<naga::Type>,
    out: &mut Vec<naga::Handle<naga::Type>>,
) {
    match &module.types[ty].inner {
        naga::TypeInner::Struct { members, .. } => {
            if !out.contains(&ty) {
                out.push(ty);
            }
            for m in members {
                structs_in(module, m.ty, out);
            }
        }
        naga::TypeInner::Array { base, .. } | naga::TypeInner::BindingArray { base, .. } => {
            structs_in(module, *base, out)
        }
        _ => {}
    }
}

/// A member's type as WGSL writes it, for the scalars, vectors and structs of a buffer.
fn wgsl_type(module: &naga::Module, ty: naga::Handle<naga::Type>) -> String {
    let scalar = |s: &naga::Scalar| match (s.kind, s.width) {
        (naga::ScalarKind::Float, 4) => "f32".to_string(),
        (naga::ScalarKind::Uint, 4) => "u32".to_string(),
        (naga::ScalarKind::Sint, 4) => "i32".to_string(),
        other => format!("{other:?}"),
    };
    let t = &module.types[ty];
    match &t.inner {
        naga::TypeInner::Scalar(s) => scalar(s),
        naga::TypeInner::Vector { size, scalar: s } => {
            format!("vec{}<{}>", *size as u8, scalar(s))
        }
        naga::TypeInner::Struct { .. } => t.name.clone().unwrap_or_default(),
        other => format!("{other:?}"),
    }
}

/// A struct's layout: its size and each member's name, offset and type.
type Layout = (usize, Vec<(String, usize, String)>);

/// naga's layout of struct `ty`.
fn naga_layout(module: &naga::Module, ty: naga::Handle<naga::Type>) -> Layout {
    match &module.types[ty].inner {
        naga::TypeInner::Struct { members, span } => (
            *span as usize,
            members
                .iter()
                .map(|m| {
                    let name = m.name.clone().unwrap_or_default();
                    (name, m.offset as usize, wgsl_type(module, m.ty))
                })
                .collect(),
        ),
        _ => unreachable!("structs_in returns structs"),
    }
}

/// Every struct a program reads from a uniform or storage buffer, by name, with naga's
/// layout (the same name in two programs must have one layout).
fn buffer_structs() -> BTreeMap<String, Layout> {
    let mut found = BTreeMap::new();
    for program in PROGRAMS {
        // The viewer's passes (blit, difference) write their few bytes themselves
        // (viewer/difference.rs); the renderer's structs are the boundary.
        if matches!(program.name, "blit" | "difference") {
            continue;
        }
        let source = shaders::source(&program).expect("a built program");
        let module = naga::front::wgsl::parse_str(source).expect("the program parses");
        for (_, var) in module.global_variables.iter() {
            let buffer = matches!(
                var.space,
                naga::AddressSpace::Uniform | naga::AddressSpace::Storage { .. }
            );
            let mut types = Vec::new();
            if buffer {
                structs_in(&module, var.ty, &mut types);
            }
            for ty in types {
                let name = module.types[ty].name.clone().unwrap_or_default();
                let layout = naga_layout(&module, ty);
                if let Some(seen) = found.insert(name.clone(), layout.clone()) {
                    assert_eq!(seen, layout, "{name} differs between programs");
                }
            }
        }
    }
    found
}

/// Where the Rust twin `rust` differs from naga's layout, if anywhere.
fn mismatch(rust: &StructLayout, wgsl: &Layout) -> Option<String> {
    let members: Vec<(String, usize, String)> = rust
        .members
        .iter()
        .map(|(n, o, t)| (n.to_string(), *o, t.to_string()))
        .collect();
    if rust.size != wgsl.0 || members != wgsl.1 {
        return Some(format!(
            "{} (Rust {}): Rust size {} members {:?}, WGSL size {} members {:?}",
            rust.wgsl, rust.rust, rust.size, members, wgsl.0, wgsl.1
        ));
    }
    None
}

#[test]
fn every_buffer_struct_has_the_layout_of_its_rust_twin() {
    let found = buffer_structs();
    // Control: the programs read the five structs of the boundary and the prefilter's two.
    for name in [
        "Globals",
        "Ball",
        "Light",
        "EnvUniform",
        "LutParams",
        "PrefilterParams",
        "BrightTexel",
    ] {
        assert!(
            found.contains_key(name),
            "no buffer reads {name}: {found:?}"
        );
    }
    for (name, layout) in &found {
        let rust = STRUCTS
            .iter()
            .find(|s| s.wgsl == name)
            .unwrap_or_else(|| panic!("{name} is read from a buffer but has no Rust twin"));
        if let Some(why) = mismatch(rust, layout) {
            panic!("{why}");
        }
    }
    assert_eq!(
        found.len(),
        STRUCTS.len(),
        "a Rust twin of no buffer struct"
    );
}

#[test]
fn a_layout_mismatch_is_found() {
    // Control: a member moved, renamed or of another type, and another size, are reported.
    let found = buffer_structs();
    let ball = STRUCTS.iter().find(|s| s.wgsl == "Ball").expect("Ball");
    let mut moved = found["Ball"].clone();
    moved.1[3].1 += 4;
    assert!(mismatch(ball, &moved).is_some());
    let mut renamed = found["Ball"].clone();
    renamed.1[6].0 = "lut_row_w".into();
    assert!(mismatch(ball, &renamed).is_some());
    let mut retyped = found["Ball"].clone();
    retyped.1[3].2 = "u32".into();
    assert!(mismatch(ball, &retyped).is_some());
    let mut resized = found["Ball"].clone();
    resized.0 += 16;
    assert!(mismatch(ball, &resized).is_some());
}

#[test]
fn the_wgsl_ball_is_generated_from_the_rust_members() {
    // The ball's one list (gpu::uniforms::BALL_MEMBERS) gives `struct Ball`, the vertex
    // input, the flat varyings and ball_of in types.wgsl; a hand edit there fails here.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders/types.wgsl");
    let text = std::fs::read_to_string(&path).expect("types.wgsl reads");
    let block = boundary::ball_wgsl();
    let expected = with_marked(&text, (BALL_BEGIN, BALL_END), &block)
        .unwrap_or_else(|e| panic!("types.wgsl: {e}"));
    if expected != text {
        if std::env::var_os("SHADEBALLS_BLESS").is_some() {
            std::fs::write(&path, &expected).expect("types.wgsl writes");
        } else {
            panic!(
                "the ball in types.wgsl differs from what gpu::uniforms::BALL_MEMBERS generates \
                 (SHADEBALLS_BLESS=1 cargo test --release --lib -- boundary:: rewrites it)"
            );
        }
    }
    // The struct is declared once, in the block.
    assert_eq!(expected.matches("struct Ball {").count(), 1);
}

/// A vertex attribute's format as the WGSL type of its input.
fn format_wgsl(format: wgpu::VertexFormat) -> &'static str {
    use wgpu::VertexFormat as F;
    match format {
        F::Float32 => "f32",
        F::Float32x2 => "vec2<f32>",
        F::Float32x3 => "vec3<f32>",
        F::Float32x4 => "vec4<f32>",
        F::Uint32 => "u32",
        F::Uint32x2 => "vec2<u32>",
        F::Uint32x3 => "vec3<u32>",
        F::Uint32x4 => "vec4<u32>",
        other => panic!("no WGSL type for {other:?}"),
    }
}

/// `vs_ball`'s vertex inputs in `program`, by location: (location, WGSL type).
fn vs_ball_inputs(source: &str) -> Option<Vec<(u32, String)>> {
    let module = naga::front::wgsl::parse_str(source).expect("the program parses");
    let entry = module.entry_points.iter().find(|e| e.name == "vs_ball")?;
    let mut inputs = Vec::new();
    let mut add = |binding: &Option<naga::Binding>, ty| {
        if let Some(naga::Binding::Location { location, .. }) = binding {
            inputs.push((*location, wgsl_type(&module, ty)));
        }
    };
    for arg in &entry.function.arguments {
        match &module.types[arg.ty].inner {
            naga::TypeInner::Struct { members, .. } => {
                for m in members {
                    add(&m.binding, m.ty);
                }
            }
            _ => add(&arg.binding, arg.ty),
        }
    }
    inputs.sort();
    Some(inputs)
}

/// The generated vertex layout's (location, WGSL type) pairs, sorted.
fn layout_inputs(attributes: &[wgpu::VertexAttribute]) -> Vec<(u32, String)> {
    let mut out: Vec<(u32, String)> = attributes
        .iter()
        .map(|a| (a.shader_location, format_wgsl(a.format).to_string()))
        .collect();
    out.sort();
    out
}

#[test]
fn the_ball_vertex_layout_is_what_vs_ball_reads() {
    let layout = layout_inputs(boundary::ball_attributes());
    let mut programs = 0;
    for program in PROGRAMS {
        let source = shaders::source(&program).expect("a built program");
        if let Some(inputs) = vs_ball_inputs(source) {
            programs += 1;
            assert_eq!(
                inputs, layout,
                "{}: vs_ball against BallInstance::LAYOUT",
                program.name
            );
        }
    }
    // Control: the balls, the truth and the Monte Carlo draw quads.
    assert!(programs >= 3, "{programs} programs with vs_ball");
    // Control: a deliberate mismatch (an attribute of another format, or moved) is found.
    let mut wrong = boundary::ball_attributes().to_vec();
    wrong[2].format = wgpu::VertexFormat::Uint32x4;
    let source = shaders::source(&PROGRAMS[0]).expect("a built program");
    let inputs = vs_ball_inputs(source).expect("the balls' program has vs_ball");
    assert_ne!(inputs, layout_inputs(&wrong));
    let mut moved = boundary::ball_attributes().to_vec();
    moved[3].shader_location = 40;
    assert_ne!(inputs, layout_inputs(&moved));
}
