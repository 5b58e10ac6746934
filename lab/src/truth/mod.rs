//! How close is Kulla-Conty to real multiple scattering: a ground-truth reference and the
//! comparison behind `shadeballs-lab truth`.
//!
//! The reference is the random walk on the GGX microsurface with height-correlated Smith
//! masking of Heitz, Hanika, d'Eon and Dachsbacher 2016 ([`walk`], [`microsurface`]), for a
//! conductor with Schlick's Fresnel or the full conductor Fresnel of a Gulbrandsen 2014
//! artist-friendly pair ([`fresnel`]). Its single-scattering part is computed exactly by
//! quadrature ([`single`]); the walk supplies the rest. The models ([`models`]) are the
//! presets exactly as the renderer evaluates them (same functions, same baked tables),
//! Kulla-Conty variants, and the compensations of Turquin 2019 and Fdez-Aguera 2019.
//! [`albedo`] and [`lobes`] run the two studies; [`report`], [`lobe_report`] and
//! [`figures`] write CSV tables, a markdown summary and PNG plots (drawn by [`crate::plot`]).

pub mod albedo;
pub mod compare;
pub mod estimate;
pub mod figures;
pub mod fresnel;
pub mod lobe_report;
pub mod lobes;
pub mod models;
pub mod report;
pub mod walk;

// The walk's building blocks live in the library (the truth renderer uses them too).
pub use shadeballs::walk::{microsurface, rng, single};

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use albedo::{Cell, Channel, Grid};
use compare::Comparison;
use lobes::{Slice, Slices};
use models::ModelTables;

use crate::plot::{write_figure, Figure};
use shadeballs::brdf::Geometry;
use shadeballs::error::{Error, Result};
use shadeballs::output::write_atomic;
use shadeballs::scene::Scene;

/// What `shadeballs-lab truth` runs and where it writes.
#[derive(Clone, Debug)]
pub struct TruthOptions {
    /// A few cells and slices with few paths (seconds) instead of the full study.
    pub quick: bool,
    pub out: PathBuf,
}

/// Everything the study computed.
pub struct Study {
    pub quick: bool,
    pub grid: Grid,
    pub slices_config: Slices,
    pub channels: Vec<Channel>,
    pub tables: ModelTables,
    pub cells: Vec<Cell>,
    pub slices: Vec<Slice>,
    /// The G that `accurate` renders with by default (the reference scene's).
    pub accurate_geometry: Geometry,
    /// Wall seconds of the albedo and the lobe studies.
    pub seconds: [f64; 2],
}

impl Study {
    /// Runs both studies (most of the time is the walk, on all cores).
    pub fn run(quick: bool) -> Self {
        let (grid, slices_config) = if quick {
            (Grid::quick(), Slices::quick())
        } else {
            (Grid::full(), Slices::full())
        };
        let channels = albedo::channels();
        let tables = ModelTables::new();
        let accurate_geometry = Scene::reference().effective_geometry();
        let start = Instant::now();
        let cells = albedo::compute(&grid, &channels);
        let t_albedo = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let slices = lobes::compute(&slices_config, &channels, &tables, accurate_geometry);
        let t_lobes = start.elapsed().as_secs_f64();
        Study {
            quick,
            grid,
            slices_config,
            channels,
            tables,
            cells,
            slices,
            accurate_geometry,
            seconds: [t_albedo, t_lobes],
        }
    }

    pub fn comparison(&self) -> Comparison<'_> {
        Comparison::new(
            &self.cells,
            &self.channels,
            &self.tables,
            self.accurate_geometry,
        )
    }
}

/// The headline numbers of a study.
#[derive(Clone, Copy, Debug)]
pub struct Headline {
    /// Largest directional-albedo error against the walk, over mu, roughness and the three
    /// materials (Schlick Fresnel), of the `accurate` and `games202` presets.
    pub accurate: f64,
    pub games202: f64,
    /// Largest standard error of the walk's albedo over the same cells.
    pub max_stderr: f64,
}

/// Runs the study, writes every file into `options.out`, returns the markdown summary
/// and the headline numbers.
pub fn run(options: &TruthOptions) -> Result<(String, Headline)> {
    std::fs::create_dir_all(&options.out).map_err(|reason| Error::Write {
        path: options.out.clone(),
        reason,
    })?;
    let study = Study::run(options.quick);
    write_all(&study, &options.out)
}

