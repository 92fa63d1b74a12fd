//! The conic form every solver of this crate receives.
//!
//! A [`Problem`] is handed to a solver as
//!
//! ```text
//! minimise qᵀx   subject to   A x + s = b,   s ∈ K
//! ```
//!
//! with `K` a product of cones, one block of rows per constraint, in the constraints' order.
//! Each constraint in its normalised form `G(x) = G₀ + Σ_v x_v G_v` (`= 0`, `≥ 0` entrywise,
//! or `⪰ 0`) becomes a block of rows with `s = G(x)`, i.e. `A = −[vec G_v]`, `b = vec G₀`:
//!
//! - zero cone: the listed entries (upper triangle only for a symmetric `G`);
//! - nonnegative cone: every entry;
//! - PSD cone of side `d`: `svec(G)` = the **upper** triangle **column by column**
//!   (`G₀₀, G₀₁, G₁₁, G₀₂, G₁₂, G₂₂, …`), off-diagonal entries scaled by `√2` so that
//!   `⟨svec A, svec B⟩ = tr(AB)`. This is also Clarabel's layout (`PSDTriangleConeT`,
//!   `src/algebra/dense/matrix_math.rs` of Clarabel), so its backend takes the rows as they
//!   are.
//!
//! There is no slack variable per LMI and a symmetric matrix variable has `n(n+1)/2`
//! columns, so the conic problem has exactly the dimensions of the model.
//!
//! **Scaling** ([`SolveOptions::scale_rows`](crate::SolveOptions::scale_rows)). Each block
//! of rows may be divided by its largest coefficient (a positive factor per block keeps
//! every cone invariant), and the objective by its largest coefficient. **Homogeneous
//! problems** (no constant term in any constraint: only the margins `ε_j` shift the cones)
//! are invariant under `x ↦ x / σ`; the rows' `b` (the margins) are divided by
//! `σ = max_j ε_j` and `x` is scaled back, which spares the solvers a feasible set at
//! distance `ε ≈ 10⁻⁶` from a cone's apex. Dual variables and the objective are mapped back
//! by [`ConicData::duals`] and [`ConicData::user_objective`].

use crate::problem::{Cone, Problem, Sense};
use pendulab_lti::Mat;
use std::f64::consts::SQRT_2;

/// One cone of `K`, in row order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ConeKind {
    /// `len` rows that must be zero.
    Zero(usize),
    /// `len` rows that must be nonnegative.
    NonNegative(usize),
    /// The `d(d+1)/2` svec rows of a `d × d` symmetric matrix that must be PSD.
    Psd(usize),
}

impl ConeKind {
    /// Number of rows of the cone.
    pub(crate) fn rows(self) -> usize {
        match self {
            ConeKind::Zero(n) | ConeKind::NonNegative(n) => n,
            ConeKind::Psd(d) => d * (d + 1) / 2,
        }
    }
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
#[derive(Debug, Clone)]
struct Block {
    cone: Cone,
    start: usize,
    len: usize,
    /// Positive factor applied to the block's rows.
    scale: f64,
    /// `(i, j)` of each row (for zero / nonnegative blocks).
    entries: Vec<(usize, usize)>,
}

/// A [`Problem`] in conic form (see the module docs), with what is needed to map a solver's
/// answer back to the problem's variables and constraints.
#[derive(Debug, Clone)]
pub(crate) struct ConicData {
    /// Rows of `A` (length of `b`).
    pub(crate) m: usize,
    /// Columns of `A` (variables).
    pub(crate) n: usize,
    /// `A` in compressed sparse column form: column pointers (`n + 1`).
    pub(crate) colptr: Vec<usize>,
    /// `A`: row index of each nonzero, ascending within a column.
    pub(crate) rowval: Vec<usize>,
    /// `A`: value of each nonzero.
    pub(crate) nzval: Vec<f64>,
    /// Right-hand side `b` (`m`).
    pub(crate) b: Vec<f64>,
    /// Linear objective `q` (`n`), always to be minimised.
    pub(crate) q: Vec<f64>,
    /// The cones in row order.
    pub(crate) cones: Vec<ConeKind>,
    /// Dimensions.
    pub(crate) dims: Dims,
    blocks: Vec<Block>,
    /// `x_user = x_scale · x_solver` (homogeneous problems).
    x_scale: f64,
    /// `objective_user = sign · scale · x_scale · qᵀx + offset`.
    obj_sign: f64,
    obj_scale: f64,
    obj_offset: f64,
}

/// Index of `(i, j)`, `i ≤ j`, in the svec order.
pub(crate) fn svec_index(i: usize, j: usize) -> usize {
    j * (j + 1) / 2 + i
}

impl ConicData {
    /// The conic form of `problem`; `scale_rows` divides each block of rows and the objective
    /// by its largest coefficient.
    pub(crate) fn build(problem: &Problem, scale_rows: bool) -> Self {
        let n = problem.num_scalar_variables();
        // Rows as (row, var, value) triplets plus b.
        let mut trip: Vec<(usize, u32, f64)> = Vec::new();
        let mut b: Vec<f64> = Vec::new();
        let mut blocks: Vec<Block> = Vec::with_capacity(problem.constraints.len());
        let mut cones = Vec::with_capacity(problem.constraints.len());
        let mut dims = Dims {
            variables: n,
            ..Dims::default()
        };
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
                    cones.push(ConeKind::Psd(dim));
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
                        cones.push(ConeKind::Zero(len));
                        dims.equalities += len;
                    } else {
                        cones.push(ConeKind::NonNegative(len));
                        dims.inequalities += len;
                    }
                }
            }
            let len = b.len() - start;
            let mut scale = 1.0;
            if scale_rows {
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

        // Homogeneous problems: see the module docs.
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

        // Objective, always minimised.
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
            if scale_rows && big > 0.0 {
                obj_scale = big;
                q.iter_mut().for_each(|v| *v /= big);
            }
        }
        Self {
            m,
            n,
            colptr,
            rowval,
            nzval,
            b,
            q,
            cones,
            dims,
            blocks,
            x_scale,
            obj_sign,
            obj_scale,
            obj_offset,
        }
    }

    /// The problem's variables from the solver's `x`.
    pub(crate) fn user_x(&self, x: &[f64]) -> Vec<f64> {
        x.iter().map(|v| v * self.x_scale).collect()
    }

    /// The objective in the user's sense from the solver's optimal value `qᵀx`.
    pub(crate) fn user_objective(&self, solver_objective: f64) -> f64 {
        self.obj_sign * solver_objective * self.obj_scale * self.x_scale + self.obj_offset
    }

    /// Per constraint, the dual variable as a matrix of the shape of `G` (PSD: symmetric `Z`
    /// with `⟨Z, G⟩ = zᵀ s`; zero/nonnegative: the multiplier of each entry, zero for entries
    /// not imposed), from the solver's `z` (one entry per row; NaN where `z` is short).
    pub(crate) fn duals(&self, problem: &Problem, z: &[f64]) -> Vec<Mat> {
        problem
            .constraints
            .iter()
            .zip(&self.blocks)
            .map(|(c, blk)| {
                let z = z.get(blk.start..blk.start + blk.len).unwrap_or(&[]);
                // In the user's units of the objective as well (`scale_rows` divides it).
                let z_at =
                    |k: usize| z.get(k).copied().unwrap_or(f64::NAN) * blk.scale * self.obj_scale;
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
            .collect()
    }
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

/// Outcome of a solver, in this crate's terms.
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

/// What a solver returned, mapped back to the problem's variables and constraints.
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
