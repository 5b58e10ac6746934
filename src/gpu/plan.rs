//! The plan: what a scene needs baked, compiled and drawn, made from the scene before any
//! work starts (docs/design/layers.md, "The modules": scene -> plan -> tables -> renderer).
//!
//! - Tables: none when no ball reads E (no ball with the term and no environment, whose
//!   single-scattering part reads E(mu_o)); one exact row per distinct roughness read when
//!   there are at most [`MAX_PLANNED_ROWS`] (no error from reading between rows); the 2-D
//!   table past that. Each row once, however many balls share it.
//! - Shader variants: the balls with the term and those without are drawn by two
//!   pipelines, the term compiled in and out, instead of one pipeline branching on a
//!   per-ball flag; a scene without lights or without an environment compiles that part
//!   out.
//!
//! - The truth: balls with `model = "truth"` read no table and are path traced by their
//!   own pipelines (`walk.wgsl`, [`crate::gpu::Renderer`]'s accumulation); the per-ball
//!   draws leave them out.
//!
//! Planning is a pass over the balls (a sort of at most [`crate::scene::MAX_BALLS`] values): cheap
//! enough to redo on every frame of the viewer, which re-bakes only when the plan's rows
//! change.

use std::fmt;

use crate::brdf::Geometry;
use crate::display::DisplayTransform;
use crate::environment::IblMethod;
use crate::lut::{roughness_coord, BakeConfig, Method, TableKey, TableSet};
use crate::prepared::base_roughness_under_coat;
use crate::scene::{CoatForm, Model, Scene, MAX_BALLS};

/// Most rows planned before the 2-D table is used instead. Measured by `shadeballs-lab bench`
/// (`plan.csv`: bake time of k rows against the 64 x 64 table): with the Chebyshev bake a
/// row costs 25 quadratures and the table 425; 16 rows baked faster than the table in each
/// of six runs, 24 and 32 in only one (docs/benchmarks.md, "Planning").
pub const MAX_PLANNED_ROWS: usize = 16;

/// How the renderer chooses its tables.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TablePolicy {
    /// Rows up to [`MAX_PLANNED_ROWS`], the 2-D table past it (the default).
    #[default]
    Auto,
    /// Always the 2-D table (what [`crate::gpu::Renderer::set_tables`] pins).
    Full,
}

/// What the renderer does besides the tables: how it draws. Each ball is drawn over its
/// screen-space bounds, the background a clear, by a pipeline per shader variant (the
/// design before planning, one full-screen triangle branching on each ball's flag, is
/// gone; its figures are in docs/benchmarks.md, "Before planning").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DrawOptions {
    /// How the tables are chosen.
    pub tables: TablePolicy,
    /// The term compiled in where balls use it (`true`), or out of every pipeline.
    pub term: bool,
    /// The split sum reads its prefiltered layers along the dominant direction (`true`,
    /// Lagarde & de Rousiers 2014: the mirror direction bent towards the normal as the lobe
    /// widens), or along the mirror direction itself (`DOMINANT_DIRECTION` in
    /// `types.wgsl`; GPU only: a measurement's switch, `bench --only light`).
    pub dominant_direction: bool,
}

impl Default for DrawOptions {
    fn default() -> Self {
        DrawOptions {
            tables: TablePolicy::Auto,
            term: true,
            dominant_direction: true,
        }
    }
}

/// How a pipeline treats the multiple-scattering term (`MS_TERM` in `types.wgsl`; the
/// value 1, a branch on each ball's flag, was the design before planning's).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum TermMode {
    /// Compiled out.
    Out = 0,
    /// Compiled in for every ball the pipeline draws.
    In = 2,
}

