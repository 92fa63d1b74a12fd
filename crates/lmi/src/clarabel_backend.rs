//! The one place that knows Clarabel's interface: the conic form of [`crate::conic`] handed
//! to Clarabel's interior-point solver, its settings, and its answer mapped back.
//!
//! Clarabel solves `minimise ½ xᵀPx + qᵀx` subject to `A x + s = b`, `s ∈ K` (here `P = 0`),
//! with the PSD cone in the svec layout [`crate::conic`] already uses
//! (`PSDTriangleConeT(n)`), so the rows pass unchanged; Clarabel's own Ruiz equilibration
//! works from them.
//!
//! **Linear algebra.** Each interior-point iteration factors the quasi-definite KKT matrix
//! `[P  Aᵀ; A  −H]`, where each PSD cone of side `d` contributes a dense `d(d+1)/2` square
//! block of `H` (Nesterov–Todd scaling), with Clarabel's simplicial LDLᵀ (QDLDL) or faer's
//! supernodal LDLᵀ ([`crate::KktSolver`]). Its SDP path calls BLAS/LAPACK routines, which
//! `pendulab-lapack` provides.
//!
//! **Feature `clarabel`** (default). Without it (`default-features = false`, as the browser
//! lab builds for `wasm32-unknown-unknown`, where Clarabel's SDP path and its sparse KKT
//! solver do not compile) there is no Clarabel: [`solve`] reports [`LmiError::Solver`], so
//! [`crate::Backend::Clarabel`] is an error and [`crate::Backend::Auto`] is one whenever
//! the dense method's answer does not pass its rechecks; [`crate::Backend::Dense`] works as
//! with the feature. [`capture_conic_problems`] then records nothing.

#[cfg(feature = "clarabel")]
use crate::conic::{ConeKind, RawStatus};
use crate::conic::{ConicData, RawSolution, Settings};
use crate::error::{LmiError, Result};
use crate::problem::Problem;
#[cfg(feature = "clarabel")]
use clarabel::algebra::CscMatrix;
#[cfg(feature = "clarabel")]
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
#[cfg(feature = "clarabel")]
use pendulab_lapack as _;
use std::cell::RefCell;
#[cfg(feature = "clarabel")]
use std::panic::{AssertUnwindSafe, catch_unwind};
#[cfg(feature = "clarabel")]
use std::time::Instant;

