//! Solving: options, status, the recheck of every constraint, SOS residuals and
//! infeasibility certificates.

use crate::clarabel_backend;
use crate::clock::Instant;
pub use crate::conic::Dims;
use crate::conic::{ConicData, RawSolution, RawStatus, Settings};
use crate::dense;
use crate::error::{LmiError, Result};
use crate::expr::{Affine, Expr};
use crate::problem::{Cone, ConstraintId, Origin, Problem, Relation, SosId};
use crate::sos;
use pendulab_lti::Mat;

/// Stopping tolerances of the interior-point methods (Clarabel's meaning, which the dense
/// method follows: see the `dense` module docs; all relative to the problem data as the
/// solver receives it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Absolute duality gap. Default 1e-8.
    pub gap_abs: f64,
    /// Relative duality gap. Default 1e-8.
    pub gap_rel: f64,
    /// Primal and dual feasibility. Default 1e-8.
    pub feasibility: f64,
    /// Infeasibility certificates (absolute and relative). Default 1e-8.
    pub infeasibility: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self {
            gap_abs: 1e-8,
            gap_rel: 1e-8,
            feasibility: 1e-8,
            infeasibility: 1e-8,
        }
    }
}

/// Options of [`Problem::solve`].
#[derive(Debug, Clone, PartialEq)]
pub struct SolveOptions {
    /// Iteration limit. Default 200.
    pub max_iterations: u32,
    /// Time limit in seconds (None: unlimited). Default None.
    pub time_limit: Option<f64>,
    /// Solver stopping tolerances.
    pub tolerances: Tolerances,
    /// Scale each constraint block and the objective to unit largest coefficient before
    /// handing them to the solver (on top of Clarabel's own Ruiz equilibration). Default
    /// false: on the textbook's LQ-type LMIs this extra scaling made Clarabel stop with
    /// numerical errors where the unscaled data solve cleanly.
    pub scale_rows: bool,
    /// Let Clarabel decompose sparse PSD cones along their chordal sparsity (Clarabel only).
    /// Default true.
    /// Even the textbook's LMI LQ servo profits: its 11 × 11 cost LMI has an arrow pattern
    /// (the constant `−I` blocks are diagonal), which Clarabel splits into cones of sides 10
    /// and 6 (35 variables, 91 cone rows instead of 20 and 81); the solve then takes 12
    /// instead of 16 interior-point iterations, for final residuals of the same order (the
    /// conic data of `crates/lmi/tests/conic_export.rs`, solved both ways).
    pub chordal_decomposition: bool,
    /// With `chordal_decomposition`, let Clarabel merge the cliques of the decomposition
    /// (Clarabel only; its `chordal_decomposition_merge_method = "clique_graph"`) instead of
    /// keeping one
    /// PSD cone per maximal clique (`"none"`). Default false: on the textbook's LMI LQ servo
    /// the unmerged cliques took 12 instead of 13 interior-point iterations and about 12 %
    /// less solve time to the same residuals, and the gain-scheduling SOS program solved in
    /// comparable time either way.
    pub merge_cliques: bool,
    /// Most iterative-refinement steps Clarabel takes after each solve with its LDLᵀ factor
    /// of the KKT matrix (Clarabel only, its `iterative_refinement_max_iter`; 0 turns
    /// refinement off; the dense method refines by its own rule).
    /// Default 1: one step of refinement in working precision already makes the solve
    /// componentwise backward stable (Skeel, "Iterative refinement implies numerical
    /// stability for Gaussian elimination", Math. Comp. 35, 1980; Higham, *Accuracy and
    /// Stability of Numerical Algorithms*, 2nd ed., ch. 12). On the textbook's LMI LQ servo
    /// and gain-scheduling SOS programs Clarabel's default of up to 10 steps took 7–45 %
    /// more solve time than one step in this build, for iteration counts within ±1 and final
    /// residuals of the same order (the conic data exported by
    /// `crates/lmi/tests/conic_export.rs`, solved with both settings; the Python build showed
    /// 0–35 %, see `tools/reference/lmi_clarabel_python.py`). The stopping tolerances are
    /// unaffected. A solve that ends in numerical trouble with fewer than 10 steps is
    /// repeated once with Clarabel's default (see [`Solution::refinement_retry`]).
    pub refinement_steps: u32,
    /// Which sparse LDLᵀ factorisation Clarabel uses for its KKT systems (Clarabel only).
    /// Default [`KktSolver::Auto`].
    pub kkt_solver: KktSolver,
    /// Which interior-point method solves the problem. Default [`Backend::Auto`].
    pub backend: Backend,
    /// Relative tolerance of the recheck: a constraint counts as satisfied when its
    /// violation is at most `check_tolerance` times the magnitude of the numbers summed to
    /// form it (at least 1). Default 1e-7 (the solver's 1e-8 accuracy with a margin for
    /// the scaling between its internal and the user's units).
    pub check_tolerance: f64,
    /// Relative tolerance of the SOS residual check (coefficient mismatch relative to the
    /// largest coefficient, and `λ_min` of the Gram matrix relative to its norm). Default
    /// 1e-6.
    pub sos_tolerance: f64,
}

