//! Disk margins of a SISO loop (MATLAB `diskmargin`, python-control `disk_margins`), after
//! Seiler, Packard & Gahinet, "An introduction to disk margins", IEEE Control Systems
//! Magazine 40(5), 2020.
//!
//! # Definition
//!
//! The loop `L` is closed with negative unit feedback and perturbed by a multiplicative
//! factor `f` in the **disk** (skew `σ`, size `α ≥ 0`)
//!
//! ```text
//! D(α, σ) = { (1 + (1 − σ)/2 · δ) / (1 − (1 + σ)/2 · δ) : δ ∈ ℂ, |δ| < α },
//! ```
//!
//! i.e. `L → f L`. `σ = 0` is the balanced disk (gain increase and decrease treated alike,
//! MATLAB's and python-control's default), `σ = 1` the disk of `S` (`f = 1/(1 − δ)`),
//! `σ = −1` that of `T` (`f = 1 + δ`). The **disk margin** is the largest `α` for which the
//! closed loop stays stable for every `f ∈ D(α, σ)`; for a stable closed loop (paper, eq. 9)
//!
//! ```text
//! α_max = 1 / ‖S + (σ − 1)/2‖∞,   S = 1/(1 + L),
//! ```
//!
//! attained at the **critical frequency** where `|S(jω) + (σ − 1)/2|` peaks (for `σ = 0`,
//! `S − ½ = (S − T)/2`). An unstable closed loop has `α_max = 0`.
//!
//! The disk cuts the real axis at `γ₋ = (1 − α(1 − σ)/2)/(1 + α(1 + σ)/2)` and
//! `γ₊ = (1 + α(1 − σ)/2)/(1 − α(1 + σ)/2)`: the loop tolerates any gain in `(γ₋, γ₊)`, the
//! **disk-based gain margin**, with `γ₊ = +∞` once `α(1 + σ)/2 ≥ 1` (the disk becomes a
//! half-plane, then the exterior of a circle whose second real intercept is the negative
//! `γ₊` of the formula); a `γ₋ ≤ 0` means the gain may drop to zero. The boundary cuts the
//! unit circle at `±φ` with `cos φ = (1 + γ₋γ₊)/(γ₋ + γ₊)` (`γ₊` from the formula, negative
//! beyond the half-plane; `cos φ = γ₋` exactly at it), the **disk-based phase margin** `φ`
//! (for `σ = 0` and `α < 2`, `φ = 2 atan(α/2)`); when the boundary does not cut the unit circle
//! (`|cos φ| > 1`: the disk holds all of it) the phase margin is 180°. python-control uses
//! the same formulas except that it reports `∞` in that last case (and 90° at exactly
//! `γ₊ = ∞`).
//!
//! # Method
//!
//! `S` is built with [`feedback`] and `‖S + (σ − 1)/2‖∞` computed by
//! [`hinf_norm`] (Hamiltonian bisection, relative tolerance `10⁻¹⁰`), so the margin is the
//! exact peak, not a grid minimum; [`disk_margin_response`] gives `α(ω)` on a grid (python-control's
//! `returnall=True`).

use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::frequency_response::freqresp;
use crate::interconnect::{FeedbackSign, feedback};
use crate::linalg::Mat;
use crate::norms::hinf_norm;
use crate::state_space::StateSpace;

/// The disk margin of a SISO loop (module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiskMargin {
    /// `α_max` (0 for an unstable closed loop).
    pub alpha: f64,
    /// The skew `σ` used.
    pub skew: f64,
    /// The gain interval `(γ₋, γ₊)` the disk guarantees (`γ₊` may be `+∞`).
    pub gain_interval: (f64, f64),
    /// The disk-based phase margin `φ` in degrees, in `[0°, 180°]`.
    pub phase_margin_deg: f64,
    /// The critical frequency in rad/s (`+∞` when the peak is approached at infinite
    /// frequency, `NaN` for an unstable closed loop).
    pub frequency: f64,
    /// `true` if the nominal closed loop is stable.
    pub closed_loop_stable: bool,
}

