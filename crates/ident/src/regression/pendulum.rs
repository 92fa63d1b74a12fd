//! The pendulum identifications of cart (`[J_p, μ_p]`, eq. 3.45) and arm (`[α₂, μ₂] → J₂`):
//! the regressions, their least-squares estimates and checks (plausible, solved, and the
//! natural frequency shown in the record and resolved by the sampling).

use super::stream::{
    BlockDerivatives, check_signals, derivs, describe_rank, needed, stream_solve, streamable,
};
use super::{
    ArmPendulumConstants, CartPendulumConstants, LsOptions, MAX_POLE_TIMES_TS, Regression,
    first_failure, plausible_and_solved,
};
use crate::differentiate::Derivatives;
use crate::error::{IdentError, Result, short};
use crate::filter::BANK_BLOCK;
use crate::least_squares::LeastSquares;

/// The parameter names of a pendulum regression and what each column is in terms of the
/// measured signals.
type Columns = ([&'static str; 2], [&'static str; 2]);

/// The cart pendulum's `[J_p, μ_p]` and its columns `[φ̈, φ̇]`.
const CART: Columns = (["Jp", "mup"], ["d²phi/dt²", "dphi/dt"]);

/// The arm pendulum's `[α₂, μ₂]` and its columns `[φ̈₂, φ̇₂ − φ̇₁]`.
const ARM: Columns = (["alpha2", "mu2"], ["d²phi2/dt²", "dphi2/dt − dphi1/dt"]);

/// The derivatives of the two `signals` by the options' differentiator, after checking their
/// lengths, finiteness and count (the explicit route).
fn checked_derivs(
    signals: [(&str, &[f64]); 2],
    ts: f64,
    opts: &LsOptions,
) -> Result<[Derivatives; 2]> {
    check_signals(&signals, ts, needed(opts))?;
    Ok([
        derivs(opts, signals[0].1, ts)?,
        derivs(opts, signals[1].1, ts)?,
    ])
}

/// The pendulum regression `columns · p = N2` named by `cols`, filtered by the options'
/// prefilter.
fn pendulum_regression(
    cols: Columns,
    columns: [Vec<f64>; 2],
    target: Vec<f64>,
    ts: f64,
    opts: &LsOptions,
) -> Result<Regression> {
    Regression {
        names: cols.0.iter().map(|s| s.to_string()).collect(),
        signals: cols.1.iter().map(|s| s.to_string()).collect(),
        columns: columns.into(),
        target_name: "N2".into(),
        target,
    }
    .filtered(&opts.prefilter, ts)
}

/// The pendulum regression named by `cols` solved by the streamed route ([`stream_solve`]):
/// `fill(k0, m, raw, [d₀, d₁])` writes rows `k0 … k0+m−1` of the two columns and the target,
/// `d₀`, `d₁` the block derivatives of the two `signals`. Rank errors name the columns.
fn stream_pendulum(
    cols: Columns,
    signals: [(&str, &[f64]); 2],
    ts: f64,
    opts: &LsOptions,
    mut fill: impl FnMut(usize, usize, &mut [[f64; BANK_BLOCK]; 3], [&mut BlockDerivatives; 2]),
) -> Result<LeastSquares> {
    let n = signals[0].1.len();
    let mut d0 = BlockDerivatives::new(n, ts);
    let mut d1 = BlockDerivatives::new(n, ts);
    stream_solve::<3>(
        &signals,
        ts,
        needed(opts),
        &opts.prefilter,
        &cols.0,
        "N2",
        |k0, m, raw| fill(k0, m, raw, [&mut d0, &mut d1]),
    )
    .map_err(|e| describe_rank(e, &cols.0, &cols.1))
}

