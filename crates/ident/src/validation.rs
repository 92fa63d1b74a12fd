//! Validation: simulate the identified model on the measured input and compare with the
//! measurement (the book's `cdip_pcont_least_square_sim` check).
//!
//! The score is MATLAB's `compare` fit, the normalised root-mean-square error as a percentage:
//! `fit = 100 (1 − ‖y − ŷ‖₂ / ‖y − mean(y)‖₂)` — 100 for a perfect match, 0 for a model no
//! better than the measured mean, negative for a worse one.
//!
//! * Drives (linear, `ÿ = −a ẏ + b v`): simulated with pendulab-lti's exact [`lsim`] under a
//!   zero-order hold (the rig's D/A holds each voltage for one sample), open loop from the
//!   measured voltage, starting from the measured position and a local quadratic fit's
//!   velocity. A drive is an integrator, so model errors accumulate: the fit measures the
//!   model over the whole record, not one step ahead.
//! * P-control steps: the closed loop the identified `a`, `b`, `k_P` imply, from the step.
//! * Free oscillation: the linear second-order model from the first detected peak (the book's
//!   `p1c321_cdip_id_pend` figure 4, [`validate_oscillation`]), or the nonlinear pendulum on a
//!   held support ([`validate_free_pendulum`]), which the large-amplitude period correction
//!   targets.
//! * Pendulums identified by least squares: the nonlinear pendulum equation (`docs/model.md` §1–2)
//!   integrated by classical Runge–Kutta on the sample grid, driven by the measured motion of
//!   its support (cart acceleration, or arm angle/velocity/acceleration, from three-point
//!   differences, linearly interpolated between samples) — the pendulum model alone is tested.

use crate::differentiate::{savgol_coefficients, three_point};
use crate::error::{IdentError, Result, UNNAMED};
use crate::regression::{ArmPendulumConstants, CartPendulumConstants};
use pendulab_lti::response::{InputHold, LsimOptions, lsim};
use pendulab_lti::{Mat, StateSpace};

/// A simulated output compared with its measurement.
#[derive(Debug, Clone, PartialEq)]
pub struct Validation {
    /// Name of the compared output.
    pub output: String,
    /// The simulated output `ŷ`, on the measurement's samples (from `start` on).
    pub simulated: Vec<f64>,
    /// Index of the first compared sample.
    pub start: usize,
    /// MATLAB `compare` fit, percent.
    pub fit_percent: f64,
    /// RMS of `y − ŷ`.
    pub rms_error: f64,
}

/// MATLAB's `compare` fit `100 (1 − ‖y − ŷ‖/‖y − mean y‖)`, percent.
///
/// # Errors
/// [`IdentError::LengthMismatch`] for different lengths; [`IdentError::TooFewSamples`] for
/// fewer than 2 samples; [`IdentError::FeatureNotFound`] for a constant measurement (the
/// fit is undefined).
#[doc(alias = "compare")]
#[doc(alias = "nrmse")]
pub fn fit_percent(y: &[f64], yhat: &[f64]) -> Result<f64> {
    if y.len() != yhat.len() {
        return Err(IdentError::LengthMismatch {
            source_name: UNNAMED.into(),
            column: "simulated output".into(),
            expected: y.len(),
            found: yhat.len(),
        });
    }
    if y.len() < 2 {
        return Err(IdentError::TooFewSamples {
            source_name: UNNAMED.into(),
            what: "a fit".into(),
            needed: 2,
            found: y.len(),
        });
    }
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let den = y.iter().map(|v| (v - mean).powi(2)).sum::<f64>().sqrt();
    let num = y
        .iter()
        .zip(yhat)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    if den == 0.0 {
        return Err(IdentError::FeatureNotFound {
            source_name: UNNAMED.into(),
            what: "the measured output is constant: the fit is undefined".into(),
        });
    }
    Ok(100.0 * (1.0 - num / den))
}

fn compare(output: &str, y: &[f64], simulated: Vec<f64>, start: usize) -> Result<Validation> {
    let fit = fit_percent(&y[start..], &simulated)?;
    let m = simulated.len() as f64;
    let rms = (y[start..]
        .iter()
        .zip(&simulated)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        / m)
        .sqrt();
    Ok(Validation {
        output: output.into(),
        simulated,
        start,
        fit_percent: fit,
        rms_error: rms,
    })
}

