//! Constrained linear model predictive control: the condensed MPC of a sampled linear model
//! with box limits on the inputs, on chosen states (a track) and on the input's rate, solved
//! each sample by a warm-started dual active-set QP method.
//!
//! # The problem
//!
//! On the discrete model `x_{k+1} = A x_k + B u_k` (the plant's linearisation sampled by ZOH at
//! the prediction step `dt`), from the measured state `x₀` and the previously applied input
//! `u₋₁`, [`LinearMpc`] minimises over `U = [u₀; …; u_{N−1}]`
//!
//! ```text
//! J = Σ_{k=0}^{N−1} (x_kᵀ Q x_k + u_kᵀ R u_k) + x_Nᵀ P x_N
//! s.t. u_min ≤ u_k ≤ u_max                     (k = 0 … N−1, inputs)
//!      |u_k − u_{k−1}| ≤ Δu_max                (k = 0 … N−1, optional; u_{−1} = u₋₁)
//!      x_min,i ≤ x_{k,i} ≤ x_max,i             (k = 1 … N, the chosen states i)
//! ```
//!
//! with `P` the stabilising DARE solution by default ([`Terminal::Dare`]), so that without
//! active constraints the first move is the infinite-horizon LQ law `u₀ = −K x₀`,
//! `K = (R + BᵀPB)⁻¹BᵀPA`. Eliminating the states (`X = Φ x₀ + Γ U`, "condensing") leaves the
//! dense QP
//!
//! ```text
//! minimise ½ Uᵀ H U + gᵀ U   s.t.   G U ≤ w,
//! H = Γᵀ Q̄ Γ + R̄ (constant),  g = Γᵀ Q̄ Φ x₀,  w = w₀ + W_x x₀ + W_u u₋₁
//! ```
//!
//! (`Q̄ = diag(Q, …, Q, P)`, `R̄ = diag(R, …, R)`; the objective is `(J − const)/2`). Only `g` and
//! `w` change from sample to sample; `H` and `G` are fixed when the controller is built.
//!
//! # The QP method, and why
//!
//! [`DualActiveSetQp`] is the dual active-set method of Goldfarb and Idnani (D. Goldfarb,
//! A. Idnani, "A numerically stable dual method for solving strictly convex quadratic
//! programs", *Math. Programming* 27, 1983) in the least-distance form of DAQP (D. Arnström,
//! A. Bemporad, D. Axehill, "A dual active-set solver for embedded quadratic programming using
//! recursive LDLᵀ updates", *IEEE Trans. Automatic Control* 67(8), 2022). With `H = RᵀR`
//! (Cholesky, once) and `v = R U + R⁻ᵀ g`, the QP is the least-distance problem
//! `min ½‖v‖²  s.t.  M v ≤ d`, `M = G R⁻¹`, `d = w + G H⁻¹ g`. Its dual is worked on an active
//! set `W`: the multipliers solve `(M_W M_Wᵀ) λ = −d_W`, the primal point is `v = −M_Wᵀ λ`,
//! a constraint violated at `v` joins `W`, one whose multiplier would turn negative leaves it
//! (a partial step keeps `λ ≥ 0`), and a joining constraint linearly dependent on `W` moves
//! `λ` along the null-space direction until some other constraint leaves — or, when none
//! can, proves the QP infeasible with a Farkas certificate `y ≥ 0, yᵀG = 0, yᵀw < 0`.
//!
//! The choice suits a 1 kHz loop on a small dense QP (`N·n_u` unknowns, a few times as many
//! constraints):
//! - everything that depends only on `H` and `G` is computed once: the Cholesky factor, `H⁻¹Gᵀ`
//!   and the Gram matrix `M Mᵀ = G H⁻¹ Gᵀ` of all constraint rows (rows scaled to unit norm in
//!   `M`). An iteration then costs one pass over `|W|` columns of the Gram matrix (the
//!   constraint values of every row) and one row appended to the Cholesky factor of
//!   `M_W M_Wᵀ` (`O(|W|²)`); a removal refactors the at most `N·n_u` active rows;
//! - it is *exact*: the answer is the QP's solution to rounding (KKT residuals near machine
//!   precision), not an approximate one as first-order methods (ADMM) give, so it can be
//!   compared with an interior-point solver to 10⁻⁶ and beyond;
//! - it warm-starts naturally: the active set of the previous sample, shifted by one stage
//!   ([`WarmStart::Shifted`]), is the first working set, so a sample whose active set did not
//!   change costs one factorisation and one check; an interior-point method cannot reuse its
//!   previous iterate that well (it must stay inside the cone), which is why Clarabel is the
//!   cross-check here, not the solver in the loop.
//!
//! # Units and sizes
//!
//! States and inputs in the model's units (for the book rigs: m or rad, rad, m/s or rad/s,
//! rad/s; volts). `dt` in seconds. Rows of `G U ≤ w` are grouped by stage: stage `s` holds the
//! input rows of `u_s`, the rate rows of `u_s − u_{s−1}` and the state rows of `x_{s+1}`, in
//! that order, each stage alike; [`LinearMpc::rows_per_stage`] gives the count.

mod condensed;
mod controller;
mod qp;
mod settings;

pub use condensed::LinearMpc;
pub use controller::{MpcController, MpcStatistics};
pub use qp::{DualActiveSetQp, KktResiduals, QpOptions, QpStatus, kkt_residuals};
pub use settings::{MpcSettings, StateBound, Terminal, WarmStart};
