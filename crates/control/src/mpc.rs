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

use crate::error::{ControlError, Result, check_matrix, check_param, check_vector};
use pendulab_lti::equations::{RiccatiOptions, dare};
use pendulab_lti::{Continuous, Discretization, Mat, StateSpace};
use pendulab_sim::Controller;

/// Options of [`DualActiveSetQp`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QpOptions {
    /// Largest constraint violation accepted at the answer, measured on rows scaled to unit
    /// norm in the metric of `H` (the distance `‖R(U − U_feasible)‖` to the row's boundary);
    /// default `1e-9`.
    pub tolerance: f64,
    /// Most active-set changes per solve; `0` means `4·(n + m)` (default 0).
    pub max_iterations: usize,
}

impl Default for QpOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-9,
            max_iterations: 0,
        }
    }
}

/// Outcome of one QP solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QpStatus {
    /// Optimal: primal feasible within the tolerance, multipliers `≥ 0`, complementary.
    Solved,
    /// The constraints admit no point; [`DualActiveSetQp::certificate`] holds `y ≥ 0` with
    /// `yᵀG = 0` and `yᵀw < 0`.
    Infeasible,
    /// The iteration limit was reached; the last iterate is not optimal.
    MaxIterations,
}

/// The KKT residuals of a QP answer `(U, λ)` for `minimise ½UᵀHU + gᵀU s.t. GU ≤ w`, each the
/// largest absolute entry ([`kkt_residuals`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KktResiduals {
    /// `‖HU + g + Gᵀλ‖_∞`.
    pub stationarity: f64,
    /// `max(0, max_i (GU − w)_i)`.
    pub primal: f64,
    /// `max(0, max_i −λ_i)`.
    pub dual: f64,
    /// `max_i |λ_i (GU − w)_i|`.
    pub complementarity: f64,
}

/// The KKT residuals of `(u, lambda)` for `minimise ½uᵀHu + gᵀu s.t. Gu ≤ w`, computed from the
/// problem data directly (nothing of the solver's factorisations).
///
/// # Errors
/// [`ControlError::ShapeMismatch`]/[`ControlError::DimensionMismatch`] for inconsistent sizes.
pub fn kkt_residuals(
    h: &Mat,
    g: &[f64],
    a: &Mat,
    w: &[f64],
    u: &[f64],
    lambda: &[f64],
) -> Result<KktResiduals> {
    let n = h.nrows();
    let m = a.nrows();
    if h.shape() != (n, n) || a.ncols() != n {
        return Err(ControlError::ShapeMismatch {
            what: "kkt_residuals: G".into(),
            expected: (m, n),
            found: a.shape(),
        });
    }
    for (what, v, len) in [("g", g, n), ("w", w, m), ("u", u, n), ("lambda", lambda, m)] {
        if v.len() != len {
            return Err(ControlError::DimensionMismatch {
                what: format!("kkt_residuals: {what}"),
                expected: len,
                found: v.len(),
            });
        }
    }
    let uv = nalgebra::DVector::from_column_slice(u);
    let lv = nalgebra::DVector::from_column_slice(lambda);
    let stat = h * &uv + nalgebra::DVector::from_column_slice(g) + a.transpose() * &lv;
    let slack = a * &uv - nalgebra::DVector::from_column_slice(w);
    Ok(KktResiduals {
        stationarity: stat.amax(),
        primal: slack.iter().fold(0.0f64, |m, &s| m.max(s)),
        dual: lambda.iter().fold(0.0f64, |m, &l| m.max(-l)),
        complementarity: slack
            .iter()
            .zip(lambda)
            .fold(0.0f64, |m, (s, l)| m.max((s * l).abs())),
    })
}

/// The dual active-set QP method (module documentation) for `minimise ½UᵀHU + gᵀU s.t.
/// GU ≤ w` with `H ≻ 0` and `G` fixed at construction and `g`, `w` given per solve.
/// Allocation-free after construction.
#[derive(Debug, Clone)]
pub struct DualActiveSetQp {
    n: usize,
    m: usize,
    options: QpOptions,
    /// Upper Cholesky factor `R` of `H` (row-major `n × n`).
    chol: Vec<f64>,
    /// `G` (row-major `m × n`), as given.
    a: Vec<f64>,
    /// `H⁻¹ Gᵀ` scaled by row: column `i` is `H⁻¹ G_iᵀ s_i` (column-major `n × m`).
    hinv_at: Vec<f64>,
    /// Gram matrix `M Mᵀ` of the scaled rows (`m × m`, symmetric, unit diagonal).
    gram: Vec<f64>,
    /// Row scales `s_i = 1/‖G_i R⁻¹‖`.
    scale: Vec<f64>,
    // Per-solve workspace.
    d: Vec<f64>,
    hinv_g: Vec<f64>,
    active: Vec<usize>,
    lambda: Vec<f64>,
    lambda_star: Vec<f64>,
    /// Lower Cholesky factor of `M_W M_Wᵀ` (row-major, stride `n`).
    l: Vec<f64>,
    tmp: Vec<f64>,
    tmp2: Vec<f64>,
    scratch_rows: Vec<usize>,
    scratch_lambda: Vec<f64>,
    slack: Vec<f64>,
    in_set: Vec<bool>,
    u: Vec<f64>,
    multipliers: Vec<f64>,
    certificate: Vec<f64>,
    iterations: usize,
    status: Option<QpStatus>,
}