/// The exact conic problem handed to Clarabel by one solve, with the settings used and what
/// Clarabel returned: `minimise qᵀx  s.t.  A x + s = b,  s ∈ K` (`P = 0` throughout this
/// crate). A debugging and reference aid, recorded only inside [`capture_conic_problems`]:
/// it lets the same data be solved by another build of Clarabel (e.g. its Python package)
/// to separate the cost of the formulation from the cost of the linear algebra.
#[derive(Debug, Clone, PartialEq)]
pub struct ConicProblem {
    /// Rows of `A` (length of `b`).
    pub m: usize,
    /// Columns of `A` (variables).
    pub n: usize,
    /// `A` in compressed sparse column form: column pointers (`n + 1`).
    pub a_colptr: Vec<usize>,
    /// `A`: row index of each nonzero.
    pub a_rowval: Vec<usize>,
    /// `A`: value of each nonzero.
    pub a_nzval: Vec<f64>,
    /// Right-hand side `b` (`m`).
    pub b: Vec<f64>,
    /// Linear objective `q` (`n`).
    pub q: Vec<f64>,
    /// The cones in row order: `("zero" | "nonneg" | "psd_triangle", dimension)`, the
    /// dimension of a PSD triangle cone being the matrix side.
    pub cones: Vec<(&'static str, usize)>,
    /// The numeric Clarabel settings this crate sets (all others are at Clarabel's
    /// defaults), as `(name, value)` in Clarabel's own setting names (`max_iter`,
    /// `tol_gap_abs`, …; booleans as 0/1); `time_limit` is omitted when infinite.
    pub settings: Vec<(&'static str, f64)>,
    /// Clarabel's `chordal_decomposition_merge_method` (`"none"` or `"clique_graph"`).
    pub merge_method: &'static str,
    /// Clarabel's status (its `Debug` name, e.g. `Solved`).
    pub status: String,
    /// Iterations Clarabel took.
    pub iterations: u32,
    /// Clarabel's own `solve_time` in seconds.
    pub solve_time: f64,
    /// Objective value in the solver's scaling.
    pub obj_val: f64,
    /// Final primal residual.
    pub r_prim: f64,
    /// Final dual residual.
    pub r_dual: f64,
}

thread_local! {
    static CAPTURE: RefCell<Option<Vec<ConicProblem>>> = const { RefCell::new(None) };
}

/// Runs `f` and returns, next to its result, the conic problem of every Clarabel solve
/// this crate made on the current thread while `f` ran, in order (see [`ConicProblem`]).
/// Outside this function nothing is recorded (one thread-local flag is read per solve).
/// Nested calls record into the innermost one.
pub fn capture_conic_problems<R>(f: impl FnOnce() -> R) -> (R, Vec<ConicProblem>) {
    /// Restores the enclosing capture state even if `f` unwinds.
    struct Restore(Option<Option<Vec<ConicProblem>>>);
    impl Drop for Restore {
        fn drop(&mut self) {
            if let Some(outer) = self.0.take() {
                CAPTURE.with(|c| c.replace(outer));
            }
        }
    }
    let mut restore = Restore(Some(CAPTURE.with(|c| c.replace(Some(Vec::new())))));
    let r = f();
    let outer = restore.0.take().unwrap_or_default();
    let got = CAPTURE.with(|c| c.replace(outer)).unwrap_or_default();
    (r, got)
}

/// The Clarabel settings [`solve`] sets, by Clarabel's names (for [`ConicProblem`]).
#[cfg(feature = "clarabel")]
fn capture_settings(s: &Settings) -> Vec<(&'static str, f64)> {
    let mut v = vec![
        ("max_iter", f64::from(s.max_iterations)),
        ("tol_gap_abs", s.gap_abs),
        ("tol_gap_rel", s.gap_rel),
        ("tol_feas", s.feasibility),
        ("tol_infeas_abs", s.infeasibility),
        ("tol_infeas_rel", s.infeasibility),
        (
            "chordal_decomposition_enable",
            f64::from(u8::from(s.chordal_decomposition)),
        ),
        (
            "iterative_refinement_enable",
            f64::from(u8::from(s.refinement_steps > 0)),
        ),
        (
            "iterative_refinement_max_iter",
            f64::from(s.refinement_steps),
        ),
    ];
    if s.time_limit.is_finite() {
        v.push(("time_limit", s.time_limit));
    }
    v
}

/// Clarabel's `chordal_decomposition_merge_method` for [`Settings::merge_cliques`].
#[cfg(feature = "clarabel")]
fn merge_method(s: &Settings) -> &'static str {
    if s.merge_cliques {
        "clique_graph"
    } else {
        "none"
    }
}

/// Without the `clarabel` feature: no Clarabel to hand the problem to (module docs).
#[cfg(not(feature = "clarabel"))]
pub(crate) fn solve(
    _problem: &Problem,
    data: &ConicData,
    _settings: &Settings,
) -> Result<RawSolution> {
    Err(LmiError::Solver(format!(
        "Clarabel is not built in (pendulab-lmi without its `clarabel` feature); the dense \
         method did not solve this problem ({} variables, {} rows)",
        data.n, data.m
    )))
}

/// Solves the conic form with Clarabel (module docs).
#[cfg(feature = "clarabel")]
pub(crate) fn solve(
    problem: &Problem,
    data: &ConicData,
    settings: &Settings,
) -> Result<RawSolution> {
    let setup_start = Instant::now();
    let (m, n) = (data.m, data.n);
    let a = CscMatrix::new(
        m,
        n,
        data.colptr.clone(),
        data.rowval.clone(),
        data.nzval.clone(),
    );
    let p = CscMatrix::<f64>::zeros((n, n));
    let cones: Vec<SupportedConeT<f64>> = data
        .cones
        .iter()
        .map(|k| match *k {
            ConeKind::Zero(d) => SupportedConeT::ZeroConeT(d),
            ConeKind::NonNegative(d) => SupportedConeT::NonnegativeConeT(d),
            ConeKind::Psd(d) => SupportedConeT::PSDTriangleConeT(d),
        })
        .collect();
    let clarabel_settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .max_iter(settings.max_iterations)
        .time_limit(settings.time_limit)
        .tol_gap_abs(settings.gap_abs)
        .tol_gap_rel(settings.gap_rel)
        .tol_feas(settings.feasibility)
        .tol_infeas_abs(settings.infeasibility)
        .tol_infeas_rel(settings.infeasibility)
        .chordal_decomposition_enable(settings.chordal_decomposition)
        .chordal_decomposition_merge_method(merge_method(settings).into())
        .iterative_refinement_enable(settings.refinement_steps > 0)
        .iterative_refinement_max_iter(settings.refinement_steps)
        .direct_solve_method(settings.kkt_solver.method(data.dims.kkt_dimension()).into())
        .build()
        .map_err(|e| LmiError::Solver(format!("settings: {e}")))?;
    let mut solver = DefaultSolver::new(&p, &data.q, &a, &data.b, &cones, clarabel_settings)
        .map_err(|e| LmiError::Solver(format!("{e:?}")))?;
    let setup_seconds = setup_start.elapsed().as_secs_f64();

    let run = catch_unwind(AssertUnwindSafe(|| {
        solver.solve();
    }));
    let status = if run.is_err() {
        RawStatus::Crashed
    } else {
        match solver.solution.status {
            SolverStatus::Solved => RawStatus::Solved,
            SolverStatus::AlmostSolved => RawStatus::AlmostSolved,
            SolverStatus::PrimalInfeasible => RawStatus::Infeasible,
            SolverStatus::AlmostPrimalInfeasible => RawStatus::AlmostInfeasible,
            SolverStatus::DualInfeasible => RawStatus::Unbounded,
            SolverStatus::AlmostDualInfeasible => RawStatus::AlmostUnbounded,
            SolverStatus::MaxIterations => RawStatus::MaxIterations,
            SolverStatus::MaxTime => RawStatus::MaxTime,
            SolverStatus::NumericalError => RawStatus::NumericalError,
            SolverStatus::InsufficientProgress => RawStatus::InsufficientProgress,
            SolverStatus::Unsolved | SolverStatus::CallbackTerminated => RawStatus::NumericalError,
        }
    };
    let sol = &solver.solution;
    CAPTURE.with(|c| {
        if let Some(list) = c.borrow_mut().as_mut() {
            list.push(ConicProblem {
                m,
                n,
                a_colptr: a.colptr.clone(),
                a_rowval: a.rowval.clone(),
                a_nzval: a.nzval.clone(),
                b: data.b.clone(),
                q: data.q.clone(),
                cones: data
                    .cones
                    .iter()
                    .map(|k| match *k {
                        ConeKind::Zero(d) => ("zero", d),
                        ConeKind::NonNegative(d) => ("nonneg", d),
                        ConeKind::Psd(d) => ("psd_triangle", d),
                    })
                    .collect(),
                settings: capture_settings(settings),
                merge_method: merge_method(settings),
                status: format!("{:?}", sol.status),
                iterations: sol.iterations,
                solve_time: sol.solve_time,
                obj_val: sol.obj_val,
                r_prim: sol.r_prim,
                r_dual: sol.r_dual,
            });
        }
    });

    let solved = matches!(status, RawStatus::Solved | RawStatus::AlmostSolved);
    let objective =
        (solved && problem.objective.is_some()).then(|| data.user_objective(sol.obj_val));
    Ok(RawSolution {
        status,
        x: data.user_x(&sol.x),
        duals: data.duals(problem, &sol.z),
        objective,
        iterations: sol.iterations,
        solver_seconds: sol.solve_time,
        setup_seconds,
        primal_residual: sol.r_prim,
        dual_residual: sol.r_dual,
        dims: data.dims.clone(),
    })
}

/// Clarabel's answer to a convex QP ([`solve_qp`]).
#[derive(Debug, Clone, PartialEq)]
pub struct QpAnswer {
    /// Clarabel's status (its `Debug` name, e.g. `Solved`).
    pub status: String,
    /// Whether the status is `Solved`.
    pub solved: bool,
    /// The minimiser `x` (length `n`).
    pub x: Vec<f64>,
    /// The multipliers `z ≥ 0` of `A x ≤ b` (length `m`).
    pub z: Vec<f64>,
    /// Interior-point iterations.
    pub iterations: u32,
    /// Clarabel's own solve time \[s\] (without the setup, which is timed by the caller).
    pub solve_seconds: f64,
}

/// Solves `minimise ½ xᵀPx + qᵀx  s.t.  A x ≤ b` (`P` symmetric positive semidefinite,
/// dense) with Clarabel's native QP path (the nonnegative cone `s = b − Ax ≥ 0`), tolerances
/// `tolerance` on the gap and feasibility. A cross-check and comparison for QP methods of
/// other crates (`pendulab-control`'s MPC), through the one file that knows Clarabel.
///
/// # Errors
/// [`LmiError::Solver`] for inconsistent sizes, Clarabel's refusal of the data or settings,
/// or a build without the `clarabel` feature. An infeasible QP is a status, not an error.
pub fn solve_qp(
    p: &pendulab_lti::Mat,
    q: &[f64],
    a: &pendulab_lti::Mat,
    b: &[f64],
    tolerance: f64,
) -> Result<QpAnswer> {
    let n = p.nrows();
    let m = a.nrows();
    if p.ncols() != n || q.len() != n || a.ncols() != n || b.len() != m {
        return Err(LmiError::Solver(format!(
            "solve_qp: P {:?}, q {}, A {:?}, b {} are inconsistent",
            p.shape(),
            q.len(),
            a.shape(),
            b.len()
        )));
    }
    qp_clarabel(p, q, a, b, tolerance)
}

#[cfg(not(feature = "clarabel"))]
fn qp_clarabel(
    _p: &pendulab_lti::Mat,
    _q: &[f64],
    _a: &pendulab_lti::Mat,
    _b: &[f64],
    _tolerance: f64,
) -> Result<QpAnswer> {
    Err(LmiError::Solver(
        "Clarabel is not built in (pendulab-lmi without its `clarabel` feature)".into(),
    ))
}

#[cfg(feature = "clarabel")]
fn qp_clarabel(
    p: &pendulab_lti::Mat,
    q: &[f64],
    a: &pendulab_lti::Mat,
    b: &[f64],
    tolerance: f64,
) -> Result<QpAnswer> {
    let n = p.nrows();
    let m = a.nrows();
    // P as its upper triangle in CSC (Clarabel reads the upper triangle), A dense in CSC.
    let csc = |rows: usize, cols: usize, at: &dyn Fn(usize, usize) -> Option<f64>| {
        let (mut colptr, mut rowval, mut nzval) = (vec![0], Vec::new(), Vec::new());
        for c in 0..cols {
            for r in 0..rows {
                if let Some(v) = at(r, c)
                    && v != 0.0
                {
                    rowval.push(r);
                    nzval.push(v);
                }
            }
            colptr.push(rowval.len());
        }
        CscMatrix::new(rows, cols, colptr, rowval, nzval)
    };
    let pm = csc(n, n, &|r, c| {
        (r <= c).then(|| 0.5 * (p[(r, c)] + p[(c, r)]))
    });
    let am = csc(m, n, &|r, c| Some(a[(r, c)]));
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(tolerance)
        .tol_gap_rel(tolerance)
        .tol_feas(tolerance)
        .build()
        .map_err(|e| LmiError::Solver(format!("settings: {e}")))?;
    let cones = [SupportedConeT::NonnegativeConeT(m)];
    let mut solver = DefaultSolver::new(&pm, q, &am, b, &cones, settings)
        .map_err(|e| LmiError::Solver(format!("{e:?}")))?;
    solver.solve();
    let sol = &solver.solution;
    Ok(QpAnswer {
        status: format!("{:?}", sol.status),
        solved: matches!(sol.status, SolverStatus::Solved),
        x: sol.x.clone(),
        z: sol.z.clone(),
        iterations: sol.iterations,
        solve_seconds: sol.solve_time,
    })
}
