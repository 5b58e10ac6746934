//! What a CPU point's shading reads besides the ball, shared by the metal's (`shade.rs`),
//! the coating's (`coating.rs`) and the Monte Carlo's (`montecarlo.rs`): the E reads as the
//! shader reads them, per-channel helpers and the map prepared for shading
//! ([`CpuEnvironment`]). The scene-wide forms and the lobe's samples are in `forms.rs`.

use std::sync::{Arc, Mutex, PoisonError};

use glam::DVec3;

use crate::brdf::GAMES202_EDGE_TINT;
use crate::brdf::{f_add_preset, FAvgForm, Geometry};
use crate::environment::sampler::LuminanceCdf;
use crate::environment::{EnvMap, Environment, MipChain, Prefiltered};
use crate::lut::{SplitSum, TableSet, Tables};

/// `1 - E(mu, roughness)` as the shader reads `e` (f32, [`TableSet::lut_loss`]), in f64.
pub(crate) fn loss(e: &TableSet, mu: f64, roughness: f64) -> f64 {
    e.lut_loss(mu as f32, roughness as f32) as f64
}

/// `1 - E_avg(roughness)` as the shader reads `e` ([`TableSet::lut_loss_avg`]), in f64.
pub(crate) fn loss_avg(e: &TableSet, roughness: f64) -> f64 {
    e.lut_loss_avg(roughness as f32) as f64
}

/// `f` applied to each channel of `v`.
pub(crate) fn per_channel(v: DVec3, f: impl Fn(f64) -> f64) -> DVec3 {
    DVec3::new(f(v.x), f(v.y), f(v.z))
}

/// `f_add_preset` per channel of `f0` (the games202 form's edge tint per channel).
pub(crate) fn f_add_rgb(form: FAvgForm, f0: DVec3, e_avg: f64) -> DVec3 {
    DVec3::new(
        f_add_preset(form, f0.x, GAMES202_EDGE_TINT[0], e_avg),
        f_add_preset(form, f0.y, GAMES202_EDGE_TINT[1], e_avg),
        f_add_preset(form, f0.z, GAMES202_EDGE_TINT[2], e_avg),
    )
}

/// The largest map (texels) [`CpuEnvironment::reused`] keeps prepared: 2048 x 1024.
pub const KEPT_MAP_TEXELS: usize = 2048 * 1024;

/// A map prepared, with what its preparation depends on.
struct Kept {
    map: Arc<EnvMap>,
    kernels: Vec<f32>,
    geometry: Geometry,
    lobe: bool,
    prepared: Arc<CpuEnvironment>,
}

/// The last map prepared through it (at most [`KEPT_MAP_TEXELS`]).
pub(crate) struct KeptMap(Mutex<Option<Arc<Kept>>>);

impl KeptMap {
    pub(crate) const fn new() -> Self {
        KeptMap(Mutex::new(None))
    }

    /// The map kept when `environment`'s is the same, with the same kernels from `tables`,
    /// G and `lobe`; else `environment` prepared, and kept if small enough.
    pub(crate) fn get_or_prepare(
        &self,
        environment: &Environment,
        tables: &Tables,
        lobe: bool,
    ) -> Arc<CpuEnvironment> {
        let kernels = crate::environment::prefilter::kernels(tables);
        let geometry = tables.config.geometry;
        let map = &environment.map;
        let kept = self
            .0
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clone();
        if let Some(k) = kept {
            let same_map = Arc::ptr_eq(&k.map, map) || *k.map == **map;
            if k.geometry == geometry && k.lobe == lobe && k.kernels == kernels && same_map {
                return k.prepared.clone();
            }
        }
        // Prepared outside the lock: another thread's render of another map waits on
        // nothing but the lookup.
        let prepared = Arc::new(CpuEnvironment::with_kernels(
            environment,
            &kernels,
            geometry,
            lobe,
        ));
        if map.texels().len() <= KEPT_MAP_TEXELS {
            *self.0.lock().unwrap_or_else(PoisonError::into_inner) = Some(Arc::new(Kept {
                map: map.clone(),
                kernels,
                geometry,
                lobe,
                prepared: prepared.clone(),
            }));
        }
        prepared
    }
}

/// What [`CpuEnvironment::reused`] keeps: one map for the whole process.
static LAST_PREPARED: KeptMap = KeptMap::new();

/// An environment map prepared for the CPU renderer: the same mip chain, prefiltered
/// layers and split-sum table the GPU binds (`gpu::environment`), computed on the CPU.
pub struct CpuEnvironment {
    /// The map's mip chain (f16 values, as uploaded).
    pub chain: Arc<MipChain>,
    /// The prefiltered layers.
    pub prefiltered: Prefiltered,
    /// The map as the balls that take its sun as a light read it: the same chain and
    /// table, the layers without the sun ([`Prefiltered::sunless`]); `None` for a map
    /// without a sun, and under the lobe mode.
    sunless: Option<Box<CpuEnvironment>>,
    /// The split sum's bias table.
    pub split: SplitSum,
    /// The map's luminance tables above their mean, as the GPU binds them for the lobe
    /// mode (`None` for a map without, a constant one, and where the scene draws with the
    /// split sum: the tables of a large map take hundreds of MB that the split sum never
    /// reads).
    pub(crate) luminance: Option<LuminanceCdf>,
}