/// Relative pivot below which a joining row counts as linearly dependent on the active rows
/// (the rows of `M` have unit norm, so the pivot is the squared sine of the row's angle to the
/// active rows' span).
const DEPENDENT: f64 = 1e-11;

impl DualActiveSetQp {
    /// Prepares the method for the Hessian `h` (`n × n`, symmetric positive definite) and the
    /// constraint matrix `a` (`m × n`, no zero row).
    ///
    /// # Errors
    /// [`ControlError::ShapeMismatch`] / [`ControlError::NonFinite`] for bad data;
    /// [`ControlError::Singular`] if `h` is not positive definite (`what = "QP Hessian H"`) or a
    /// row of `a` is zero (`what = "constraint row i"`); [`ControlError::InvalidParameter`] for
    /// options out of range.
    pub fn new(h: &Mat, a: &Mat, options: QpOptions) -> Result<Self> {
        let n = h.nrows();
        check_matrix("QP Hessian H", h, n, n)?;
        let m = a.nrows();
        check_matrix("QP constraint matrix G", a, m, n)?;
        check_param(
            "QpOptions::tolerance",
            options.tolerance,
            options.tolerance > 0.0,
            "must be finite and > 0",
        )?;
        let hs = (h + h.transpose()) * 0.5;
        let chol = hs.clone().cholesky().ok_or(ControlError::Singular {
            what: "QP Hessian H (not positive definite)".into(),
            value: 0.0,
        })?;
        let lower = chol.l();
        // M = G R⁻¹ with R = Lᵀ: Mᵀ = L⁻¹ Gᵀ.
        let mt = lower
            .solve_lower_triangular(&a.transpose())
            .ok_or(ControlError::Singular {
                what: "QP Hessian H".into(),
                value: 0.0,
            })?;
        let mut scale = vec![0.0; m];
        for i in 0..m {
            let norm = mt.column(i).norm();
            if !(norm > 0.0 && norm.is_finite()) {
                return Err(ControlError::Singular {
                    what: format!("constraint row {i} (zero)"),
                    value: norm,
                });
            }
            scale[i] = 1.0 / norm;
        }
        let mut mts = mt.clone();
        for i in 0..m {
            mts.column_mut(i).scale_mut(scale[i]);
        }
        let gram_m = mts.transpose() * &mts;
        let hinv_at_m = chol.solve(&a.transpose());
        let mut hinv_at = vec![0.0; n * m];
        for i in 0..m {
            for r in 0..n {
                hinv_at[i * n + r] = hinv_at_m[(r, i)] * scale[i];
            }
        }
        let upper = lower.transpose();
        let mut chol_rm = vec![0.0; n * n];
        let mut a_rm = vec![0.0; m * n];
        for r in 0..n {
            for c in 0..n {
                chol_rm[r * n + c] = upper[(r, c)];
            }
        }
        for r in 0..m {
            for c in 0..n {
                a_rm[r * n + c] = a[(r, c)];
            }
        }
        let mut gram = vec![0.0; m * m];
        for j in 0..m {
            for i in 0..m {
                gram[j * m + i] = gram_m[(i, j)];
            }
        }
        Ok(Self {
            n,
            m,
            options,
            chol: chol_rm,
            a: a_rm,
            hinv_at,
            gram,
            scale,
            d: vec![0.0; m],
            hinv_g: vec![0.0; n],
            active: Vec::with_capacity(n + 1),
            lambda: Vec::with_capacity(n + 1),
            lambda_star: vec![0.0; n + 1],
            l: vec![0.0; (n + 1) * (n + 1)],
            tmp: vec![0.0; n + 1],
            tmp2: vec![0.0; n + 1],
            scratch_rows: Vec::with_capacity(n + 1),
            scratch_lambda: Vec::with_capacity(n + 1),
            slack: vec![0.0; m],
            in_set: vec![false; m],
            u: vec![0.0; n],
            multipliers: vec![0.0; m],
            certificate: vec![0.0; m],
            iterations: 0,
            status: None,
        })
    }

    /// Number of unknowns `n`.
    pub fn num_variables(&self) -> usize {
        self.n
    }

    /// Number of constraint rows `m`.
    pub fn num_constraints(&self) -> usize {
        self.m
    }

    /// Solves `minimise ½UᵀHU + gᵀU s.t. GU ≤ w`, starting from the working set `warm_start`
    /// (row indices; out-of-range, repeated and linearly dependent rows are skipped; the
    /// multipliers start at 0). Allocation-free.
    ///
    /// # Errors
    /// [`ControlError::DimensionMismatch`]/[`ControlError::NonFinite`] for `g` (length `n`) or
    /// `w` (length `m`). An infeasible QP is a status ([`QpStatus::Infeasible`]), not an error.
    pub fn solve(&mut self, g: &[f64], w: &[f64], warm_start: &[usize]) -> Result<QpStatus> {
        check_vector("QP gradient g", g, self.n)?;
        check_vector("QP bounds w", w, self.m)?;
        Ok(self.solve_unchecked(g, w, warm_start))
    }

