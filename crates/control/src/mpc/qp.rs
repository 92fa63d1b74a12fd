//! The dual active-set QP method [`DualActiveSetQp`] (Goldfarb–Idnani in DAQP's
//! least-distance form; module documentation of `mpc`) for `min ½ Uᵀ H U + gᵀ U s.t. G U ≤ w`,
//! its options and status, and the KKT residuals that check a solution independently.

use crate::error::{ControlError, Result, check_matrix, check_param, check_vector};
use pendulab_lti::Mat;

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

    pub(super) fn solve_unchecked(
        &mut self,
        g: &[f64],
        w: &[f64],
        warm_start: &[usize],
    ) -> QpStatus {
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
