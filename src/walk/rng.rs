//! A small seeded generator for the Monte Carlo estimators: SplitMix64 (Steele, Lea and
//! Flood 2014, "Fast Splittable Pseudorandom Number Generators"). Every stream comes from
//! hashed keys (the study's (study, cell, chunk), a render's (seed, pixel)), so results do
//! not depend on how rayon schedules the work or on the number of threads.

/// SplitMix64: a 64-bit state advanced by a Weyl constant and mixed on output.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
}

const GOLDEN_GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// SplitMix64's output mix (a variant of MurmurHash3's finaliser).
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl Rng {
    /// A stream for the given key parts (hashed together, so nearby keys give unrelated
    /// streams).
    pub fn new(keys: &[u64]) -> Self {
        let mut h = 0x5348_4144_4542_414c_u64; // "SHADEBAL"
        for &k in keys {
            h = mix(h ^ k.wrapping_mul(GOLDEN_GAMMA));
        }
        Self { state: h }
    }

    /// The next 64 random bits.
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(GOLDEN_GAMMA);
        mix(self.state)
    }

    /// Uniform in `[0, 1)` with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}
