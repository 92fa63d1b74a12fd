//! Shared set-up of the closed-loop tests: the book's plants and rig presets.
#![allow(dead_code)]

use pendulab_lti::Mat;
use pendulab_plants::RigSpec;
use pendulab_sim::rig::RigChains;
use pendulab_sim::scenario::Imperfections;

/// The rig preset "with quantizer" of a rig description: the rig's `RigSpec::chains` with
/// `Imperfections::with_quantizer` (encoders, pseudo-differentiated velocities in the state
/// layout, ±5 V, 16-bit D/A).
pub fn quantized(rig: &RigSpec) -> RigChains {
    rig.chains(&Imperfections::with_quantizer()).unwrap()
}

/// `diag(d)`.
pub fn diag(d: &[f64]) -> Mat {
    Mat::from_diagonal(&nalgebra::DVector::from_row_slice(d))
}

/// Column `j` of the recorded states.
pub fn column(x: &Mat, j: usize) -> Vec<f64> {
    (0..x.nrows()).map(|i| x[(i, j)]).collect()
}

/// Largest |v| over the samples with `t ≥ from`.
pub fn max_abs_after(t: &[f64], v: &[f64], from: f64) -> f64 {
    t.iter()
        .zip(v)
        .filter(|(ti, _)| **ti >= from - 1e-12)
        .map(|(_, v)| v.abs())
        .fold(0.0, f64::max)
}