/// One shader variant: the pipeline-time constants that depend on the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Variant {
    /// How the multiple-scattering term is compiled.
    pub term: TermMode,
    /// The environment's part compiled in.
    pub environment: bool,
    /// The directional lights' loop compiled in.
    pub lights: bool,
    /// The map's sun taken as a light by the balls it suits (`SUN_LIGHT`;
    /// [`Scene::sun_light`]): the split sum's pipelines under a map with a sun.
    pub sun: bool,
    /// The environment map's part (`IBL` in `types.wgsl`): 0 without a map, 1 with one
    /// under the split sum, 2 under the lobe's samples ([`Scene::ibl_method`]; each
    /// ball's term is its own, `Ball.term`).
    pub ibl: u8,
    /// Lobe samples a pixel a frame with `ibl = 2` (`IBL_SAMPLES`; [`Scene::ibl_samples`]),
    /// else 0.
    pub ibl_samples: u16,
    /// The cosine strategy's samples a pixel a frame with `ibl = 2`
    /// (`IBL_COSINE_SAMPLES`; [`Scene::cosine_samples`]), else 0.
    pub ibl_cosine_samples: u16,
    /// Antialiased silhouettes (`AA` in `types.wgsl`; [`Scene::antialias`]).
    pub aa: bool,
    /// The split sum's read along the dominant direction (`DOMINANT_DIRECTION`;
    /// [`DrawOptions::dominant_direction`]).
    pub dominant: bool,
    /// The term of every ball the pipeline draws (`BALL_TERM`: its `TERM_*` code) where the
    /// term is compiled in and all of them share one, else 0 (each ball's own).
    pub ball_term: u32,
    /// The clear coat's code compiled in (`HAS_CLEARCOAT`): some ball the pipeline draws
    /// has a coat.
    pub clearcoat: bool,
    /// The anisotropic lobe's code compiled in (`HAS_ANISOTROPY`): some ball the pipeline
    /// draws is anisotropic.
    pub anisotropy: bool,
    /// A metal base's code compiled in (`HAS_METAL`): some ball the pipeline draws has
    /// metallic above 0.
    pub metal: bool,
    /// A dielectric base's code compiled in (`HAS_DIELECTRIC`): some ball the pipeline
    /// draws has metallic below 1.
    pub dielectric: bool,
    /// The display transform of a display target (`TONE_MAP`, `TRANSFER`;
    /// [`Scene::display`]).
    pub display: DisplayTransform,
}

/// The plan of one scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// The G the tables and the shader use ([`Scene::effective_geometry`]).
    pub geometry: Geometry,
    /// The bake settings (geometry = the scene's).
    pub bake: BakeConfig,
    /// The tables to bake and bind, by key: none, one row per roughness read (clamped,
    /// ascending, distinct), or the 2-D table of `bake`.
    pub tables: TableKey,
    /// The variants drawn, each with the indices of its balls (in the scene's order).
    pub draws: Vec<(Variant, Vec<usize>)>,
    /// The truth balls (scene order), path traced and accumulated (`walk.wgsl`); the
    /// per-ball draws leave them out.
    pub truth: Vec<usize>,
    /// The variant the truth's pipelines are compiled with (no term; the scene's lights,
    /// environment and map).
    pub truth_variant: Variant,
}