    fn solve_unchecked(&mut self, g: &[f64], w: &[f64], warm_start: &[usize]) -> QpStatus {
        let (n, m) = (self.n, self.m);
        // H⁻¹ g by the two triangular solves with R (row-major upper).
        self.hinv_g.copy_from_slice(g);
        solve_upper_transposed(&self.chol, n, &mut self.hinv_g);
        solve_upper(&self.chol, n, &mut self.hinv_g);
        // d_i = s_i (w_i + G_i H⁻¹ g).
        for i in 0..m {
            let row = &self.a[i * n..(i + 1) * n];
            let dot: f64 = row.iter().zip(&self.hinv_g).map(|(x, y)| x * y).sum();
            self.d[i] = self.scale[i] * (w[i] + dot);
        }
        self.active.clear();
        self.lambda.clear();
        self.in_set.iter_mut().for_each(|x| *x = false);
        for &j in warm_start {
            if j < m && !self.in_set[j] && self.active.len() < n && self.append(j) {
                self.lambda.push(0.0);
            }
        }
        let max_iter = if self.options.max_iterations == 0 {
            4 * (n + m)
        } else {
            self.options.max_iterations
        };
        let tol = self.options.tolerance;
        self.iterations = 0;
        let status = loop {
            if self.iterations >= max_iter {
                break QpStatus::MaxIterations;
            }
            self.iterations += 1;
            let k = self.active.len();
            // λ* on the working set.
            for (i, &j) in self.active.iter().enumerate() {
                self.lambda_star[i] = -self.d[j];
            }
            chol_solve(&self.l, n + 1, k, &mut self.lambda_star[..k]);
            if self.lambda_star[..k].iter().all(|&x| x >= 0.0) {
                self.lambda.copy_from_slice(&self.lambda_star[..k]);
                // Constraint values (M v − d) with v = −M_Wᵀ λ.
                for (s, d) in self.slack.iter_mut().zip(&self.d) {
                    *s = -d;
                }
                for (i, &j) in self.active.iter().enumerate() {
                    let li = self.lambda[i];
                    let col = &self.gram[j * m..(j + 1) * m];
                    for (s, gij) in self.slack.iter_mut().zip(col) {
                        *s -= gij * li;
                    }
                }
                let mut worst = None;
                let mut worst_val = tol;
                for (j, &s) in self.slack.iter().enumerate() {
                    if !self.in_set[j] && s > worst_val {
                        worst_val = s;
                        worst = Some(j);
                    }
                }
                let Some(j) = worst else {
                    break QpStatus::Solved;
                };
                if self.active.len() < n && self.append(j) {
                    self.lambda.push(0.0);
                    continue;
                }
                // j depends on the active rows: M_j = Σ c_i M_{W_i}, c = (M_W M_Wᵀ)⁻¹ M_W M_jᵀ.
                let k = self.active.len();
                for (i, &r) in self.active.iter().enumerate() {
                    self.tmp[i] = self.gram[j * m + r];
                }
                chol_solve(&self.l, n + 1, k, &mut self.tmp[..k]);
                let mut block = None;
                let mut t_min = f64::INFINITY;
                for i in 0..k {
                    let c = self.tmp[i];
                    if c > 1e-12 {
                        let t = self.lambda[i] / c;
                        if t < t_min {
                            t_min = t;
                            block = Some(i);
                        }
                    }
                }
                let Some(p) = block else {
                    // Farkas: y_W = −c (≥ 0 as no c_i > 0), y_j = 1.
                    self.certificate.iter_mut().for_each(|x| *x = 0.0);
                    for (i, &r) in self.active.iter().enumerate() {
                        self.certificate[r] = (-self.tmp[i]).max(0.0) * self.scale[r];
                    }
                    self.certificate[j] = self.scale[j];
                    break QpStatus::Infeasible;
                };
                for i in 0..k {
                    self.lambda[i] = (self.lambda[i] - t_min * self.tmp[i]).max(0.0);
                }
                self.remove(p);
                if self.append(j) {
                    self.lambda.push(t_min);
                }
                // (If j still depends on the rest, the next pass adds it again and steps on.)
            } else {
                // Partial step towards λ*, dropping the first multiplier to reach 0.
                let mut block = 0;
                let mut alpha = f64::INFINITY;
                for i in 0..k {
                    let ls = self.lambda_star[i];
                    if ls < 0.0 {
                        let li = self.lambda[i];
                        let a = li / (li - ls);
                        if a < alpha {
                            alpha = a;
                            block = i;
                        }
                    }
                }
                for i in 0..k {
                    self.lambda[i] += alpha * (self.lambda_star[i] - self.lambda[i]);
                }
                self.remove(block);
            }
        };
        // U = −H⁻¹ g − Σ (H⁻¹ G_iᵀ s_i) λ_i; multipliers of G U ≤ w are s_i λ_i.
        for (u, hg) in self.u.iter_mut().zip(&self.hinv_g) {
            *u = -hg;
        }
        self.multipliers.iter_mut().for_each(|x| *x = 0.0);
        for (i, &j) in self.active.iter().enumerate() {
            let li = self.lambda[i];
            let col = &self.hinv_at[j * n..(j + 1) * n];
            for (u, c) in self.u.iter_mut().zip(col) {
                *u -= c * li;
            }
            self.multipliers[j] = li * self.scale[j];
        }
        self.status = Some(status);
        status
    }

