//! H∞ synthesis by Riccati equations (Doyle, Glover, Khargonekar & Francis, "State-space
//! solutions to standard H2 and H∞ control problems", IEEE TAC 34(8), 1989; the formulas
//! with cross terms and general `D₁₂`, `D₂₁` as in Zhou, Doyle & Glover, *Robust and Optimal
//! Control*, 1996, ch. 16–17; MATLAB `hinfsyn`, python-control `hinfsyn`, SLICOT `SB10AD`).
//!
//! For the [`StandardPlant`] with `D₁₁ = 0`, `R₁ = D₁₂ᵀD₁₂ ≻ 0` and `R₂ = D₂₁D₂₁ᵀ ≻ 0`, a
//! controller with `‖T_zw‖∞ < γ` exists iff
//!
//! 1. `X∞` — the stabilising solution of
//!    `ÃᵀX + XÃ − X(B₂R₁⁻¹B₂ᵀ − γ⁻²B₁B₁ᵀ)X + C₁ᵀ(I − D₁₂R₁⁻¹D₁₂ᵀ)C₁ = 0`,
//!    `Ã = A − B₂R₁⁻¹D₁₂ᵀC₁` — exists and `X∞ ⪰ 0`;
//! 2. `Y∞` — the stabilising solution of the dual equation
//!    `ĀY + YĀᵀ − Y(C₂ᵀR₂⁻¹C₂ − γ⁻²C₁ᵀC₁)Y + B₁(I − D₂₁ᵀR₂⁻¹D₂₁)B₁ᵀ = 0`,
//!    `Ā = A − B₁D₂₁ᵀR₂⁻¹C₂` — exists and `Y∞ ⪰ 0`;
//! 3. `ρ(X∞Y∞) < γ²`.
//!
//! The central controller (`u = K y`, `D₂₂ = 0`) is then, with
//! `F = −R₁⁻¹(B₂ᵀX∞ + D₁₂ᵀC₁)`, `L = −(Y∞C₂ᵀ + B₁D₂₁ᵀ)R₂⁻¹`, `Z = (I − γ⁻²Y∞X∞)⁻¹`:
//!
//! ```text
//! A_k = A + γ⁻²B₁B₁ᵀX∞ + B₂F + Z L (C₂ + γ⁻²D₂₁B₁ᵀX∞),   B_k = −Z L,   C_k = F,   D_k = 0
//! ```
//!
//! (an observer of the worst-case disturbance `ŵ = γ⁻²B₁ᵀX∞x̂`); a non-zero `D₂₂` is
//! handled by loop shifting ([`StandardPlant::shift_d22`]).
//!
//! **`D₁₁ ≠ 0`** (Glover & Doyle, "State-space formulae for all stabilizing controllers that
//! satisfy an H∞-norm bound and relations to risk sensitivity", Systems & Control Letters
//! 11, 1988; Zhou, Doyle & Glover §17.1, theorem 17.1; the formulas of SLICOT `SB10AD`):
//! the plant is first normalised to `D₁₂ = [0; I]`, `D₂₁ = [0 I]` by `u = T_u ũ`
//! (`T_u = (D₁₂ᵀD₁₂)^{-1/2}`), `ỹ = T_y y` (`T_y = (D₂₁D₂₁ᵀ)^{-1/2}`) and orthogonal changes of
//! `z` and `w` (which leave `‖T_zw‖∞` unchanged). `D₁₁` is partitioned conformally,
//! `D₁₁ = [D₁₁₁₁ D₁₁₁₂; D₁₁₂₁ D₁₁₂₂]` with `D₁₁₂₂` of size `ncon × nmeas`: no controller
//! changes `D₁₁₁₁`, `D₁₁₁₂` (the `z` directions `u` cannot reach) or `D₁₁₂₁` (the `w`
//! directions `y` does not see), so a level is feasible only if (condition 0)
//! `γ > max(‖[D₁₁₁₁ D₁₁₁₂]‖₂, ‖[D₁₁₁₁; D₁₁₂₁]‖₂)` ([`HinfCondition::D11Bound`]). With
//! `D₁• = [D₁₁ D₁₂]`, `D•₁ = [D₁₁; D₂₁]`, `R = D₁•ᵀD₁• − diag(γ²I, 0)`,
//! `R̃ = D•₁D•₁ᵀ − diag(γ²I, 0)`, `B = [B₁ B₂]`, `C = [C₁; C₂]`, the Riccati equations are
//! `AₓᵀX + XAₓ − X B R⁻¹Bᵀ X + C₁ᵀ(I − D₁•R⁻¹D₁•ᵀ)C₁ = 0`, `Aₓ = A − BR⁻¹D₁•ᵀC₁`, and
//! `A_yY + YA_yᵀ − Y CᵀR̃⁻¹C Y + B₁(I − D•₁ᵀR̃⁻¹D•₁)B₁ᵀ = 0`, `A_y = A − B₁D•₁ᵀR̃⁻¹C`
//! (conditions 1–3 as above). With `F = −R⁻¹(D₁•ᵀC₁ + BᵀX∞) = [F₁₁; F₁₂; F₂]`,
//! `L = −(B₁D•₁ᵀ + Y∞Cᵀ)R̃⁻¹ = [L₁₁ L₁₂ L₂]`, `Z = (I − γ⁻²Y∞X∞)⁻¹` and
//! `D̂₁₁ = −D₁₁₂₁D₁₁₁₁ᵀ(γ²I − D₁₁₁₁D₁₁₁₁ᵀ)⁻¹D₁₁₁₂ − D₁₁₂₂`, the central controller is
//!
//! ```text
//! B̂₁ = −Z L₂ + Z (B₂ + L₁₂) D̂₁₁,   Ĉ₁ = F₂ − D̂₁₁ (C₂ + F₁₂),
//! Â = A + B F − B̂₁ (C₂ + F₁₂),      K̃ = (Â, B̂₁, Ĉ₁, D̂₁₁),
//! ```
//!
//! mapped back as `K = (Â, B̂₁T_y, T_uĈ₁, T_uD̂₁₁T_y)`. These formulas are used whenever
//! `D₁₁ ≠ 0` (for `D₁₁ = 0` they reduce to the ones above, which are used then; a unit test
//! checks that both give the same optimal level). The state-feedback
//! (full-information) problem needs condition 1 only, with the static gain
//! `u = −K x`, `K = R₁⁻¹(B₂ᵀX∞ + D₁₂ᵀC₁)` ([`hinf_state_feedback`]).
//!
//! Each indefinite Riccati equation is solved by the ordered real Schur form of its
//! Hamiltonian `[[Ã, −G], [−Q̃, −Ãᵀ]]` (balanced by `s = √(‖Q̃‖/‖G‖)`) followed by Newton
//! steps in residual-correction form; the solution counts as **stabilising** when no
//! Hamiltonian eigenvalue lies within [`IMAGINARY_TOLERANCE`]`·‖H‖_F` of the imaginary axis,
//! the stable-subspace basis `U₁` is invertible to working precision (otherwise `X∞` is
//! unbounded, which is how condition 1 fails as `γ` decreases to the optimum of many
//! problems), the relative residual is at most [`RESIDUAL_TOLERANCE`] and the closed loop
//! `Ã − GX` is Hurwitz; **positive semidefinite** when its smallest eigenvalue is at least
//! `−`[`PSD_TOLERANCE`]`·max(1, ‖X‖₂)`.
//!
//! A level `γ` at which a condition fails is reported as [`LtiError::HinfInfeasible`] with
//! the [`HinfCondition`] that failed (the first of 1, 2, 3); the assumptions of the plant
//! are checked first ([`StandardPlant::check_assumptions`], [`LtiError::SynthesisAssumption`]).
//! The optimal level is found by bisection on `γ` ([`hinf_syn_optimal`],
//! [`hinf_state_feedback_optimal`]).

