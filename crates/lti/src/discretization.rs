//! Discretisation (`c2d`) and its inverse (`d2c`), for state space and transfer functions.
//!
//! | method | `c2d` | `d2c` |
//! |---|---|---|
//! | [`Discretization::Zoh`] | `Φ = e^{A ts}`, `Γ = ∫₀^{ts} e^{As}ds B` from one block exponential | principal `logm` of `[[A_d, B_d], [0, I]]` |
//! | [`Discretization::Foh`] | triangle hold (MATLAB `'foh'`), one block exponential | `logm(A_d)`, then `B`, `D` from the hold integrals |
//! | [`Discretization::Tustin`] | bilinear `s = k (z − 1)/(z + 1)`, `k = 2/ts` or `ω/tan(ω ts/2)` | exact inverse |
//! | [`Discretization::ForwardEuler`] | `s = (z − 1)/ts` | exact inverse |
//! | [`Discretization::BackwardEuler`] | `s = (z − 1)/(ts z)` | exact inverse |
//! | [`Discretization::Matched`] | pole-zero matching `z = e^{s ts}` (SISO), low-frequency gain matched | — (error) |
//! | [`Discretization::Impulse`] | impulse invariance `h_d[k] = ts·h(k ts)` (strictly proper) | — (error) |
//!
//! Tustin and the Euler rules are the generalised bilinear transformation
//! `s = (z − 1)/(h(αz + 1 − α))` with `α = ½, 0, 1` (Zhang, Shi & Chen, "A generalized bilinear
//! transformation", 2007): with `M = (I − αhA)⁻¹`,
//! `A_d = M(I + (1 − α)hA)`, `B_d = hMB`, `C_d = CM`, `D_d = D + αhCMB`; the inverse is
//! `E = (1 − α)I + αA_d`, `A = E⁻¹(A_d − I)/h`, `B = E⁻¹B_d/h`, `C = C_d(I − αhA)`,
//! `D = D_d − αC_dE⁻¹B_d`, so `d2c(c2d(G)) = G` holds realisation by realisation.
//!
//! Matched pole-zero mapping (MATLAB `c2d(G, ts, 'matched')`, Franklin, Powell & Workman,
//! *Digital Control of Dynamic Systems*, 3rd ed., §6.3.3): every finite pole and zero `p` of
//! `G(s)` goes to `e^{p ts}`; of the `r = deg den − deg num` zeros at `s = ∞`, `r − 1` go to
//! `z = −1` (the Nyquist frequency) and one stays at `z = ∞`, so that `G(z)` is strictly
//! proper when `G(s)` is (MATLAB's choice: `c2d(tf(11, [1 1 0]), 0.1, 'matched')` is
//! `0.052339 (z + 1)/((z − 1)(z − 0.9048))`). The gain matches the low-frequency asymptote:
//! with `q` = (poles at `s = 0`) − (zeros at `s = 0`), `lim_{s→0} s^q G(s) =
//! lim_{z→1} ((z − 1)/ts)^q G(z)`, which is the DC gain when `q = 0` (python-control's
//! `sample_system(…, 'matched')` matches the DC gain, keeps every zero at infinity there and
//! fails with an integrator). Defined for SISO systems; a state-space system is converted
//! through its transfer function and back to the controllable realisation.
//!
//! Impulse invariance (MATLAB `'impulse'`, SciPy `cont2discrete(…, 'impulse')`): the discrete
//! impulse response is the continuous one sampled and scaled by `ts`,
//! `h_d[k] = ts · C e^{A k ts} B`, i.e. `A_d = e^{A ts}`, `B_d = ts e^{A ts} B`, `C_d = C`,
//! `D_d = ts C B`. The scaling by `ts` keeps the DC gain approximately (exactly as
//! `ts → 0`). A feedthrough `D ≠ 0` (an impulse in `h`) has no sampled value: it is an error,
//! as in SciPy.
//!
//! `d2c` by ZOH/FOH returns the principal logarithm: a continuous system whose poles have
//! `|Im λ| ts ≥ π` (sampled above Nyquist) is aliased and cannot be recovered; discrete poles
//! on the closed negative real axis have no real continuous counterpart (error).

use crate::domain::{Continuous, Discrete};
use crate::error::{LtiError, Result};
use crate::linalg::{Complex64, Mat};
use crate::matrix_functions::{foh_integrals, logm, zoh_integrals};
use crate::polynomial::Polynomial;
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
    /// Pole-zero matching `z = e^{s ts}` with the low-frequency gain matched and all but one
    /// zero at infinity mapped to `z = −1` (MATLAB `'matched'`; SISO only; module
    /// documentation).
    Matched,
    /// Impulse invariance `h_d[k] = ts·h(k ts)` (MATLAB `'impulse'`, SciPy `'impulse'`;
    /// strictly proper systems only; module documentation).
    Impulse,
}