    /// Appends row `j` to the working set's Cholesky factor; `false` (and nothing changed) if
    /// it depends on the rows already there.
    fn append(&mut self, j: usize) -> bool {
        let (m, stride) = (self.m, self.n + 1);
        let k = self.active.len();
        for (i, &r) in self.active.iter().enumerate() {
            let mut s = self.gram[j * m + r];
            for c in 0..i {
                s -= self.l[i * stride + c] * self.tmp2[c];
            }
            self.tmp2[i] = s / self.l[i * stride + i];
        }
        let norm2: f64 = self.tmp2[..k].iter().map(|x| x * x).sum();
        let pivot = self.gram[j * m + j] - norm2;
        if pivot <= DEPENDENT {
            return false;
        }
        for c in 0..k {
            self.l[k * stride + c] = self.tmp2[c];
        }
        self.l[k * stride + k] = pivot.sqrt();
        self.active.push(j);
        self.in_set[j] = true;
        true
    }

    /// Removes the `p`-th working row: the factor's rows before it stay, the rows after it are
    /// appended again.
    fn remove(&mut self, p: usize) {
        self.in_set[self.active[p]] = false;
        self.scratch_rows.clear();
        self.scratch_rows.extend_from_slice(&self.active[p + 1..]);
        self.scratch_lambda.clear();
        self.scratch_lambda.extend_from_slice(&self.lambda[p + 1..]);
        for &r in &self.active[p + 1..] {
            self.in_set[r] = false;
        }
        self.active.truncate(p);
        self.lambda.truncate(p);
        for i in 0..self.scratch_rows.len() {
            let r = self.scratch_rows[i];
            if self.append(r) {
                self.lambda.push(self.scratch_lambda[i]);
            }
        }
    }

    /// The answer `U` of the last solve (length `n`).
    pub fn solution(&self) -> &[f64] {
        &self.u
    }

    /// The multipliers `λ ≥ 0` of `GU ≤ w` at the last answer (length `m`, zero off the active
    /// set).
    pub fn multipliers(&self) -> &[f64] {
        &self.multipliers
    }

    /// Rows in the final working set of the last solve (the active constraints).
    pub fn active_set(&self) -> &[usize] {
        &self.active
    }

    /// Active-set iterations of the last solve.
    pub fn iterations(&self) -> usize {
        self.iterations
    }

    /// Status of the last solve (`None` before the first).
    pub fn status(&self) -> Option<QpStatus> {
        self.status
    }

    /// After [`QpStatus::Infeasible`]: `y ≥ 0` (length `m`) with `yᵀG = 0` and `yᵀw < 0`, the
    /// proof that `GU ≤ w` has no solution; `None` otherwise.
    pub fn certificate(&self) -> Option<&[f64]> {
        (self.status == Some(QpStatus::Infeasible)).then_some(&self.certificate[..])
    }
}

/// Solves `Rᵀ x = b` in place (`R` row-major upper `n × n`).
fn solve_upper_transposed(r: &[f64], n: usize, x: &mut [f64]) {
    for i in 0..n {
        let mut s = x[i];
        for k in 0..i {
            s -= r[k * n + i] * x[k];
        }
        x[i] = s / r[i * n + i];
    }
}

/// Solves `R x = b` in place (`R` row-major upper `n × n`).
fn solve_upper(r: &[f64], n: usize, x: &mut [f64]) {
    for i in (0..n).rev() {
        let mut s = x[i];
        for k in i + 1..n {
            s -= r[i * n + k] * x[k];
        }
        x[i] = s / r[i * n + i];
    }
}

/// Solves `L Lᵀ x = b` in place for the leading `k × k` block of `l` (row-major lower,
/// row stride `stride`).
fn chol_solve(l: &[f64], stride: usize, k: usize, x: &mut [f64]) {
    for i in 0..k {
        let mut s = x[i];
        for c in 0..i {
            s -= l[i * stride + c] * x[c];
        }
        x[i] = s / l[i * stride + i];
    }
    for i in (0..k).rev() {
        let mut s = x[i];
        for r in i + 1..k {
            s -= l[r * stride + i] * x[r];
        }
        x[i] = s / l[i * stride + i];
    }
}

/// The terminal weight `P` of the MPC cost.
#[derive(Debug, Clone, PartialEq)]
pub enum Terminal {
    /// The stabilising solution of the DARE of `(A, B, Q, R)` (default): the unconstrained MPC
    /// law is then the infinite-horizon LQ law.
    Dare,
    /// A given symmetric positive semidefinite `n_x × n_x` weight.
    Weight(Mat),
}

/// Bounds `min ≤ x_{k,index} ≤ max` on one state over the predicted states `k = 1 … N`
/// (infinite for none on a side).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StateBound {
    /// The state's index (0-based).
    pub index: usize,
    /// Lower bound (state's unit; `−∞` for none).
    pub min: f64,
    /// Upper bound (`+∞` for none).
    pub max: f64,
}

/// The MPC problem's settings (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct MpcSettings {
    /// Horizon `N` in prediction steps (1 to 1000).
    pub horizon: usize,
    /// State weight `Q` (`n_x × n_x`, symmetric).
    pub q: Mat,
    /// Input weight `R` (`n_u × n_u`, symmetric positive definite).
    pub r: Mat,
    /// Terminal weight.
    pub terminal: Terminal,
    /// Lower input bounds (`n_u` entries; `−∞` for none).
    pub u_min: Vec<f64>,
    /// Upper input bounds (`n_u` entries; `+∞` for none).
    pub u_max: Vec<f64>,
    /// Largest change of each input per prediction step, `|u_k − u_{k−1}| ≤ Δu_max`
    /// (`n_u` entries > 0, `+∞` for none), or `None`.
    pub du_max: Option<Vec<f64>>,
    /// State bounds over the predicted states.
    pub state_bounds: Vec<StateBound>,
    /// Options of the QP method.
    pub qp: QpOptions,
}

