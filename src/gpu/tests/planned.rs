//! The planned renderer on the GPU: what it bakes and binds per case, its row cache, and
//! its images against the full-table renders (GPU-vs-CPU bound) and the term compiled out
//! (exactly equal where no ball has the term).
use std::time::Duration;

use crate::cpu;
use crate::gpu::Renderer;
use crate::gpu::{DrawOptions, MAX_PLANNED_ROWS};
use crate::lut::BakeConfig;
use crate::lut::TableSet;
use crate::scene::{Model, Scene};
use glam::DVec3;

use super::plan::{no_term, scene_with_roughness};
use crate::pixels::{assert_close, compare, vulkan};

const W: u32 = 640;
const H: u32 = 360;

/// The CPU renders of `scene`: from the 2-D table, and from the rows the GPU bound.
fn cpu_renders(r: &mut Renderer, scene: &Scene) -> (Vec<u8>, Option<Vec<u8>>) {
    let bound = r.bound_tables();
    let rows = match &bound {
        TableSet::Rows(_) => Some(cpu::to_display_rgba8(
            &cpu::render_radiance(scene, &crate::prepared::Prepared::new(scene, &bound), W, H),
            scene.exposure,
            scene.display(),
        )),
        _ => None,
    };
    let full = TableSet::full(r.tables_for(scene.effective_geometry()));
    let full = cpu::to_display_rgba8(
        &cpu::render_radiance(scene, &crate::prepared::Prepared::new(scene, &full), W, H),
        scene.exposure,
        scene.display(),
    );
    (full, rows)
}

fn environment_scene() -> Scene {
    let mut s = Scene::reference();
    s.environment = DVec3::new(0.2, 0.25, 0.3);
    s.balls[3].model = Model::None;
    s
}

/// Planned renders (rows, none, the 2-D table past the threshold) equal the CPU's render
/// from the full table, and from the very rows bound, within the GPU-vs-CPU bound.
#[test]
fn planned_renders_match_the_full_table_render() {
    let mut r = vulkan();
    for (name, scene) in [
        ("default", Scene::reference()),
        ("no term", no_term()),
        ("environment", environment_scene()),
        (
            "past the threshold",
            scene_with_roughness(MAX_PLANNED_ROWS + 1),
        ),
    ] {
        let gpu = r.render_ldr(&scene, W, H).unwrap().rgba;
        println!("{name}: {}", r.plan().unwrap());
        let (full, rows) = cpu_renders(&mut r, &scene);
        assert_close(
            &compare(&gpu, &full, W),
            &format!("planned {name} vs CPU full table"),
        );
        if let Some(rows) = rows {
            assert_close(
                &compare(&gpu, &rows, W),
                &format!("planned {name} vs CPU rows"),
            );
        }
    }
}

/// What is baked: nothing without the term; the default scene's five rows once; a change
/// of one roughness bakes one row; an unchanged scene bakes nothing.
#[test]
fn bakes_only_new_rows() {
    let mut r = vulkan();
    r.plan_for(&no_term());
    assert!(matches!(r.bound_tables(), TableSet::None));
    assert_eq!(r.last_bake_time(), Some(Duration::ZERO));
    assert_eq!(r.cached_rows(), 0);

    let mut scene = Scene::reference();
    r.plan_for(&scene);
    assert_eq!(r.cached_rows(), 5);
    assert!(r.last_bake_time().unwrap() > Duration::ZERO);
    match r.bound_tables() {
        TableSet::Rows(rows) => assert_eq!(rows.rows.len(), 5),
        _ => panic!("rows expected"),
    }
    // The first ball's roughness changes (its twin below has no term): one new row baked,
    // five bound.
    scene.balls[0].roughness = 0.5;
    r.plan_for(&scene);
    assert_eq!(r.cached_rows(), 6, "one new row");
    match r.bound_tables() {
        TableSet::Rows(rows) => assert_eq!(rows.rows.len(), 5),
        _ => panic!("rows expected"),
    }
    // Back to a plan whose rows are all cached: nothing baked.
    r.plan_for(&Scene::reference());
    assert_eq!(r.last_bake_time(), Some(Duration::ZERO));
    assert_eq!(r.cached_rows(), 6);
    // Asking for the 2-D table between planned frames rebinds the same rows (kept).
    let TableSet::Rows(before) = r.bound_tables() else {
        panic!("rows expected")
    };
    r.tables_for(Scene::reference().effective_geometry());
    assert!(matches!(r.bound_tables(), TableSet::Full(_)));
    r.plan_for(&Scene::reference());
    let TableSet::Rows(after) = r.bound_tables() else {
        panic!("rows expected")
    };
    assert!(
        std::sync::Arc::ptr_eq(&before, &after),
        "the rows were bound anew"
    );
    // Another bake config is another key.
    r.set_bake_config(BakeConfig {
        samples: 16,
        ..BakeConfig::default()
    });
    r.plan_for(&Scene::reference());
    assert_eq!(r.cached_rows(), 11);
}

/// Without the term, the planned image equals the one with the term compiled out of every
/// pipeline.
#[test]
fn no_term_scene_equals_the_plain_shader() {
    let mut r = vulkan();
    let scene = no_term();
    let planned = r.render_ldr(&scene, W, H).unwrap().rgba;
    r.set_draw_options(DrawOptions {
        term: false,
        ..DrawOptions::default()
    });
    let plain = r.render_ldr(&scene, W, H).unwrap().rgba;
    let d = compare(&planned, &plain, W);
    assert_eq!(d.pixels, d.equal, "{}", d.report("no term vs plain"));
}

/// The probe along the default scene's rows (the shader's `lut_loss_row`, on the GPU)
/// returns exactly the CPU model of the read, and is within 2e-4 of the precise reference
/// at the scene's roughness values (the bound); a scene that reads no rows has none.
#[test]
fn probe_along_the_scenes_rows() {
    let mut r = vulkan();
    let scene = Scene::reference();
    let (rows, samples) = r.probe_rows(&scene, 65).unwrap().expect("rows planned");
    assert_eq!(samples.len(), 65 * 5);
    let g = scene.effective_geometry();
    let mut worst: f64 = 0.0;
    for s in &samples {
        let cpu = 1.0 - rows.lut_loss(s.mu, s.roughness);
        assert_eq!(
            s.e, cpu,
            "GPU and CPU reads differ at ({}, {})",
            s.mu, s.roughness
        );
        assert_eq!(s.e_avg, 1.0 - rows.lut_loss_avg(s.roughness));
        let exact = crate::lut::e_reference(s.mu as f64, s.roughness as f64, g);
        worst = worst.max((s.e as f64 - exact).abs());
    }
    println!("probe along the default scene's rows: max E error {worst:.2e}");
    assert!(worst <= 2e-4, "{worst:e}");
    assert!(r.probe_rows(&no_term(), 65).unwrap().is_none());
}