impl Default for SolveOptions {
    fn default() -> Self {
        Self {
            max_iterations: 200,
            time_limit: None,
            tolerances: Tolerances::default(),
            scale_rows: false,
            chordal_decomposition: true,
            merge_cliques: false,
            refinement_steps: 1,
            kkt_solver: KktSolver::Auto,
            backend: Backend::Auto,
            check_tolerance: 1e-7,
            sos_tolerance: 1e-6,
        }
    }
}

/// The sparse LDLᵀ factorisation Clarabel uses for the KKT system of each interior-point
/// iteration (its `direct_solve_method`). Both solve the same quasi-definite system with the
/// same static and dynamic regularisation and iterative refinement; they differ in speed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum KktSolver {
    /// [`KktSolver::Qdldl`] for KKT systems of fewer than [`KktSolver::AUTO_FAER_DIMENSION`]
    /// rows (variables plus constraint rows), [`KktSolver::Faer`] from there on.
    #[default]
    Auto,
    /// QDLDL, Clarabel's own simplicial (column-by-column) LDLᵀ: the least overhead on small
    /// systems.
    Qdldl,
    /// faer's supernodal LDLᵀ (dense blocks with matrix–matrix kernels): much faster once the
    /// PSD cones' dense scaling blocks fill the factor, as in SOS programs.
    Faer,
}

impl KktSolver {
    /// KKT dimension from which [`KktSolver::Auto`] picks faer. On the textbook's problems
    /// (the exact conic data of `crates/lmi/tests/conic_export.rs`, solved with both): the LMI
    /// LQ servo (KKT dimension 101) takes the same time either way, the gain-scheduling SOS
    /// program (2 752) 2–3× less with faer, for the same iteration counts.
    pub const AUTO_FAER_DIMENSION: usize = 500;

    /// Clarabel's `direct_solve_method` for a KKT system of `dimension` rows.
    pub fn method(self, dimension: usize) -> &'static str {
        match self {
            KktSolver::Qdldl => "qdldl",
            KktSolver::Faer => "faer",
            KktSolver::Auto if dimension >= Self::AUTO_FAER_DIMENSION => "faer",
            KktSolver::Auto => "qdldl",
        }
    }
}

/// The interior-point method that solves a [`Problem`].
///
/// Both solve the conic form of the problem (see the `conic` module docs) to the same
/// [`Tolerances`]; every solution is rechecked on the problem's own constraints either way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Backend {
    /// [`Backend::Dense`] for problems within [`Backend::dense_suits`], with
    /// [`Backend::Clarabel`] as the fallback whenever the dense method does not end with a
    /// solution that passes every recheck or an infeasibility certificate that checks out
    /// ([`Solution::dense_attempt`] then tells what it reported); Clarabel for larger
    /// problems.
    #[default]
    Auto,
    /// Clarabel, the sparse homogeneous interior-point solver (its semidefinite path on
    /// `pendulab-lapack`): any size, chordal decomposition of sparse PSD cones.
    Clarabel,
    /// pendulab's dense primal–dual interior-point method (homogeneous self-dual embedding,
    /// Nesterov–Todd scaling, Mehrotra predictor–corrector, Schur-complement normal
    /// equations): for small problems, several times faster there than a sparse
    /// factorisation of the KKT matrix with its dense PSD blocks. No fallback.
    Dense,
}