/// Which working set a solve starts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WarmStart {
    /// The empty set (the unconstrained optimum first).
    Cold,
    /// The last solve's active set as it is.
    Same,
    /// The last solve's active set moved one stage earlier (the stage-0 rows dropped): the
    /// receding horizon's guess one prediction step later.
    Shifted,
}

/// The condensed MPC of a discrete model (module documentation): its QP data and the QP
/// method, reused across samples.
#[derive(Debug, Clone)]
pub struct LinearMpc {
    nx: usize,
    nu: usize,
    horizon: usize,
    h: Mat,
    /// `g = F x₀`.
    f: Mat,
    /// Constraint matrix `G`.
    a: Mat,
    w0: Vec<f64>,
    /// `W_x` (`m × n_x`, row-major).
    wx: Vec<f64>,
    /// `W_u` (`m × n_u`, row-major).
    wu: Vec<f64>,
    rows_per_stage: usize,
    terminal: Mat,
    lq_gain: Mat,
    qp: DualActiveSetQp,
    g: Vec<f64>,
    w: Vec<f64>,
    warm: Vec<usize>,
}

impl LinearMpc {
    /// Builds the condensed problem of `x_{k+1} = A x_k + B u_k` (`a_d`: `n_x × n_x`, `b_d`:
    /// `n_x × n_u`) with `settings`.
    ///
    /// # Errors
    /// [`ControlError::ShapeMismatch`]/[`ControlError::DimensionMismatch`]/
    /// [`ControlError::NonFinite`] for data of the wrong size or NaN;
    /// [`ControlError::InvalidParameter`] naming `horizon`, `u_min`/`u_max` (`min > max`),
    /// `du_max` (not > 0), `state_bounds[i]` (index out of range, `min > max`);
    /// [`ControlError::Lti`] if the DARE has no stabilising solution; [`ControlError::Singular`]
    /// if `R` is not positive definite.
    pub fn new(a_d: &Mat, b_d: &Mat, settings: &MpcSettings) -> Result<Self> {
        let nx = a_d.nrows();
        check_matrix("MPC model A", a_d, nx, nx)?;
        let nu = b_d.ncols();
        check_matrix("MPC model B", b_d, nx, nu)?;
        check_matrix("MPC weight Q", &settings.q, nx, nx)?;
        check_matrix("MPC weight R", &settings.r, nu, nu)?;
        let n_h = settings.horizon;
        if !(1..=1000).contains(&n_h) {
            return Err(ControlError::InvalidParameter {
                name: "horizon".into(),
                value: n_h as f64,
                requirement: "must be 1 to 1000 steps".into(),
            });
        }
        if settings.r.clone().cholesky().is_none() {
            return Err(ControlError::Singular {
                what: "MPC weight R (not positive definite)".into(),
                value: 0.0,
            });
        }
        bounds_pair("u_min", "u_max", &settings.u_min, &settings.u_max, nu)?;
        if let Some(du) = &settings.du_max {
            if du.len() != nu {
                return Err(ControlError::DimensionMismatch {
                    what: "du_max".into(),
                    expected: nu,
                    found: du.len(),
                });
            }
            for &v in du {
                check_param("du_max", v, v > 0.0, "must be > 0 (+∞ for no limit)")?;
            }
        }
        for (i, sb) in settings.state_bounds.iter().enumerate() {
            let name = format!("state_bounds[{i}]");
            if sb.index >= nx {
                return Err(ControlError::InvalidParameter {
                    name: format!("{name}.index"),
                    value: sb.index as f64,
                    requirement: format!("must be below the state count {nx}"),
                });
            }
            bounds_pair(
                &format!("{name}.min"),
                &format!("{name}.max"),
                &[sb.min],
                &[sb.max],
                1,
            )?;
        }
        let terminal = match &settings.terminal {
            Terminal::Dare => {
                dare(
                    a_d,
                    b_d,
                    &settings.q,
                    &settings.r,
                    None,
                    &RiccatiOptions::default(),
                )?
                .x
            }
            Terminal::Weight(p) => {
                check_matrix("MPC terminal weight P", p, nx, nx)?;
                p.clone()
            }
        };
        // Φ (stacked A^k, k = 1…N) and Γ.
        let mut phi = Mat::zeros(n_h * nx, nx);
        let mut gamma = Mat::zeros(n_h * nx, n_h * nu);
        let mut ak = a_d.clone();
        // A^{k} B blocks: powers[k] = A^k B.
        let mut powers = vec![b_d.clone()];
        for k in 1..n_h {
            let next = a_d * &powers[k - 1];
            powers.push(next);
        }
        for k in 0..n_h {
            phi.view_mut((k * nx, 0), (nx, nx)).copy_from(&ak);
            ak = a_d * &ak;
            for j in 0..=k {
                gamma
                    .view_mut((k * nx, j * nu), (nx, nu))
                    .copy_from(&powers[k - j]);
            }
        }
        let mut qbar = Mat::zeros(n_h * nx, n_h * nx);
        for k in 0..n_h {
            let wk = if k + 1 == n_h { &terminal } else { &settings.q };
            qbar.view_mut((k * nx, k * nx), (nx, nx)).copy_from(wk);
        }
        let gt_q = gamma.transpose() * &qbar;
        let mut h = &gt_q * &gamma;
        for k in 0..n_h {
            let mut blk = h.view_mut((k * nu, k * nu), (nu, nu));
            blk += &settings.r;
        }
        let h = (&h + h.transpose()) * 0.5;
        let f = &gt_q * &phi;
        // Constraint rows, stage by stage.
        let mut rows: Vec<Row> = Vec::new();
        let nv = n_h * nu;
        for s in 0..n_h {
            for i in 0..nu {
                for (sign, bound) in [(1.0, settings.u_max[i]), (-1.0, settings.u_min[i])] {
                    if bound.is_finite() {
                        let mut g = vec![0.0; nv];
                        g[s * nu + i] = sign;
                        rows.push((g, sign * bound, vec![0.0; nx], vec![0.0; nu]));
                    }
                }
            }
            if let Some(du) = &settings.du_max {
                for i in 0..nu {
                    if du[i].is_finite() {
                        for sign in [1.0, -1.0] {
                            let mut g = vec![0.0; nv];
                            g[s * nu + i] = sign;
                            let mut wu = vec![0.0; nu];
                            if s > 0 {
                                g[(s - 1) * nu + i] = -sign;
                            } else {
                                wu[i] = sign;
                            }
                            rows.push((g, du[i], vec![0.0; nx], wu));
                        }
                    }
                }
            }
            for sb in &settings.state_bounds {
                let r = s * nx + sb.index;
                for (sign, bound) in [(1.0, sb.max), (-1.0, sb.min)] {
                    if bound.is_finite() {
                        let g: Vec<f64> = (0..nv).map(|c| sign * gamma[(r, c)]).collect();
                        let wx: Vec<f64> = (0..nx).map(|c| -sign * phi[(r, c)]).collect();
                        rows.push((g, sign * bound, wx, vec![0.0; nu]));
                    }
                }
            }
        }
        let m = rows.len();
        let rows_per_stage = m / n_h;
        let mut a = Mat::zeros(m, nv);
        let mut w0 = vec![0.0; m];
        let mut wx = vec![0.0; m * nx];
        let mut wu = vec![0.0; m * nu];
        for (i, (g, b, x, u)) in rows.into_iter().enumerate() {
            for c in 0..nv {
                a[(i, c)] = g[c];
            }
            w0[i] = b;
            wx[i * nx..(i + 1) * nx].copy_from_slice(&x);
            wu[i * nu..(i + 1) * nu].copy_from_slice(&u);
        }
        let qp = DualActiveSetQp::new(&h, &a, settings.qp)?;
        // K = (R + BᵀPB)⁻¹ BᵀPA, the unconstrained law of the terminal cost.
        let btp = b_d.transpose() * &terminal;
        let lq_gain = (&settings.r + &btp * b_d)
            .cholesky()
            .ok_or(ControlError::Singular {
                what: "R + BᵀPB".into(),
                value: 0.0,
            })?
            .solve(&(&btp * a_d));
        Ok(Self {
            nx,
            nu,
            horizon: n_h,
            h,
            f,
            a,
            w0,
            wx,
            wu,
            rows_per_stage,
            terminal,
            lq_gain,
            qp,
            g: vec![0.0; nv],
            w: vec![0.0; m],
            warm: Vec::with_capacity(nv),
        })
    }

