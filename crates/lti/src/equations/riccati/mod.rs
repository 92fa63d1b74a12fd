//! Algebraic Riccati equations, continuous ([`care`]) and discrete ([`dare`]), with cross term.
//!
//! Continuous (CARE):
//! `AᵀX + XA − (XB + N) R⁻¹ (BᵀX + Nᵀ) + Q = 0`, stabilising gain `K = R⁻¹(BᵀX + Nᵀ)`,
//! closed loop `A − BK` Hurwitz.
//!
//! Discrete (DARE):
//! `AᵀXA − X − (AᵀXB + N)(BᵀXB + R)⁻¹(BᵀXA + Nᵀ) + Q = 0`, stabilising gain
//! `K = (BᵀXB + R)⁻¹(BᵀXA + Nᵀ)`, closed loop `A − BK` Schur-stable.
//!
//! Both return a [`RiccatiSolution`] carrying the solution, the gain, the closed-loop poles and
//! the relative residual (module [`equations`](crate::equations) defines it).
//!
//! ## How a solution is computed and checked
//! 1. The data are validated (shapes, finiteness, symmetry, `R ≻ 0`).
//! 2. The cross term is removed: `Ã = A − B R⁻¹ Nᵀ`, `Q̃ = Q − N R⁻¹ Nᵀ`, `G = B R⁻¹ Bᵀ`.
//! 3. With `scaling`, `Q̃` and `G` are balanced by `X = s Y`, `s = sqrt(‖Q̃‖_F / ‖G‖_F)` (the
//!    equation for `Y` has `sG`, `Q̃/s`; SLICOT `SB02MD`'s scaling).
//! 4. The stabilising solution is computed by the chosen [`RiccatiMethod`].
//! 5. Newton refinement (Kleinman for the CARE, Hewer for the DARE, in residual-correction
//!    form: one Lyapunov/Stein solve per step) is applied while the relative residual is above
//!    the rounding level `REFINEMENT_FLOOR · n · ε` ([`REFINEMENT_FLOOR`]); a step is kept only
//!    if it lowers the residual, and the iteration stops when a step gains less than a factor 2.
//!    After Laub's method the CARE steps first reuse the ordered Schur form of the Hamiltonian
//!    (`A − BK = U₁T₁₁U₁⁻¹`, so no Schur decomposition of `A − BK` is needed), and after the
//!    doubling method they are solved by the Smith iteration under the doubling's own Cayley
//!    shift (matrix products only, see `smith.rs`); when such a step does not lower the
//!    residual or gains less than a factor 2, the exact step follows.
//! 6. The closed-loop poles are computed and judged once, for every method, by the boundary
//!    verdict of `boundary.rs`: a pole on or beyond the stability boundary fails, and so does
//!    a pole nearer to it than the reach `ρ(λ) = κ(λ)·η·(‖L‖_F + |λ|‖M‖_F)` of the
//!    solution's backward error `η` (its relative residual), `κ(λ)` the eigenvalue condition
//!    number of the Hamiltonian matrix `L = H`, `M = I` (symplectic pencil `L − zM`) — the
//!    computed `X` is exact for data perturbed by `η`, which can move that eigenvalue by
//!    `ρ(λ)`, so it might lie on the boundary ([`LtiError::BoundaryEigenvalue`], naming the
//!    poles and their mirror images); a distance below [`BOUNDARY_ROUNDING`]`·ε·‖L‖_F` always
//!    fails. Only poles within [`BOUNDARY_SCREEN`] of the boundary
//!    are judged this way (at most [`BOUNDARY_MAX_TESTED`]). The relative residual is
//!    required to be below [`RESIDUAL_LIMIT`].
//!
//! A Hamiltonian (symplectic) eigenvalue of multiplicity two exactly on the stability
//! boundary is split by rounding into a pair at distance `O(sqrt(ε))` on either side of it;
//! its eigenvalue condition number is then `O(1/sqrt(ε))` and the verdict rejects it (CAREX
//! 2.5 at `ε = 0`: poles `−3·10⁻⁸ ± j`, `d/ρ ≈ 0.1–0.7`). A genuine near-boundary pole with a
//! well-conditioned eigenvalue passes however near it is: the `−5·10⁻¹³ ± j` poles of
//! CAREX 2.8 (`d/ρ ≈ 190`), the `1 − 2·10⁻⁸` pole of DAREX 2.5 (`d/ρ ≈ 2·10⁸`), the
//! `−10⁻⁶ ± j` poles of CAREX 2.5 at `ε = 10⁻⁶` (`d/ρ ≈ 970`).
//!
//! Fail fast: above [`FAIL_FAST_MIN_STATES`] states, a stable-subspace basis `U₁` that is
//! singular to working precision ends the solve with [`LtiError::IllConditioned`] and its
//! estimated condition number, without trying the other methods or the diagnosis.
//!
//! [`RiccatiMethod::Auto`] tries its methods in order and returns the first accepted solution
//! whose residual is at most [`GOOD_RESIDUAL`], otherwise the most accurate accepted one. When
//! all fail, the data are diagnosed (PBH tests on the unstable and boundary modes) so that the
//! error names the cause: [`LtiError::NotStabilizable`], [`LtiError::NotDetectable`] or
//! [`LtiError::BoundaryEigenvalue`]. For the CARE, `Auto` first makes one bounded doubling
//! attempt accepted only under strict rules (relative residual `≤ 100·n·ε` after refinement,
//! Hurwitz closed loop, `X ⪰ 0` for LQR data); see [`care`].