impl Backend {
    /// Most scalar variables [`Backend::Auto`] hands the dense method: its normal equations
    /// are a dense `n × n` Cholesky factorisation per iteration, formed in `O(n² · rows)`.
    /// On SDPs with dense coefficient matrices ([`crate::planted::planted_sdp`], one or two
    /// PSD cones of side 5–30 with 4–100 variables, `pendulab bench lmi-planted`) the dense
    /// method takes 1.6–8× less time than Clarabel for about the same iteration counts, the
    /// ratio growing with the size; on the book's gain-scheduling SOS program (1081
    /// variables, each Gram entry entering one row) it is far slower than Clarabel's sparse
    /// factorisation.
    pub const DENSE_MAX_VARIABLES: usize = 200;
    /// Largest PSD cone side [`Backend::Auto`] hands the dense method.
    pub const DENSE_MAX_SIDE: usize = 40;
    /// Most constraint rows [`Backend::Auto`] hands the dense method (the scaled coefficient
    /// matrix `W⁻ᵀG` is formed densely, rows × variables, each iteration).
    pub const DENSE_MAX_ROWS: usize = 2000;

    /// Whether [`Backend::Auto`] tries the dense method on a problem of these dimensions:
    /// at most [`Backend::DENSE_MAX_VARIABLES`] variables and as many equalities, PSD sides
    /// and rows within the other two limits, and at least one inequality (cone) row.
    pub fn dense_suits(dims: &Dims) -> bool {
        let rows = dims.kkt_dimension() - dims.variables;
        let cone_rows = rows - dims.equalities;
        dims.variables <= Self::DENSE_MAX_VARIABLES
            && dims.equalities <= Self::DENSE_MAX_VARIABLES
            && dims.psd_sizes.iter().all(|&d| d <= Self::DENSE_MAX_SIDE)
            && rows <= Self::DENSE_MAX_ROWS
            && cone_rows > 0
    }
}

/// What the dense method reported when [`Backend::Auto`] fell back to Clarabel.
#[derive(Debug, Clone, PartialEq)]
pub struct DenseAttempt {
    /// Its status.
    pub status: Status,
    /// Whether its solution passed every recheck (for a solved status).
    pub checks_passed: bool,
    /// Its iterations.
    pub iterations: u32,
    /// Its seconds.
    pub seconds: f64,
}

/// Outcome of a solve.
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    /// Solved to the requested tolerances.
    Solved,
    /// Solved to reduced accuracy (Clarabel's relaxed tolerances; the dense method's best
    /// iterate within the same).
    AlmostSolved,
    /// The constraints have no common solution; the certificate proves it.
    Infeasible {
        /// Farkas certificate of infeasibility.
        certificate: Certificate,
        /// Found at reduced accuracy only.
        reduced_accuracy: bool,
    },
    /// The objective is unbounded on the feasible set.
    Unbounded {
        /// Found at reduced accuracy only.
        reduced_accuracy: bool,
    },
    /// The iteration limit was reached.
    MaxIterations,
    /// The time limit was reached.
    MaxTime,
    /// The solver stopped without an answer (numerical error, no progress, or a failed
    /// dense factorisation inside it).
    NumericalTrouble {
        /// What the solver reported.
        reason: String,
    },
}

impl Status {
    /// Solved or almost solved: the variable values are meaningful.
    pub fn is_solved(&self) -> bool {
        matches!(self, Status::Solved | Status::AlmostSolved)
    }

    /// Infeasible (at full or reduced accuracy).
    pub fn is_infeasible(&self) -> bool {
        matches!(self, Status::Infeasible { .. })
    }
}