fn write_text(dir: &Path, name: &str, text: &str) -> Result<()> {
    write_atomic(&dir.join(name), text.as_bytes())
}

/// Writes the CSV files, the figures and `summary.md` of `study` into `dir`.
pub fn write_all(study: &Study, dir: &Path) -> Result<(String, Headline)> {
    let cmp = study.comparison();
    write_text(dir, "albedo.csv", &report::albedo_csv(&cmp).0)?;
    write_text(dir, "albedo_conductor.csv", &report::conductor_csv(&cmp).0)?;
    let (ablation_csv, ablation_md) = report::ablation(&cmp);
    write_text(dir, "ablation.csv", &ablation_csv.0)?;
    let theta_o = &study.slices_config.theta_o;
    let lobes = lobe_report::lobes_csv(&study.slices, theta_o, &study.channels);
    write_text(dir, "lobes.csv", &lobes.0)?;
    for material in ["white", "copper", "gold"] {
        let figs = figures::albedo_figures(&cmp, material, &study.grid.roughness, &study.grid.mu);
        for (stem, fig) in figs {
            png(dir, &stem, &fig)?;
        }
        let fig = figures::lobe_figure(&cmp, &study.slices, theta_o, material, false);
        png(dir, &format!("lobes_{material}"), &fig)?;
        let fig = figures::lobe_figure(&cmp, &study.slices, theta_o, material, true);
        png(dir, &format!("lobes_ms_{material}"), &fig)?;
    }
    let (summary, headline) = summary(study, &cmp, &ablation_md);
    write_text(dir, "summary.md", &summary)?;
    Ok((summary, headline))
}

fn png(dir: &Path, stem: &str, fig: &Figure) -> Result<()> {
    write_figure(fig, &dir.join(format!("{stem}.png")))
}

fn summary(study: &Study, cmp: &Comparison, ablation_md: &str) -> (String, Headline) {
    let ids = cmp.channel_ids(albedo::FresnelKind::Schlick, None);
    let (table, accurate, games202) = report::headline(cmp);
    let max_stderr = cmp.max_stderr(&ids);
    let g = &study.grid;
    let sl = &study.slices_config;
    let mut md = String::from("# shadeballs-lab truth\n\n");
    let _ = writeln!(
        md,
        "Mode: {}. Walk: {} paths per albedo cell ({} roughness x {} mu, mu from {} to {}, \
         roughness {} to {}), {} per lobe slice; {:.1} s + {:.1} s wall. Largest standard \
         error of the walk's albedo: {:.1e}. The `accurate` preset is evaluated with the G it \
         renders with by default: {}.\n",
        if study.quick { "quick" } else { "full" },
        g.paths,
        g.roughness.len(),
        g.mu.len(),
        g.mu.first().unwrap_or(&0.0),
        g.mu.last().unwrap_or(&0.0),
        g.roughness.first().unwrap_or(&0.0),
        g.roughness.last().unwrap_or(&0.0),
        sl.paths,
        study.seconds[0],
        study.seconds[1],
        max_stderr,
        study.accurate_geometry,
    );
    md.push_str("## Directional albedo: largest |model - walk| (Schlick Fresnel with F0 = r)\n\n");
    md.push_str(&table);
    let _ = writeln!(
        md,
        "\n`accurate` / `games202` = {:.2} (goal: at most 1/3).\n",
        accurate / games202.max(1e-300)
    );
    md.push_str("## Largest |model - walk| per roughness (all materials)\n\n");
    md.push_str(&report::by_roughness(cmp, &g.roughness));
    md.push_str("\n## Kulla-Conty parts: largest |model - walk| per variant (Schlick Fresnel)\n\n");
    md.push_str(ablation_md);
    md.push_str("\n## The full conductor Fresnel (Gulbrandsen 2014 pairs)\n\n");
    md.push_str(&report::conductor_summary(study, cmp));
    md.push_str("\n## Lobe slices (plane of incidence)\n\n");
    // White, and copper's green channel (F0 = 0.17: where Fresnel matters).
    let copper_g = study.channels.iter().position(|c| {
        c.kind == albedo::FresnelKind::Schlick && c.material == "copper" && c.index == 1
    });
    for k in std::iter::once(0).chain(copper_g) {
        let table = lobe_report::lobes_summary(&study.slices, &sl.theta_o, &study.channels, k);
        md.push_str(&table);
        md.push('\n');
    }
    let headline = Headline {
        accurate,
        games202,
        max_stderr,
    };
    (md, headline)
}