/// The natural frequency `ω_n = √(m g l / α)` of a pendulum of inertia `α` about its pivot must
/// be resolved by the sampling and show in the record: `ω_n span ≥ 1` (a sixth of a period),
/// `ω_n t_s ≤` [`MAX_POLE_TIMES_TS`].
fn pendulum_in_record(j: (&str, f64), alpha: f64, mgl: f64, ts: f64, n: usize) -> Result<()> {
    let wn = (mgl / alpha).sqrt();
    let span = (n.max(2) - 1) as f64 * ts;
    let reason = if !wn.is_finite() {
        format!("the natural frequency √(m g l/(J + m l²)) = {wn} is not finite")
    } else if wn * span < 1.0 {
        format!(
            "the natural frequency it implies, ω_n = √(m g l/(J + m l²)) = {wn:.3e} rad/s, \
             would not show in the record ({} s: ω_n·span < 1 rad)",
            short(span)
        )
    } else if wn * ts > MAX_POLE_TIMES_TS {
        format!(
            "the natural frequency it implies, ω_n = {wn:.3e} rad/s, is faster than the \
             sampling at {} s resolves (ω_n t_s > {MAX_POLE_TIMES_TS})",
            short(ts)
        )
    } else {
        return Ok(());
    };
    Err(IdentError::Implausible {
        what: j.0.into(),
        value: j.1,
        reason,
    })
}

/// The cart-pendulum regression of eq. 3.45, filtered.
///
/// `z` in metres, `phi` = θ − π in radians (from the hanging rest).
///
/// # Errors
/// As [`cart_drive_regression`], and [`IdentError::InvalidParameter`] for non-positive
/// constants.
pub fn cart_pendulum_regression(
    ts: f64,
    z: &[f64],
    phi: &[f64],
    c: &CartPendulumConstants,
    opts: &LsOptions,
) -> Result<Regression> {
    c.validate()?;
    let [dz, dp] = checked_derivs([("z", z), ("phi", phi)], ts, opts)?;
    let (ml, ml2, mgl) = (c.mp * c.lp, c.mp * c.lp * c.lp, c.mp * c.g * c.lp);
    let target: Vec<f64> = (0..z.len())
        .map(|k| {
            let (s, co) = phi[k].sin_cos();
            ml * co * dz.second[k] - ml2 * dp.second[k] - mgl * s
        })
        .collect();
    pendulum_regression(CART, [dp.second, dp.first], target, ts, opts)
}

/// The cart pendulum `[J_p, μ_p]` identified by least squares.
#[derive(Debug, Clone, PartialEq)]
pub struct CartPendulumLs {
    /// Moment of inertia about the centre of mass `J_p`, kg m².
    pub jp: f64,
    /// Viscous friction `μ_p`, N m s/rad.
    pub mup: f64,
    /// The least-squares solution (names `Jp, mup`).
    pub lsq: LeastSquares,
}

impl CartPendulumLs {
    /// Checks `J_p > 0` and `μ_p ≥ 0`.
    ///
    /// # Errors
    /// [`IdentError::Implausible`] otherwise.
    pub fn check_plausible(&self) -> Result<()> {
        pendulum_plausible(("Jp", self.jp), ("mup", self.mup))
    }

    /// Every check of an estimate from data sampled every `ts` seconds with the constants
    /// `c`: [`CartPendulumLs::check_plausible`], [`LeastSquares::check`] (finite, well
    /// conditioned), and the natural frequency `ω_n = √(m_p g l_p/(J_p + m_p l_p²))` must
    /// show in the record (`ω_n span ≥ 1`) and be resolved by the sampling
    /// (`ω_n t_s ≤` [`MAX_POLE_TIMES_TS`]).
    ///
    /// # Errors
    /// [`IdentError::Implausible`], [`IdentError::NonFiniteResult`],
    /// [`IdentError::IllConditioned`].
    pub fn check(&self, ts: f64, c: &CartPendulumConstants) -> Result<()> {
        first_failure(self.failed_checks(ts, c))
    }

    /// Every failed check of [`CartPendulumLs::check`], not only the first.
    pub fn failed_checks(&self, ts: f64, c: &CartPendulumConstants) -> Vec<IdentError> {
        pendulum_failed_checks(
            self.check_plausible(),
            &self.lsq,
            ("Jp", self.jp),
            self.jp + c.mp * c.lp * c.lp,
            c.mp * c.g * c.lp,
            ts,
        )
    }
}

