//! Linear-quadratic regulators: [`lqr`] (continuous and discrete), the sampled-data cost
//! discretisation of Van Loan ([`sampled_data_cost`], [`lqr_sampled_data`]), and the
//! steady-state Kalman (LQE) gain by duality ([`lqe`]).

use crate::domain::{Continuous, Discrete, TimeDomain};
use crate::equations::{RiccatiOptions, RiccatiSolution, care, dare};
use crate::error::{LtiError, Result};
use crate::linalg::{Complex64, Mat, check_finite, check_shape, check_square};
use crate::matrix_functions::van_loan_integral;
use crate::state_space::StateSpace;

/// An LQ-optimal state feedback `u = −K x` with its diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct Lqr {
    /// The gain `K` (`m × n`), control law `u = −K x`.
    pub gain: Mat,
    /// The stabilising Riccati solution `X` (`n × n`, symmetric positive semidefinite); the
    /// optimal cost from `x₀` is `x₀ᵀ X x₀`.
    pub riccati: Mat,
    /// Eigenvalues of `A − BK`.
    pub closed_loop_poles: Vec<Complex64>,
    /// Relative residual of the Riccati equation at `X`.
    pub residual: f64,
}

impl From<RiccatiSolution> for Lqr {
    fn from(s: RiccatiSolution) -> Self {
        Self {
            gain: s.gain,
            riccati: s.x,
            closed_loop_poles: s.closed_loop_poles,
            residual: s.residual,
        }
    }
}

/// LQ regulator for `sys` (MATLAB `lqr` in continuous time, `dlqr` in discrete time).
///
/// Continuous: minimises `∫₀^∞ (xᵀQx + uᵀRu + 2xᵀNu) dt` for `ẋ = Ax + Bu`, through the CARE
/// `AᵀX + XA − (XB + N)R⁻¹(BᵀX + Nᵀ) + Q = 0`, `K = R⁻¹(BᵀX + Nᵀ)`.
/// Discrete: minimises `Σ (xₖᵀQxₖ + uₖᵀRuₖ + 2xₖᵀNuₖ)` for `xₖ₊₁ = Axₖ + Buₖ`, through the
/// DARE, `K = (BᵀXB + R)⁻¹(BᵀXA + Nᵀ)`. The control law is `u = −K x` (the textbook writes
/// `K_book = −K`, see [`StateFeedback`](super::StateFeedback)).
///
/// Only `A` and `B` of `sys` are used. Solved by [`care`]/[`dare`] with default
/// [`RiccatiOptions`]; see [`lqr_with_options`].
///
/// **Only LQ problems are answered.** The cost must be a cost: the joint weight
/// `W = [[Q, N], [Nᵀ, R]]` (`Q` alone and `R` alone when `N` is absent) must be positive
/// semidefinite, and `R` positive definite in continuous time (in discrete time a singular
/// `R ⪰ 0` is allowed, as long as `BᵀXB + R` is invertible at the solution, see [`dare`]).
/// A weight counts as semidefinite when its smallest eigenvalue is at least
/// `−τ`, `τ = LQ_WEIGHT_TOLERANCE · (n + m) · ε · ‖W‖_F` ([`LQ_WEIGHT_TOLERANCE`] `= 100`): a
/// semidefinite matrix formed in floating point (`CᵀC`, a Van Loan integral) has eigenvalue
/// errors of a few `(n + m)·ε·‖W‖`, while an indefinite weight (`Q = −1`, which [`care`]
/// itself would accept as an equation) is refused with its smallest eigenvalue. The Riccati
/// equations of indefinite data remain available through [`care`]/[`dare`], whose results
/// are always verified (stabilising closed loop, residual, boundary verdict).
///
/// # Errors
/// Shape/finiteness errors naming `Q`, `R` or `N`; [`LtiError::NotSymmetric`];
/// [`LtiError::NotPositiveDefinite`] for `R` (continuous);
/// [`LtiError::NotPositiveSemidefinite`] for an indefinite `Q`, `R` or `[Q N; Nᵀ R]`;
/// [`LtiError::NotStabilizable`], [`LtiError::NotDetectable`],
/// [`LtiError::BoundaryEigenvalue`] (Hamiltonian / symplectic eigenvalues on or numerically
/// near the stability boundary) when no stabilising solution exists;
/// [`LtiError::IllConditioned`] and the solvers' numerical errors.
#[doc(alias = "dlqr")]
pub fn lqr<D: TimeDomain>(sys: &StateSpace<D>, q: &Mat, r: &Mat, n: Option<&Mat>) -> Result<Lqr> {
    lqr_with_options(sys, q, r, n, &RiccatiOptions::default())
}

