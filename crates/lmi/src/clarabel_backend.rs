//! The one place that knows Clarabel's problem format.
//!
//! Clarabel solves
//!
//! ```text
//! minimise ½ xᵀPx + qᵀx   subject to   A x + s = b,   s ∈ K
//! ```
//!
//! with `K` a product of cones. Each constraint of a [`Problem`] in its normalised form
//! `G(x) = G₀ + Σ_v x_v G_v` (`= 0`, `≥ 0` entrywise, or `⪰ 0`) becomes a block of rows with
//! `s = G(x)`, i.e. `A = −[vec G_v]`, `b = vec G₀`:
//!
//! - zero cone (`ZeroConeT`): the listed entries (upper triangle only for a symmetric `G`);
//! - nonnegative cone (`NonnegativeConeT`): every entry;
//! - PSD cone (`PSDTriangleConeT(n)`): `svec(G)` = the **upper** triangle **column by
//!   column** (`G₀₀, G₀₁, G₁₁, G₀₂, G₁₂, G₂₂, …`), off-diagonal entries scaled by `√2` so
//!   that `⟨svec A, svec B⟩ = tr(AB)` (Clarabel's `svec_to_mat`/`mat_to_svec` convention,
//!   `src/algebra/dense/matrix_math.rs`).
//!
//! There is no slack variable per LMI and a symmetric matrix variable has `n(n+1)/2`
//! columns, so the problem Clarabel sees has exactly the dimensions of the model.
//!
//! **Scaling.** Each block of rows is divided by its largest coefficient (a positive factor
//! per block keeps every cone invariant), and the objective by its largest coefficient;
//! Clarabel's own Ruiz equilibration then works from well-balanced data. Dual variables are
//! scaled back before they leave this file.
//!
//! **Linear algebra.** Each interior-point iteration factors the quasi-definite KKT matrix
//! `[P  Aᵀ; A  −H]`, where each PSD cone of side `d` contributes a dense `d(d+1)/2` square block
//! of `H` (Nesterov–Todd scaling), with Clarabel's default simplicial LDLᵀ (QDLDL). On the
//! textbook's gain-scheduling SOS program the Gram blocks of side 20–31 make that factor nearly
//! dense and the factorisation dominates the design time (about two thirds of it). Clarabel's
//! `faer-sparse` feature (a supernodal LDLᵀ on dense kernels) halves that time, but brings a
//! second matrix library and about sixty crates into the build; it is left off.

use crate::error::{LmiError, Result};
use crate::problem::{Cone, Problem, Sense};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use pendulab_lapack as _;
use pendulab_lti::Mat;
use std::cell::RefCell;
use std::f64::consts::SQRT_2;
use std::panic::{AssertUnwindSafe, catch_unwind};
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

/// Solver settings handed through from [`crate::SolveOptions`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct Settings {
    pub(crate) max_iterations: u32,
    pub(crate) time_limit: f64,
    pub(crate) gap_abs: f64,
    pub(crate) gap_rel: f64,
    pub(crate) feasibility: f64,
    pub(crate) infeasibility: f64,
    pub(crate) scale_rows: bool,
    pub(crate) chordal_decomposition: bool,
    pub(crate) merge_cliques: bool,
    pub(crate) refinement_steps: u32,
    pub(crate) kkt_solver: crate::KktSolver,
}

/// Outcome of the solver, in this crate's terms.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RawStatus {
    Solved,
    AlmostSolved,
    Infeasible,
    AlmostInfeasible,
    Unbounded,
    AlmostUnbounded,
    MaxIterations,
    MaxTime,
    NumericalError,
    InsufficientProgress,
    /// The solver panicked (e.g. a dense factorisation failed inside it).
    Crashed,
}

/// What the solver returned, mapped back to the problem's variables and constraints.
#[derive(Debug, Clone)]
pub(crate) struct RawSolution {
    pub(crate) status: RawStatus,
    pub(crate) x: Vec<f64>,
    /// Per constraint: the dual variable as a matrix of the shape of `G` (PSD: symmetric
    /// `Z` with `⟨Z, G⟩ = zᵀ s`; zero/nonnegative: the multiplier of each entry, zero for
    /// entries not imposed).
    pub(crate) duals: Vec<Mat>,
    /// Objective value in the user's sense (None when not solved or no objective).
    pub(crate) objective: Option<f64>,
    pub(crate) iterations: u32,
    pub(crate) solver_seconds: f64,
    pub(crate) setup_seconds: f64,
    pub(crate) primal_residual: f64,
    pub(crate) dual_residual: f64,
    pub(crate) dims: Dims,
}