use super::standard_plant::StandardPlant;
use crate::domain::Continuous;
use crate::equations::lyap;
use crate::equations::riccati::solution_from_subspace;
use crate::error::{LtiError, Result};
#[cfg(test)]
use crate::linalg::Complex64;
use crate::linalg::schur::real_schur;
use crate::linalg::{Mat, eigenvalues, symmetric_eigenvalues, symmetrize};
use crate::state_space::StateSpace;

mod glover_doyle;
use glover_doyle::{Normalized, output_feedback_d11};

/// A Hamiltonian eigenvalue `λ` with `|Re λ| ≤ IMAGINARY_TOLERANCE · ‖H‖_F` counts as lying
/// on the imaginary axis (no stabilising solution).
pub const IMAGINARY_TOLERANCE: f64 = 1e-10;

/// A Riccati solution counts as positive semidefinite when its smallest eigenvalue is at least
/// `−PSD_TOLERANCE · max(1, ‖X‖₂)`.
pub const PSD_TOLERANCE: f64 = 1e-9;

/// Largest relative residual `‖Res(X)‖_F / (2‖ÃᵀX‖_F + ‖XGX‖_F + ‖Q̃‖_F)` of an accepted
/// Riccati solution.
pub const RESIDUAL_TOLERANCE: f64 = 1e-8;