/// A Farkas certificate that the (normalised) constraints `G_j(x) ⪰ 0` / `≥ 0` / `= 0` have
/// no common solution: multipliers `Z_j` in the dual cones (PSD `Z_j ⪰ 0`, nonnegative
/// `Z_j ≥ 0`, free for equalities) with
///
/// ```text
/// Σ_j ⟨G_{j,v}, Z_j⟩ = 0  for every variable v,      Σ_j ⟨G_{j,0}, Z_j⟩ = −1 < 0,
/// ```
///
/// so `Σ_j ⟨G_j(x), Z_j⟩ = −1` for every `x`, while feasibility would make it `≥ 0`.
/// Here `G_j` is the constraint in the form the solver sees: `F − εI` for `F ⪰ εI`,
/// `−F − εI` for `F ⪯ −εI`. The residuals are recomputed from the constraint expressions.
#[derive(Debug, Clone, PartialEq)]
pub struct Certificate {
    /// `(constraint, Z_j)`, normalised so that `Σ_j ⟨G_{j,0}, Z_j⟩ = −1`.
    pub multipliers: Vec<(ConstraintId, Mat)>,
    /// `max_v |Σ_j ⟨G_{j,v}, Z_j⟩|` relative to `max_v Σ_j Σ |G_{j,v} ∘ Z_j|`.
    pub stationarity_residual: f64,
    /// Most negative eigenvalue (PSD) or entry (nonnegative) over the multipliers, relative
    /// to the largest multiplier entry (≥ 0 up to round-off for a valid certificate).
    pub cone_violation: f64,
}

impl Certificate {
    /// Whether the certificate checks out to `tol` (e.g. 1e-6).
    pub fn is_valid(&self, tol: f64) -> bool {
        self.stationarity_residual <= tol && self.cone_violation >= -tol
    }
}

/// The recheck of one constraint on the returned values.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintCheck {
    /// Constraint name.
    pub name: String,
    /// Its relation.
    pub relation: Relation,
    /// Where it comes from.
    pub origin: Origin,
    /// Matrix inequalities: smallest eigenvalue of `F` (of `−F` for `⪯`), to be `≥ ε`.
    /// Equalities: largest `|F_ij|`, to be 0. Entrywise `≥ 0`: smallest entry.
    pub value: f64,
    /// The margin `ε` required (0 for non-strict constraints and equalities).
    pub margin: f64,
    /// Absolute tolerance granted (check tolerance × magnitude of the summed numbers).
    pub tolerance: f64,
    /// `value ≥ margin − tolerance` (equalities: `value ≤ tolerance`).
    pub satisfied: bool,
}

/// The residual check of one SOS decomposition `M(ρ) = Z(ρ)ᵀ Q Z(ρ)`.
#[derive(Debug, Clone, PartialEq)]
pub struct SosCheck {
    /// SOS constraint name.
    pub name: String,
    /// The constraint `Q ⪰ 0` on the Gram matrix.
    pub gram_constraint: ConstraintId,
    /// The equality constraint on coefficients no Gram entry produces, if any.
    pub matching_constraint: Option<ConstraintId>,
    /// Size of the Gram matrix `Q`.
    pub gram_size: usize,
    /// `max |coef(M) − coef(Zᵀ Q Z)|` over all entries and monomials.
    pub residual: f64,
    /// The same relative to the largest coefficient of `M` (at least 1).
    pub relative_residual: f64,
    /// `λ_min(Q)`.
    pub gram_min_eigenvalue: f64,
    /// `relative_residual ≤ tol` and `λ_min(Q) ≥ −tol · max(1, ‖Q‖)`.
    pub satisfied: bool,
}

/// Result of [`Problem::solve`].
#[derive(Debug, Clone)]
pub struct Solution {
    /// Outcome.
    pub status: Status,
    /// Objective value in the user's sense (None unless solved and an objective was set).
    pub objective: Option<f64>,
    /// Interior-point iterations.
    pub iterations: u32,
    /// Seconds spent by the solver proper.
    pub solver_seconds: f64,
    /// Seconds spent turning the problem into solver data (including the solver's setup).
    pub setup_seconds: f64,
    /// Final primal residual reported by the solver.
    pub primal_residual: f64,
    /// Final dual residual reported by the solver.
    pub dual_residual: f64,
    /// Dimensions of the conic problem solved.
    pub dims: Dims,
    /// The recheck of every constraint, indexed by [`ConstraintId`] (empty unless solved).
    pub checks: Vec<ConstraintCheck>,
    /// The residual check of every SOS constraint, indexed by [`SosId`] (empty unless
    /// solved).
    pub sos_checks: Vec<SosCheck>,
    /// Whether the first solve, with [`SolveOptions::refinement_steps`] refinement steps,
    /// ended in numerical trouble and the problem was solved again with Clarabel's default
    /// iterative refinement (up to 10 steps per KKT solve); the other fields then describe
    /// the repeated solve, with both solves' seconds added.
    pub refinement_retry: bool,
    /// The method that produced this solution ([`Backend::Dense`] or
    /// [`Backend::Clarabel`]).
    pub backend: Backend,
    /// With [`Backend::Auto`]: what the dense method reported before the problem was handed
    /// to Clarabel (None when the dense method's answer was kept or was not tried).
    pub dense_attempt: Option<DenseAttempt>,
    x: Vec<f64>,
    duals: Vec<Mat>,
    owner: u64,
}

