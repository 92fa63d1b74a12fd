//! The drive identifications `ÿ = −a ẏ + b v` of cart and arm (eq. 3.43 and its arm form):
//! the regression `[−ẏ, v] [a, b]ᵀ = ÿ`, its least-squares estimate [`DriveLs`] and its checks.

use super::stream::{
    BlockDerivatives, check_signals, derivs, describe_rank, needed, stream_solve, streamable,
};
use super::{LsOptions, MAX_POLE_TIMES_TS, Regression, first_failure, plausible_and_solved};
use crate::error::{IdentError, Result, short};
use crate::least_squares::LeastSquares;

/// The drive regression `[−ẏ, v] [a, b]ᵀ = ÿ` (filtered), shared by cart and arm.
pub(super) fn drive_regression(
    ts: f64,
    y: (&str, &[f64]),
    v: &[f64],
    names: [&str; 2],
    opts: &LsOptions,
) -> Result<Regression> {
    check_signals(&[y, ("v", v)], ts, needed(opts))?;
    let d = derivs(opts, y.1, ts)?;
    let minus_dy: Vec<f64> = d.first.iter().map(|v| -v).collect();
    Regression {
        names: names.iter().map(|s| s.to_string()).collect(),
        signals: vec![format!("−d{}/dt", y.0), "v".into()],
        columns: vec![minus_dy, v.to_vec()],
        target_name: format!("{}_ddot", y.0),
        target: d.second,
    }
    .filtered(&opts.prefilter, ts)
}

/// The cart-drive regression of eq. 3.43 (`M₁ = [−ż, v]`, `N₁ = z̈`), filtered.
///
/// `z` is the cart position in metres and `v` the motor voltage in volts, sampled every `ts`
/// seconds.
///
/// # Errors
/// [`IdentError::InvalidParameter`] for a bad `ts` or options; [`IdentError::LengthMismatch`],
/// [`IdentError::NonFinite`] naming the signal and sample; [`IdentError::TooFewSamples`].
pub fn cart_drive_regression(
    ts: f64,
    z: &[f64],
    v: &[f64],
    opts: &LsOptions,
) -> Result<Regression> {
    drive_regression(ts, ("z", z), v, ["ac", "bc"], opts)
}

/// A drive `ÿ = −a ẏ + b v` identified by least squares.
#[derive(Debug, Clone, PartialEq)]
pub struct DriveLs {
    /// `a` (1/s): `a_c` for the cart, `a₁` for the arm.
    pub a: f64,
    /// `b` (m/(s² V) for the cart, rad/(s² V) for the arm).
    pub b: f64,
    /// The least-squares solution with its diagnostics (names `ac, bc` or `a1, b1`).
    pub lsq: LeastSquares,
}

impl DriveLs {
    /// Checks that the estimate describes a damped drive (`a > 0`, `b ≠ 0`).
    ///
    /// # Errors
    /// [`IdentError::Implausible`] otherwise.
    pub fn check_plausible(&self) -> Result<()> {
        if self.a.is_nan() || self.a <= 0.0 {
            return Err(IdentError::Implausible {
                what: self.lsq.names[0].clone(),
                value: self.a,
                reason: "a drive with back-EMF and friction has a > 0".into(),
            });
        }
        if self.b == 0.0 {
            return Err(IdentError::Implausible {
                what: self.lsq.names[1].clone(),
                value: self.b,
                reason: "the input has no effect".into(),
            });
        }
        Ok(())
    }
}

impl DriveLs {
    /// Every check of an estimate from data sampled every `ts` seconds: as
    /// [`DriveLs::check_plausible`] and [`LeastSquares::check`] (finite, well conditioned),
    /// and the pole `a` must be resolved by the record: `1/span ≤ a ≤`
    /// [`MAX_POLE_TIMES_TS`]`/t_s` (a time constant longer than the record is not seen in
    /// it; a shorter one than four samples is not resolved).
    ///
    /// # Errors
    /// [`IdentError::Implausible`], [`IdentError::NonFiniteResult`],
    /// [`IdentError::IllConditioned`].
    pub fn check(&self, ts: f64) -> Result<()> {
        first_failure(self.failed_checks(ts))
    }