/// [`lqr`] with explicit Riccati solver options.
///
/// # Errors
/// As [`lqr`].
pub fn lqr_with_options<D: TimeDomain>(
    sys: &StateSpace<D>,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    options: &RiccatiOptions,
) -> Result<Lqr> {
    let continuous = sys.domain().sample_time().is_none();
    crate::equations::riccati::validate(sys.a(), sys.b(), q, r, n, continuous)?;
    check_lq_weights(["Q", "R", "N"], q, r, n)?;
    let sol = if continuous {
        care(sys.a(), sys.b(), q, r, n, options)?
    } else {
        dare(sys.a(), sys.b(), q, r, n, options)?
    };
    Ok(sol.into())
}

/// Weights of an LQ cost count as positive semidefinite down to a smallest eigenvalue of
/// `−LQ_WEIGHT_TOLERANCE · (n + m) · ε · ‖W‖_F` (see [`lqr`]).
pub const LQ_WEIGHT_TOLERANCE: f64 = 100.0;

/// Checks that `[[Q, N], [Nᵀ, R]]` (or `Q` and `R` separately when `N` is absent) is positive
/// semidefinite to the tolerance of [`lqr`]; `names` are the names of `Q`, `R`, `N` in
/// messages. Shapes, finiteness and symmetry must already be validated.
fn check_lq_weights(names: [&str; 3], q: &Mat, r: &Mat, n: Option<&Mat>) -> Result<()> {
    let (nx, m) = (q.nrows(), r.nrows());
    match n {
        Some(nm) => {
            let mut w = Mat::zeros(nx + m, nx + m);
            w.view_mut((0, 0), (nx, nx)).copy_from(q);
            w.view_mut((nx, nx), (m, m)).copy_from(r);
            w.view_mut((0, nx), (nx, m)).copy_from(nm);
            w.view_mut((nx, 0), (m, nx)).copy_from(&nm.transpose());
            let what = format!("[{} {}; {}ᵀ {}]", names[0], names[2], names[2], names[1]);
            check_psd(&what, &crate::linalg::symmetrize(&w))
        }
        None => {
            check_psd(names[0], &crate::linalg::symmetrize(q))?;
            check_psd(names[1], &crate::linalg::symmetrize(r))
        }
    }
}

/// `NotPositiveSemidefinite` unless the symmetric `w` has no eigenvalue below
/// `−τ = −LQ_WEIGHT_TOLERANCE·k·ε·‖w‖_F` (`k` its order). A Cholesky factorisation of
/// `w + τI` settles the common case (it exists iff `λ_min(w) > −τ`, up to its own backward
/// error `≈ kε‖w‖ ≪ τ`); the eigenvalues are computed only when it fails.
fn check_psd(what: &str, w: &Mat) -> Result<()> {
    let k = w.nrows();
    if k == 0 {
        return Ok(());
    }
    let tolerance = LQ_WEIGHT_TOLERANCE * k as f64 * f64::EPSILON * w.norm();
    let shifted = w + Mat::identity(k, k) * tolerance;
    if tolerance > 0.0 && shifted.cholesky().is_some() {
        return Ok(());
    }
    let min = crate::linalg::symmetric_eigenvalues(w)
        .first()
        .copied()
        .unwrap_or(f64::NAN);
    if min.is_nan() || min < -tolerance {
        return Err(LtiError::NotPositiveSemidefinite {
            what: what.into(),
            min_eigenvalue: min,
            tolerance,
        });
    }
    Ok(())
}

/// The discretised weights of a continuous quadratic cost under zero-order hold.
#[derive(Debug, Clone, PartialEq)]
pub struct SampledDataCost {
    /// `Q_d = ∫₀^{ts} Φ(τ)ᵀ Q Φ(τ) + … dτ` (`n × n`), see [`sampled_data_cost`].
    pub q: Mat,
    /// `R_d` (`m × m`).
    pub r: Mat,
    /// Cross weight `N_d` (`n × m`) — non-zero even when the continuous `N` is zero.
    pub n: Mat,
}

