//! `shadeballs-lab compare`: each model's picture against the truth's (the lab's
//! [`crate::compare`]).

use std::time::Instant;

use super::args::CompareArgs;
use crate::compare::{self, CompareOptions};

pub fn run(args: CompareArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    shadeballs::output::check_output_folder(&args.out)?;
    shadeballs::cli::check_wgpu_backend_env(args.backend)?;
    // The homework's scene by default: the one docs/truth.md's figures are of.
    let scene = args.scene.load_or(shadeballs::scene::Scene::reference)?;
    let scene = compare::with_rows_material(scene, args.ball as usize - 1)?;
    // The library's opening of a backend, with its fallbacks (`shadeballs::render::open`).
    let (mut renderer, notice) = shadeballs::render::open(args.backend)?;
    if let Some(notice) = notice {
        eprintln!("{notice}");
    }
    let options = CompareOptions {
        scene,
        out: args.out,
        spp: args.spp.unwrap_or(if args.quick { 32 } else { 256 }),
        seed: args.seed,
        cell: if args.quick { 64 } else { 160 },
        timing_size: if args.quick { (640, 360) } else { (1280, 720) },
    };
    let comparison = compare::run(&options, renderer.as_mut())?;
    shadeballs::cli::print_stdout(&compare::summary(&comparison));
    let headline = comparison.headline().map_or(String::new(), |(err, floor)| {
        format!(
            "accurate preset's mean relative image error {:.2} % (truth noise {:.2} %), ",
            100.0 * err,
            100.0 * floor
        )
    });
    eprintln!(
        "compare: {headline}truth {} spp in {:.1} s, {:.1} s in all -> {}",
        comparison.truth_spp,
        comparison.truth_seconds,
        start.elapsed().as_secs_f64(),
        options.out.display()
    );
    Ok(())
}