impl Plan {
    /// The plan of `scene` under `options`, tables baked with `bake` (its geometry replaced
    /// by the scene's).
    pub fn new(scene: &Scene, bake: BakeConfig, options: DrawOptions) -> Self {
        let geometry = scene.effective_geometry();
        let bake = BakeConfig { geometry, ..bake };
        let balls = &scene.balls[..scene.balls.len().min(MAX_BALLS)];
        let environment = scene.environment != glam::DVec3::ZERO;
        let scene_lights = !scene.lights.is_empty();
        let ibl = match (&scene.environment_map, scene.ibl_method) {
            (None, _) => 0,
            (Some(_), IblMethod::SplitSum) => 1,
            (Some(_), IblMethod::Lobe) => 2,
        };
        let (ibl_samples, ibl_cosine_samples) = if ibl == 2 {
            (
                scene.lobe_sample_count() as u16,
                scene.cosine_samples() as u16,
            )
        } else {
            (0, 0)
        };
        // The split sum takes the map's sun as a light (and so compiles the lights' loop in);
        // the walk and the Monte Carlo read the map itself.
        let sun = ibl == 1 && scene.sun_light().is_some();
        let lights = scene_lights || sun;
        let display = scene.display();
        let uses_term = |b: &crate::scene::Ball| options.term && b.model.has_term();
        let is_truth = |b: &crate::scene::Ball| b.model == Model::Truth;
        // Balls that read E: with the term (its lobe), or all of them but the truth under an
        // environment (its single-scattering part reads E(mu_o)).
        let mut roughness: Vec<f32> = balls
            .iter()
            .filter(|b| !is_truth(b) && (uses_term(b) || environment || ibl != 0))
            .map(|b| roughness_coord(b.shading_roughness() as f32))
            .collect();
        // A clear coat reads E at its own roughness (its term, its albedo under light).
        roughness.extend(
            balls
                .iter()
                .filter(|b| !is_truth(b) && b.material.clearcoat.is_on())
                .filter(|b| uses_term(b) || environment || ibl != 0)
                .map(|b| roughness_coord(b.material.clearcoat.roughness as f32)),
        );
        // A glossy base under a physical clear coat leaves it with a wider lobe, whose
        // energy factor reads E at the base's roughness and at the widened one
        // (coating.wgsl clearcoat_base_lobe; ClearcoatConstants::base_row).
        if scene.coat_form == CoatForm::Physical {
            for b in balls
                .iter()
                .filter(|b| !is_truth(b) && b.material.clearcoat.is_on())
            {
                roughness.push(roughness_coord(b.shading_roughness() as f32));
                roughness.push(roughness_coord(base_roughness_under_coat(scene, b) as f32));
            }
        }
        roughness.sort_by(f32::total_cmp);
        roughness.dedup();
        let tables = match options.tables {
            _ if roughness.is_empty() => TableSet::None,
            TablePolicy::Auto if roughness.len() <= MAX_PLANNED_ROWS => {
                TableKey::rows(&bake, &roughness)
            }
            TablePolicy::Full | TablePolicy::Auto => TableSet::Full(bake),
        };
        let variant = |term| Variant {
            term,
            environment,
            lights,
            sun,
            ibl,
            ibl_samples,
            ibl_cosine_samples,
            aa: scene.antialias,
            dominant: options.dominant_direction,
            ball_term: 0,
            clearcoat: false,
            anisotropy: false,
            metal: true,
            dielectric: true,
            display,
        };
        let truth: Vec<usize> = (0..balls.len()).filter(|&k| is_truth(&balls[k])).collect();
        // The per-ball draws leave the truth out.
        let all: Vec<usize> = (0..balls.len()).filter(|&k| !is_truth(&balls[k])).collect();
        let draws = if !options.term {
            vec![(variant(TermMode::Out), all)]
        } else {
            let (with, without): (Vec<usize>, Vec<usize>) =
                all.into_iter().partition(|&k| balls[k].model.has_term());
            // One term for every ball with it: a pipeline-time choice (BALL_TERM).
            let codes: Vec<u32> = with
                .iter()
                .map(|&k| super::uniforms::term_code(balls[k].model))
                .collect();
            let shared = match codes.first() {
                Some(&c) if codes.iter().all(|&x| x == c) => c,
                _ => 0,
            };
            [
                (
                    Variant {
                        ball_term: shared,
                        ..variant(TermMode::In)
                    },
                    with,
                ),
                (variant(TermMode::Out), without),
            ]
            .into_iter()
            .filter(|(_, balls)| !balls.is_empty())
            .collect()
        };
        // Each pipeline compiles in the layers its own balls have, and no other.
        let draws = draws
            .into_iter()
            .map(|(v, drawn): (Variant, Vec<usize>)| {
                let any =
                    |has: fn(&crate::scene::Ball) -> bool| drawn.iter().any(|&k| has(&balls[k]));
                let variant = Variant {
                    clearcoat: any(|b| b.material.clearcoat.is_on()),
                    anisotropy: any(|b| b.material.anisotropy > 0.0),
                    metal: any(|b| b.material.metallic > 0.0),
                    dielectric: any(|b| b.material.metallic < 1.0),
                    ..v
                };
                (variant, drawn)
            })
            .collect();
        Plan {
            geometry,
            bake,
            tables,
            draws,
            truth,
            // The walk traces one ray through each pixel's centre: truth balls are not
            // antialiased.
            // The walk reads the map along its own paths: the lobe's samples are not its.
            truth_variant: Variant {
                term: TermMode::Out,
                environment,
                lights: scene_lights,
                sun: false,
                ibl: ibl.min(1),
                ibl_samples: 0,
                ibl_cosine_samples: 0,
                aa: false,
                dominant: options.dominant_direction,
                ball_term: 0,
                clearcoat: balls.iter().any(|b| b.material.clearcoat.is_on()),
                anisotropy: balls.iter().any(|b| b.material.anisotropy > 0.0),
                metal: balls.iter().any(|b| b.material.metallic > 0.0),
                dielectric: balls.iter().any(|b| b.material.metallic < 1.0),
                display,
            },
        }
    }

