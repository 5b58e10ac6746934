//! The BRDF out (docs/interop.md): `export-shader` writes the ball shading through naga's
//! back ends (its GLSL passes glslangValidator), `bake --out tables.h|.glsl` writes the
//! tables as C / GLSL arrays that compile and hold the bake's values exactly.

use std::process::Command;

use crate::cli::{shadeballs, temp_dir};

/// Runs a tool the test needs, failing loudly with the Debian package that has it.
fn tool(program: &str, package: &str, args: &[&str]) -> (bool, String) {
    let out = Command::new(program).args(args).output().unwrap_or_else(|e| {
        panic!("cannot run {program} ({e}): install the Debian package {package} (tests/run.sh does)")
    });
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), text)
}

#[test]
fn the_exported_shader_translates_and_its_glsl_validates() {
    let dir = temp_dir("export-shader");
    for (lang, file) in [
        ("glsl", "ball.frag"),
        ("wgsl", "ball.wgsl"),
        ("hlsl", "ball.hlsl"),
        ("msl", "ball.metal"),
    ] {
        let out = dir.join(file);
        let (ok, stderr) = shadeballs(&[
            "export-shader",
            "--lang",
            lang,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{lang}: {stderr}");
        let text = std::fs::read_to_string(&out).unwrap();
        assert!(
            text.contains("fs_ball") || lang == "glsl",
            "{lang}: no entry point"
        );
        // The Kulla-Conty pieces are there in every language.
        for f in ["lut_loss", "f_micro", "substrate_albedo", "f_base_physical"] {
            assert!(text.contains(f), "{lang}: no {f}");
        }
    }
    let frag = dir.join("ball.frag");
    let (ok, text) = tool(
        "glslangValidator",
        "glslang-tools",
        &[frag.to_str().unwrap()],
    );
    assert!(ok, "glslangValidator refuses the exported GLSL: {text}");
    // The validator does refuse a broken shader (the check can fail).
    let broken = dir.join("broken.frag");
    let glsl = std::fs::read_to_string(&frag).unwrap();
    std::fs::write(&broken, glsl.replace("void main()", "void main(")).unwrap();
    assert!(
        !tool(
            "glslangValidator",
            "glslang-tools",
            &[broken.to_str().unwrap()]
        )
        .0
    );
    // The WGSL reads back into naga and validates.
    let wgsl = std::fs::read_to_string(dir.join("ball.wgsl")).unwrap();
    let module = naga::front::wgsl::parse_str(&wgsl).expect("the exported WGSL parses");
    naga::valid::Validator::new(Default::default(), naga::valid::Capabilities::empty())
        .validate(&module)
        .expect("the exported WGSL validates");
    // A bad language is one line.
    let (ok, stderr) = shadeballs(&["export-shader", "--lang", "spirv", "--out", "x"]);
    assert!(!ok && stderr.trim_end().lines().count() == 1, "{stderr}");
}

#[test]
fn the_c_header_compiles_and_holds_the_bake() {
    let dir = temp_dir("bake-header");
    let h = dir.join("tables.h");
    let (ok, stderr) = shadeballs(&["bake", "--out", h.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let c = dir.join("print.c");
    std::fs::write(
        &c,
        "#include <stdio.h>\n#include \"tables.h\"\nint main(void) {\n\
         for (int i = 0; i < SHADEBALLS_MU_SIZE * SHADEBALLS_R_SIZE; i++) printf(\"%.9g\\n\", SHADEBALLS_LOSS[i]);\n\
         for (int j = 0; j < SHADEBALLS_R_SIZE; j++) printf(\"%.9g\\n\", SHADEBALLS_LOSS_AVG[j]);\n\
         return 0;\n}\n",
    )
    .unwrap();
    // `cc -c` of the header alone (through a file that includes it), then a program that
    // prints every value.
    let unit = dir.join("unit.c");
    std::fs::write(
        &unit,
        "#include \"tables.h\"\nfloat first(void) { return SHADEBALLS_LOSS[0]; }\n",
    )
    .unwrap();
    let obj = dir.join("unit.o");
    let (ok, text) = tool(
        "cc",
        "gcc",
        &[
            "-std=c99",
            "-Wall",
            "-Werror",
            "-c",
            unit.to_str().unwrap(),
            "-o",
            obj.to_str().unwrap(),
        ],
    );
    assert!(ok, "cc -c: {text}");
    let exe = dir.join("print");
    let (ok, text) = tool(
        "cc",
        "gcc",
        &["-std=c99", c.to_str().unwrap(), "-o", exe.to_str().unwrap()],
    );
    assert!(ok, "cc: {text}");
    let (ok, printed) = tool(exe.to_str().unwrap(), "gcc", &[]);
    assert!(ok);
    let values: Vec<f32> = printed.lines().map(|l| l.parse().unwrap()).collect();
    let tables = shadeballs::bake(&shadeballs::BakeConfig::default());
    let expected: Vec<f32> = tables
        .stored_loss
        .iter()
        .chain(&tables.stored_loss_avg)
        .copied()
        .collect();
    assert_eq!(values.len(), expected.len());
    for (k, (a, b)) in values.iter().zip(&expected).enumerate() {
        assert_eq!(
            a.to_bits(),
            b.to_bits(),
            "value {k}: {a} against the bake's {b}"
        );
    }
    let text = std::fs::read_to_string(&h).unwrap();
    assert!(
        text.contains("mu_scale = ") && text.contains("row-major"),
        "no layout comment"
    );
}

#[test]
fn the_glsl_tables_validate() {
    let dir = temp_dir("bake-glsl");
    let g = dir.join("tables.glsl");
    let (ok, stderr) = shadeballs(&["bake", "--out", g.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let frag = dir.join("tables.frag");
    std::fs::write(
        &frag,
        format!(
            "#version 450\n{}\nlayout(location = 0) out vec4 colour;\nvoid main() {{\n    \
             colour = vec4(SHADEBALLS_LOSS[SHADEBALLS_MU_SIZE + 3], SHADEBALLS_LOSS_AVG[2], 0.0, 1.0);\n}}\n",
            std::fs::read_to_string(&g).unwrap()
        ),
    )
    .unwrap();
    let (ok, text) = tool(
        "glslangValidator",
        "glslang-tools",
        &[frag.to_str().unwrap()],
    );
    assert!(ok, "glslangValidator refuses the GLSL tables: {text}");
}