mod boundary;
mod care;
mod compact;
mod dare;
mod data;
mod finish;
mod residual;
mod small;
mod smith;
mod subspace;

pub use boundary::{BOUNDARY_MAX_TESTED, BOUNDARY_ROUNDING, BOUNDARY_SCREEN};
pub use care::care;
pub use compact::{COMPACT_MAX, CompactCare, care_compact, care_compact_from};
pub use dare::dare;
pub use residual::{care_residual, dare_residual};

pub(crate) use data::{Reduced, reduce, scale_factor, validate};
pub(crate) use finish::{Finisher, empty_solution, solve_with_fallback, solve_with_fallback_prior};
pub(crate) use subspace::{
    ClosedLoopSchur, Computed, NewtonHint, solution_and_factor_from_subspace,
    solution_from_subspace,
};

#[cfg(doc)]
use crate::error::LtiError;
use crate::linalg::{Complex64, Mat};

/// The relative residual above which a computed solution is rejected with
/// [`LtiError::Inaccurate`] (after every method and refinement has been tried). A
/// backward-stable method reaches `≈ 1e-15`; even badly conditioned problems (CAREX/DAREX)
/// stay far below this limit, so exceeding it signals a breakdown, not ill conditioning.
pub const RESIDUAL_LIMIT: f64 = 1e-8;

/// Newton refinement stops once the relative residual is at most `REFINEMENT_FLOOR · n · ε`:
/// a backward-stable solution cannot be improved further by a step.
pub const REFINEMENT_FLOOR: f64 = 10.0;

/// A solution from [`RiccatiMethod::Auto`] with a relative residual at most this is returned
/// at once; a larger (but acceptable) residual makes `Auto` try its other methods and return
/// the most accurate solution.
pub const GOOD_RESIDUAL: f64 = 1e-12;

/// Above this many states, a method that finds the stable-subspace basis `U₁` singular to
/// working precision (estimated condition number above `1/(n·ε)`) ends the solve with
/// [`LtiError::IllConditioned`]: no other method and no diagnosis is tried. The diagnosis
/// tests every non-stable mode by a PBH singular value decomposition, `O(n³)` each (0.7 s at
/// `n = 600`, with about `n/2` such modes on random data); below the limit it runs as usual
/// and names the cause.
pub const FAIL_FAST_MIN_STATES: usize = 64;