/// Initial velocity from a quadratic least-squares fit to the first samples (up to 21):
/// robust to encoder steps, unlike a one-sided difference.
fn initial_velocity(y: &[f64], ts: f64) -> Result<f64> {
    let mut w = y.len().min(21);
    if w.is_multiple_of(2) {
        w -= 1;
    }
    if w < 3 {
        return three_point(y, ts).map(|d| d[0]);
    }
    let c = savgol_coefficients(w, 2, 1, ts, 0)?;
    Ok(c.iter().zip(y).map(|(c, v)| c * v).sum())
}

fn check_same_len(signals: &[(&str, &[f64])]) -> Result<()> {
    let n = signals[0].1.len();
    for (name, s) in signals {
        if s.len() != n {
            return Err(IdentError::LengthMismatch {
                source_name: UNNAMED.into(),
                column: name.to_string(),
                expected: n,
                found: s.len(),
            });
        }
    }
    if n < 3 {
        return Err(IdentError::TooFewSamples {
            source_name: UNNAMED.into(),
            what: "a validation simulation".into(),
            needed: 3,
            found: n,
        });
    }
    Ok(())
}

fn uniform_t(n: usize, ts: f64) -> Vec<f64> {
    (0..n).map(|k| k as f64 * ts).collect()
}

/// The drive model `P(s) = b/(s(s + a))` as `x = [y, ẏ]`, output `y`.
pub fn drive_model(a: f64, b: f64) -> Result<StateSpace<pendulab_lti::Continuous>> {
    Ok(StateSpace::continuous(
        Mat::from_row_slice(2, 2, &[0.0, 1.0, 0.0, -a]),
        Mat::from_row_slice(2, 1, &[0.0, b]),
        Mat::from_row_slice(1, 2, &[1.0, 0.0]),
        Mat::zeros(1, 1),
    )?)
}

/// Simulates the drive `ÿ = −a ẏ + b v` on the measured voltage `v` (zero-order hold, sample
/// time `ts`) from the measured initial position and velocity, and compares with `y`.
///
/// # Errors
/// [`IdentError::LengthMismatch`], [`IdentError::TooFewSamples`]; errors of [`lsim`] (NaN);
/// those of [`fit_percent`].
pub fn validate_drive(
    ts: f64,
    y: &[f64],
    v: &[f64],
    a: f64,
    b: f64,
    output: &str,
) -> Result<Validation> {
    check_same_len(&[(output, y), ("v", v)])?;
    let sys = drive_model(a, b)?;
    let x0 = [y[0], initial_velocity(y, ts)?];
    let tr = lsim(
        &sys,
        &Mat::from_column_slice(v.len(), 1, v),
        &uniform_t(v.len(), ts),
        Some(&x0),
        &LsimOptions {
            hold: InputHold::Zoh,
        },
    )?;
    compare(output, y, tr.y_signal(0).to_vec(), 0)
}

/// Simulates the P-control loop the identified drive implies, `ÿ = −a ẏ + b k_P (y_c − y)`,
/// from the sample at `step_time` (at rest, at the measured value) and compares with `y`
/// from there on.
///
/// # Errors
/// As [`validate_drive`].
pub fn validate_p_step(
    t: &[f64],
    y: &[f64],
    step_time: f64,
    target: f64,
    k_p: f64,
    a: f64,
    b: f64,
) -> Result<Validation> {
    check_same_len(&[("t", t), ("y", y)])?;
    let k0 = t.partition_point(|&v| v < step_time - 1e-9);
    let m = t.len() - k0;
    let sys = StateSpace::continuous(
        Mat::from_row_slice(2, 2, &[0.0, 1.0, -b * k_p, -a]),
        Mat::from_row_slice(2, 1, &[0.0, b * k_p]),
        Mat::from_row_slice(1, 2, &[1.0, 0.0]),
        Mat::zeros(1, 1),
    )?;
    let ts = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    let tr = lsim(
        &sys,
        &Mat::from_element(m, 1, target),
        &uniform_t(m, ts),
        Some(&[y[k0], 0.0]),
        &LsimOptions {
            hold: InputHold::Zoh,
        },
    )?;
    compare("y", y, tr.y_signal(0).to_vec(), k0)
}

