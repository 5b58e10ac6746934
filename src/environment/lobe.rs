//! Lighting that follows the lobe (`ibl_method = "lobe"`, docs/design/environment.md,
//! "Lighting that follows the lobe"): per pixel, `N` directions drawn from the model's own
//! lobe (GGX visible normals, Heitz 2018), each reading the map's mip chain at the level
//! its solid angle covers (filtered importance sampling, Colbert & Krivanek 2007, "GPU-Based
//! Importance Sampling", GPU Gems 3, ch. 20). Frame `k` of a progressive image takes the
//! sample indices `k N .. (k + 1) N` of one low-discrepancy sequence per pixel.
//!
//! The sequence's functions here are the CPU twins of `shaders/environment.wgsl`'s (same
//! names, the same integer arithmetic, so the CPU and the GPU draw the same points); the
//! shading that uses them is `cpu::shade`'s `shade_environment_mis`.

use std::f64::consts::PI;

use glam::DVec3;

use super::prefilter::POLE_SIN_MIN;
use crate::brdf::DIV_EPSILON;

/// How a ball is lit by the environment map (`ibl_method` in a scene file,
/// `--ibl-method`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum IblMethod {
    /// The split sum (Karis 2013): the prefiltered layers along the bent mirror direction
    /// times `F0 A + B`. One read a pixel; the default.
    #[default]
    SplitSum,
    /// `N` samples of the lobe a pixel a frame, each read at its footprint's mip level.
    Lobe,
}

impl IblMethod {
    /// Every method, in the order the help lists them.
    pub(crate) const ALL: [IblMethod; 2] = [IblMethod::SplitSum, IblMethod::Lobe];

    /// The name the command line and the scene file use.
    pub(crate) fn name(self) -> &'static str {
        match self {
            IblMethod::SplitSum => "split-sum",
            IblMethod::Lobe => "lobe",
        }
    }
}

crate::named_enum!(IblMethod, "ibl method");

/// Most lobe samples a pixel a frame (`ibl_samples`, `--ibl-samples`): the count is a
/// pipeline-time constant, one pipeline per value used.
pub(crate) const MAX_IBL_SAMPLES: u32 = 256;

/// Lobe samples a pixel a frame when a scene names none.
pub const DEFAULT_IBL_SAMPLES: u32 = 16;

/// Most frames `render --ibl-frames` accumulates.
pub(crate) const MAX_IBL_FRAMES: u32 = 4096;

/// Added to a lobe sample's mip level (Colbert & Krivanek suggest 1 for a smoother image
/// at the price of a wider lobe; 0 keeps the estimate closest to the lobe's integral).
pub(crate) const LOBE_LOD_BIAS: f64 = 0.0;

/// The R2 sequence's steps in 32-bit fixed point (Roberts 2018, "The Unreasonable
/// Effectiveness of Quasirandom Sequences": point `i` is `frac(i / g, i / g^2)`, `g` the
/// plastic number 1.3247...): `round(2^32 / g)` and `round(2^32 / g^2)`.
pub(crate) const R2_STEPS: [u32; 2] = [3_242_174_889, 2_447_445_414];

/// Checks a lobe sample count: `1..=MAX_IBL_SAMPLES`, else a one-line reason.
pub(crate) fn check_ibl_samples(n: u32) -> Result<u32, String> {
    if (1..=MAX_IBL_SAMPLES).contains(&n) {
        Ok(n)
    } else {
        Err(format!("{n}: must be in 1..={MAX_IBL_SAMPLES}"))
    }
}

/// PCG's hash of one 32-bit value (Jarzynski & Olano 2020, "Hash Functions for GPU
/// Rendering", JCGT 9(3): one LCG step and PCG's output permutation).
pub fn lobe_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// The per-pixel scramble of the sequence, two 32-bit words (the seeds of
/// [`lobe_sobol_point`]'s Owen scrambling): a hash of the pixel's column and row.
pub fn pixel_scramble(px: u32, py: u32) -> [u32; 2] {
    let a = lobe_hash(px ^ lobe_hash(py));
    [a, lobe_hash(a ^ 0x9e37_79b9)]
}