/// The failed checks of a pendulum estimate: `plausible` and the solution's
/// ([`plausible_and_solved`]), then, for a positive inertia `j`, its natural frequency
/// `√(mgl/alpha)` in the record ([`pendulum_in_record`]).
fn pendulum_failed_checks(
    plausible: Result<()>,
    lsq: &LeastSquares,
    j: (&str, f64),
    alpha: f64,
    mgl: f64,
    ts: f64,
) -> Vec<IdentError> {
    let mut out = plausible_and_solved(plausible, lsq);
    if j.1 > 0.0 {
        out.extend(pendulum_in_record(j, alpha, mgl, ts, lsq.samples).err());
    }
    out
}

fn pendulum_plausible(j: (&str, f64), mu: (&str, f64)) -> Result<()> {
    if j.1.is_nan() || j.1 <= 0.0 {
        return Err(IdentError::Implausible {
            what: j.0.into(),
            value: j.1,
            reason: "a moment of inertia is positive".into(),
        });
    }
    if mu.1.is_nan() || mu.1 < 0.0 {
        return Err(IdentError::Implausible {
            what: mu.0.into(),
            value: mu.1,
            reason: "viscous friction dissipates energy (μ ≥ 0)".into(),
        });
    }
    Ok(())
}

/// Cart pendulum `[J_p, μ_p]` by least squares (eq. 3.45; book `p1c322`), with `m_p`,
/// `l_p`, `g` known.
///
/// # Errors
/// As [`cart_pendulum_regression`] and [`least_squares`].
#[doc(alias = "p1c322_cdip_id_least_square")]
pub fn cart_pendulum_ls(
    ts: f64,
    z: &[f64],
    phi: &[f64],
    c: &CartPendulumConstants,
    opts: &LsOptions,
) -> Result<CartPendulumLs> {
    let lsq = if streamable(opts) {
        c.validate()?;
        let (ml, ml2, mgl) = (c.mp * c.lp, c.mp * c.lp * c.lp, c.mp * c.g * c.lp);
        let mut scratch = [0.0; BANK_BLOCK];
        stream_pendulum(
            CART,
            [("z", z), ("phi", phi)],
            ts,
            opts,
            |k0, m, raw, [dz, dp]| {
                let [ddp, dp1, target] = raw;
                // ż is not needed: `scratch` takes it; the target slot first holds z̈.
                dz.load(z, k0, k0 + m, &mut scratch, target);
                dp.load(phi, k0, k0 + m, dp1, ddp);
                for i in 0..m {
                    let (s, co) = phi[k0 + i].sin_cos();
                    target[i] = ml * co * target[i] - ml2 * ddp[i] - mgl * s;
                }
            },
        )?
    } else {
        cart_pendulum_regression(ts, z, phi, c, opts)?.solve()?
    };
    Ok(CartPendulumLs {
        jp: lsq.estimate[0],
        mup: lsq.estimate[1],
        lsq,
    })
}

/// The arm-pendulum regression (book part 1 §3.3, the arm form of eqs 3.43–3.45), filtered.
/// `phi1` = θ₁ (arm), `phi2` = θ₂ − π (pendulum from hanging), radians.
///
/// # Errors
/// As [`cart_pendulum_regression`].
pub fn arm_pendulum_regression(
    ts: f64,
    phi1: &[f64],
    phi2: &[f64],
    c: &ArmPendulumConstants,
    opts: &LsOptions,
) -> Result<Regression> {
    c.validate()?;
    let [d1, d2] = checked_derivs([("phi1", phi1), ("phi2", phi2)], ts, opts)?;
    let (a3, a5) = (c.alpha3(), c.alpha5());
    let target: Vec<f64> = (0..phi1.len())
        .map(|k| {
            let (s12, c12) = (phi1[k] - phi2[k]).sin_cos();
            a3 * c12 * d1.second[k] - a3 * d1.first[k] * d1.first[k] * s12 - a5 * phi2[k].sin()
        })
        .collect();
    let rel: Vec<f64> = d2.first.iter().zip(&d1.first).map(|(a, b)| a - b).collect();
    pendulum_regression(ARM, [d2.second, rel], target, ts, opts)
}

