//! Pipelines from programs specialised to their override constants (src/gpu/specialise.rs):
//! the branches the constants decide are gone from what the driver gets, what they call
//! with them, and the pictures are byte for byte those the whole programs draw.

use std::collections::BTreeSet;

use crate::display::DisplayTransform;
use crate::environment::IblMethod;
use crate::gpu::specialise::{cut_decided_branches, parse, specialise, validate, visit};
use crate::gpu::{shaders, TermMode, Variant};
use crate::pixels::vulkan;
use crate::scene::Scene;

/// A split-sum variant of the showcase's first row, with the switches given.
fn variant(ibl: u8, clearcoat: bool, anisotropy: bool, lights: bool) -> Variant {
    Variant {
        term: TermMode::In,
        environment: false,
        lights,
        sun: false,
        ibl,
        ibl_samples: if ibl == 2 { 16 } else { 0 },
        ibl_cosine_samples: if ibl == 2 { 4 } else { 0 },
        aa: true,
        dominant: true,
        ball_term: 1,
        clearcoat,
        anisotropy,
        metal: true,
        dielectric: clearcoat,
        display: DisplayTransform::HOMEWORK,
    }
}

fn parsed(source: &str) -> (naga::Module, naga::valid::ModuleInfo) {
    parse(source).unwrap_or_else(|e| panic!("the program does not parse or validate: {e}"))
}

fn function_names(module: &naga::Module) -> BTreeSet<String> {
    module
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.clone())
        .collect()
}

/// How many `if`s of `module` still branch on a constant `bool`.
fn decided_ifs(module: &naga::Module) -> usize {
    let mut n = 0;
    let functions = module.functions.iter().map(|(_, f)| f);
    for f in functions.chain(module.entry_points.iter().map(|ep| &ep.function)) {
        visit(&f.body, &mut |s| {
            if let naga::Statement::If { condition, .. } = *s {
                let e = match f.expressions[condition] {
                    naga::Expression::Constant(c) => {
                        &module.global_expressions[module.constants[c].init]
                    }
                    ref e => e,
                };
                if matches!(e, naga::Expression::Literal(naga::Literal::Bool(_))) {
                    n += 1;
                }
            }
        });
    }
    n
}

