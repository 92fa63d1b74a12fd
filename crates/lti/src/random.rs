//! SplitMix64 (G. L. Steele, D. Lea and C. H. Flood, "Fast splittable pseudorandom number
//! generators", OOPSLA 2014; S. Vigna's reference `splitmix64.c`): the small deterministic
//! generator behind the workspace's seeded test problems, benchmark data and Monte-Carlo
//! draws, so that a seed gives the same numbers on every platform without a dependency. Not
//! for cryptography.
//!
//! ```
//! use pendulab_lti::random::SplitMix64;
//! // Vigna's splitmix64.c seeded with 0: the first output.
//! assert_eq!(SplitMix64::new(0).next_u64(), 0xe220_a839_7b1d_cdaf);
//! let m = SplitMix64::new(7).matrix(3, 2);
//! assert!(m.iter().all(|v| (-1.0..1.0).contains(v)));
//! ```

use crate::Mat;

/// The generator's state increment, `⌊2⁶⁴/φ⌋` (φ the golden ratio).
pub const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// The SplitMix64 generator: the state (the field; the seed before the first draw) advances by
/// [`GAMMA`] and each output is the state through [`SplitMix64::mix`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The generator seeded with `seed` (its first output is `mix(seed + GAMMA)`).
    pub const fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The finaliser (Stafford's "Mix13" variant): a bijection of `u64` whose output bits each
    /// depend on every input bit; on its own, a counter-based generator `mix(f(counter))`.
    pub const fn mix(mut z: u64) -> u64 {
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(GAMMA);
        Self::mix(self.0)
    }

    /// Uniform in `[0, 1)`: the top 53 bits of [`SplitMix64::next_u64`] over `2⁵³`.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[−1, 1)`: the top 53 bits of [`SplitMix64::next_u64`] times `2⁻⁵²`, minus 1
    /// (exact: every step is a power-of-two scaling or an exact subtraction).
    pub fn symmetric(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (2.0 / (1u64 << 53) as f64) - 1.0
    }

    /// An `r × c` matrix of [`SplitMix64::symmetric`] entries, filled column by column.
    pub fn matrix(&mut self, r: usize, c: usize) -> Mat {
        Mat::from_fn(r, c, |_, _| self.symmetric())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first outputs of Vigna's `splitmix64.c` seeded with 0 and with 1234567, as
    /// `tools/reference/splitmix64.py` (a transcription in Python) prints them.
    #[test]
    fn matches_the_reference_sequence() {
        let mut g = SplitMix64::new(0);
        let want = [
            0xe220_a839_7b1d_cdaf,
            0x6e78_9e6a_a1b9_65f4,
            0x06c4_5d18_8009_454f,
        ];
        for w in want {
            assert_eq!(g.next_u64(), w);
        }
        let mut g = SplitMix64::new(1234567);
        for w in [
            0x599e_d017_fb08_fc85,
            0x2c73_f084_5854_0fa5,
            0x883e_bce5_a3f2_7c77,
        ] {
            assert_eq!(g.next_u64(), w);
        }
    }

    /// `unit` and `symmetric` are `k/2⁵³` and `2k/2⁵³ − 1` of the same top bits `k`.
    #[test]
    fn uniform_draws_are_the_top_53_bits_scaled() {
        let (mut a, mut b, mut c) = (SplitMix64::new(9), SplitMix64::new(9), SplitMix64::new(9));
        for _ in 0..100 {
            let k = (a.next_u64() >> 11) as f64;
            assert_eq!(b.unit(), k / 9_007_199_254_740_992.0);
            assert_eq!(c.symmetric(), 2.0 * k / 9_007_199_254_740_992.0 - 1.0);
        }
    }
}