/// Which of the two H∞ Riccati equations.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HinfRiccati {
    /// The control (state-feedback) equation for `X∞`.
    X,
    /// The filter (estimation) equation for `Y∞`.
    Y,
}

impl std::fmt::Display for HinfRiccati {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            HinfRiccati::X => "X∞",
            HinfRiccati::Y => "Y∞",
        })
    }
}

/// The existence condition of the module documentation that fails at a level `γ`.
#[derive(Debug, Clone, PartialEq)]
pub enum HinfCondition {
    /// The Riccati equation has no stabilising solution at this `γ` (conditions 1, 2).
    NoStabilizingSolution {
        /// Which equation.
        riccati: HinfRiccati,
        /// Why: an imaginary-axis Hamiltonian eigenvalue, an unbounded solution (singular
        /// `U₁`), an inaccurate solution or a closed loop that is not Hurwitz.
        reason: String,
    },
    /// The stabilising solution exists but is not positive semidefinite (conditions 1, 2).
    NotPositiveSemidefinite {
        /// Which equation.
        riccati: HinfRiccati,
        /// Its smallest eigenvalue.
        min_eigenvalue: f64,
    },
    /// `γ` is not above the bound that `D₁₁` sets (condition 0 of the `D₁₁ ≠ 0` formulas):
    /// `γ ≤ max(‖[D₁₁₁₁ D₁₁₁₂]‖₂, ‖[D₁₁₁₁; D₁₁₂₁]‖₂)`, the parts of `D₁₁` that no
    /// controller can reach (module documentation).
    D11Bound {
        /// The bound `max(‖[D₁₁₁₁ D₁₁₁₂]‖₂, ‖[D₁₁₁₁; D₁₁₂₁]‖₂)`.
        bound: f64,
    },
    /// The coupling condition fails: `ρ(X∞Y∞) ≥ γ²` (condition 3).
    SpectralRadius {
        /// `ρ(X∞Y∞)`.
        rho: f64,
        /// `γ²`.
        gamma_squared: f64,
    },
}

impl std::fmt::Display for HinfCondition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            HinfCondition::NoStabilizingSolution { riccati, reason } => {
                write!(f, "{riccati} has no stabilising solution ({reason})")
            }
            HinfCondition::NotPositiveSemidefinite {
                riccati,
                min_eigenvalue,
            } => write!(
                f,
                "{riccati} is not positive semidefinite (smallest eigenvalue {min_eigenvalue:e})"
            ),
            HinfCondition::SpectralRadius { rho, gamma_squared } => {
                write!(f, "ρ(X∞Y∞) = {rho:e} ≥ γ² = {gamma_squared:e}")
            }
            HinfCondition::D11Bound { bound } => write!(
                f,
                "γ ≤ max(‖[D1111 D1112]‖, ‖[D1111; D1121]‖) = {bound:e}, the part of D11 no controller reaches"
            ),
        }
    }
}

/// An output-feedback H∞ controller at the level `γ`.
#[derive(Debug, Clone, PartialEq)]
pub struct HinfController {
    /// The central controller `K` (`nmeas` inputs, `ncon` outputs, `n` states), connected as
    /// `u = K y` (positive feedback, the lower LFT).
    pub controller: StateSpace<Continuous>,
    /// The level `γ`: `‖T_zw‖∞ < γ`.
    pub gamma: f64,
    /// `X∞ ⪰ 0`.
    pub x: Mat,
    /// `Y∞ ⪰ 0`.
    pub y: Mat,
    /// `ρ(X∞Y∞) < γ²`.
    pub spectral_radius: f64,
    /// The closed loop `T_zw = F_l(P, K)` (states `[x; x_k]`).
    pub closed_loop: StateSpace<Continuous>,
}

/// A state-feedback (full-information) H∞ gain at the level `γ`.
#[derive(Debug, Clone, PartialEq)]
pub struct HinfStateFeedback {
    /// `K` of `u = −K x` (`ncon × n`).
    pub gain: Mat,
    /// The level `γ`: `‖T_zw‖∞ < γ`.
    pub gamma: f64,
    /// `X∞ ⪰ 0`.
    pub x: Mat,
    /// The closed loop `ẋ = (A − B₂K)x + B₁w`, `z = (C₁ − D₁₂K)x + D₁₁w`.
    pub closed_loop: StateSpace<Continuous>,
}