impl Solution {
    /// Whether the status is solved and every constraint and SOS decomposition passes its
    /// recheck.
    pub fn all_checks_pass(&self) -> bool {
        self.status.is_solved()
            && self.checks.iter().all(|c| c.satisfied)
            && self.sos_checks.iter().all(|c| c.satisfied)
    }

    /// The check of constraint `id`.
    pub fn check(&self, id: ConstraintId) -> Option<&ConstraintCheck> {
        self.checks.get(id.0)
    }

    /// The solver's dual variable of constraint `id` (empty unless solved): for a
    /// semidefinite constraint the symmetric `Z ⪰ 0` paired with `G`, the constraint in the
    /// form the solver sees (`F − εI` for `F ⪰ εI`, `−F − εI` for `F ⪯ −εI`); for an equality
    /// or entrywise constraint the multiplier of each entry (zero for entries not imposed).
    ///
    /// With `G_j(x) = G_{j,0} + Σ_v x_v G_{j,v}`, a maximisation of `cᵀx` is certified by
    /// these duals when `c_v + Σ_j ⟨Z_j, G_{j,v}⟩ ≈ 0` for every variable `v`: then
    /// `Σ_j ⟨Z_j, G_{j,0}⟩` bounds the optimum from above and `Σ_j ⟨Z_j, G_j(x*)⟩` is the
    /// duality gap at the returned point (for a minimisation, `c_v − Σ_j ⟨Z_j, G_{j,v}⟩ ≈ 0`,
    /// lower bound `−Σ_j ⟨Z_j, G_{j,0}⟩`). Callers can recompute both from their own
    /// constraint matrices, independently of the solver.
    pub fn dual(&self, id: ConstraintId) -> Option<&Mat> {
        self.duals.get(id.0)
    }

    /// The residual check of SOS constraint `id`.
    pub fn sos_check(&self, id: SosId) -> Option<&SosCheck> {
        self.sos_checks.get(id.0)
    }

    /// Value of a parameter-free expression of this problem at the solution.
    ///
    /// # Errors
    /// The expression's deferred error; [`LmiError::ForeignExpression`] for another problem's
    /// expression; [`LmiError::ParameterDependent`] (use [`value_at`](Self::value_at));
    /// [`LmiError::InvalidArgument`] when the solve produced no values.
    pub fn value(&self, e: &Expr) -> Result<Mat> {
        self.value_at(e, &[])
    }

    /// Value of an expression at the solution and the given parameter values
    /// `(parameter, value)`; every parameter appearing in `e` must be given.
    ///
    /// # Errors
    /// As [`value`](Self::value); [`LmiError::NotAParameter`] for a first element that is not
    /// a parameter.
    pub fn value_at(&self, e: &Expr, params: &[(&Expr, f64)]) -> Result<Mat> {
        e.check()?;
        if e.owner().is_some_and(|o| o != self.owner) {
            return Err(LmiError::ForeignExpression {
                op: "Solution::value".into(),
            });
        }
        if !self.status.is_solved() {
            return Err(LmiError::InvalidArgument {
                what: "solution".into(),
                reason: format!("no values: status {:?}", self.status),
            });
        }
        let mut sub = e.clone();
        for (p, v) in params {
            sub = sub.at(p, *v);
        }
        sub.check()?;
        if sub.is_parametric() {
            return Err(LmiError::ParameterDependent {
                what: "the evaluated expression (give every parameter a value)".into(),
            });
        }
        if sub.max_var().is_some_and(|v| v as usize >= self.x.len()) {
            return Err(LmiError::ForeignExpression {
                op: "Solution::value".into(),
            });
        }
        Ok(sub.eval(&self.x, &[]))
    }
}