impl CpuEnvironment {
    /// Prepares `environment` for shading with E from `tables` (its geometry), with its
    /// luminance tables where the lobe mode samples them (`lobe`).
    pub fn new(environment: &Environment, tables: &Tables, lobe: bool) -> Self {
        let kernels = crate::environment::prefilter::kernels(tables);
        Self::with_kernels(environment, &kernels, tables.config.geometry, lobe)
    }

    /// [`CpuEnvironment::new`], or the last map prepared when it was the same (the same
    /// texels, prefilter kernels, G and `lobe`): the CPU renders of one map (a twin test's
    /// scenes, a bench's images, each frame of a progressive render) prepare it once; its
    /// prefiltered layers take a second or more for a 1024-wide map. Only a map of at most
    /// [`KEPT_MAP_TEXELS`] is kept, which bounds what stays in memory after a render.
    pub(crate) fn reused(environment: &Environment, tables: &Tables, lobe: bool) -> Arc<Self> {
        LAST_PREPARED.get_or_prepare(environment, tables, lobe)
    }

    fn with_kernels(
        environment: &Environment,
        kernels: &[f32],
        geometry: Geometry,
        lobe: bool,
    ) -> Self {
        let chain = MipChain::new(&environment.map);
        let prefiltered = Prefiltered::new(&chain, kernels, geometry);
        let chain = Arc::new(chain);
        let split = SplitSum::shipped(geometry);
        let sunless = (!lobe && environment.map.sun_of_chain(&chain).is_some())
            .then(|| crate::environment::prefilter::Bright::new(&chain))
            .flatten()
            .map(|bright| {
                Box::new(CpuEnvironment {
                    chain: chain.clone(),
                    prefiltered: Prefiltered::sunless(&chain, &bright, kernels, geometry),
                    sunless: None,
                    split: split.clone(),
                    luminance: None,
                })
            });
        // The lobe mode's tables of the map at unit intensity (its own is applied where it
        // is read), compensated as the GPU's (gpu::map_cache).
        let luminance = lobe
            .then(|| {
                LuminanceCdf::compensated(&Environment {
                    intensity: 1.0,
                    ..environment.clone()
                })
            })
            .flatten();
        CpuEnvironment {
            chain,
            prefiltered,
            sunless,
            split,
            luminance,
        }
    }

    /// The map as a ball reads it: without its sun where the ball takes the sun as a
    /// light (`sun`, [`crate::scene::SunLight::takes`]), else whole.
    pub(crate) fn for_ball(&self, sun: bool) -> &CpuEnvironment {
        match &self.sunless {
            Some(sunless) if sun => sunless,
            _ => self,
        }
    }

    /// The intensity the GPU's uniform holds: the environment's times the chain's f16
    /// scale, which its levels and the prefiltered layers are divided by.
    pub fn intensity(&self, environment: &Environment) -> f64 {
        environment.intensity * f64::from(self.chain.scale)
    }

    /// `background_radiance`'s map part in `footprint.wgsl`: the map along world direction `d`
    /// (level 0, bilinear), times the intensity.
    pub(crate) fn background(&self, environment: &Environment, d: DVec3) -> DVec3 {
        let uv = crate::environment::direction_to_uv(environment.to_map(d));
        self.intensity(environment) * self.chain.levels[0].bilinear(uv)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::environment::Builtin;
    use crate::lut::{bake, BakeConfig};

    /// A small map of `b` (64 x 32), in an `Arc` of its own.
    fn small(b: Builtin) -> Environment {
        Environment {
            map: Arc::new(b.generate(64)),
            ..Environment::builtin(b)
        }
    }

    /// A kept map serves a map of the same texels (another `Arc`) with the same kernels, G
    /// and `lobe`, and nothing else: another map, another G or the lobe's tables each
    /// prepare again.
    #[test]
    fn a_kept_map_serves_the_same_map_only() {
        let kept = KeptMap::new();
        let schlick = bake(&BakeConfig::default());
        let smith = bake(&BakeConfig {
            geometry: Geometry::SmithCorrelated,
            ..BakeConfig::default()
        });
        assert_ne!(schlick.config.geometry, smith.config.geometry);
        let studio = kept.get_or_prepare(&small(Builtin::Studio), &schlick, false);
        let again = kept.get_or_prepare(&small(Builtin::Studio), &schlick, false);
        assert!(Arc::ptr_eq(&studio, &again), "the same texels are reused");
        let sky = kept.get_or_prepare(&small(Builtin::Sky), &schlick, false);
        assert!(!Arc::ptr_eq(&studio, &sky));
        assert_ne!(studio.chain.levels[0], sky.chain.levels[0]);
        let sky_smith = kept.get_or_prepare(&small(Builtin::Sky), &smith, false);
        assert!(!Arc::ptr_eq(&sky, &sky_smith), "another G");
        let sky_lobe = kept.get_or_prepare(&small(Builtin::Sky), &smith, true);
        assert!(!Arc::ptr_eq(&sky_smith, &sky_lobe), "the lobe's tables");
        assert!(sky_smith.luminance.is_none() && sky_lobe.luminance.is_some());
        // Only the last is kept: the studio is prepared again.
        let studio_again = kept.get_or_prepare(&small(Builtin::Studio), &schlick, false);
        assert!(!Arc::ptr_eq(&studio, &studio_again));
        assert_eq!(studio.chain.levels[0], studio_again.chain.levels[0]);
    }
}