/// Options of the γ-iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GammaIteration {
    /// Relative tolerance: the iteration stops when `γ_feasible − γ_infeasible ≤ tol ·
    /// γ_feasible`. Default `1e-6`.
    pub tolerance: f64,
    /// The first level tried (doubled while infeasible, halved while feasible to bracket the
    /// optimum). Default `1`.
    pub start: f64,
    /// Most levels tried. Default 300.
    pub max_levels: usize,
}

impl Default for GammaIteration {
    fn default() -> Self {
        Self {
            tolerance: 1e-6,
            start: 1.0,
            max_levels: 300,
        }
    }
}

/// The result of a γ-iteration: the design at the smallest feasible level found.
///
/// A controller this close to the optimum is ill-conditioned (`Z = (I − γ⁻²Y∞X∞)⁻¹` or
/// `X∞` nearly singular or unbounded): its closed loop can exceed `γ` by rounding (on the
/// test plants by up to 2·10⁻⁷ relative at the default tolerance 10⁻⁶; SB10AD's
/// controllers at its tolerance 10⁻⁸ by 3 % and 55 % on two of them). For a controller to
/// use, call [`hinf_syn`] at a level a little above `gamma` (MATLAB's `hinfsyn` stops 1 %
/// above).
#[derive(Debug, Clone, PartialEq)]
pub struct GammaOptimal<T> {
    /// The design at `gamma`.
    pub design: T,
    /// The smallest level found feasible (an upper bound of the optimum `γ_opt`).
    pub gamma: f64,
    /// The largest level found infeasible (a lower bound of `γ_opt`; `0` if every level
    /// tried down to `start·2⁻⁶⁰` was feasible).
    pub gamma_infeasible: f64,
    /// Levels tried.
    pub levels: usize,
}

/// The output-feedback H∞ controller at the level `γ` (module documentation).
///
/// # Errors
/// [`LtiError::InvalidArgument`] unless `γ` is finite and positive;
/// [`LtiError::SynthesisAssumption`] for a plant violating an assumption (any `D₁₁` is
/// accepted); [`LtiError::HinfInfeasible`] naming the failed [`HinfCondition`]
/// ([`HinfCondition::D11Bound`] when `γ` is not above the bound `D₁₁` sets);
/// numerical errors of the eigenvalue and Lyapunov solvers.
#[doc(alias = "hinfsyn")]
pub fn hinf_syn(plant: &StandardPlant, gamma: f64) -> Result<HinfController> {
    check_gamma(gamma)?;
    plant.check_assumptions(false)?;
    output_feedback(plant, gamma)
}

/// The optimal output-feedback H∞ level by bisection on `γ` (geometric means), each level
/// decided by the three conditions of the module documentation; returns the controller at
/// the smallest feasible level found.
///
/// # Errors
/// As [`hinf_syn`]; [`LtiError::InvalidArgument`] for invalid options;
/// [`LtiError::NoConvergence`] when no feasible level is found within `max_levels`.
#[doc(alias = "hinfsyn")]
pub fn hinf_syn_optimal(
    plant: &StandardPlant,
    options: &GammaIteration,
) -> Result<GammaOptimal<HinfController>> {
    plant.check_assumptions(false)?;
    if d11_is_zero(plant) {
        gamma_iteration(options, |g| output_feedback_at(plant, g))
    } else {
        let normalized = Normalized::new(plant)?;
        gamma_iteration(options, |g| output_feedback_d11(plant, &normalized, g))
    }
}

/// The state-feedback (full-information) H∞ gain `u = −K x` at the level `γ`: condition 1
/// of the module documentation. Only `A, B₁, B₂, C₁, D₁₁, D₁₂` of the plant are used.
///
/// # Errors
/// [`LtiError::InvalidArgument`] for an invalid `γ`; [`LtiError::SynthesisAssumption`] for
/// `D₁₁ ≠ 0`, `D₁₂` not of full column rank, `(A, B₂)` not stabilisable or `P₁₂` with an
/// imaginary-axis zero; [`LtiError::HinfInfeasible`].
pub fn hinf_state_feedback(plant: &StandardPlant, gamma: f64) -> Result<HinfStateFeedback> {
    check_gamma(gamma)?;
    check_state_feedback_assumptions(plant)?;
    state_feedback_at(plant, gamma)
}

