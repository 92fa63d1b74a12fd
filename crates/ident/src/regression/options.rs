//! The options of the least-squares identifications ([`LsOptions`]: differentiator and
//! prefilter) and the checks that they suit the data: enough stencils, a prefilter time
//! constant within the record and above the sampling, derivative errors below
//! [`MAX_DERIVATIVE_ERROR`] at the dynamics' frequencies, constants within physical ranges.

use super::positive;
use crate::differentiate::{Differentiator, savgol_coefficients};
use crate::error::{IdentError, Result, UNNAMED, short};
use crate::filter::{BOOK_TF, Prefilter};

/// Options shared by the least-squares identifications.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LsOptions {
    /// How velocities and accelerations are obtained (default: three-point, twice).
    pub differentiator: Differentiator,
    /// The filter applied to every regressor column and the target (default: the book's
    /// causal `1/(0.075 s + 1)³`, ZOH-exact).
    pub prefilter: Prefilter,
}

/// The fewest differentiator stencils a record must hold: 4. A stencil is the span of samples
/// one derivative value is computed from (5 for the book's three-point formulas applied
/// twice, `window` for Savitzky–Golay). With fewer, most samples sit within half a stencil of
/// an end, where the one-sided end formulas (less accurate, and for Savitzky–Golay one
/// polynomial for half a window) make up the regression.
pub const MIN_STENCILS: usize = 4;

/// The longest prefilter time constant, as a fraction of the record span: 1/10. The impulse
/// response of `1/(T_f s + 1)³`, `t² e^{−t/T_f}/(2 T_f³)`, leaves `e^{−10}(1 + 10 + 50) ≈ 0.3 %`
/// of its weight beyond `10 T_f`; with a longer `T_f` no filtered sample has settled, and the
/// regression is fitted to the filter's start-up transient (with `T_f = 10⁹ s` the columns are
/// triple integrals scaled by `10⁻²⁷`, and the residual 10⁻³⁰ means nothing).
pub const MAX_TF_FRACTION: f64 = 0.1;

/// The largest relative error of the derivatives over the band the regression uses: 1 %.
/// The band ends at the prefilter's corner `1/T_f` (without a prefilter, at the book's
/// `1/`[`BOOK_TF`] `= 13.3 rad/s`, above the rigs' dynamics: table 3.5's drive pole
/// `a_c = 6.25 /s`, the pendulums' `ω ≈ 6–7 rad/s`). The error at `ω` is that of the
/// differentiator's frequency response against `iω` and `−ω²`: for the three-point formula
/// `1 − sin(ω t_s)/(ω t_s)` and, applied twice, `1 − (sin(ω t_s)/(ω t_s))²`; for
/// Savitzky–Golay that of its centre kernel. A larger error biases the estimates, since the
/// undifferentiated columns (the voltage, `sin φ`) are not distorted alike: a 4001-sample
/// window on the 4001-sample book record gives `J_p` 113× too large.
pub const MAX_DERIVATIVE_ERROR: f64 = 0.01;

/// Largest pole (or natural frequency) times the sample time an estimate may have: 0.25. At
/// `ω t_s = 0.25` the book's twice-applied three-point derivative already errs by 2 %
/// (`1 − (sin x/x)²`), so a faster mode is not resolved by the sampling: such an estimate
/// is an artefact (a 3-sample window returns `a_c = 1/t_s` exactly).
pub const MAX_POLE_TIMES_TS: f64 = 0.25;

/// The frequency response error of a derivative stencil: `coefs[j]` at sample offsets
/// `j − centre`, the `deriv`-th derivative, at `ω` rad/s with sample time `ts`; relative to
/// `(iω)^deriv`.
pub(super) fn stencil_error(
    coefs: &[f64],
    centre: usize,
    deriv: usize,
    omega: f64,
    ts: f64,
) -> f64 {
    let (mut re, mut im) = (0.0, 0.0);
    for (j, c) in coefs.iter().enumerate() {
        let x = omega * (j as f64 - centre as f64) * ts;
        re += c * x.cos();
        im += c * x.sin();
    }
    // (iω)¹ = iω, (iω)² = −ω².
    let (tr, ti) = if deriv == 1 {
        (0.0, omega)
    } else {
        (-omega * omega, 0.0)
    };
    ((re - tr).hypot(im - ti)) / (tr.hypot(ti))
}

