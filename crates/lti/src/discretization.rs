//! Discretisation (`c2d`) and its inverse (`d2c`), for state space and transfer functions.
//!
//! | method | `c2d` | `d2c` |
//! |---|---|---|
//! | [`Discretization::Zoh`] | `Φ = e^{A ts}`, `Γ = ∫₀^{ts} e^{As}ds B` from one block exponential | principal `logm` of `[[A_d, B_d], [0, I]]` |
//! | [`Discretization::Foh`] | triangle hold (MATLAB `'foh'`), one block exponential | `logm(A_d)`, then `B`, `D` from the hold integrals |
//! | [`Discretization::Tustin`] | bilinear `s = k (z − 1)/(z + 1)`, `k = 2/ts` or `ω/tan(ω ts/2)` | exact inverse |
//! | [`Discretization::ForwardEuler`] | `s = (z − 1)/ts` | exact inverse |
//! | [`Discretization::BackwardEuler`] | `s = (z − 1)/(ts z)` | exact inverse |
//!
//! Tustin and the Euler rules are the generalised bilinear transformation
//! `s = (z − 1)/(h(αz + 1 − α))` with `α = ½, 0, 1` (Zhang, Shi & Chen, "A generalized bilinear
//! transformation", 2007): with `M = (I − αhA)⁻¹`,
//! `A_d = M(I + (1 − α)hA)`, `B_d = hMB`, `C_d = CM`, `D_d = D + αhCMB`; the inverse is
//! `E = (1 − α)I + αA_d`, `A = E⁻¹(A_d − I)/h`, `B = E⁻¹B_d/h`, `C = C_d(I − αhA)`,
//! `D = D_d − αC_dE⁻¹B_d`, so `d2c(c2d(G)) = G` holds realisation by realisation.
//!
//! `d2c` by ZOH/FOH returns the principal logarithm: a continuous system whose poles have
//! `|Im λ| ts ≥ π` (sampled above Nyquist) is aliased and cannot be recovered; discrete poles
//! on the closed negative real axis have no real continuous counterpart (error).

use crate::domain::{Continuous, Discrete};
use crate::error::{LtiError, Result};
use crate::linalg::Mat;
use crate::matrix_functions::{foh_integrals, logm, zoh_integrals};
use crate::state_space::StateSpace;
use crate::transfer_function::TransferFunction;

/// A discretisation method, with its own parameters.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Discretization {
    /// Zero-order hold: the input is constant over each sample interval (exact for
    /// piecewise-constant inputs; MATLAB's default).
    #[default]
    Zoh,
    /// First-order (triangle) hold: the input is linear between samples (exact for
    /// piecewise-linear inputs; MATLAB `'foh'`).
    Foh,
    /// Bilinear (Tustin) transform. With `prewarp: Some(ω)` (rad/s, `0 < ω < π/ts`) the
    /// frequency response matches the continuous one exactly at `ω`.
    Tustin {
        /// Prewarp frequency in rad/s, or `None`.
        prewarp: Option<f64>,
    },
    /// Forward Euler (forward rectangle) `s ← (z − 1)/ts`.
    ForwardEuler,
    /// Backward Euler (backward rectangle) `s ← (z − 1)/(ts z)`.
    BackwardEuler,
}

/// `(α, h)` of the generalised bilinear transform for the bilinear-family methods.
fn gbt_parameters(method: Discretization, ts: f64) -> Result<Option<(f64, f64)>> {
    Ok(match method {
        Discretization::Zoh | Discretization::Foh => None,
        Discretization::ForwardEuler => Some((0.0, ts)),
        Discretization::BackwardEuler => Some((1.0, ts)),
        Discretization::Tustin { prewarp: None } => Some((0.5, ts)),
        Discretization::Tustin { prewarp: Some(w) } => {
            if !(w.is_finite() && w > 0.0 && w * ts < std::f64::consts::PI) {
                return Err(LtiError::InvalidArgument(format!(
                    "Tustin prewarp frequency must satisfy 0 < ω < π/ts = {} rad/s, got {w}",
                    std::f64::consts::PI / ts
                )));
            }
            Some((0.5, 2.0 * (w * ts / 2.0).tan() / w))
        }
    })
}

fn inverse(m: &Mat, what: &str) -> Result<Mat> {
    let n = m.nrows();
    let rc = 1.0 / crate::analysis::cond2(m);
    if n > 0 && (rc.is_nan() || rc <= n as f64 * f64::EPSILON) {
        return Err(LtiError::Singular {
            what: what.to_string(),
            rcond: rc,
        });
    }
    m.clone()
        .lu()
        .solve(&Mat::identity(n, n))
        .ok_or(LtiError::Singular {
            what: what.to_string(),
            rcond: 0.0,
        })
}