/// The optimal state-feedback H∞ level by bisection ([`hinf_state_feedback`] at each level).
///
/// # Errors
/// As [`hinf_state_feedback`] and [`hinf_syn_optimal`].
pub fn hinf_state_feedback_optimal(
    plant: &StandardPlant,
    options: &GammaIteration,
) -> Result<GammaOptimal<HinfStateFeedback>> {
    check_state_feedback_assumptions(plant)?;
    gamma_iteration(options, |g| state_feedback_at(plant, g))
}

fn check_gamma(gamma: f64) -> Result<()> {
    if !(gamma.is_finite() && gamma > 0.0) {
        return Err(LtiError::InvalidArgument(format!(
            "H∞ level γ must be finite and > 0, got {gamma}"
        )));
    }
    Ok(())
}

fn check_state_feedback_assumptions(plant: &StandardPlant) -> Result<()> {
    if plant.ncon() == 0 {
        return Err(LtiError::SynthesisAssumption {
            assumption: super::PlantAssumption::HasMeasurementsAndControls,
            detail: "ncon = 0".into(),
        });
    }
    plant.check_d11(true)?;
    plant.check_d12_rank()?;
    let sys = StateSpace::continuous(
        plant.a().clone(),
        plant.b2(),
        Mat::zeros(0, plant.nx()),
        Mat::zeros(0, plant.ncon()),
    )?;
    if !sys.is_stabilizable()? {
        return Err(LtiError::SynthesisAssumption {
            assumption: super::PlantAssumption::Stabilizable,
            detail: "(A, B2) has an uncontrollable mode that is not stable".into(),
        });
    }
    plant.check_p12_zeros()
}

/// Bisection on `γ` (module documentation of [`GammaIteration`]): `try_level` returns the
/// design or [`LtiError::HinfInfeasible`].
pub(crate) fn gamma_iteration<T, F>(
    options: &GammaIteration,
    mut try_level: F,
) -> Result<GammaOptimal<T>>
where
    F: FnMut(f64) -> Result<T>,
{
    let GammaIteration {
        tolerance,
        start,
        max_levels,
    } = *options;
    let valid = tolerance.is_finite()
        && tolerance > 0.0
        && tolerance < 1.0
        && start.is_finite()
        && start > 0.0;
    if !valid {
        return Err(LtiError::InvalidArgument(format!(
            "γ-iteration: tolerance must be in (0, 1) and start > 0, got {tolerance}, {start}"
        )));
    }
    let mut levels = 0;
    let mut attempt = |g: f64, levels: &mut usize| -> Result<Option<T>> {
        *levels += 1;
        match try_level(g) {
            Ok(t) => Ok(Some(t)),
            Err(LtiError::HinfInfeasible { .. }) => Ok(None),
            Err(e) => Err(e),
        }
    };
    let exhausted = |levels: usize| LtiError::NoConvergence {
        algorithm: "H∞ γ-iteration".into(),
        iterations: levels,
    };
    // Bracket: double until feasible, or halve while feasible.
    let (mut lo, mut hi, mut best);
    let mut g = start;
    match attempt(g, &mut levels)? {
        Some(t) => {
            hi = g;
            best = t;
            lo = 0.0;
            for _ in 0..60 {
                g = hi / 2.0;
                match attempt(g, &mut levels)? {
                    Some(t) => {
                        hi = g;
                        best = t;
                    }
                    None => {
                        lo = g;
                        break;
                    }
                }
            }
        }
        None => {
            lo = g;
            loop {
                if levels >= max_levels || !g.is_finite() {
                    return Err(exhausted(levels));
                }
                g *= 2.0;
                if let Some(t) = attempt(g, &mut levels)? {
                    hi = g;
                    best = t;
                    break;
                }
                lo = g;
            }
        }
    }
    while lo > 0.0 && hi - lo > tolerance * hi {
        if levels >= max_levels {
            return Err(exhausted(levels));
        }
        let mid = (lo * hi).sqrt();
        match attempt(mid, &mut levels)? {
            Some(t) => {
                hi = mid;
                best = t;
            }
            None => lo = mid,
        }
    }
    Ok(GammaOptimal {
        design: best,
        gamma: hi,
        gamma_infeasible: lo,
        levels,
    })
}

fn infeasible(gamma: f64, condition: HinfCondition) -> LtiError {
    LtiError::HinfInfeasible { gamma, condition }
}