/// Relative PBH margin below which a mode counts as numerically uncontrollable (unobservable)
/// when a failure is diagnosed (`≈ 100·sqrt(ε)`).
pub const PBH_TOLERANCE: f64 = 1e-6;

/// The algorithm used to compute the stabilising solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RiccatiMethod {
    /// Choose automatically: for the CARE the Schur method, then the doubling method; for the
    /// DARE the doubling method, then the Schur method. The first accepted result with a
    /// residual at most [`GOOD_RESIDUAL`] is returned, otherwise the most accurate accepted one.
    ///
    /// Every CARE first tries the doubling method under strict acceptance — a relative
    /// residual at most `100·n·ε` after refinement, a Hurwitz closed loop and (for `Q̃ ⪰ 0`)
    /// `X ⪰ 0`; such a result reports [`RiccatiMethod::Doubling`]. Small CAREs (`n ≤ 8`
    /// states, `m ≤ n` inputs) use fixed-size, stack-allocated matrices; larger ones the
    /// general doubling code with a bound of 11 doubling steps, so that a slowly converging
    /// attempt is abandoned early. When the attempt declines, the general path above runs
    /// (see [`care`]).
    #[default]
    Auto,
    /// Ordered real Schur form of the Hamiltonian matrix (CARE) or of the symplectic matrix
    /// (DARE, requires `A − B R⁻¹ Nᵀ` invertible), Laub's method.
    Schur,
    /// Structure-preserving doubling (SDA; Chu, Fan, Lin, Wang 2004 for the DARE and, after a
    /// Cayley transform, Chu, Fan, Lin 2005 for the CARE): quadratically convergent iteration
    /// on `n × n` matrices, refined by Newton's method. Requires `R ≻ 0`.
    Doubling,
}

/// Options for [`care`] and [`dare`], with documented defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RiccatiOptions {
    /// Algorithm (default [`RiccatiMethod::Auto`]).
    pub method: RiccatiMethod,
    /// Scale the data before solving (default `true`); the solution is returned unscaled.
    pub scaling: bool,
    /// Maximum number of Newton (Kleinman / Hewer) refinement steps applied to the computed
    /// solution (default 8). A step is kept only if it lowers the relative residual; no step
    /// is attempted when the residual is already at rounding level
    /// (`≤ REFINEMENT_FLOOR · n · ε`), and the refinement stops when a step gains less than a
    /// factor 2 (Newton converges quadratically near the solution, so a well-conditioned
    /// problem needs at most one step).
    pub max_refinement_steps: usize,
}

impl Default for RiccatiOptions {
    fn default() -> Self {
        Self {
            method: RiccatiMethod::Auto,
            scaling: true,
            max_refinement_steps: 8,
        }
    }
}

/// Stabilising solution of an algebraic Riccati equation, with diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct RiccatiSolution {
    /// The stabilising solution `X` (symmetric).
    pub x: Mat,
    /// The optimal gain `K` (the control law is `u = −K x`).
    pub gain: Mat,
    /// Eigenvalues of `A − B K`, sorted as [`sort_eigenvalues`](crate::linalg::sort_eigenvalues).
    pub closed_loop_poles: Vec<Complex64>,
    /// Relative residual of the equation at `X`.
    pub residual: f64,
    /// The algorithm that produced `X`.
    pub method: RiccatiMethod,
    /// Newton refinement steps applied.
    pub refinement_steps: usize,
}

/// Time domain of a Riccati problem, for the shared diagnostics.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Domain {
    Continuous,
    Discrete,
}

impl Domain {
    /// Distance of `λ` from the stability boundary, positive inside the stable region.
    pub(crate) fn stability_margin(self, l: Complex64) -> f64 {
        match self {
            Domain::Continuous => -l.re,
            Domain::Discrete => 1.0 - l.norm(),
        }
    }
}

#[cfg(test)]
mod tests;