/// The `x = ω t_s` at which the twice-applied three-point derivative's error
/// `1 − (sin x/x)²` reaches [`MAX_DERIVATIVE_ERROR`] (≈ 0.1735), by bisection on (0, 1].
pub(super) fn three_point_limit() -> f64 {
    let err = |x: f64| 1.0 - (x.sin() / x).powi(2);
    let (mut lo, mut hi) = (1e-6, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if err(mid) > MAX_DERIVATIVE_ERROR {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    lo
}

impl LsOptions {
    /// Checks that the options suit `n` samples every `ts` seconds, so that the regression
    /// means what it models:
    /// * the record holds at least [`MIN_STENCILS`] differentiator stencils (5 samples for the
    ///   three-point formulas applied twice, `window` for Savitzky–Golay);
    /// * a prefilter time constant is at most [`MAX_TF_FRACTION`] of the record span;
    /// * the derivatives err by at most [`MAX_DERIVATIVE_ERROR`] at the band edge (`1/T_f`,
    ///   or `1/`[`BOOK_TF`] unfiltered) — this bounds `T_f` from below relative to `t_s`
    ///   (`T_f ≥ 5.8 t_s` for three-point derivatives) and a Savitzky–Golay window from above
    ///   relative to the dynamics.
    ///
    /// The `*_ls` functions do not call it (they compute whatever the data give, for studies
    /// such as the book's unfiltered failure); the command-line tool does.
    ///
    /// # Errors
    /// [`IdentError::InvalidParameter`] for a bad `ts` or method parameters;
    /// [`IdentError::TooFewSamples`] for a record shorter than [`MIN_STENCILS`] stencils;
    /// [`IdentError::UnsuitedOption`] naming the time constant or window and the bound.
    pub fn check_data(&self, ts: f64, n: usize) -> Result<()> {
        positive("sample time ts", ts)?;
        self.differentiator.validate()?;
        self.prefilter.design(ts)?;
        let (stencil, what) = match self.differentiator {
            Differentiator::ThreePoint => (
                5,
                "the three-point derivatives applied twice (a 5-sample stencil)".to_string(),
            ),
            Differentiator::SavitzkyGolay { window, .. } => (
                window,
                format!("the Savitzky–Golay derivatives (a {window}-sample window)"),
            ),
        };
        let needed = MIN_STENCILS * stencil;
        if n < needed {
            return Err(IdentError::TooFewSamples {
                source_name: UNNAMED.into(),
                what: format!("{what}, which must fit {MIN_STENCILS} times into the record,"),
                needed,
                found: n,
            });
        }
        let span = (n - 1) as f64 * ts;
        let tf = match self.prefilter {
            Prefilter::None => None,
            Prefilter::Causal { tf, .. } | Prefilter::ZeroPhase { tf, .. } => Some(tf),
        };
        if let Some(tf) = tf
            && tf > MAX_TF_FRACTION * span
        {
            return Err(IdentError::UnsuitedOption {
                option: "prefilter time constant T_f".into(),
                value: tf,
                unit: "s".into(),
                reason: format!(
                    "longer than {MAX_TF_FRACTION} of the record span {} s (the filter \
                     needs about 10 T_f to settle); use T_f ≤ {} s or a longer record",
                    short(span),
                    short(MAX_TF_FRACTION * span)
                ),
            });
        }
        let omega = 1.0 / tf.unwrap_or(BOOK_TF);
        let band = match tf {
            Some(tf) => format!("the prefilter's corner 1/T_f = {omega:.4} rad/s (T_f = {tf} s)"),
            None => format!("the rigs' band up to 1/{BOOK_TF} s = {omega:.4} rad/s (no prefilter)"),
        };
        let (e1, e2) = match self.differentiator {
            Differentiator::ThreePoint => {
                let x = omega * ts;
                let r = if x == 0.0 { 1.0 } else { x.sin() / x };
                ((1.0 - r).abs(), (1.0 - r * r).abs())
            }
            Differentiator::SavitzkyGolay { window, order } => {
                let c = window / 2;
                let k1 = savgol_coefficients(window, order, 1, ts, c)?;
                let k2 = savgol_coefficients(window, order, 2, ts, c)?;
                (
                    stencil_error(&k1, c, 1, omega, ts),
                    stencil_error(&k2, c, 2, omega, ts),
                )
            }
        };
        let err = e1.max(e2);
        if err > MAX_DERIVATIVE_ERROR || err.is_nan() {
            let pct = 100.0 * err;
            let limit = 100.0 * MAX_DERIVATIVE_ERROR;
            return Err(match (self.differentiator, tf) {
                (Differentiator::ThreePoint, Some(tf)) => IdentError::UnsuitedOption {
                    option: "prefilter time constant T_f".into(),
                    value: tf,
                    unit: "s".into(),
                    reason: format!(
                        "too short for the sample time {} s: the three-point derivatives err \
                         by {pct:.3} % at {band} (limit {limit} %); use T_f ≥ {} s",
                        short(ts),
                        short(ts / three_point_limit())
                    ),
                },
                (Differentiator::ThreePoint, None) => IdentError::UnsuitedOption {
                    option: "sample time ts".into(),
                    value: ts,
                    unit: "s".into(),
                    reason: format!(
                        "too long: the three-point derivatives err by {pct:.3} % at {band} \
                         (limit {limit} %)"
                    ),
                },
                (Differentiator::SavitzkyGolay { window, .. }, _) => IdentError::UnsuitedOption {
                    option: "Savitzky–Golay window".into(),
                    value: window as f64,
                    unit: "samples".into(),
                    reason: format!(
                        "too long for the dynamics: spanning {} s, its derivatives err by \
                         {pct:.3} % at {band} (limit {limit} %); use a shorter window",
                        short((window - 1) as f64 * ts)
                    ),
                },
            });
        }
        Ok(())
    }
}