    /// [`LinearMpc::new`] on the ZOH sampling of the continuous model `sys` at the prediction
    /// step `dt` \[s\] (only `A` and `B` of `sys` are used).
    ///
    /// # Errors
    /// As [`LinearMpc::new`]; [`ControlError::Lti`] if `dt` is not a positive finite time.
    pub fn sampled(sys: &StateSpace<Continuous>, dt: f64, settings: &MpcSettings) -> Result<Self> {
        let d = sys.c2d(dt, Discretization::Zoh)?;
        Self::new(d.a(), d.b(), settings)
    }

    /// State count `n_x`.
    pub fn nx(&self) -> usize {
        self.nx
    }
    /// Input count `n_u`.
    pub fn nu(&self) -> usize {
        self.nu
    }
    /// Horizon `N`.
    pub fn horizon(&self) -> usize {
        self.horizon
    }
    /// The condensed Hessian `H` (`N n_u × N n_u`).
    pub fn hessian(&self) -> &Mat {
        &self.h
    }
    /// The constraint matrix `G` (`m × N n_u`).
    pub fn constraint_matrix(&self) -> &Mat {
        &self.a
    }
    /// Constraint rows per stage (the rows of stage `s` are `s·rows_per_stage …`).
    pub fn rows_per_stage(&self) -> usize {
        self.rows_per_stage
    }
    /// The terminal weight `P` in use.
    pub fn terminal_weight(&self) -> &Mat {
        &self.terminal
    }
    /// `K = (R + BᵀPB)⁻¹BᵀPA` (`n_u × n_x`): the first move `u₀ = −K x₀` when no constraint is
    /// active (with [`Terminal::Dare`], the discrete LQR gain).
    pub fn lq_gain(&self) -> &Mat {
        &self.lq_gain
    }