/// Dimensions of the conic problem handed to the solver.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Dims {
    /// Scalar variables (columns of `A`).
    pub variables: usize,
    /// Rows in the zero cone (equalities).
    pub equalities: usize,
    /// Rows in the nonnegative cone.
    pub inequalities: usize,
    /// Side lengths of the PSD cones.
    pub psd_sizes: Vec<usize>,
    /// Nonzeros of `A`.
    pub nonzeros: usize,
}

impl Dims {
    /// Rows of the KKT system Clarabel factors: variables plus constraint rows (a PSD cone of
    /// side `k` contributes its `k(k+1)/2` svec rows). Chooses [`crate::KktSolver::Auto`]'s
    /// factorisation.
    pub fn kkt_dimension(&self) -> usize {
        self.variables
            + self.equalities
            + self.inequalities
            + self
                .psd_sizes
                .iter()
                .map(|k| k * (k + 1) / 2)
                .sum::<usize>()
    }
}

/// Row layout of one constraint block.
struct Block {
    cone: Cone,
    start: usize,
    len: usize,
    /// Positive factor applied to the block's rows.
    scale: f64,
    /// `(i, j)` of each row (for zero / nonnegative blocks).
    entries: Vec<(usize, usize)>,
}

/// The Clarabel settings [`solve`] sets, by Clarabel's names (for [`ConicProblem`]).
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
fn merge_method(s: &Settings) -> &'static str {
    if s.merge_cliques {
        "clique_graph"
    } else {
        "none"
    }
}

/// Index of `(i, j)`, `i ≤ j`, in Clarabel's svec order.
fn svec_index(i: usize, j: usize) -> usize {
    j * (j + 1) / 2 + i
}

