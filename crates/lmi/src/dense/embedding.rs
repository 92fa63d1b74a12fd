//! The homogeneous self-dual embedding's search direction, iterate and residuals, and the
//! stopping measures and outcomes of an iterate (module docs of [`super`], **Method** and
//! **Stopping**).
//!
//! Neighbours: `driver.rs` runs the iteration on these types; `kkt.rs` solves the Newton
//! systems; `scaling.rs` holds the cones' scaling; `kernels.rs` the dense kernels.

use super::kernels::dot;
use super::kkt::Structure;
use super::{Outcome, REDUCED_FEASIBILITY, REDUCED_GAP};
use crate::conic::{ConicData, RawStatus, Settings};

/// A search direction: `Δx`; `Δy` on the zero-cone rows and the scaled `Δẑ = WΔz` on the
/// cone rows of `yz`; the scaled `Δŝ = W⁻ᵀΔs`; `Δτ`, `Δκ`.
pub(super) struct Direction {
    pub(super) x: Vec<f64>,
    pub(super) yz: Vec<f64>,
    pub(super) s_hat: Vec<f64>,
    pub(super) tau: f64,
    pub(super) kappa: f64,
}

/// The iterate of the homogeneous embedding.
#[derive(Clone)]
pub(super) struct Iterate {
    pub(super) x: Vec<f64>,
    /// `y` on the zero-cone rows, `z` on the cone rows.
    pub(super) zf: Vec<f64>,
    /// `s` on the cone rows (zero on the zero-cone rows).
    pub(super) s: Vec<f64>,
    pub(super) tau: f64,
    pub(super) kappa: f64,
}

/// Residuals of the embedding at an iterate.
pub(super) struct Residuals {
    /// `Eᵀy + Gᵀz + cτ`.
    pub(super) x: Vec<f64>,
    /// `Ex − fτ` and `Gx + s − hτ`.
    pub(super) row: Vec<f64>,
    /// `κ + cᵀx + fᵀy + hᵀz`.
    pub(super) tau: f64,
}

/// The embedding's residuals at `it`.
pub(super) fn residuals(st: &Structure, data: &ConicData, it: &Iterate) -> Residuals {
    let (m, n) = (st.m, st.n);
    let mut rx = vec![0.0; n];
    st.at_mul(data, &it.zf, &mut rx);
    for (r, ci) in rx.iter_mut().zip(&data.q) {
        *r += ci * it.tau;
    }
    let mut row = vec![0.0; m];
    st.a_mul(data, &it.x, &mut row);
    for i in 0..m {
        row[i] += it.s[i] - data.b[i] * it.tau;
    }
    let tau = it.kappa + dot(&data.q, &it.x) + dot(&data.b, &it.zf);
    Residuals { x: rx, row, tau }
}

/// The stopping measures of an iterate (module docs), relative to the tolerances.
#[derive(Debug, Clone, Copy)]
pub(super) struct Measures {
    pub(super) pres: f64,
    pub(super) dres: f64,
    pub(super) pcost: f64,
    /// Largest of the gap measures relative to their tolerances (≤ 1: within tolerance).
    pub(super) gap_ratio: f64,
}

impl Measures {
    /// Largest ratio to the requested tolerances (≤ 1: solved).
    pub(super) fn ratio(&self, s: &Settings) -> f64 {
        (self.pres / s.feasibility)
            .max(self.dres / s.feasibility)
            .max(self.gap_ratio)
    }

    /// Within the reduced tolerances.
    fn almost(&self, s: &Settings) -> bool {
        self.pres <= REDUCED_FEASIBILITY * s.feasibility
            && self.dres <= REDUCED_FEASIBILITY * s.feasibility
            && self.gap_ratio <= REDUCED_GAP
    }
}

pub(super) fn outcome(status: RawStatus, it: &Iterate, m: &Measures, iterations: u32) -> Outcome {
    let inv = 1.0 / it.tau;
    Outcome {
        status,
        x: it.x.iter().map(|v| v * inv).collect(),
        z: it.zf.iter().map(|v| v * inv).collect(),
        objective: m.pcost,
        iterations,
        primal_residual: m.pres,
        dual_residual: m.dres,
    }
}

/// Ends a run that stopped short: the best iterate as almost solved if it meets the reduced
/// tolerances, else `status` with the last iterate.
pub(super) fn stop_short(
    status: RawStatus,
    it: &Iterate,
    best: &Option<(Iterate, Measures)>,
    settings: &Settings,
    iterations: u32,
) -> Outcome {
    if let Some((b, m)) = best
        && m.almost(settings)
    {
        return outcome(RawStatus::AlmostSolved, b, m, iterations);
    }
    Outcome {
        status,
        x: it.x.clone(),
        z: it.zf.clone(),
        objective: f64::NAN,
        iterations,
        primal_residual: f64::NAN,
        dual_residual: f64::NAN,
    }
}