/// `(α, h)` of the generalised bilinear transform for the bilinear-family methods.
fn gbt_parameters(method: Discretization, ts: f64) -> Result<Option<(f64, f64)>> {
    Ok(match method {
        Discretization::Zoh
        | Discretization::Foh
        | Discretization::Matched
        | Discretization::Impulse => None,
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
    /// frequency outside `(0, π/ts)`, or `D ≠ 0` with [`Discretization::Impulse`];
    /// [`LtiError::NotSiso`] for a MIMO system with [`Discretization::Matched`];
    /// [`LtiError::Singular`] if `I − αhA` is singular (a pole at `s = 2/ts` for Tustin,
    /// `1/ts` for backward Euler).
    pub fn c2d(&self, ts: f64, method: Discretization) -> Result<StateSpace<Discrete>> {
        let domain = Discrete::new(ts)?;
        let n = self.nx();
        let (a, b, c, d) = (self.a(), self.b(), self.c(), self.d());
        match method {
            Discretization::Matched => {
                if self.nu() != 1 || self.ny() != 1 {
                    return Err(LtiError::NotSiso {
                        what: "c2d by pole-zero matching".into(),
                        ny: self.ny(),
                        nu: self.nu(),
                    });
                }
                TransferFunction::from_state_space(self)?
                    .c2d(ts, method)?
                    .to_state_space()
            }
            Discretization::Impulse => {
                if d.iter().any(|&v| v != 0.0) {
                    return Err(LtiError::InvalidArgument(
                        "c2d by impulse invariance needs a strictly proper system (D = 0)".into(),
                    ));
                }
                let phi = crate::matrix_functions::expm(&(a * ts))?;
                let bd = &phi * b * ts;
                let dd = c * b * ts;
                StateSpace::new(phi, bd, c.clone(), dd, domain)
            }
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
            Discretization::Matched | Discretization::Impulse => Err(LtiError::InvalidArgument(
                format!("d2c by {method:?} is not implemented: use zoh, foh or a bilinear method"),
            )),
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
    /// [`Discretization::Matched`] maps the poles and zeros directly (module documentation).
    ///
    /// # Errors
    /// [`LtiError::Improper`], and as [`StateSpace::c2d`].
    pub fn c2d(&self, ts: f64, method: Discretization) -> Result<TransferFunction<Discrete>> {
        if method == Discretization::Matched {
            return matched(self, ts);
        }
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

/// `p = s^q p₀` with `p₀(0) ≠ 0`: `(p₀, q)` (exact trailing zero coefficients).
fn split_origin(p: &Polynomial) -> (Polynomial, usize) {
    let c = p.coefficients();
    let q = c.iter().rev().take_while(|&&v| v == 0.0).count();
    let q = q.min(c.len() - 1);
    (Polynomial::from_vec_unchecked(c[..c.len() - q].to_vec()), q)
}

/// Pole-zero matching with the low-frequency gain matched (module documentation).
fn matched(g: &TransferFunction<Continuous>, ts: f64) -> Result<TransferFunction<Discrete>> {
    let domain = Discrete::new(ts)?;
    if !g.is_proper() {
        return Err(LtiError::Improper {
            what: "c2d by pole-zero matching".into(),
            num_degree: g.num().degree(),
            den_degree: g.den().degree(),
        });
    }
    if g.num().is_zero() {
        return TransferFunction::new(Polynomial::zero(), Polynomial::one(), domain);
    }
    let (num0, qz) = split_origin(g.num());
    let (den0, qp) = split_origin(g.den());
    let to_z = |roots: Vec<Complex64>| -> Vec<Complex64> {
        roots.into_iter().map(|p| (p * ts).exp()).collect()
    };
    let mut zeros = to_z(num0.roots()?);
    let at_infinity = g.relative_degree() as usize;
    zeros.extend(std::iter::repeat_n(
        Complex64::new(-1.0, 0.0),
        at_infinity.saturating_sub(1),
    ));
    let num_shape = Polynomial::from_roots(&zeros)?;
    let den_shape = Polynomial::from_roots(&to_z(den0.roots()?))?;
    // lim_{s→0} s^q G(s) = num0(0)/den0(0) = lim_{z→1} ((z − 1)/ts)^q G(z) = K ts^{−q}
    // num_shape(1)/den_shape(1), q = qp − qz.
    let q = qp as i32 - qz as i32;
    let k =
        num0.eval(0.0) / den0.eval(0.0) * ts.powi(q) * den_shape.eval(1.0) / num_shape.eval(1.0);
    let z_minus_1 = Polynomial::from_vec_unchecked(vec![1.0, -1.0]);
    let power = |p: Polynomial, times: usize| (0..times).fold(p, |acc, _| &acc * &z_minus_1);
    TransferFunction::new(power(num_shape, qz).scale(k), power(den_shape, qp), domain)
}
