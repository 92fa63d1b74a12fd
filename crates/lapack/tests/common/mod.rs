//! Helpers shared by the shim's integration tests.
#![allow(dead_code)]

/// `len` deterministic entries in (−1, 1) from a linear congruential sequence (Knuth's MMIX
/// multiplier and increment), the column-major data of the tests' random matrices.
pub fn lcg_entries(len: usize, seed: u64) -> Vec<f64> {
    let mut s = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (0..len)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        })
        .collect()
}