    /// The variants (pipelines per target format) the plan draws with.
    pub(crate) fn variants(&self) -> Vec<Variant> {
        self.draws.iter().map(|(v, _)| *v).collect()
    }

    /// The roughness of each row planned (empty unless the plan reads rows).
    pub fn rows(&self) -> Vec<f32> {
        self.tables.roughness()
    }
}

impl fmt::Display for Variant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let term = match self.term {
            TermMode::Out => "term out",
            TermMode::In => "term in",
        };
        let part = |on: bool, name: &str| format!("{}{name}", if on { "" } else { "no " });
        write!(
            f,
            "{term}, {}, {}",
            part(self.lights, "lights"),
            part(self.environment, "environment")
        )?;
        match self.ibl {
            0 => Ok(()),
            1 if self.sun => write!(f, ", environment map (its sun a light)"),
            1 => write!(f, ", environment map"),
            _ => write!(
                f,
                ", environment map (lobe, {} a frame)",
                crate::stats::count(self.ibl_samples, "sample")
            ),
        }?;
        if !self.aa {
            write!(f, ", no antialiasing")?;
        }
        if !self.dominant && self.ibl == 1 {
            write!(f, ", read along the mirror direction")?;
        }
        if self.clearcoat {
            write!(f, ", clear coat")?;
        }
        if self.anisotropy {
            write!(f, ", anisotropy")?;
        }
        match (self.metal, self.dielectric) {
            (true, false) => write!(f, ", metals only")?,
            (false, true) => write!(f, ", dielectrics only")?,
            _ => {}
        }
        Ok(())
    }
}

impl fmt::Display for Plan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let bake = &self.bake;
        let method = match bake.method {
            Method::Chebyshev => format!("chebyshev, {} nodes a segment", bake.samples),
            m => format!(
                "{m}, {}",
                crate::stats::count(bake.samples as u64, "sample")
            ),
        };
        let l = &bake.layout;
        match &self.tables {
            TableSet::None => writeln!(f, "tables: none (no ball reads E): nothing baked")?,
            TableSet::Rows(_) => {
                let r = self.rows();
                let list: Vec<String> = r.iter().map(|v| format!("{v}")).collect();
                writeln!(
                    f,
                    "tables: {} exact rows of {} texels along mu ({} layout, {}), at roughness {} ({} G, {method})",
                    r.len(),
                    l.mu_size,
                    l.kind,
                    l.storage,
                    list.join(", "),
                    self.geometry
                )?
            }
            TableSet::Full(_) => writeln!(
                f,
                "tables: the {}x{} table ({} layout, {}; {} G, {method})",
                l.mu_size, l.r_size, l.kind, l.storage, self.geometry
            )?,
        }
        write!(
            f,
            "draw: each ball over its screen-space bounds, background cleared; pipelines:"
        )?;
        for (v, balls) in &self.draws {
            write!(f, "\n  {v}: {} balls", balls.len())?;
        }
        if !self.truth.is_empty() {
            write!(
                f,
                "\n  truth (random walk, accumulated), {}: {} balls",
                self.truth_variant,
                self.truth.len()
            )?;
        }
        Ok(())
    }
}