/// `R⁻¹` of a symmetric positive definite weight (`D₁₂ᵀD₁₂` or `D₂₁D₂₁ᵀ`, full rank by
/// the assumptions).
fn spd_inverse(what: &str, r: &Mat) -> Result<Mat> {
    symmetrize(r)
        .cholesky()
        .map(|c| symmetrize(&c.inverse()))
        .ok_or_else(|| LtiError::NotPositiveDefinite {
            what: what.into(),
            min_eigenvalue: symmetric_eigenvalues(r)
                .first()
                .copied()
                .unwrap_or(f64::NAN),
        })
}

/// `X∞` of the plant at `γ` (condition 1) with `R₁⁻¹`.
fn x_infinity(plant: &StandardPlant, gamma: f64) -> Result<(Mat, Mat)> {
    let (b1, b2, c1, d12) = (plant.b1(), plant.b2(), plant.c1(), plant.d12());
    let r1inv = spd_inverse("D12ᵀD12", &(d12.transpose() * &d12))?;
    let at = plant.a() - &b2 * &r1inv * d12.transpose() * &c1;
    let g = symmetrize(&(&b2 * &r1inv * b2.transpose() - &b1 * b1.transpose() / (gamma * gamma)));
    let nz = c1.nrows();
    let q = symmetrize(
        &(c1.transpose() * (Mat::identity(nz, nz) - &d12 * &r1inv * d12.transpose()) * &c1),
    );
    let x = psd_solution(gamma, HinfRiccati::X, &at, &g, &q)?;
    Ok((x, r1inv))
}

/// `Y∞` of the plant at `γ` (condition 2) with `R₂⁻¹`.
fn y_infinity(plant: &StandardPlant, gamma: f64) -> Result<(Mat, Mat)> {
    let (b1, c1, c2, d21) = (plant.b1(), plant.c1(), plant.c2(), plant.d21());
    let r2inv = spd_inverse("D21D21ᵀ", &(&d21 * d21.transpose()))?;
    let abar = plant.a() - &b1 * d21.transpose() * &r2inv * &c2;
    let g = symmetrize(&(c2.transpose() * &r2inv * &c2 - c1.transpose() * &c1 / (gamma * gamma)));
    let nw = b1.ncols();
    let q = symmetrize(
        &(&b1 * (Mat::identity(nw, nw) - d21.transpose() * &r2inv * &d21) * b1.transpose()),
    );
    let y = psd_solution(gamma, HinfRiccati::Y, &abar.transpose(), &g, &q)?;
    Ok((y, r2inv))
}

/// The stabilising solution, checked positive semidefinite, or the failed condition.
fn psd_solution(gamma: f64, riccati: HinfRiccati, a: &Mat, g: &Mat, q: &Mat) -> Result<Mat> {
    let x = stabilizing_solution(a, g, q)?.map_err(|reason| {
        infeasible(
            gamma,
            HinfCondition::NoStabilizingSolution { riccati, reason },
        )
    })?;
    if x.nrows() > 0 {
        let ev = symmetric_eigenvalues(&x);
        let min = ev.first().copied().unwrap_or(0.0);
        let scale = ev.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        if min.is_nan() || min < -PSD_TOLERANCE * scale {
            return Err(infeasible(
                gamma,
                HinfCondition::NotPositiveSemidefinite {
                    riccati,
                    min_eigenvalue: min,
                },
            ));
        }
    }
    Ok(x)
}