/// Magnitude of the numbers summed to form each entry of `a` at `x`:
/// `max_ij (|C_ij| + Σ_v |coef · x_v|)`.
fn magnitude(a: &Affine, x: &[f64]) -> f64 {
    let mut m = a.constant.map(f64::abs);
    for l in &a.lin {
        m[(l.row as usize, l.col as usize)] += (l.coef * x[l.var as usize]).abs();
    }
    m.iter().copied().fold(0.0, f64::max)
}

fn min_eigenvalue(m: &Mat) -> f64 {
    if m.nrows() == 0 {
        return f64::INFINITY;
    }
    if m.iter().any(|v| !v.is_finite()) {
        return f64::NAN;
    }
    m.clone()
        .symmetric_eigenvalues()
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min)
}

fn recheck(problem: &Problem, x: &[f64], tol: f64) -> Vec<ConstraintCheck> {
    problem
        .constraints
        .iter()
        .map(|c| {
            let f = c.expr.eval(x);
            let tolerance = tol * magnitude(&c.expr, x).max(1.0);
            let margin = c.relation.margin();
            let (value, satisfied) = match c.relation {
                Relation::PositiveSemidefinite | Relation::PositiveDefinite { .. } => {
                    let v = min_eigenvalue(&crate::linalg::sym(&f));
                    (v, v >= margin - tolerance)
                }
                Relation::NegativeSemidefinite | Relation::NegativeDefinite { .. } => {
                    let v = min_eigenvalue(&(-crate::linalg::sym(&f)));
                    (v, v >= margin - tolerance)
                }
                Relation::Zero => {
                    let v = f.iter().map(|v| v.abs()).fold(0.0, f64::max);
                    (v, v <= tolerance)
                }
                Relation::NonNegative => {
                    let v = f.iter().copied().fold(f64::INFINITY, f64::min);
                    (v, v >= -tolerance)
                }
            };
            ConstraintCheck {
                name: c.name.clone(),
                relation: c.relation,
                origin: c.origin.clone(),
                value,
                margin,
                tolerance,
                satisfied,
            }
        })
        .collect()
}

/// Builds and checks the Farkas certificate from the solver's dual ray.
fn certificate(problem: &Problem, duals: &[Mat]) -> Certificate {
    let n = problem.num_scalar_variables();
    let mut station = vec![0.0; n];
    let mut station_mag = vec![0.0; n];
    let mut value = 0.0;
    for (c, z) in problem.constraints.iter().zip(duals) {
        let g = &c.g;
        value += g.constant.component_mul(z).sum();
        for l in &g.lin {
            let zij = z[(l.row as usize, l.col as usize)];
            station[l.var as usize] += l.coef * zij;
            station_mag[l.var as usize] += (l.coef * zij).abs();
        }
    }
    // Normalise so that Σ ⟨G_0, Z⟩ = −1 (a valid ray has value < 0).
    let norm = if value < 0.0 { -value } else { f64::NAN };
    let mag = station_mag.iter().copied().fold(0.0, f64::max);
    let stationarity_residual = if mag > 0.0 {
        station.iter().map(|v| v.abs()).fold(0.0, f64::max) / mag
    } else {
        0.0
    };
    let biggest = duals
        .iter()
        .flat_map(|z| z.iter())
        .map(|v| v.abs())
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut cone_violation: f64 = 0.0;
    for (c, z) in problem.constraints.iter().zip(duals) {
        let v = match c.cone {
            Cone::Psd => min_eigenvalue(z),
            Cone::NonNegative => z.iter().copied().fold(0.0, f64::min),
            Cone::Zero => 0.0,
        };
        cone_violation = cone_violation.min(v / biggest);
    }
    if !value.is_finite() || value >= 0.0 {
        // Not a separating ray: make that visible through the residual.
        cone_violation = cone_violation.min(-1.0);
    }
    Certificate {
        multipliers: duals
            .iter()
            .enumerate()
            .map(|(k, z)| (ConstraintId(k), z / norm))
            .collect(),
        stationarity_residual,
        cone_violation,
    }
}