/// Van Loan's discretisation of a continuous LQ cost for a zero-order-hold input (MATLAB
/// `lqrd` internals; Van Loan, IEEE TAC 23(3), 1978; Franklin, Powell & Workman, *Digital
/// Control of Dynamic Systems*, §9.4).
///
/// With `F = [[A, B], [0, 0]]` and `W = [[Q, N], [Nᵀ, R]]`, the cost over one interval with
/// `u` held at `uₖ` is `[xₖ; uₖ]ᵀ W_d [xₖ; uₖ]` where
/// `W_d = ∫₀^{ts} e^{Fᵀτ} W e^{Fτ} dτ = [[Q_d, N_d], [N_dᵀ, R_d]]`, computed with
/// [`van_loan_integral`] from one block exponential that also yields the ZOH pair
/// `e^{F ts} = [[A_d, B_d], [0, I]]`.
///
/// Returns the ZOH-discretised system (`C`, `D` kept) and the weights.
///
/// # Errors
/// Shape/finiteness errors naming `Q`, `R`, `N`; [`LtiError::InvalidSampleTime`].
#[doc(alias = "lqrd")]
pub fn sampled_data_cost(
    sys: &StateSpace<Continuous>,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    ts: f64,
) -> Result<(StateSpace<Discrete>, SampledDataCost)> {
    let domain = Discrete::new(ts)?;
    let (nx, m) = (sys.nx(), sys.nu());
    check_shape("Q", q, nx, nx)?;
    check_shape("R", r, m, m)?;
    check_finite("Q", q)?;
    check_finite("R", r)?;
    let mut f = Mat::zeros(nx + m, nx + m);
    f.view_mut((0, 0), (nx, nx)).copy_from(sys.a());
    f.view_mut((0, nx), (nx, m)).copy_from(sys.b());
    let mut w = Mat::zeros(nx + m, nx + m);
    w.view_mut((0, 0), (nx, nx)).copy_from(q);
    w.view_mut((nx, nx), (m, m)).copy_from(r);
    if let Some(nm) = n {
        check_shape("N", nm, nx, m)?;
        check_finite("N", nm)?;
        w.view_mut((0, nx), (nx, m)).copy_from(nm);
        w.view_mut((nx, 0), (m, nx)).copy_from(&nm.transpose());
    }
    let w = crate::linalg::symmetrize(&w);
    let (e, wd) = van_loan_integral(&f, &w, ts)?;
    let ad = e.view((0, 0), (nx, nx)).clone_owned();
    let bd = e.view((0, nx), (nx, m)).clone_owned();
    let dsys = StateSpace::new(ad, bd, sys.c().clone(), sys.d().clone(), domain)?;
    Ok((
        dsys,
        SampledDataCost {
            q: wd.view((0, 0), (nx, nx)).clone_owned(),
            r: wd.view((nx, nx), (m, m)).clone_owned(),
            n: wd.view((0, nx), (nx, m)).clone_owned(),
        },
    ))
}

/// A sampled-data LQ design: the ZOH model, its discretised cost and the discrete LQR.
#[derive(Debug, Clone, PartialEq)]
pub struct SampledDataLqr {
    /// ZOH discretisation of the plant at `ts`.
    pub system: StateSpace<Discrete>,
    /// Van Loan weights `Q_d`, `R_d`, `N_d`.
    pub cost: SampledDataCost,
    /// The discrete LQR on `(A_d, B_d)` with those weights (`u_k = −K_d x_k`).
    pub lqr: Lqr,
}

/// Sampled-data LQR (MATLAB `lqrd(A, B, Q, R, N, ts)`): the discrete gain `K_d` that minimises
/// the **continuous** cost `∫ (xᵀQx + uᵀRu + 2xᵀNu) dt` over zero-order-hold inputs,
/// `u(t) = −K_d x(kts)` on each interval; [`sampled_data_cost`] followed by the discrete
/// [`lqr`] with cross term `N_d`.
///
/// # Errors
/// As [`sampled_data_cost`] and [`lqr`].
#[doc(alias = "lqrd")]
pub fn lqr_sampled_data(
    sys: &StateSpace<Continuous>,
    q: &Mat,
    r: &Mat,
    n: Option<&Mat>,
    ts: f64,
) -> Result<SampledDataLqr> {
    let (system, cost) = sampled_data_cost(sys, q, r, n, ts)?;
    let lqr = lqr(&system, &cost.q, &cost.r, Some(&cost.n))?;
    Ok(SampledDataLqr { system, cost, lqr })
}