/// Simulates the free linear oscillation `ÿ + 2ζω_n ẏ + ω_n² y = 0` from the sample `start`
/// (a peak: at rest there) and compares with `y` from there on.
///
/// # Errors
/// As [`validate_drive`].
pub fn validate_oscillation(
    ts: f64,
    y: &[f64],
    start: usize,
    omega_n: f64,
    zeta: f64,
) -> Result<Validation> {
    if start + 3 > y.len() {
        return Err(IdentError::TooFewSamples {
            source_name: UNNAMED.into(),
            what: "a validation simulation after the first peak".into(),
            needed: start + 3,
            found: y.len(),
        });
    }
    let sys = StateSpace::continuous(
        Mat::from_row_slice(2, 2, &[0.0, 1.0, -omega_n * omega_n, -2.0 * zeta * omega_n]),
        Mat::zeros(2, 1),
        Mat::from_row_slice(1, 2, &[1.0, 0.0]),
        Mat::zeros(1, 1),
    )?;
    let m = y.len() - start;
    let tr = lsim(
        &sys,
        &Mat::zeros(m, 1),
        &uniform_t(m, ts),
        Some(&[y[start], 0.0]),
        &LsimOptions::default(),
    )?;
    compare("y", y, tr.y_signal(0).to_vec(), start)
}

/// Simulates the nonlinear pendulum on a held support,
/// `(J + m l²) φ̈ = −μ φ̇ − m g l sin φ`, from the sample `start` (a peak: at rest there), and
/// compares with `phi` from there on — the model the free-oscillation parameters belong to
/// (`docs/model.md` §1–2 with the cart or arm held).
///
/// # Errors
/// As [`validate_drive`]; [`IdentError::InvalidParameter`] for `J + m l² ≤ 0`.
pub fn validate_free_pendulum(
    ts: f64,
    phi: &[f64],
    start: usize,
    j: f64,
    mu: f64,
    (m, l, g): (f64, f64, f64),
) -> Result<Validation> {
    if start + 3 > phi.len() {
        return Err(IdentError::TooFewSamples {
            source_name: UNNAMED.into(),
            what: "a validation simulation after the first peak".into(),
            needed: start + 3,
            found: phi.len(),
        });
    }
    let total = j + m * l * l;
    if total.is_nan() || total <= 0.0 {
        return Err(IdentError::InvalidParameter {
            name: "J + m l^2".into(),
            value: total,
            reason: "the pendulum's inertia about its pivot must be positive".into(),
        });
    }
    let mgl = m * g * l;
    let sim = rk4_second_order(phi.len() - start, ts, phi[start], 0.0, |_, x, v| {
        (-mu * v - mgl * x.sin()) / total
    });
    compare("phi", phi, sim, start)
}

/// Classical RK4 on the sample grid for `ẍ = f(k_frac, x, ẋ)`, inputs interpolated inside.
///
/// The stages and weights are those of the simulator's one RK4 stepper
/// (`pendulab_sim::rk4_step`: stage states `x + (h/2)·k₁`, `x + (h/2)·k₂`, `x + h·k₃`, update
/// `x + (h/6)·(k₁ + 2k₂ + 2k₃ + k₄)`), written out here on the pair `(x, ẋ)` because `ident`
/// depends on `lti` alone (`docs/architecture.md`, "the arrows"): calling the simulator's
/// stepper would add the arrow `ident → sim` (with `sim`'s rayon and random-number
/// dependencies) for one step function, and `lti` holds no ODE integration to share.
fn rk4_second_order<F: Fn(f64, f64, f64) -> f64>(
    n: usize,
    ts: f64,
    x0: f64,
    v0: f64,
    f: F,
) -> Vec<f64> {
    let mut out = Vec::with_capacity(n);
    let (mut x, mut v) = (x0, v0);
    for k in 0..n {
        out.push(x);
        if k + 1 == n {
            break;
        }
        let s = k as f64;
        let (k1x, k1v) = (v, f(s, x, v));
        let (k2x, k2v) = (
            v + 0.5 * ts * k1v,
            f(s + 0.5, x + 0.5 * ts * k1x, v + 0.5 * ts * k1v),
        );
        let (k3x, k3v) = (
            v + 0.5 * ts * k2v,
            f(s + 0.5, x + 0.5 * ts * k2x, v + 0.5 * ts * k2v),
        );
        let (k4x, k4v) = (v + ts * k3v, f(s + 1.0, x + ts * k3x, v + ts * k3v));
        x += ts / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        v += ts / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    }
    out
}