/// The arm pendulum identified by least squares.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmPendulumLs {
    /// `α₂ = J₂ + m₂ l₂²`, kg m².
    pub alpha2: f64,
    /// Viscous friction `μ₂`, N m s/rad.
    pub mu2: f64,
    /// `J₂ = α₂ − m₂ l₂²`, kg m² (its standard error is that of `α₂`).
    pub j2: f64,
    /// The least-squares solution (names `alpha2, mu2`).
    pub lsq: LeastSquares,
}

impl ArmPendulumLs {
    /// Checks `J₂ > 0` and `μ₂ ≥ 0`.
    ///
    /// # Errors
    /// [`IdentError::Implausible`] otherwise.
    pub fn check_plausible(&self) -> Result<()> {
        pendulum_plausible(("J2", self.j2), ("mu2", self.mu2))
    }

    /// Every check of an estimate from data sampled every `ts` seconds with the constants
    /// `c`, as [`CartPendulumLs::check`] with `ω_n = √(α₅/α₂)`.
    ///
    /// # Errors
    /// [`IdentError::Implausible`], [`IdentError::NonFiniteResult`],
    /// [`IdentError::IllConditioned`].
    pub fn check(&self, ts: f64, c: &ArmPendulumConstants) -> Result<()> {
        first_failure(self.failed_checks(ts, c))
    }

    /// Every failed check of [`ArmPendulumLs::check`], not only the first.
    pub fn failed_checks(&self, ts: f64, c: &ArmPendulumConstants) -> Vec<IdentError> {
        pendulum_failed_checks(
            self.check_plausible(),
            &self.lsq,
            ("J2", self.j2),
            self.alpha2,
            c.alpha5(),
            ts,
        )
    }
}

/// Arm pendulum `[α₂, μ₂] → J₂` by least squares (book `p1c332`), with `L₁`, `m₂`, `l₂`,
/// `g` known.
///
/// # Errors
/// As [`arm_pendulum_regression`] and [`least_squares`].
#[doc(alias = "p1c332_adip_id_least_square")]
pub fn arm_pendulum_ls(
    ts: f64,
    phi1: &[f64],
    phi2: &[f64],
    c: &ArmPendulumConstants,
    opts: &LsOptions,
) -> Result<ArmPendulumLs> {
    let lsq = if streamable(opts) {
        c.validate()?;
        let (a3, a5) = (c.alpha3(), c.alpha5());
        let mut w1 = [0.0; BANK_BLOCK];
        stream_pendulum(
            ARM,
            [("phi1", phi1), ("phi2", phi2)],
            ts,
            opts,
            |k0, m, raw, [d1, d2]| {
                let [dd2, rel, target] = raw;
                // The target slot first holds φ̈₁; `w1` takes φ̇₁.
                d1.load(phi1, k0, k0 + m, &mut w1, target);
                d2.load(phi2, k0, k0 + m, rel, dd2);
                for i in 0..m {
                    let k = k0 + i;
                    let (s12, c12) = (phi1[k] - phi2[k]).sin_cos();
                    let w = w1[i];
                    rel[i] -= w;
                    target[i] = a3 * c12 * target[i] - a3 * w * w * s12 - a5 * phi2[k].sin();
                }
            },
        )?
    } else {
        arm_pendulum_regression(ts, phi1, phi2, c, opts)?.solve()?
    };
    Ok(ArmPendulumLs {
        alpha2: lsq.estimate[0],
        mu2: lsq.estimate[1],
        j2: lsq.estimate[0] - c.m2 * c.l2 * c.l2,
        lsq,
    })
}