pub(crate) fn solve(problem: &Problem, options: &SolveOptions) -> Result<Solution> {
    let positive = |what: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(LmiError::InvalidArgument {
                what: what.into(),
                reason: format!("must be finite and > 0, got {v}"),
            })
        }
    };
    let t = &options.tolerances;
    positive("tolerances.gap_abs", t.gap_abs)?;
    positive("tolerances.gap_rel", t.gap_rel)?;
    positive("tolerances.feasibility", t.feasibility)?;
    positive("tolerances.infeasibility", t.infeasibility)?;
    positive("check_tolerance", options.check_tolerance)?;
    positive("sos_tolerance", options.sos_tolerance)?;
    if let Some(tl) = options.time_limit {
        positive("time_limit", tl)?;
    }
    solve_with(problem, options, clarabel_backend::solve)
}

/// Clarabel's own default of iterative-refinement steps per KKT solve
/// (`iterative_refinement_max_iter`), used for the repeated solve of [`solve_with`].
pub(crate) const FULL_REFINEMENT_STEPS: u32 = 10;

/// Relative tolerance of [`Certificate::is_valid`] for keeping the dense method's
/// infeasibility certificate under [`Backend::Auto`].
const DENSE_CERTIFICATE_TOL: f64 = 1e-6;

/// [`solve`] with the Clarabel backend as a parameter (tests substitute one that fails on
/// demand).
///
/// The problem is put in conic form once. [`SolveOptions::backend`] decides who solves it:
/// the dense method (kept under [`Backend::Auto`] only when its solution passes every
/// recheck or its infeasibility certificate checks out), Clarabel otherwise.
///
/// When a Clarabel solve ends in numerical trouble (its `NumericalError` or
/// `InsufficientProgress`) with fewer than [`FULL_REFINEMENT_STEPS`] refinement steps per
/// KKT solve, the problem is solved once more with Clarabel's default refinement: the
/// shortened refinement of [`SolveOptions::refinement_steps`] is a speed setting and must not
/// decide whether a problem near the solver's numerical limits solves. The solution then
/// reports the repeated solve (with [`Solution::refinement_retry`] set and both solves'
/// seconds added).
pub(crate) fn solve_with(
    problem: &Problem,
    options: &SolveOptions,
    clarabel: impl Fn(&Problem, &ConicData, &Settings) -> Result<RawSolution>,
) -> Result<Solution> {
    let t = &options.tolerances;
    let settings = Settings {
        max_iterations: options.max_iterations,
        time_limit: options.time_limit.unwrap_or(f64::INFINITY),
        gap_abs: t.gap_abs,
        gap_rel: t.gap_rel,
        feasibility: t.feasibility,
        infeasibility: t.infeasibility,
        scale_rows: options.scale_rows,
        chordal_decomposition: options.chordal_decomposition,
        merge_cliques: options.merge_cliques,
        kkt_solver: options.kkt_solver,
        refinement_steps: options.refinement_steps,
    };
    let build_start = Instant::now();
    let data = ConicData::build(problem, settings.scale_rows);
    let build_seconds = build_start.elapsed().as_secs_f64();
    let try_dense = match options.backend {
        Backend::Dense => true,
        Backend::Auto => Backend::dense_suits(&data.dims),
        Backend::Clarabel => false,
    };
    let mut dense_attempt = None;
    if try_dense {
        let start = Instant::now();
        let out = dense::solve(&data, &settings);
        let seconds = start.elapsed().as_secs_f64();
        let solved = matches!(out.status, RawStatus::Solved | RawStatus::AlmostSolved);
        let raw = RawSolution {
            status: out.status,
            x: data.user_x(&out.x),
            duals: data.duals(problem, &out.z),
            objective: (solved && problem.objective.is_some())
                .then(|| data.user_objective(out.objective)),
            iterations: out.iterations,
            solver_seconds: seconds,
            setup_seconds: build_seconds,
            primal_residual: out.primal_residual,
            dual_residual: out.dual_residual,
            dims: data.dims.clone(),
        };
        let sol = finish(problem, options, raw, false, Backend::Dense, None);
        let keep = sol.all_checks_pass()
            || matches!(&sol.status, Status::Infeasible { certificate, reduced_accuracy: false }
                if certificate.is_valid(DENSE_CERTIFICATE_TOL));
        if keep || options.backend == Backend::Dense {
            return Ok(sol);
        }
        dense_attempt = Some(DenseAttempt {
            checks_passed: sol.all_checks_pass(),
            status: sol.status,
            iterations: sol.iterations,
            seconds,
        });
    }
    let mut raw = clarabel(problem, &data, &settings)?;
    raw.setup_seconds += build_seconds;
    let mut refinement_retry = false;
    if matches!(
        raw.status,
        RawStatus::NumericalError | RawStatus::InsufficientProgress
    ) && settings.refinement_steps < FULL_REFINEMENT_STEPS
    {
        let first_seconds = (raw.solver_seconds, raw.setup_seconds);
        raw = clarabel(
            problem,
            &data,
            &Settings {
                refinement_steps: FULL_REFINEMENT_STEPS,
                ..settings
            },
        )?;
        raw.solver_seconds += first_seconds.0;
        raw.setup_seconds += first_seconds.1;
        refinement_retry = true;
    }
    Ok(finish(
        problem,
        options,
        raw,
        refinement_retry,
        Backend::Clarabel,
        dense_attempt,
    ))
}