/// The scramble of strategy `k`'s points in a pixel (the lobe mode's multiple importance
/// sampling: 0 the visible normals', 1 the cosine's, 2 and 3 the map's texel and its
/// position in it): `scramble` itself for `k = 0`, else each coordinate plus `k` times an
/// odd constant, hashed, so the strategies' point sets are shifted independently.
pub(crate) fn strategy_scramble(scramble: [u32; 2], k: u32) -> [u32; 2] {
    if k == 0 {
        return scramble;
    }
    [
        lobe_hash(scramble[0].wrapping_add(k.wrapping_mul(0x68bc_21eb))),
        lobe_hash(scramble[1].wrapping_add(k.wrapping_mul(0x02e5_be93))),
    ]
}

/// Point `i` of the R2 sequence rotated by `scramble`, in `[0, 1)^2`: the 24 high bits of
/// each fixed-point coordinate (exact in f32). The later frames' points before the Sobol
/// sequence ([`lobe_frame_point`]); kept for lab/examples/lobe's study.
pub fn lobe_point(i: u32, scramble: [u32; 2]) -> (f64, f64) {
    let x = i.wrapping_mul(R2_STEPS[0]).wrapping_add(scramble[0]);
    let y = i.wrapping_mul(R2_STEPS[1]).wrapping_add(scramble[1]);
    let unit = 1.0 / 16_777_216.0;
    (f64::from(x >> 8) * unit, f64::from(y >> 8) * unit)
}

/// Point `j` of the `count` points of a pixel's first frame before the Sobol sequence
/// ([`lobe_frame_point`]; kept for lab/examples/lobe's study), in `[0, 1)^2`: Hammersley's
/// set `(j / count, radical_inverse(j))` (Hammersley 1960) in 32-bit fixed point, each
/// coordinate XORed with `scramble` (a digital shift, which keeps the set a (0, m, 2)-net
/// when `count = 2^m`: every elementary box of area `1 / count` holds one point; Kollig &
/// Keller 2002, "Efficient Multidimensional Sampling"); the same 24 high bits as
/// [`lobe_point`]. `j / count` is `j` times `floor((2^32 - 1) / count) + 1` (exactly
/// `2^32 / count` for a power of two; below `2^32` for every `j < count <= 65536`).
pub fn lobe_net_point(j: u32, count: u32, scramble: [u32; 2]) -> (f64, f64) {
    let step = (u32::MAX / count.max(1)).wrapping_add(1);
    let x = j.wrapping_mul(step) ^ scramble[0];
    let y = j.reverse_bits() ^ scramble[1];
    let unit = 1.0 / 16_777_216.0;
    (f64::from(x >> 8) * unit, f64::from(y >> 8) * unit)
}

/// Point `i` of the 2-D Sobol sequence (Sobol 1967) in 32-bit fixed point: `x` the van der
/// Corput radical inverse of `i`, `y` its image under the Pascal matrix mod 2, Sobol's
/// second dimension: bit `r` of `y` (from the top) is the XOR of the bits `k` of `x` whose
/// position is a binary subset of `r`'s (Lucas: `C(r, k)` is odd exactly then), five
/// shift-and-mask steps. The two form a (0, 2)-sequence in base 2: every aligned block of
/// `2^m` indices is a (0, m, 2)-net.
pub fn sobol_2d(i: u32) -> [u32; 2] {
    let x = i.reverse_bits();
    let mut y = x;
    for (b, mask) in SOBOL_MASKS.iter().enumerate() {
        y ^= (y << (1u32 << b)) & mask;
    }
    [x, y]
}