/// The stabilising solution of `AᵀX + XA − XGX + Q = 0` (`G`, `Q` symmetric, `G`
/// indefinite), or the reason it does not exist (module documentation).
fn stabilizing_solution(a: &Mat, g: &Mat, q: &Mat) -> Result<std::result::Result<Mat, String>> {
    let n = a.nrows();
    if n == 0 {
        return Ok(Ok(Mat::zeros(0, 0)));
    }
    let (qn, gn) = (q.norm(), g.norm());
    let s = if qn > 0.0 && gn > 0.0 {
        (qn / gn).sqrt()
    } else {
        1.0
    };
    let mut h = Mat::zeros(2 * n, 2 * n);
    h.view_mut((0, 0), (n, n)).copy_from(a);
    h.view_mut((0, n), (n, n)).copy_from(&(g * -s));
    h.view_mut((n, 0), (n, n)).copy_from(&(q * (-1.0 / s)));
    h.view_mut((n, n), (n, n)).copy_from(&(-a.transpose()));
    let hn = h.norm();
    let mut sch = real_schur(&h)?;
    let ev = sch.eigenvalues();
    if let Some(l) = ev
        .iter()
        .filter(|l| l.re.abs() <= IMAGINARY_TOLERANCE * hn)
        .min_by(|x, y| x.re.abs().total_cmp(&y.re.abs()))
    {
        return Ok(Err(format!(
            "Hamiltonian eigenvalue {:e}{:+e}j on the imaginary axis (|Re λ| ≤ {IMAGINARY_TOLERANCE:e}·‖H‖_F)",
            l.re, l.im
        )));
    }
    let k = match sch.reorder(|l| l.re < 0.0) {
        Ok(k) => k,
        Err(LtiError::Inaccurate { .. }) => {
            return Ok(Err(
                "the Hamiltonian's stable and unstable eigenvalues cannot be separated".into(),
            ));
        }
        Err(e) => return Err(e),
    };
    if k != n {
        return Ok(Err(format!(
            "the Hamiltonian has {k} stable eigenvalues, not {n}"
        )));
    }
    let z = sch.z();
    let u1 = z.view((0, 0), (n, n)).clone_owned();
    let u2 = z.view((n, 0), (n, n)).clone_owned();
    let mut x = match solution_from_subspace(&u1, &u2) {
        Ok(y) => y * s,
        Err(LtiError::IllConditioned { condition, .. }) => {
            return Ok(Err(format!(
                "unbounded: the stable-subspace basis U1 is singular (condition {condition:e})"
            )));
        }
        Err(e) => return Err(e),
    };
    let residual = |x: &Mat| -> (Mat, f64) {
        let atx = a.transpose() * x;
        let xgx = x * g * x;
        let r = symmetrize(&(&atx + atx.transpose() - &xgx + q));
        let scale = 2.0 * atx.norm() + xgx.norm() + qn;
        let rel = if scale > 0.0 {
            r.norm() / scale
        } else {
            r.norm()
        };
        (r, rel)
    };
    let (mut r, mut rel) = residual(&x);
    // Newton (Kleinman) steps: (A − GX)ᵀΔ + Δ(A − GX) + Res(X) = 0.
    for _ in 0..4 {
        if rel <= 10.0 * n as f64 * f64::EPSILON {
            break;
        }
        let acl = a - g * &x;
        let Ok(step) = lyap(&acl.transpose(), &r) else {
            break;
        };
        let xn = symmetrize(&(&x + step.x));
        let (rn, reln) = residual(&xn);
        if reln < 0.5 * rel {
            x = xn;
            r = rn;
            rel = reln;
        } else {
            break;
        }
    }
    if rel.is_nan() || rel > RESIDUAL_TOLERANCE {
        return Ok(Err(format!(
            "inaccurate: relative residual {rel:e} > {RESIDUAL_TOLERANCE:e}"
        )));
    }
    let poles = eigenvalues(&(a - g * &x))?;
    if let Some(p) = poles.iter().find(|p| p.re.is_nan() || p.re >= 0.0) {
        return Ok(Err(format!(
            "the closed loop A − GX has the pole {:e}{:+e}j",
            p.re, p.im
        )));
    }
    Ok(Ok(x))
}

/// `ρ(M)` of a square matrix (`0` if empty).
fn spectral_radius(m: &Mat) -> Result<f64> {
    if m.nrows() == 0 {
        return Ok(0.0);
    }
    Ok(eigenvalues(m)?.iter().map(|l| l.norm()).fold(0.0, f64::max))
}

/// The central controller at `γ` (assumptions already checked).
fn output_feedback_at(plant: &StandardPlant, gamma: f64) -> Result<HinfController> {
    let (b1, b2, c1, c2, d12, d21) = (
        plant.b1(),
        plant.b2(),
        plant.c1(),
        plant.c2(),
        plant.d12(),
        plant.d21(),
    );
    let g2 = 1.0 / (gamma * gamma);
    let (x, r1inv) = x_infinity(plant, gamma)?;
    let (y, r2inv) = y_infinity(plant, gamma)?;
    let rho = spectral_radius(&(&x * &y))?;
    if rho.is_nan() || rho >= gamma * gamma {
        return Err(infeasible(
            gamma,
            HinfCondition::SpectralRadius {
                rho,
                gamma_squared: gamma * gamma,
            },
        ));
    }
    let n = plant.nx();
    let f = -(&r1inv * (b2.transpose() * &x + d12.transpose() * &c1));
    let l = -((&y * c2.transpose() + &b1 * d21.transpose()) * &r2inv);
    let zinv = Mat::identity(n, n) - &y * &x * g2;
    let zl = zinv.clone().lu().solve(&l).ok_or_else(|| {
        infeasible(
            gamma,
            HinfCondition::SpectralRadius {
                rho,
                gamma_squared: gamma * gamma,
            },
        )
    })?;
    let ak = plant.a()
        + &b1 * b1.transpose() * &x * g2
        + &b2 * &f
        + &zl * (&c2 + &d21 * b1.transpose() * &x * g2);
    let k0 = StateSpace::continuous(ak, -zl, f, Mat::zeros(plant.ncon(), plant.nmeas()))?;
    let controller = plant.shift_d22(k0)?;
    let closed_loop = plant.close_loop(&controller)?;
    Ok(HinfController {
        controller,
        gamma,
        x,
        y,
        spectral_radius: rho,
        closed_loop,
    })
}