impl StateSpace<Continuous> {
    /// Discretises with sample time `ts` seconds (MATLAB `c2d(sys, ts, method)`).
    ///
    /// # Errors
    /// [`LtiError::InvalidSampleTime`]; [`LtiError::InvalidArgument`] for a prewarp
    /// frequency outside `(0, π/ts)`; [`LtiError::Singular`] if `I − αhA` is singular (a
    /// pole at `s = 2/ts` for Tustin, `1/ts` for backward Euler).
    pub fn c2d(&self, ts: f64, method: Discretization) -> Result<StateSpace<Discrete>> {
        let domain = Discrete::new(ts)?;
        let n = self.nx();
        let (a, b, c, d) = (self.a(), self.b(), self.c(), self.d());
        match method {
            Discretization::Zoh => {
                let (phi, gamma) = zoh_integrals(a, b, ts)?;
                StateSpace::new(phi, gamma, c.clone(), d.clone(), domain)
            }
            Discretization::Foh => {
                let (phi, g0, g1) = foh_integrals(a, b, ts)?;
                let bd = &g0 + (&phi - Mat::identity(n, n)) * &g1;
                let dd = d + c * &g1;
                StateSpace::new(phi, bd, c.clone(), dd, domain)
            }
            _ => {
                let (alpha, h) = gbt_parameters(method, ts)?.expect("bilinear family");
                let m = inverse(
                    &(Mat::identity(n, n) - a * (alpha * h)),
                    "I − αhA in the bilinear transform",
                )?;
                let ad = &m * (Mat::identity(n, n) + a * ((1.0 - alpha) * h));
                let bd = &m * b * h;
                let cd = c * &m;
                let dd = d + &cd * b * (alpha * h);
                StateSpace::new(ad, bd, cd, dd, domain)
            }
        }
    }
}

impl StateSpace<Discrete> {
    /// Continuous system whose discretisation by `method` at this system's sample time is this
    /// system (MATLAB `d2c`).
    ///
    /// # Errors
    /// [`LtiError::NoRealLogarithm`] (ZOH, FOH) if `A_d` has an eigenvalue on the closed
    /// negative real axis; [`LtiError::Singular`] if the inverse bilinear map is singular (a
    /// pole at `z = −1` for Tustin, `z = 0` for backward Euler) or the FOH input map cannot be
    /// inverted; [`LtiError::InvalidArgument`] for a bad prewarp frequency.
    pub fn d2c(&self, method: Discretization) -> Result<StateSpace<Continuous>> {
        let ts = self.ts();
        let n = self.nx();
        let m = self.nu();
        let (ad, bd, cd, dd) = (self.a(), self.b(), self.c(), self.d());
        let relabel = |e: LtiError| match e {
            LtiError::NoRealLogarithm { eigenvalue, .. } => LtiError::NoRealLogarithm {
                what: "discrete-time A (d2c)".into(),
                eigenvalue,
            },
            other => other,
        };
        match method {
            Discretization::Zoh => {
                let mut big = Mat::zeros(n + m, n + m);
                big.view_mut((0, 0), (n, n)).copy_from(ad);
                big.view_mut((0, n), (n, m)).copy_from(bd);
                for i in 0..m {
                    big[(n + i, n + i)] = 1.0;
                }
                let l = logm(&big).map_err(relabel)? / ts;
                StateSpace::new(
                    l.view((0, 0), (n, n)).clone_owned(),
                    l.view((0, n), (n, m)).clone_owned(),
                    cd.clone(),
                    dd.clone(),
                    Continuous,
                )
            }
            Discretization::Foh => {
                let a = logm(ad).map_err(relabel)? / ts;
                let (phi, w0, w1) = foh_integrals(&a, &Mat::identity(n, n), ts)?;
                let map = &w0 + (&phi - Mat::identity(n, n)) * &w1;
                let b = inverse(&map, "FOH input map (d2c)")? * bd;
                let d = dd - cd * &w1 * &b;
                StateSpace::new(a, b, cd.clone(), d, Continuous)
            }
            _ => {
                let (alpha, h) = gbt_parameters(method, ts)?.expect("bilinear family");
                let e = Mat::identity(n, n) * (1.0 - alpha) + ad * alpha;
                let einv = inverse(&e, "(1 − α)I + αA_d in the inverse bilinear transform")?;
                let a = &einv * (ad - Mat::identity(n, n)) / h;
                let b = &einv * bd / h;
                let c = cd * (Mat::identity(n, n) - &a * (alpha * h));
                let d = dd - cd * &einv * bd * alpha;
                StateSpace::new(a, b, c, d, Continuous)
            }
        }
    }
}

impl TransferFunction<Continuous> {
    /// Discretises a proper transfer function (MATLAB `c2d(G, ts, method)`): through its
    /// controllable realisation and [`StateSpace::c2d`], back by
    /// [`TransferFunction::from_state_space`].
    ///
    /// # Errors
    /// [`LtiError::Improper`], and as [`StateSpace::c2d`].
    pub fn c2d(&self, ts: f64, method: Discretization) -> Result<TransferFunction<Discrete>> {
        TransferFunction::from_state_space(&self.to_state_space()?.c2d(ts, method)?)
    }
}

impl TransferFunction<Discrete> {
    /// Continuous transfer function whose discretisation is this one (MATLAB `d2c`).
    ///
    /// # Errors
    /// [`LtiError::Improper`], and as [`StateSpace::d2c`].
    pub fn d2c(&self, method: Discretization) -> Result<TransferFunction<Continuous>> {
        TransferFunction::from_state_space(&self.to_state_space()?.d2c(method)?)
    }
}

/// `c2d` as a free function (MATLAB spelling): `c2d(&sys, ts, method)`.
///
/// # Errors
/// As [`StateSpace::c2d`].
pub fn c2d(
    sys: &StateSpace<Continuous>,
    ts: f64,
    method: Discretization,
) -> Result<StateSpace<Discrete>> {
    sys.c2d(ts, method)
}

/// `d2c` as a free function (MATLAB spelling): `d2c(&sys, method)`.
///
/// # Errors
/// As [`StateSpace::d2c`].
pub fn d2c(sys: &StateSpace<Discrete>, method: Discretization) -> Result<StateSpace<Continuous>> {
    sys.d2c(method)
}