    /// Every failed check of [`DriveLs::check`], not only the first (for reports that print
    /// the estimate anyway).
    pub fn failed_checks(&self, ts: f64) -> Vec<IdentError> {
        let mut out = plausible_and_solved(self.check_plausible(), &self.lsq);
        out.extend(self.pole_in_record(ts).err());
        out
    }

    fn pole_in_record(&self, ts: f64) -> Result<()> {
        let span = (self.lsq.samples.max(2) - 1) as f64 * ts;
        let name = &self.lsq.names[0];
        if !self.a.is_finite() || self.a <= 0.0 {
            return Ok(()); // check_plausible / lsq.check name it
        }
        if self.a * ts > MAX_POLE_TIMES_TS {
            return Err(IdentError::Implausible {
                what: name.clone(),
                value: self.a,
                reason: format!(
                    "its time constant 1/{name} = {:.3e} s is shorter than the {} s the \
                     sampling at {} s resolves",
                    1.0 / self.a,
                    short(ts / MAX_POLE_TIMES_TS),
                    short(ts)
                ),
            });
        }
        if self.a * span < 1.0 {
            return Err(IdentError::Implausible {
                what: name.clone(),
                value: self.a,
                reason: format!(
                    "its time constant 1/{name} = {:.3e} s is longer than the record ({} s)",
                    1.0 / self.a,
                    short(span)
                ),
            });
        }
        Ok(())
    }
}

pub(super) fn drive_from(lsq: LeastSquares) -> DriveLs {
    DriveLs {
        a: lsq.estimate[0],
        b: lsq.estimate[1],
        lsq,
    }
}

/// Cart drive `z̈ = −a_c ż + b_c v` by least squares (eq. 3.43; book `p1c322`).
///
/// # Errors
/// As [`cart_drive_regression`] and [`least_squares`] (rank deficiency, e.g. `v ≡ 0`).
#[doc(alias = "p1c322_cdip_id_least_square")]
pub fn cart_drive_ls(ts: f64, z: &[f64], v: &[f64], opts: &LsOptions) -> Result<DriveLs> {
    drive_ls(ts, ("z", z), v, ["ac", "bc"], opts)
}

pub(super) fn drive_ls(
    ts: f64,
    y: (&str, &[f64]),
    v: &[f64],
    names: [&str; 2],
    opts: &LsOptions,
) -> Result<DriveLs> {
    if !streamable(opts) {
        return Ok(drive_from(
            drive_regression(ts, y, v, names, opts)?.solve()?,
        ));
    }
    opts.differentiator.validate()?;
    let n = y.1.len();
    let x = y.1;
    let mut d = BlockDerivatives::new(n, ts);
    let target = format!("{}_ddot", y.0);
    let signals = [y, ("v", v)];
    let lsq = stream_solve::<3>(
        &signals,
        ts,
        needed(opts),
        &opts.prefilter,
        &names,
        &target,
        |k0, m, raw| {
            let [dy, vv, ddy] = raw;
            d.load(x, k0, k0 + m, dy, ddy);
            for a in &mut dy[..m] {
                *a = -*a;
            }
            vv[..m].copy_from_slice(&v[k0..k0 + m]);
        },
    )
    .map_err(|e| describe_rank(e, &names, &[&format!("−d{}/dt", y.0), "v"]))?;
    Ok(drive_from(lsq))
}

/// Arm drive `φ̈₁ = −a₁ φ̇₁ + b₁ v` by least squares (`M₁ = [−φ̇₁, v]`, `N₁ = φ̈₁`).
///
/// # Errors
/// As [`cart_drive_ls`].
#[doc(alias = "p1c332_adip_id_least_square")]
pub fn arm_drive_ls(ts: f64, phi1: &[f64], v: &[f64], opts: &LsOptions) -> Result<DriveLs> {
    drive_ls(ts, ("phi1", phi1), v, ["a1", "b1"], opts)
}