impl DiskMargin {
    /// The gain interval and phase margin of the disk of size `alpha` and skew `skew`
    /// (no loop involved; frequency NaN, stability assumed).
    pub fn from_alpha(alpha: f64, skew: f64) -> Self {
        let a = 0.5 * alpha * (1.0 - skew);
        let b = 0.5 * alpha * (1.0 + skew);
        let lo = (1.0 - a) / (1.0 + b);
        // The boundary's second real intercept (negative for b > 1: the disk is then the
        // exterior of a circle).
        let raw_hi = (1.0 + a) / (1.0 - b);
        let hi = if b < 1.0 { raw_hi } else { f64::INFINITY };
        let c = if raw_hi.is_infinite() {
            lo
        } else {
            (1.0 + lo * raw_hi) / (lo + raw_hi)
        };
        let phase_margin_deg = if c.abs() > 1.0 || !c.is_finite() {
            180.0
        } else {
            c.acos().to_degrees()
        };
        Self {
            alpha,
            skew,
            gain_interval: (lo, hi),
            phase_margin_deg,
            frequency: f64::NAN,
            closed_loop_stable: true,
        }
    }

    /// The disk-based gain margin in dB, `20 log₁₀ min(1/γ₋, γ₊)` (`1/γ₋` read as `∞` for
    /// `γ₋ ≤ 0`), python-control's `DGM`.
    pub fn gain_margin_db(&self) -> f64 {
        let (lo, hi) = self.gain_interval;
        let inv = if lo > 0.0 { 1.0 / lo } else { f64::INFINITY };
        20.0 * inv.min(hi).log10()
    }
}

fn check(l_nu: usize, l_ny: usize, skew: f64) -> Result<()> {
    if l_nu != 1 || l_ny != 1 {
        return Err(LtiError::NotSiso {
            what: "disk_margin".into(),
            ny: l_ny,
            nu: l_nu,
        });
    }
    if !skew.is_finite() {
        return Err(LtiError::InvalidArgument(format!(
            "disk_margin: the skew must be finite, got {skew}"
        )));
    }
    Ok(())
}

/// `S + (σ − 1)/2` as a state-space system.
fn shifted_sensitivity<D: TimeDomain>(l: &StateSpace<D>, skew: f64) -> Result<StateSpace<D>> {
    let one = StateSpace::static_gain(Mat::identity(1, 1), l.domain())?;
    let s = feedback(&one, l, FeedbackSign::Negative)?;
    let d = s.d() + Mat::from_element(1, 1, 0.5 * (skew - 1.0));
    StateSpace::new(s.a().clone(), s.b().clone(), s.c().clone(), d, s.domain())
}

/// The disk margin of the SISO loop `L` with skew `σ` (module documentation).
///
/// # Errors
/// [`LtiError::NotSiso`]; [`LtiError::InvalidArgument`] for a non-finite skew;
/// [`LtiError::Singular`] for an ill-posed loop (`1 + D = 0`); the H∞ norm's errors.
#[doc(alias = "diskmargin")]
#[doc(alias = "disk_margins")]
pub fn disk_margin<D: TimeDomain>(l: &StateSpace<D>, skew: f64) -> Result<DiskMargin> {
    check(l.nu(), l.ny(), skew)?;
    let st = shifted_sensitivity(l, skew)?;
    if !st.is_stable()? {
        let mut m = DiskMargin::from_alpha(0.0, skew);
        m.closed_loop_stable = false;
        return Ok(m);
    }
    let h = hinf_norm(&st, 1e-10)?;
    let alpha = if h.value > 0.0 {
        1.0 / h.value
    } else {
        f64::INFINITY
    };
    let mut m = DiskMargin::from_alpha(alpha, skew);
    m.frequency = h.peak_frequency;
    Ok(m)
}

/// The frequency-wise disk margin `α(ω) = 1/|S(jω) + (σ − 1)/2|` at each `w` (rad/s),
/// python-control's `disk_margins(L, omega, skew, returnall=True)[0]` (meaningful for a
/// stable closed loop).
///
/// # Errors
/// As [`disk_margin`]; [`freqresp`]'s errors.
pub fn disk_margin_response<D: TimeDomain>(
    l: &StateSpace<D>,
    skew: f64,
    w: &[f64],
) -> Result<Vec<f64>> {
    check(l.nu(), l.ny(), skew)?;
    let st = shifted_sensitivity(l, skew)?;
    let r = freqresp(&st, w)?;
    Ok(r.response.iter().map(|g| 1.0 / g[(0, 0)].norm()).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn balanced_phase_margin_closed_form() {
        for alpha in [0.1, 0.5, 1.0, 1.9] {
            let m = DiskMargin::from_alpha(alpha, 0.0);
            let want = 2.0 * (alpha / 2.0f64).atan();
            assert!((m.phase_margin_deg.to_radians() - want).abs() < 1e-12);
            let g = (2.0 + alpha) / (2.0 - alpha);
            assert!((m.gain_interval.1 - g).abs() < 1e-12 * g);
            assert!((m.gain_interval.0 - 1.0 / g).abs() < 1e-12);
        }
    }
}
