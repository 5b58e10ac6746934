//! `shadeballs probe`: what the shader reads from the tables, evaluated on the GPU (CSV).

use std::fmt::Write as _;

use super::args::ProbeArgs;
use crate::brdf::Geometry;
use crate::error::Error;
use crate::gpu::{Gpu, Renderer};
use crate::{output, scene};

pub(crate) fn run(args: ProbeArgs) -> anyhow::Result<()> {
    output::check_output_path(&args.out)?;
    let scene = args
        .scene
        .iter()
        .map(|p| ("the scene file --scene".to_string(), p.clone()));
    super::guard::check_out(&args.out, &scene.collect::<Vec<_>>())?;
    if output::extension(&args.out) != "csv" {
        anyhow::bail!(
            "--out '{}' must be a .csv file (the probe writes CSV)",
            args.out.display()
        );
    }
    if let Some(warning) = super::args::ignored_geometry(args.preset, args.geometry) {
        eprintln!("warning: {warning}");
    }
    // The probe needs a GPU: no CPU fallback (and no warning announcing one); `--backend
    // cpu` is refused by the flag's parser.
    super::check_wgpu_backend_env(args.backend)?;
    let backends = args
        .backend
        .wgpu_backends()
        .unwrap_or(wgpu::Backends::VULKAN);
    let mut renderer = match Gpu::new(backends) {
        Ok(gpu) => Renderer::new(gpu),
        Err(Error::NoAdapter { message, .. }) => anyhow::bail!(
            "the probe runs on the GPU and no adapter was found ({message}); \
             for software Vulkan install the package mesa-vulkan-drivers"
        ),
        Err(e) => return Err(e.into()),
    };
    let (geometry, samples, what) = match &args.scene {
        Some(path) => {
            let scene = scene::load(path)?;
            let geometry = scene.effective_geometry();
            let Some((rows, samples)) = renderer.probe_rows(&scene, args.grid)? else {
                anyhow::bail!(
                    "{}: the scene's plan bakes no rows (no ball reads E, or more roughness \
                     values than rows are planned for); probe without --scene",
                    path.display()
                );
            };
            (
                geometry,
                samples,
                format!("{}x{} rows", args.grid, rows.rows.len()),
            )
        }
        None => {
            let geometry = args
                .preset
                .geometry()
                .or(args.geometry)
                .unwrap_or(Geometry::Schlick);
            let (_, samples) = renderer.probe(geometry, args.grid)?;
            (geometry, samples, format!("{}x{}", args.grid, args.grid))
        }
    };
    let mut csv = String::from("roughness,mu,E,E_avg\n");
    for s in &samples {
        let _ = writeln!(csv, "{},{},{},{}", s.roughness, s.mu, s.e, s.e_avg);
    }
    output::write_atomic(&args.out, csv.as_bytes())?;
    eprintln!(
        "probed {what} ({} G) on {} -> {}",
        geometry,
        renderer.gpu().describe(),
        args.out.display()
    );
    Ok(())
}