    /// The QP's varying data at `x0` (length `n_x`) and `u_prev` (`n_u`): `g` (length
    /// `N n_u`) and `w` (length `m`), written into the slices.
    ///
    /// # Errors
    /// [`ControlError::DimensionMismatch`] for slices of the wrong length.
    pub fn qp_vectors(
        &self,
        x0: &[f64],
        u_prev: &[f64],
        g: &mut [f64],
        w: &mut [f64],
    ) -> Result<()> {
        check_vector("x0", x0, self.nx)?;
        check_vector("u_prev", u_prev, self.nu)?;
        if g.len() != self.g.len() || w.len() != self.w.len() {
            return Err(ControlError::DimensionMismatch {
                what: "qp_vectors: g, w".into(),
                expected: self.g.len() + self.w.len(),
                found: g.len() + w.len(),
            });
        }
        fill(
            &self.f,
            &self.w0,
            &self.wx,
            &self.wu,
            (self.nx, self.nu),
            x0,
            u_prev,
            g,
            w,
        );
        Ok(())
    }

    /// Solves the QP at `x0` and `u_prev` starting from `warm`; the plan is
    /// [`LinearMpc::plan`], the first move its first `n_u` entries. Allocation-free.
    ///
    /// # Errors
    /// [`ControlError::DimensionMismatch`]/[`ControlError::NonFinite`] for `x0` (`n_x`) or
    /// `u_prev` (`n_u`). Infeasibility is the status [`QpStatus::Infeasible`].
    pub fn solve(&mut self, x0: &[f64], u_prev: &[f64], warm: WarmStart) -> Result<QpStatus> {
        check_vector("x0", x0, self.nx)?;
        check_vector("u_prev", u_prev, self.nu)?;
        fill(
            &self.f,
            &self.w0,
            &self.wx,
            &self.wu,
            (self.nx, self.nu),
            x0,
            u_prev,
            &mut self.g,
            &mut self.w,
        );
        self.warm.clear();
        match warm {
            WarmStart::Cold => {}
            WarmStart::Same => self.warm.extend_from_slice(self.qp.active_set()),
            WarmStart::Shifted => {
                let rps = self.rows_per_stage;
                self.warm.extend(
                    self.qp
                        .active_set()
                        .iter()
                        .filter(|&&r| r >= rps)
                        .map(|&r| r - rps),
                );
            }
        }
        Ok(self.qp.solve_unchecked(&self.g, &self.w, &self.warm))
    }

    /// The plan `U = [u₀; …; u_{N−1}]` of the last solve.
    pub fn plan(&self) -> &[f64] {
        self.qp.solution()
    }

    /// The QP method (its multipliers, active set, iterations, certificate).
    pub fn qp(&self) -> &DualActiveSetQp {
        &self.qp
    }

    /// `g` and `w` of the last solve.
    pub fn last_qp_vectors(&self) -> (&[f64], &[f64]) {
        (&self.g, &self.w)
    }
}

/// One constraint row while the MPC is built: `G_i`, `w₀,i`, `W_x,i`, `W_u,i`.
type Row = (Vec<f64>, f64, Vec<f64>, Vec<f64>);

/// `g = F x₀`, `w = w₀ + W_x x₀ + W_u u₋₁`.
#[allow(clippy::too_many_arguments)]
fn fill(
    f: &Mat,
    w0: &[f64],
    wx: &[f64],
    wu: &[f64],
    (nx, nu): (usize, usize),
    x0: &[f64],
    u_prev: &[f64],
    g: &mut [f64],
    w: &mut [f64],
) {
    for (i, gi) in g.iter_mut().enumerate() {
        *gi = (0..nx).map(|c| f[(i, c)] * x0[c]).sum();
    }
    for (i, wi) in w.iter_mut().enumerate() {
        let sx: f64 = wx[i * nx..(i + 1) * nx]
            .iter()
            .zip(x0)
            .map(|(a, b)| a * b)
            .sum();
        let su: f64 = wu[i * nu..(i + 1) * nu]
            .iter()
            .zip(u_prev)
            .map(|(a, b)| a * b)
            .sum();
        *wi = w0[i] + sx + su;
    }
}

fn bounds_pair(lo_name: &str, hi_name: &str, lo: &[f64], hi: &[f64], n: usize) -> Result<()> {
    for (name, v) in [(lo_name, lo), (hi_name, hi)] {
        if v.len() != n {
            return Err(ControlError::DimensionMismatch {
                what: name.into(),
                expected: n,
                found: v.len(),
            });
        }
        if let Some((index, &value)) = v.iter().enumerate().find(|(_, x)| x.is_nan()) {
            return Err(ControlError::NonFinite {
                what: name.into(),
                index,
                value,
            });
        }
    }
    for i in 0..n {
        if lo[i] > hi[i] || lo[i] == f64::INFINITY || hi[i] == f64::NEG_INFINITY {
            return Err(ControlError::InvalidParameter {
                name: format!("{lo_name}[{i}]"),
                value: lo[i],
                requirement: format!("must be ≤ {hi_name}[{i}] = {} and below +∞", hi[i]),
            });
        }
    }
    Ok(())
}

/// Counters of an [`MpcController`]'s solves since its last reset.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MpcStatistics {
    /// QPs solved.
    pub solves: u64,
    /// Solves that ended [`QpStatus::Infeasible`] (the fallback law was applied).
    pub infeasible: u64,
    /// Solves that hit the iteration limit (the fallback law was applied).
    pub max_iterations_hit: u64,
    /// Most active-set iterations of one solve.
    pub max_iterations: usize,
    /// Active-set iterations summed over the solves.
    pub total_iterations: u64,
}