/// Laine and Karras's permutation of a 32-bit value (as given by Burley 2020, "Practical
/// Hash-based Owen Scrambling", JCGT 9(4)): each bit flipped by a hash of the bits below it
/// and `seed`.
fn laine_karras_permutation(x: u32, seed: u32) -> u32 {
    let mut x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// Owen's nested uniform scramble of a fixed-point coordinate in `[0, 1)` (Owen 1995; the
/// hash-based form of Burley 2020): each bit, from the top, flipped by a hash of the bits
/// above it and `seed`. It keeps every (t, m, s)-net a net, and unlike a digital shift it
/// breaks the Sobol points' lattice-like rows.
pub fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    laine_karras_permutation(x.reverse_bits(), seed).reverse_bits()
}

/// Point `i` of the pixel's sequence, in `[0, 1)^2`: the 2-D Sobol point [`sobol_2d`] with
/// each coordinate Owen-scrambled ([`nested_uniform_scramble`]) by its word of `scramble`,
/// so every aligned block of `2^m` indices is still a (0, m, 2)-net. The 24 high bits of
/// each coordinate, as [`lobe_point`].
pub fn lobe_sobol_point(i: u32, scramble: [u32; 2]) -> (f64, f64) {
    let [x, y] = sobol_2d(i);
    let x = nested_uniform_scramble(x, scramble[0]);
    let y = nested_uniform_scramble(y, scramble[1]);
    let unit = 1.0 / 16_777_216.0;
    (f64::from(x >> 8) * unit, f64::from(y >> 8) * unit)
}

/// The bit positions (from the top) whose index has bit `b` set, for `b` in 0..5:
/// [`sobol_2d`]'s subset steps.
pub(crate) const SOBOL_MASKS: [u32; 5] = [
    0xaaaa_aaaa,
    0xcccc_cccc,
    0xf0f0_f0f0,
    0xff00_ff00,
    0xffff_0000,
];

/// Sample `j` of a frame whose first index is `first`: point `first + j` of the pixel's
/// Sobol sequence ([`lobe_sobol_point`]). With `2^m` samples a frame every frame's points
/// are a (0, m, 2)-net, and so are the first `2^k` frames' together: the progressive
/// image's points keep filling the square evenly. Before, the first frame took Hammersley's
/// net ([`lobe_net_point`]; alone 1.1 to 1.4 times closer at 16 to 64 samples under studio
/// and sky in the light bench) and later frames the R2 sequence ([`lobe_point`]), which
/// continued no net: two frames were barely better than one (docs/design/environment.md,
/// "Points that keep filling the square").
pub fn lobe_frame_point(first: u32, j: u32, scramble: [u32; 2]) -> (f64, f64) {
    lobe_sobol_point(first.wrapping_add(j), scramble)
}

/// The cosine strategy's samples a frame in the lobe mode, whose other strategies draw
/// `count` each, under a map that leaves `below_mean` of its light to them
/// ([`super::EnvMap::light_below_mean`]): all `count` from a share of
/// [`COSINE_FULL_SHARE`], half from [`COSINE_HALF_SHARE`], else a quarter, rounded up.
/// Under the sky (0.72) all: half cost the progressive lobe 0.73 % -> 0.84 % after 8
/// frames. Under the studio (0.16) a quarter: the map's samples find what the cosine's
/// would, and a quarter left its error within its noise for 0.98x the metals' frame and
/// 0.91x the plastics' against half, where an eighth put the metals above 1 %
/// (docs/design/environment.md, "Fewer cosine samples where the map's find the light" and
/// "A quarter of the cosine's samples under the studio"). The GPU takes it as the pipeline
/// constant `IBL_COSINE_SAMPLES`.
pub fn cosine_samples(count: u32, below_mean: f64) -> u32 {
    if below_mean >= COSINE_FULL_SHARE {
        count
    } else if below_mean >= COSINE_HALF_SHARE {
        count.div_ceil(2)
    } else {
        count.div_ceil(4)
    }
}