pub(crate) fn solve(problem: &Problem, settings: &Settings) -> Result<RawSolution> {
    let setup_start = Instant::now();
    let n = problem.num_scalar_variables();

    // Rows as (row, var, value) triplets plus b.
    let mut trip: Vec<(usize, u32, f64)> = Vec::new();
    let mut b: Vec<f64> = Vec::new();
    let mut blocks: Vec<Block> = Vec::with_capacity(problem.constraints.len());
    let mut cones: Vec<SupportedConeT<f64>> = Vec::new();
    let mut dims = Dims {
        variables: n,
        ..Dims::default()
    };
    // Clarabel accepts cones in any order; keep the constraints' order.
    for c in &problem.constraints {
        let g = &c.g;
        let start = b.len();
        let first_trip = trip.len();
        let mut entries = Vec::new();
        match c.cone {
            Cone::Psd => {
                let dim = g.nrows();
                let len = dim * (dim + 1) / 2;
                b.resize(start + len, 0.0);
                for j in 0..dim {
                    for i in 0..=j {
                        let w = if i == j { 1.0 } else { SQRT_2 };
                        b[start + svec_index(i, j)] = w * g.constant[(i, j)];
                    }
                }
                for l in &g.lin {
                    let (i, j) = (l.row as usize, l.col as usize);
                    if i <= j {
                        let w = if i == j { 1.0 } else { SQRT_2 };
                        trip.push((start + svec_index(i, j), l.var, -w * l.coef));
                    }
                }
                cones.push(SupportedConeT::PSDTriangleConeT(dim));
                dims.psd_sizes.push(dim);
            }
            Cone::Zero | Cone::NonNegative => {
                let (r, cl) = (g.nrows(), g.ncols());
                let mut row_of = vec![usize::MAX; r * cl];
                for j in 0..cl {
                    for i in 0..r {
                        if c.upper_only && i > j {
                            continue;
                        }
                        row_of[i + j * r] = start + entries.len();
                        entries.push((i, j));
                        b.push(g.constant[(i, j)]);
                    }
                }
                for l in &g.lin {
                    let row = row_of[l.row as usize + l.col as usize * r];
                    if row != usize::MAX {
                        trip.push((row, l.var, -l.coef));
                    }
                }
                let len = entries.len();
                if c.cone == Cone::Zero {
                    cones.push(SupportedConeT::ZeroConeT(len));
                    dims.equalities += len;
                } else {
                    cones.push(SupportedConeT::NonnegativeConeT(len));
                    dims.inequalities += len;
                }
            }
        }
        let len = b.len() - start;
        let mut scale = 1.0;
        if settings.scale_rows {
            let big = trip[first_trip..]
                .iter()
                .map(|t| t.2.abs())
                .chain(b[start..].iter().map(|v| v.abs()))
                .fold(0.0, f64::max);
            if big > 0.0 && big.is_finite() {
                scale = 1.0 / big;
                trip[first_trip..].iter_mut().for_each(|t| t.2 *= scale);
                b[start..].iter_mut().for_each(|v| *v *= scale);
            }
        }
        blocks.push(Block {
            cone: c.cone,
            start,
            len,
            scale,
            entries,
        });
    }
    let m = b.len();

    // Homogeneous problems (no constant term in any constraint: only the margins ε_j shift
    // the cones) are invariant under x ↦ x / s; solving with margins ε_j / s, s = max ε_j,
    // and scaling x back is exact and spares the solver a feasible set at distance ε ≈ 1e-6
    // from a cone's apex, where its infeasibility detection stalls.
    let homogeneous = problem
        .constraints
        .iter()
        .all(|c| c.expr.constant.iter().all(|v| *v == 0.0));
    let margin_scale = problem
        .constraints
        .iter()
        .map(|c| c.relation.margin())
        .fold(0.0, f64::max);
    let x_scale = if homogeneous && margin_scale > 0.0 {
        b.iter_mut().for_each(|v| *v /= margin_scale);
        margin_scale
    } else {
        1.0
    };

    // CSC by counting sort on the variable (column), rows ascending within a column.
    let mut colptr = vec![0usize; n + 1];
    for t in &trip {
        colptr[t.1 as usize + 1] += 1;
    }
    for j in 0..n {
        colptr[j + 1] += colptr[j];
    }
    let mut next = colptr.clone();
    let mut rowval = vec![0usize; trip.len()];
    let mut nzval = vec![0.0; trip.len()];
    trip.sort_unstable_by_key(|t| (t.1, t.0));
    for (row, var, v) in &trip {
        let k = next[*var as usize];
        rowval[k] = *row;
        nzval[k] = *v;
        next[*var as usize] += 1;
    }
    dims.nonzeros = trip.len();
    let a = CscMatrix::new(m, n, colptr, rowval, nzval);
    let p = CscMatrix::<f64>::zeros((n, n));

    // Objective.
    let mut q = vec![0.0; n];
    let mut obj_scale = 1.0;
    let mut obj_offset = 0.0;
    let mut obj_sign = 1.0;
    if let Some((sense, f)) = &problem.objective {
        obj_sign = if *sense == Sense::Maximize { -1.0 } else { 1.0 };
        obj_offset = f.constant[(0, 0)];
        for l in &f.lin {
            q[l.var as usize] += obj_sign * l.coef;
        }
        let big = q.iter().map(|v| v.abs()).fold(0.0, f64::max);
        if settings.scale_rows && big > 0.0 {
            obj_scale = big;
            q.iter_mut().for_each(|v| *v /= big);
        }
    }

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
        .direct_solve_method(settings.kkt_solver.method(dims.kkt_dimension()).into())
        .build()
        .map_err(|e| LmiError::Solver(format!("settings: {e}")))?;
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, clarabel_settings)
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
                b: b.clone(),
                q: q.clone(),
                cones: cones
                    .iter()
                    .map(|k| match k {
                        SupportedConeT::ZeroConeT(d) => ("zero", *d),
                        SupportedConeT::NonnegativeConeT(d) => ("nonneg", *d),
                        SupportedConeT::PSDTriangleConeT(d) => ("psd_triangle", *d),
                        _ => ("other", 0),
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

    // Duals back to matrices in the constraints' (unscaled) normalised form.
    let duals = problem
        .constraints
        .iter()
        .zip(&blocks)
        .map(|(c, blk)| {
            let z = sol.z.get(blk.start..blk.start + blk.len).unwrap_or(&[]);
            let z_at = |k: usize| z.get(k).copied().unwrap_or(f64::NAN) * blk.scale;
            match blk.cone {
                Cone::Psd => {
                    let dim = c.g.nrows();
                    let mut zm = Mat::zeros(dim, dim);
                    for j in 0..dim {
                        for i in 0..=j {
                            let v = z_at(svec_index(i, j));
                            if i == j {
                                zm[(i, i)] = v;
                            } else {
                                zm[(i, j)] = v / SQRT_2;
                                zm[(j, i)] = v / SQRT_2;
                            }
                        }
                    }
                    zm
                }
                Cone::Zero | Cone::NonNegative => {
                    let mut zm = Mat::zeros(c.g.nrows(), c.g.ncols());
                    for (k, &(i, j)) in blk.entries.iter().enumerate() {
                        zm[(i, j)] = z_at(k);
                    }
                    zm
                }
            }
        })
        .collect();

    let solved = matches!(status, RawStatus::Solved | RawStatus::AlmostSolved);
    let objective = (solved && problem.objective.is_some())
        .then_some(obj_sign * sol.obj_val * obj_scale * x_scale + obj_offset);
    Ok(RawSolution {
        status,
        x: sol.x.iter().map(|v| v * x_scale).collect(),
        duals,
        objective,
        iterations: sol.iterations,
        solver_seconds: sol.solve_time,
        setup_seconds,
        primal_residual: sol.r_prim,
        dual_residual: sol.r_dual,
        dims,
    })
}