/// The [`Solution`] of a solver's raw answer: status, rechecks, SOS residuals.
fn finish(
    problem: &Problem,
    options: &SolveOptions,
    raw: RawSolution,
    refinement_retry: bool,
    backend: Backend,
    dense_attempt: Option<DenseAttempt>,
) -> Solution {
    let status = match raw.status {
        RawStatus::Solved => Status::Solved,
        RawStatus::AlmostSolved => Status::AlmostSolved,
        RawStatus::Infeasible | RawStatus::AlmostInfeasible => Status::Infeasible {
            certificate: certificate(problem, &raw.duals),
            reduced_accuracy: raw.status == RawStatus::AlmostInfeasible,
        },
        RawStatus::Unbounded => Status::Unbounded {
            reduced_accuracy: false,
        },
        RawStatus::AlmostUnbounded => Status::Unbounded {
            reduced_accuracy: true,
        },
        RawStatus::MaxIterations => Status::MaxIterations,
        RawStatus::MaxTime => Status::MaxTime,
        RawStatus::NumericalError => Status::NumericalTrouble {
            reason: "numerical error".into(),
        },
        RawStatus::InsufficientProgress => Status::NumericalTrouble {
            reason: "insufficient progress".into(),
        },
        RawStatus::Crashed => Status::NumericalTrouble {
            reason: "the solver aborted (a dense factorisation failed)".into(),
        },
    };
    let status_solved = status.is_solved();
    let (checks, sos_checks) = if status.is_solved() {
        let checks = recheck(problem, &raw.x, options.check_tolerance);
        let sos_checks = problem
            .sos
            .iter()
            .map(|rec| {
                let (residual, scale, min_eig) = sos::check(rec, &raw.x);
                let relative_residual = residual / scale.max(1.0);
                let qn = rec.gram.eval(&raw.x).norm().max(1.0);
                SosCheck {
                    name: rec.name.clone(),
                    gram_constraint: rec.gram_constraint,
                    matching_constraint: rec.matching_constraint,
                    gram_size: rec.gram.nrows(),
                    residual,
                    relative_residual,
                    gram_min_eigenvalue: min_eig,
                    satisfied: relative_residual <= options.sos_tolerance
                        && min_eig >= -options.sos_tolerance * qn,
                }
            })
            .collect();
        (checks, sos_checks)
    } else {
        (Vec::new(), Vec::new())
    };
    Solution {
        status,
        objective: raw.objective,
        iterations: raw.iterations,
        solver_seconds: raw.solver_seconds,
        setup_seconds: raw.setup_seconds,
        primal_residual: raw.primal_residual,
        dual_residual: raw.dual_residual,
        dims: raw.dims,
        checks,
        sos_checks,
        refinement_retry,
        backend,
        dense_attempt,
        x: raw.x,
        duals: if status_solved { raw.duals } else { Vec::new() },
        owner: problem.id(),
    }
}

#[cfg(test)]
mod tests;