/// The lobe strategy's samples a frame in the lobe mode for a ball of `metallic`, whose
/// other strategies draw `count` each and the cosine `cosine` ([`cosine_samples`]): half,
/// rounded up, on a dielectric (`metallic` 0) where the cosine's are fewer (a map whose own
/// samples find most of its light), else all `count`. A dielectric's lobe is its specular,
/// at most its Fresnel's share of the light; under the studio the other half of its samples
/// left the progressive lobe's error where it was for about 0.86x the frame
/// (docs/design/environment.md, "Half the lobe's samples on a dielectric"). The GPU's twin
/// is `lobe_samples` of `lighting.wgsl`.
pub fn lobe_samples(count: u32, cosine: u32, metallic: f64) -> u32 {
    if cosine < count && metallic <= 0.0 {
        count.div_ceil(2)
    } else {
        count
    }
}

/// The share of a map's light below its mean from which the cosine strategy keeps all its
/// samples ([`cosine_samples`]): where most of the light is where the map's samples do
/// not go.
pub const COSINE_FULL_SHARE: f64 = 0.5;

/// The share of a map's light below its mean from which the cosine strategy keeps half its
/// samples, and below which a quarter ([`cosine_samples`]).
pub const COSINE_HALF_SHARE: f64 = 0.25;