/// Linear interpolation of a sampled signal at fractional sample position `s`.
fn interp(x: &[f64], s: f64) -> f64 {
    let k = (s.floor() as usize).min(x.len() - 1);
    let f = s - k as f64;
    if f == 0.0 || k + 1 >= x.len() {
        x[k]
    } else {
        x[k] + f * (x[k + 1] - x[k])
    }
}

/// Simulates the nonlinear cart pendulum
/// `(J_p + m_p l_p²) φ̈ = m_p l_p cos φ z̈ − μ_p φ̇ − m_p g l_p sin φ` driven by the measured
/// cart acceleration, from the measured initial angle and velocity, and compares with `phi`.
///
/// # Errors
/// As [`validate_drive`].
pub fn validate_cart_pendulum(
    ts: f64,
    z: &[f64],
    phi: &[f64],
    jp: f64,
    mup: f64,
    c: &CartPendulumConstants,
) -> Result<Validation> {
    check_same_len(&[("z", z), ("phi", phi)])?;
    let ddz = three_point(&three_point(z, ts)?, ts)?;
    let j = jp + c.mp * c.lp * c.lp;
    let (ml, mgl) = (c.mp * c.lp, c.mp * c.g * c.lp);
    let sim = rk4_second_order(
        phi.len(),
        ts,
        phi[0],
        initial_velocity(phi, ts)?,
        |s, x, v| (ml * x.cos() * interp(&ddz, s) - mup * v - mgl * x.sin()) / j,
    );
    if sim.iter().any(|v| !v.is_finite()) {
        return Err(IdentError::Implausible {
            what: "simulated pendulum angle".into(),
            value: f64::NAN,
            reason: "the identified model diverges on the measured cart motion".into(),
        });
    }
    compare("phi", phi, sim, 0)
}

/// Simulates the nonlinear arm pendulum (`docs/model.md` §2 with `φ₂ = θ₂ − π`)
/// `α₂ φ̈₂ = α₃ cos(φ₁−φ₂) φ̈₁ − α₃ φ̇₁² sin(φ₁−φ₂) − α₅ sin φ₂ − μ₂ (φ̇₂ − φ̇₁)` driven by
/// the measured arm motion, and compares with `phi2`.
///
/// # Errors
/// As [`validate_drive`].
pub fn validate_arm_pendulum(
    ts: f64,
    phi1: &[f64],
    phi2: &[f64],
    alpha2: f64,
    mu2: f64,
    c: &ArmPendulumConstants,
) -> Result<Validation> {
    check_same_len(&[("phi1", phi1), ("phi2", phi2)])?;
    let d1 = three_point(phi1, ts)?;
    let dd1 = three_point(&d1, ts)?;
    let (a3, a5) = (c.alpha3(), c.alpha5());
    let sim = rk4_second_order(
        phi2.len(),
        ts,
        phi2[0],
        initial_velocity(phi2, ts)?,
        |s, x, v| {
            let p1 = interp(phi1, s);
            let w1 = interp(&d1, s);
            let (s12, c12) = (p1 - x).sin_cos();
            (a3 * c12 * interp(&dd1, s) - a3 * w1 * w1 * s12 - a5 * x.sin() - mu2 * (v - w1))
                / alpha2
        },
    );
    if sim.iter().any(|v| !v.is_finite()) {
        return Err(IdentError::Implausible {
            what: "simulated pendulum angle".into(),
            value: f64::NAN,
            reason: "the identified model diverges on the measured arm motion".into(),
        });
    }
    compare("phi2", phi2, sim, 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_definition() {
        let y = [1.0, 2.0, 3.0];
        assert_eq!(fit_percent(&y, &y).unwrap(), 100.0);
        // ŷ = mean gives 0 by definition.
        assert!(fit_percent(&y, &[2.0, 2.0, 2.0]).unwrap().abs() < 1e-12);
        assert!(fit_percent(&[1.0, 1.0], &[1.0, 1.0]).is_err());
    }

    #[test]
    fn rk4_reproduces_a_linear_oscillator() {
        // ẍ = −ω² x from x0 = 1: cos ωt; RK4 at h = 1 ms, ω = 6 → global error ~ (ωh)⁴ ωT/120.
        let w = 6.0;
        let sim = rk4_second_order(5001, 1e-3, 1.0, 0.0, |_, x, _| -w * w * x);
        for (k, s) in sim.iter().enumerate() {
            assert!((s - (w * k as f64 * 1e-3).cos()).abs() < 1e-9);
        }
    }
}