/// A steady-state Kalman (LQE) estimator gain with its diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct Kalman {
    /// The estimator gain `L` (`n × p`): `x̂' = A x̂ + B u + L (y − C x̂ − D u)`.
    pub gain: Mat,
    /// Steady-state estimation-error covariance `P` (continuous; for discrete systems the
    /// one-step-ahead prediction covariance).
    pub covariance: Mat,
    /// Eigenvalues of `A − LC`.
    pub estimator_poles: Vec<Complex64>,
    /// Relative residual of the dual Riccati equation.
    pub residual: f64,
}

/// Steady-state Kalman gain (MATLAB `lqe`; `kalman`'s gain for the predictor form in
/// discrete time), by duality with [`lqr`].
///
/// Model: `ẋ = Ax + Bu + Gw`, `y = Cx + Du + v`, `E[wwᵀ] = Q_n`, `E[vvᵀ] = R_n`,
/// `E[wvᵀ] = N_n`. Continuous: `P` solves the CARE of `(Aᵀ, Cᵀ, G Q_n Gᵀ, R_n, G N_n)` and
/// `L = (P Cᵀ + G N_n) R_n⁻¹`. Discrete: `P` solves the dual DARE and
/// `L = (A P Cᵀ + G N_n)(C P Cᵀ + R_n)⁻¹`, the gain of the one-step predictor
/// `x̂ₖ₊₁ = A x̂ₖ + B uₖ + L (yₖ − C x̂ₖ − D uₖ)`.
///
/// The noise intensities must be covariances: `[[Q_n, N_n], [N_nᵀ, R_n]] ⪰ 0` to the
/// tolerance of [`lqr`] ([`LtiError::NotPositiveSemidefinite`] otherwise).
///
/// # Errors
/// Shape errors naming `G`, `Qn`, `Rn`, `Nn`; as [`lqr`] (with "stabilisable" meaning
/// `(Aᵀ, Cᵀ)`, i.e. `(C, A)` detectable).
#[doc(alias = "kalman")]
#[doc(alias = "dlqe")]
pub fn lqe<D: TimeDomain>(
    sys: &StateSpace<D>,
    g: &Mat,
    qn: &Mat,
    rn: &Mat,
    nn: Option<&Mat>,
) -> Result<Kalman> {
    let nx = sys.nx();
    check_shape("G", g, nx, g.ncols())?;
    check_finite("G", g)?;
    check_square("Qn", qn)?;
    check_shape("Qn", qn, g.ncols(), g.ncols())?;
    check_shape("Rn", rn, sys.ny(), sys.ny())?;
    check_finite("Qn", qn)?;
    check_finite("Rn", rn)?;
    let cross = match nn {
        Some(nm) => {
            check_shape("Nn", nm, g.ncols(), sys.ny())?;
            check_finite("Nn", nm)?;
            Some(g * nm)
        }
        None => None,
    };
    // Noise intensities are covariances: [Qn Nn; Nnᵀ Rn] ⪰ 0, as the weights of `lqr`.
    check_lq_weights(["Qn", "Rn", "Nn"], qn, rn, nn)?;
    let w = crate::linalg::symmetrize(&(g * qn * g.transpose()));
    let (at, ct) = (sys.a().transpose(), sys.c().transpose());
    let opts = RiccatiOptions::default();
    let sol = match sys.domain().sample_time() {
        None => care(&at, &ct, &w, rn, cross.as_ref(), &opts)?,
        Some(_) => dare(&at, &ct, &w, rn, cross.as_ref(), &opts)?,
    };
    let l = sol.gain.transpose();
    let poles = crate::linalg::eigenvalues(&(sys.a() - &l * sys.c()))?;
    Ok(Kalman {
        gain: l,
        covariance: sol.x,
        estimator_poles: poles,
        residual: sol.residual,
    })
}

/// Checks that a gain has shape `m × n` for `sys`.
pub(crate) fn check_gain<D: TimeDomain>(sys: &StateSpace<D>, k: &Mat, what: &str) -> Result<()> {
    check_shape(what, k, sys.nu(), sys.nx())?;
    check_finite(what, k).map_err(|e| match e {
        LtiError::NonFinite {
            row, col, value, ..
        } => LtiError::NonFinite {
            what: what.to_string(),
            row,
            col,
            value,
        },
        other => other,
    })
}