/// The mip level a lobe sample of density `pdf` reads (filtered importance sampling):
/// `0.5 log2(Omega_s / Omega_p) + LOBE_LOD_BIAS`, `Omega_s = 1 / (count pdf)` the solid
/// angle the sample stands for among `count` samples, `Omega_p` a base-level texel's about
/// map-frame direction `d` (`2 pi^2 sin(theta) / (w h)` of a `w x h` equirectangular map,
/// `sin(theta)` at least `POLE_SIN_MIN`); clamped to `[0, max_level]`.
pub fn lobe_lod(pdf: f64, count: f64, d: DVec3, size: (f64, f64), max_level: f64) -> f64 {
    let sin_theta = (1.0 - d.y * d.y).max(0.0).sqrt().max(POLE_SIN_MIN);
    let omega_p = 2.0 * PI * PI * sin_theta / (size.0 * size.1);
    let omega_s = 1.0 / (count * pdf).max(DIV_EPSILON);
    (0.5 * (omega_s / omega_p).log2() + LOBE_LOD_BIAS).clamp(0.0, max_level)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_r2_steps_are_the_plastic_numbers_powers_in_fixed_point() {
        let g = 1.324_717_957_244_746_f64;
        assert_eq!(R2_STEPS[0], (2f64.powi(32) / g).round() as u32);
        assert_eq!(R2_STEPS[1], (2f64.powi(32) / (g * g)).round() as u32);
    }

    #[test]
    fn the_points_cover_the_square_evenly() {
        // 256 points of one pixel's sequence: each of the 16 x 16 cells of the square
        // holds at most 3 of them (measured for this pixel; independent uniform points
        // would put 4 or more in about 2 % of the cells, Poisson(1), some 5 cells of 256).
        let s = pixel_scramble(17, 5);
        let mut cells = [0u32; 256];
        for i in 0..256 {
            let (x, y) = lobe_point(i, s);
            assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&y));
            cells[(y * 16.0) as usize * 16 + (x * 16.0) as usize] += 1;
        }
        assert!(cells.iter().all(|&c| c <= 3), "{cells:?}");
    }

    /// Whether `points` (`2^m` of them) are a (0, m, 2)-net: every elementary box of area
    /// `2^-m` (`2^a x 2^(m - a)` cells) holds exactly one.
    fn is_net(points: &[(f64, f64)]) -> bool {
        let m = points.len().trailing_zeros();
        assert_eq!(points.len(), 1 << m);
        (0..=m).all(|a| {
            let (cols, rows) = (1usize << a, 1usize << (m - a));
            let mut cells = vec![0u32; points.len()];
            for &(x, y) in points {
                assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&y));
                cells[(y * rows as f64) as usize * cols + (x * cols as f64) as usize] += 1;
            }
            cells.iter().all(|&c| c == 1)
        })
    }

    #[test]
    fn the_second_coordinate_is_sobols_second_dimension() {
        // The textbook construction: direction numbers v_0 = 1/2, v_k = v_(k-1) XOR
        // v_(k-1) / 2 (the Pascal matrix mod 2), XORed over the set bits of i.
        for i in (0..4096).chain([65_535, 1 << 20, u32::MAX]) {
            let (mut y, mut v) = (0u32, 1u32 << 31);
            for b in 0..32 {
                if (i >> b) & 1 == 1 {
                    y ^= v;
                }
                v ^= v >> 1;
            }
            assert_eq!(sobol_2d(i), [i.reverse_bits(), y], "{i}");
        }
    }

    #[test]
    fn every_frame_and_the_first_frames_together_are_nets() {
        // Any pixel: a frame of 64 samples is a net wherever it starts (frames 0, 1 and 5),
        // and so are the first 4 frames of 16 together (what the progressive image holds
        // after 4 frames). The points before (the first frame Hammersley's net, later
        // frames the R2 sequence) failed the second: the R2 points continue no net.
        for (px, py) in [(0, 0), (17, 5), (1279, 719)] {
            let s = pixel_scramble(px, py);
            for first in [0, 64, 320] {
                let frame: Vec<_> = (0..64).map(|j| lobe_frame_point(first, j, s)).collect();
                assert!(is_net(&frame), "{px},{py}: frame from {first}");
            }
            let four: Vec<_> = (0..4)
                .flat_map(|k| (0..16).map(move |j| lobe_frame_point(16 * k, j, s)))
                .collect();
            assert!(is_net(&four), "{px},{py}: four frames of 16");
            let before: Vec<_> = (0..4)
                .flat_map(|k| {
                    (0..16).map(move |j| {
                        if k == 0 {
                            lobe_net_point(j, 16, s)
                        } else {
                            lobe_point(16 * k + j, s)
                        }
                    })
                })
                .collect();
            assert!(is_net(&before[..16]) && !is_net(&before), "{px},{py}");
        }
    }

    #[test]
    fn hammersleys_net_is_a_net_for_any_pixel() {
        // The first frame's points before (kept for lab/examples/lobe's study).
        for (px, py) in [(0, 0), (17, 5), (1279, 719)] {
            let s = pixel_scramble(px, py);
            let points: Vec<_> = (0..64).map(|j| lobe_net_point(j, 64, s)).collect();
            assert!(is_net(&points), "{px},{py}");
        }
        // A count that is no power of two still spreads over the square: unshifted, point
        // j's x is j / 48 to the 24-bit fixed point's resolution (2^-24, the truncation of
        // the low 8 bits; the step is rounded up, so at most one unit either way).
        for j in 0..48 {
            let (x, _) = lobe_net_point(j, 48, [0, 0]);
            assert!(
                (x - f64::from(j) / 48.0).abs() <= 1.0 / 16_777_216.0,
                "{j}: {x}"
            );
        }
    }

    #[test]
    fn frames_continue_one_sequence() {
        let s = pixel_scramble(3, 4);
        assert_eq!(lobe_frame_point(16, 2, s), lobe_sobol_point(18, s));
        assert_eq!(lobe_frame_point(0, 2, s), lobe_sobol_point(2, s));
    }

    #[test]
    fn the_sample_counts_outside_the_range_are_refused() {
        assert!(check_ibl_samples(0).is_err());
        assert!(check_ibl_samples(MAX_IBL_SAMPLES + 1).is_err());
        assert_eq!(check_ibl_samples(1), Ok(1));
        assert_eq!(check_ibl_samples(MAX_IBL_SAMPLES), Ok(MAX_IBL_SAMPLES));
    }
}