/// [`LinearMpc`] as a sampled-data [`Controller`]: it measures the full state `y = x` (a
/// setpoint `x_ref` subtracted), solves one warm-started QP at every loop sample and applies
/// the first move.
///
/// The prediction step `dt` is `periods_per_step` loop periods `ts`: the plan is re-solved every
/// period from the measured state (the first move held for the whole step in the prediction,
/// then replaced one period later), and the working set is shifted one stage every
/// `periods_per_step` samples ([`WarmStart::Shifted`], else [`WarmStart::Same`]). `u₋₁` of the
/// rate limit is the input applied at the previous sample. When a QP ends infeasible or at the
/// iteration limit the controller applies the fallback `u = clamp(−K x, u_min, u_max)` with the
/// terminal cost's LQ gain `K` ([`LinearMpc::lq_gain`]) and counts it
/// ([`MpcStatistics`]).
#[derive(Debug, Clone)]
pub struct MpcController {
    mpc: LinearMpc,
    ts: f64,
    periods_per_step: usize,
    counter: usize,
    x_ref: Vec<f64>,
    x: Vec<f64>,
    u_prev: Vec<f64>,
    u_min: Vec<f64>,
    u_max: Vec<f64>,
    stats: MpcStatistics,
}

impl MpcController {
    /// The controller of `mpc` at loop period `ts` \[s\], predicting with steps of
    /// `periods_per_step · ts` (the step `mpc` was discretised with), about the setpoint
    /// `x_ref` (`n_x` entries) with input bounds `u_min`, `u_max` for the fallback (those of
    /// the settings).
    ///
    /// # Errors
    /// [`ControlError::InvalidParameter`] for `ts` not positive or `periods_per_step` 0;
    /// [`ControlError::DimensionMismatch`]/[`ControlError::NonFinite`] for `x_ref`, bounds.
    pub fn new(
        mpc: LinearMpc,
        ts: f64,
        periods_per_step: usize,
        x_ref: &[f64],
        u_min: &[f64],
        u_max: &[f64],
    ) -> Result<Self> {
        check_param("ts", ts, ts > 0.0, "must be finite and > 0")?;
        if periods_per_step == 0 {
            return Err(ControlError::InvalidParameter {
                name: "periods_per_step".into(),
                value: 0.0,
                requirement: "must be ≥ 1".into(),
            });
        }
        check_vector("x_ref", x_ref, mpc.nx())?;
        bounds_pair("u_min", "u_max", u_min, u_max, mpc.nu())?;
        let (nx, nu) = (mpc.nx(), mpc.nu());
        Ok(Self {
            mpc,
            ts,
            periods_per_step,
            counter: 0,
            x_ref: x_ref.to_vec(),
            x: vec![0.0; nx],
            u_prev: vec![0.0; nu],
            u_min: u_min.to_vec(),
            u_max: u_max.to_vec(),
            stats: MpcStatistics::default(),
        })
    }

    /// The MPC (its last plan and QP).
    pub fn mpc(&self) -> &LinearMpc {
        &self.mpc
    }

    /// Counters since the last reset.
    pub fn statistics(&self) -> &MpcStatistics {
        &self.stats
    }
}

impl Controller for MpcController {
    fn ny(&self) -> usize {
        self.mpc.nx()
    }
    fn nu(&self) -> usize {
        self.mpc.nu()
    }
    fn reset(&mut self) {
        self.counter = 0;
        self.u_prev.iter_mut().for_each(|x| *x = 0.0);
        self.stats = MpcStatistics::default();
    }
    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        for ((x, yi), r) in self.x.iter_mut().zip(y).zip(&self.x_ref) {
            *x = yi - r;
        }
        let warm = if self.counter == 0 {
            WarmStart::Cold
        } else if self.counter.is_multiple_of(self.periods_per_step) {
            WarmStart::Shifted
        } else {
            WarmStart::Same
        };
        self.counter += 1;
        let status = if self.x.iter().all(|x| x.is_finite()) {
            self.mpc.solve(&self.x, &self.u_prev, warm).ok()
        } else {
            None
        };
        self.stats.solves += 1;
        let iters = self.mpc.qp().iterations();
        self.stats.total_iterations += iters as u64;
        self.stats.max_iterations = self.stats.max_iterations.max(iters);
        match status {
            Some(QpStatus::Solved) => {
                u.copy_from_slice(&self.mpc.plan()[..self.mpc.nu()]);
            }
            other => {
                match other {
                    Some(QpStatus::Infeasible) => self.stats.infeasible += 1,
                    _ => self.stats.max_iterations_hit += 1,
                }
                let k = self.mpc.lq_gain();
                for (i, ui) in u.iter_mut().enumerate() {
                    let v: f64 = -(0..self.x.len())
                        .map(|c| k[(i, c)] * self.x[c])
                        .sum::<f64>();
                    *ui = if v.is_finite() {
                        v.clamp(self.u_min[i], self.u_max[i])
                    } else {
                        0.0
                    };
                }
            }
        }
        self.u_prev.copy_from_slice(u);
    }
    fn sample_time(&self) -> Option<f64> {
        Some(self.ts)
    }
}