/// The state-feedback gain at `γ` (assumptions already checked).
fn state_feedback_at(plant: &StandardPlant, gamma: f64) -> Result<HinfStateFeedback> {
    let (x, r1inv) = x_infinity(plant, gamma)?;
    let (b2, c1, d12) = (plant.b2(), plant.c1(), plant.d12());
    let k = &r1inv * (b2.transpose() * &x + d12.transpose() * &c1);
    let closed_loop = StateSpace::continuous(
        plant.a() - &b2 * &k,
        plant.b1(),
        &c1 - &d12 * &k,
        plant.d11(),
    )?;
    Ok(HinfStateFeedback {
        gain: k,
        gamma,
        x,
        closed_loop,
    })
}

fn d11_is_zero(plant: &StandardPlant) -> bool {
    plant.d11().iter().all(|v| *v == 0.0)
}

/// The central controller at `γ` by the formulas for the plant's `D₁₁`.
fn output_feedback(plant: &StandardPlant, gamma: f64) -> Result<HinfController> {
    if d11_is_zero(plant) {
        output_feedback_at(plant, gamma)
    } else {
        output_feedback_d11(plant, &Normalized::new(plant)?, gamma)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic pseudo-random plant (linear congruential generator) with `D₁₁ = 0`.
    fn plant(seed: u64) -> StandardPlant {
        let mut state = seed;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let mut mat = |r: usize, c: usize| Mat::from_fn(r, c, |_, _| next());
        let (n, nw, nu, nz, ny) = (5, 3, 2, 3, 1);
        let (a, b1, b2, c1, c2) = (mat(n, n), mat(n, nw), mat(n, nu), mat(nz, n), mat(ny, n));
        let (d12, d21, d22) = (mat(nz, nu), mat(ny, nw), mat(ny, nu));
        StandardPlant::from_blocks(
            &a,
            &b1,
            &b2,
            &c1,
            &c2,
            &Mat::zeros(nz, nw),
            &d12,
            &d21,
            &d22,
        )
        .unwrap()
    }

    /// For `D₁₁ = 0` the general formulas (normalised plant, `R`, `R̃`) and the DGKF ones
    /// decide every level alike: the same optimal level, and at a level above it the same
    /// closed loop (the central controller is unique up to a state transformation).
    #[test]
    fn general_formulas_reduce_to_dgkf() {
        let options = GammaIteration {
            tolerance: 1e-10,
            ..GammaIteration::default()
        };
        for seed in [1, 2, 3] {
            let p = plant(seed);
            p.check_assumptions(true).unwrap();
            let nm = Normalized::new(&p).unwrap();
            assert_eq!(nm.bound, 0.0);
            let dgkf = gamma_iteration(&options, |g| output_feedback_at(&p, g)).unwrap();
            let general = gamma_iteration(&options, |g| output_feedback_d11(&p, &nm, g)).unwrap();
            assert!(
                (dgkf.gamma - general.gamma).abs() <= 1e-8 * dgkf.gamma,
                "{seed}: {} vs {}",
                dgkf.gamma,
                general.gamma
            );
            let g = 1.1 * dgkf.gamma;
            let (k0, k1) = (
                output_feedback_at(&p, g).unwrap(),
                output_feedback_d11(&p, &nm, g).unwrap(),
            );
            for w in [0.01, 0.3, 1.0, 7.0] {
                let s = Complex64::new(0.0, w);
                let d = k0.closed_loop.evaluate(s).unwrap() - k1.closed_loop.evaluate(s).unwrap();
                assert!(d.norm() < 1e-7, "{seed} at {w}: {d}");
            }
        }
    }
}