/// The ball program's fragment stage, per variant: what wgpu's own folding of the
/// constants leaves (every branch) against the specialised module (none on a constant,
/// and only the functions the variant calls).
#[test]
fn specialising_cuts_the_branches_the_constants_decide() {
    let (module, info) = parsed(shaders::balls_source(false));
    let cases = [
        (
            "one light",
            variant(0, false, false, true),
            &[][..],
            &[
                "clearcoat_begin",
                "shade_environment_mis",
                "specular_direction_aniso",
            ][..],
        ),
        (
            "split sum",
            variant(1, false, false, false),
            &["env_specular"][..],
            &["clearcoat_begin", "shade_environment_mis"][..],
        ),
        (
            "lobe mode",
            variant(2, false, false, false),
            &["shade_environment_mis"][..],
            &["clearcoat_begin"][..],
        ),
        (
            "coated",
            variant(1, true, false, false),
            &["clearcoat_begin"][..],
            &["shade_environment_mis", "specular_direction_aniso"][..],
        ),
        (
            "anisotropic",
            variant(1, false, true, false),
            &["specular_direction_aniso"][..],
            &["clearcoat_begin"][..],
        ),
    ];
    for (name, v, kept, cut) in cases {
        let constants = shaders::overrides_for(
            crate::brdf::Geometry::SmithCorrelated,
            false,
            crate::lut::MuAxis::Warped,
            v,
            false,
        );
        let values: naga::back::PipelineConstants =
            constants.iter().map(|&(k, x)| (k.to_owned(), x)).collect();
        let (folded, _) = naga::back::pipeline_constants::process_overrides(
            &module,
            &info,
            Some((naga::ShaderStage::Fragment, shaders::FS_BALL)),
            &values,
        )
        .unwrap();
        let special = specialise(
            &module,
            &info,
            naga::ShaderStage::Fragment,
            shaders::FS_BALL,
            &constants,
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        let before = function_names(&folded);
        let after = function_names(&special);
        println!(
            "{name}: {} functions and {} decided ifs as wgpu folds it, {} and {} specialised",
            before.len(),
            decided_ifs(&folded),
            after.len(),
            decided_ifs(&special)
        );
        assert!(
            decided_ifs(&folded) > 0,
            "{name}: the control has decided branches"
        );
        assert_eq!(decided_ifs(&special), 0, "{name}: a decided branch is left");
        assert!(after.is_subset(&before), "{name}");
        for f in kept {
            assert!(
                after.contains(*f),
                "{name}: {f} was cut, yet the variant calls it"
            );
        }
        for f in cut {
            assert!(before.contains(*f), "{name}: the control lacks {f}");
            assert!(
                !after.contains(*f),
                "{name}: {f} is kept, yet no branch taken calls it"
            );
        }
    }
}

/// Cutting keeps the side taken: a function whose result rests on a constant's branch
/// returns the taken side's value after the cut (naga's own constant evaluation of the
/// specialised module, no GPU).
#[test]
fn a_cut_branch_keeps_the_side_its_constant_takes() {
    let source = "
        override FLAG: bool = false;
        @fragment fn main() -> @location(0) vec4<f32> {
            var x = 1.0;
            if FLAG { x = 2.0; } else { x = 3.0; }
            if !FLAG { x = x * 5.0; }
            return vec4<f32>(x);
        }";
    let (module, info) = parsed(source);
    for (flag, side) in [(1.0, "2f"), (0.0, "3f")] {
        let m = specialise(
            &module,
            &info,
            naga::ShaderStage::Fragment,
            "main",
            &[("FLAG", flag)],
        )
        .unwrap();
        assert_eq!(decided_ifs(&m), 0);
        let wgsl = naga::back::wgsl::write_string(
            &m,
            &validate(&m).unwrap(),
            naga::back::wgsl::WriterFlags::empty(),
        )
        .unwrap();
        assert!(wgsl.contains(side), "FLAG = {flag}: {wgsl}");
        let other = if side == "2f" { "3f" } else { "2f" };
        assert!(!wgsl.contains(other), "FLAG = {flag}: {wgsl}");
        assert_eq!(wgsl.contains("5f"), flag == 0.0, "FLAG = {flag}: {wgsl}");
    }
    // The pass alone, on a module whose flag is already a constant: the same cut.
    let mut m = naga::front::wgsl::parse_str(
        "const FLAG: bool = true;
         @fragment fn main() -> @location(0) vec4<f32> {
             var x = 1.0;
             if FLAG { x = 2.0; } else { x = 3.0; }
             return vec4<f32>(x);
         }",
    )
    .unwrap();
    cut_decided_branches(&mut m);
    assert_eq!(decided_ifs(&m), 0);
}

/// The pictures: specialised ball pipelines draw every pixel the whole ball programs draw,
/// on the showcase (split sum under the studio), the homework's scene (one light), the lobe
/// mode, and a coated and an anisotropic chart. (The truth's, the Monte Carlo's and the
/// lobe accumulation's programs are specialised on both sides; tests/same_pictures.sh
/// compares whole binaries.)
#[test]
fn specialised_pipelines_draw_what_the_whole_programs_draw() {
    let (w, h) = (320, 180);
    let mut lobe = Scene::showcase();
    lobe.ibl_method = IblMethod::Lobe;
    let asset = |name: &str| {
        crate::scene::load(
            &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("assets/scenes")
                .join(name),
        )
        .unwrap()
    };
    let scenes = [
        ("showcase", Scene::showcase()),
        ("homework", Scene::reference()),
        ("lobe mode", lobe),
        ("clear coat", asset("clearcoat.toml")),
        ("anisotropy", asset("anisotropy.toml")),
    ];
    let mut specialised = vulkan();
    let mut whole = vulkan();
    whole.set_specialise(false);
    for (name, scene) in scenes {
        let a = specialised.render_ldr(&scene, w, h).unwrap().rgba;
        let b = whole.render_ldr(&scene, w, h).unwrap().rgba;
        let differing = a
            .chunks_exact(4)
            .zip(b.chunks_exact(4))
            .filter(|(p, q)| p != q)
            .count();
        assert_eq!(differing, 0, "{name}: {differing} pixels differ");
    }
}

/// The conditions naga does not fold itself: a flag and-ed with a varying value, in a
/// helper that returns it (naga lowers `&&` to a local and an `if`), and or-ed inline.
#[test]
fn a_flag_behind_a_helper_and_a_logical_operator_is_cut() {
    let source = "
        override HAS_X: bool = false;
        fn has_x(v: f32) -> bool { return HAS_X && v > 0.0; }
        fn heavy(v: f32) -> f32 { return v * 3.0; }
        @fragment fn main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
            var x = p.x;
            if has_x(x) { x = heavy(x); }
            if HAS_X || x > 2.0 { x = x + 7.0; }
            return vec4<f32>(x);
        }";
    let (module, info) = parsed(source);
    let names = |flag: f64| {
        let m = specialise(
            &module,
            &info,
            naga::ShaderStage::Fragment,
            "main",
            &[("HAS_X", flag)],
        )
        .unwrap();
        let main = &m.entry_points[0].function;
        let mut ifs = 0;
        for s in main.body.iter() {
            if let naga::Statement::If { .. } = s {
                ifs += 1;
            }
        }
        (function_names(&m), ifs, decided_ifs(&m))
    };
    let (off, off_ifs, off_decided) = names(0.0);
    assert!(!off.contains("heavy"), "HAS_X false: {off:?}");
    // `x > 2.0` still decides the second branch.
    assert_eq!((off_ifs, off_decided), (1, 0));
    let (on, on_ifs, on_decided) = names(1.0);
    assert!(on.contains("heavy"), "HAS_X true: {on:?}");
    // The first branch rests on `v > 0.0`. The second is taken whatever `x`, but naga
    // writes the or's `true` into a local declared without a value, which the pass does not
    // take for a constant (a read before the store would see false). The branch stays; its
    // body is code the variant runs, so nothing it cannot run is left.
    assert_eq!((on_ifs, on_decided), (2, 0));
}
