//! State-feedback synthesis by LMIs: guaranteed-cost LQ, pole regions, polytopic robustness,
//! input saturation.

use super::Region;
use crate::error::{LmiError, Result};
use crate::expr::Expr;
use crate::linalg::{check_finite, check_shape, psd_sqrt};
use crate::problem::Problem;
use crate::solution::{Solution, SolveOptions, Status};
use pendulab_lti::{Complex64, Mat};

/// One plant model `ẋ = A x + B u`: the nominal model or a vertex of a polytope of models.
#[derive(Debug, Clone, PartialEq)]
pub struct Vertex {
    /// `A` (`n × n`).
    pub a: Mat,
    /// `B` (`n × m`).
    pub b: Mat,
}

/// Quadratic cost `J = ∫₀^∞ (xᵀ Q x + uᵀ R u) dt`.
#[derive(Debug, Clone, PartialEq)]
pub struct LqWeights {
    /// `Q ⪰ 0` (`n × n`, symmetric).
    pub q: Mat,
    /// `R ≻ 0` (`m × m`, symmetric).
    pub r: Mat,
}

/// Input-saturation avoidance: `|u_i(t)| ≤ u_max_i` for all `t ≥ 0` from every listed initial
/// state, by the invariant ellipsoid `E = {x : xᵀ X⁻¹ x ≤ 1}`.
#[derive(Debug, Clone, PartialEq)]
pub struct InputBound {
    /// Bound of each input (`m` positive numbers, input units).
    pub u_max: Vec<f64>,
    /// Initial states that must lie in `E` (each of length `n`).
    pub initial_states: Vec<Vec<f64>>,
}

/// What to do after the optimisation (maximise `tr X`) has been solved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Refinement {
    /// Return the optimiser's solution.
    None,
    /// Re-solve as a feasibility problem with `tr X ≥ (1 − relax) · tr X*`: the
    /// interior-point method then returns a point well inside the feasible set, with
    /// strictly satisfied LMIs, instead of one on its boundary.
    Feasibility {
        /// Relative relaxation of the optimal objective (e.g. 0.06).
        relax: f64,
    },
    /// [`Refinement::Feasibility`] only when the optimisation did not end cleanly (status
    /// other than [`Status::Solved`], or a recheck failing): maximising `tr X` under pole
    /// regions or several vertices typically drives `X` to the margin `X ⪰ εI` (an optimum
    /// on the boundary with `κ(X) ~ 10⁹`), which double-precision interior-point methods
    /// reach only to reduced accuracy.
    WhenInaccurate {
        /// Relative relaxation of the optimal objective (e.g. 0.01).
        relax: f64,
    },
}

/// Coordinates the LMIs are solved in: `x = T x̂`, `T = diag(t)`. This is a congruence of
/// every LMI (margins included), so the feasible set and the optimum are unchanged; results
/// are returned in the plant's coordinates.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum StateScaling {
    /// The plant's coordinates.
    None,
    /// The given positive `t` (one per state).
    Diagonal(Vec<f64>),
    /// For the plain LQ design (one model, no regions, no input bound): `t_i = √X_ii` of
    /// the optimal `X = P⁻¹` estimated from the Riccati equation, so that `X̂` has unit
    /// diagonal (halves the solver's iterations on the book's servo). The plant's
    /// coordinates for every other specification.
    #[default]
    Auto,
}

/// Specification of [`state_feedback`].
#[derive(Debug, Clone, PartialEq)]
pub struct StateFeedbackSpec {
    /// Guaranteed-cost LQ condition (and objective: maximise `tr X`). Default None.
    pub lq: Option<LqWeights>,
    /// Pole regions every closed loop must satisfy. Default empty.
    pub regions: Vec<Region>,
    /// Input bounds by invariant ellipsoids. Default None.
    pub input_bound: Option<InputBound>,
    /// Post-optimisation re-solve. Default `WhenInaccurate { relax: 0.01 }`.
    pub refinement: Refinement,
    /// Coordinates to solve in. Default [`StateScaling::Auto`].
    pub scaling: StateScaling,
    /// Margin `ε` of the strict inequalities (`≺ 0` imposed as `⪯ −εI`). Default 1e-6.
    pub margin: f64,
}

impl Default for StateFeedbackSpec {
    fn default() -> Self {
        Self {
            lq: None,
            regions: Vec::new(),
            input_bound: None,
            refinement: Refinement::WhenInaccurate { relax: 0.01 },
            scaling: StateScaling::Auto,
            margin: 1e-6,
        }
    }
}

/// The gain and its certificate.
#[derive(Debug, Clone, PartialEq)]
pub struct Feedback {
    /// `K = −L X⁻¹` (`m × n`); the control law is `u = −K x`.
    pub gain: Mat,
    /// The Lyapunov matrix `X ≻ 0` (`V(x) = xᵀ X⁻¹ x`).
    pub x: Mat,
    /// `L = −K X`.
    pub l: Mat,
    /// Eigenvalues of `A − B K` at each vertex.
    pub closed_loop_poles: Vec<Vec<Complex64>>,
    /// Whether every closed-loop pole of every vertex lies inside every region.
    pub poles_in_regions: bool,
}

impl Feedback {
    /// The guaranteed LQ cost bound `x₀ᵀ X⁻¹ x₀` from the initial state `x0`.
    ///
    /// # Errors
    /// [`LmiError::ShapeMismatch`] for a wrong length; [`LmiError::InvalidArgument`] if `X`
    /// is not positive definite.
    pub fn cost_bound(&self, x0: &[f64]) -> Result<f64> {
        let n = self.x.nrows();
        if x0.len() != n {
            return Err(LmiError::ShapeMismatch {
                op: "cost_bound: x0".into(),
                left: (n, 1),
                right: (x0.len(), 1),
            });
        }
        let chol = self.x.clone().cholesky().ok_or(LmiError::InvalidArgument {
            what: "X".into(),
            reason: "not positive definite".into(),
        })?;
        let v = pendulab_lti::Vector::from_column_slice(x0);
        Ok(v.dot(&chol.solve(&v)))
    }
}

/// Result of [`state_feedback`].
#[derive(Debug, Clone)]
pub struct StateFeedbackDesign {
    /// Status of the final solve (the refinement if one was run, else the optimisation).
    pub status: Status,
    /// The gain when the final solve succeeded and passed its rechecks.
    pub feedback: Option<Feedback>,
    /// The optimisation solve (rechecks, iterations, timing).
    pub solution: Solution,
    /// The feasibility re-solve, if requested and the optimisation succeeded.
    pub refined: Option<Solution>,
}

/// Whether a region by itself forces `Re λ < 0` (so no separate stability LMI is needed).
fn implies_stability(r: &Region) -> bool {
    match r {
        Region::DecayRate { alpha } => *alpha >= 0.0,
        Region::Sector { .. } => true,
        Region::Disk { center, radius } => center >= radius,
        _ => false,
    }
}

/// A factor `C` with `CᵀC = Q` and only as many rows as `Q` has positive eigenvalues.
pub(crate) fn weight_factor(what: &str, q: &Mat) -> Result<Mat> {
    let s = psd_sqrt(what, q)?;
    // Drop the null directions: rows of the symmetric root along zero eigenvalues are zero
    // in the eigenbasis. Use the eigenbasis form C = diag(√λ₊) V₊ᵀ.
    let e = crate::linalg::sym(q).symmetric_eigen();
    let tol = 1e-12 * q.norm().max(f64::MIN_POSITIVE);
    let keep: Vec<usize> = (0..q.nrows()).filter(|&i| e.eigenvalues[i] > tol).collect();
    if keep.len() == q.nrows() {
        return Ok(s);
    }
    let mut c = Mat::zeros(keep.len(), q.ncols());
    for (r, &i) in keep.iter().enumerate() {
        let scale = e.eigenvalues[i].sqrt();
        for j in 0..q.ncols() {
            c[(r, j)] = scale * e.eigenvectors[(j, i)];
        }
    }
    Ok(c)
}

fn validate(vertices: &[Vertex], spec: &StateFeedbackSpec) -> Result<(usize, usize)> {
    let first = vertices.first().ok_or(LmiError::InvalidArgument {
        what: "vertices".into(),
        reason: "at least one plant model is needed".into(),
    })?;
    let (n, m) = (first.a.nrows(), first.b.ncols());
    if n == 0 || m == 0 {
        return Err(LmiError::InvalidArgument {
            what: "plant".into(),
            reason: format!("needs n ≥ 1 states and m ≥ 1 inputs, got n = {n}, m = {m}"),
        });
    }
    for (k, v) in vertices.iter().enumerate() {
        check_shape(&format!("A of vertex {k}"), &v.a, n, n)?;
        check_shape(&format!("B of vertex {k}"), &v.b, n, m)?;
        check_finite(&format!("A of vertex {k}"), &v.a)?;
        check_finite(&format!("B of vertex {k}"), &v.b)?;
    }
    if !(spec.margin.is_finite() && spec.margin > 0.0) {
        return Err(LmiError::InvalidArgument {
            what: "margin".into(),
            reason: format!("must be finite and > 0, got {}", spec.margin),
        });
    }
    if let Some(lq) = &spec.lq {
        check_shape("Q", &lq.q, n, n)?;
        check_shape("R", &lq.r, m, m)?;
        check_finite("Q", &lq.q)?;
        check_finite("R", &lq.r)?;
        let rmin = crate::linalg::sym(&lq.r)
            .symmetric_eigenvalues()
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        if rmin.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(LmiError::InvalidArgument {
                what: "R".into(),
                reason: format!("must be positive definite (smallest eigenvalue {rmin:e})"),
            });
        }
    }
    for r in &spec.regions {
        r.matrices()?;
    }
    if let Some(ib) = &spec.input_bound {
        if ib.u_max.len() != m {
            return Err(LmiError::ShapeMismatch {
                op: "input bound u_max".into(),
                left: (m, 1),
                right: (ib.u_max.len(), 1),
            });
        }
        if let Some(v) = ib.u_max.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
            return Err(LmiError::InvalidArgument {
                what: "u_max".into(),
                reason: format!("bounds must be finite and > 0, got {v}"),
            });
        }
        for x0 in &ib.initial_states {
            if x0.len() != n {
                return Err(LmiError::ShapeMismatch {
                    op: "initial state".into(),
                    left: (n, 1),
                    right: (x0.len(), 1),
                });
            }
            if x0.iter().any(|v| !v.is_finite()) {
                return Err(LmiError::InvalidArgument {
                    what: "initial state".into(),
                    reason: "non-finite entry".into(),
                });
            }
        }
    }
    if let Refinement::Feasibility { relax } | Refinement::WhenInaccurate { relax } =
        spec.refinement
        && !(relax.is_finite() && (0.0..1.0).contains(&relax))
    {
        return Err(LmiError::InvalidArgument {
            what: "refinement relax".into(),
            reason: format!("must be in [0, 1), got {relax}"),
        });
    }
    Ok((n, m))
}

/// State-feedback synthesis over one or several plant models with a common Lyapunov matrix.
///
/// Variables `X = Xᵀ` (`n × n`) and `L` (`m × n`); the gain is `K = −L X⁻¹`, the closed loop
/// at vertex `k` is `A_k − B_k K` and `A_k X − B_k K X = A_k X + B_k L =: Y_k`. Constraints
/// (strict ones with the margin `ε` of the spec):
///
/// - `X ≻ 0`;
/// - **LQ guaranteed cost** (if `spec.lq`), at every vertex, with `Q = C_qᵀ C_q`:
///   ```text
///   [ He(Y_k)   X C_qᵀ   Lᵀ R^½ ]
///   [ C_q X     −I       0      ]  ≺ 0
///   [ R^½ L     0        −I     ]
///   ```
///   equivalent (Schur complement, `P = X⁻¹`) to
///   `(A−BK)ᵀP + P(A−BK) + Q + KᵀRK ≺ 0`, so `J ≤ x₀ᵀ X⁻¹ x₀`; the objective is then to
///   maximise `tr X`, which for one vertex drives `X⁻¹` to the Riccati solution and `K` to
///   the LQR gain;
/// - **pole regions** `spec.regions`, at every vertex: `L_D ⊗ X + M_D ⊗ Y_k + M_Dᵀ ⊗ Y_kᵀ ≺ 0`
///   (Chilali–Gahinet);
/// - if neither of these implies stability: `He(Y_k) ≺ 0`;
/// - **input bound** (if `spec.input_bound`): `[[X, L_iᵀ], [L_i, u_max_i²]] ⪰ 0` for every
///   input row `L_i` (so `|u_i| = |K_i x| ≤ u_max_i` on `E = {xᵀX⁻¹x ≤ 1}`) and
///   `[[1, x₀ᵀ], [x₀, X]] ⪰ 0` for every initial state (`x₀ ∈ E`); since `E` is invariant,
///   the input never exceeds its bound from those initial states.
///
/// Without `lq` the problem is a feasibility problem. `spec.refinement` optionally re-solves
/// for a point inside the feasible set.
///
/// An infeasible specification is reported in the returned `status` (with a certificate),
/// `feedback` then being `None`.
///
/// # Errors
/// Shape, finiteness and range errors of the data ([`LmiError::ShapeMismatch`],
/// [`LmiError::NonFinite`], [`LmiError::InvalidArgument`]), solver setup errors.
pub fn state_feedback(
    vertices: &[Vertex],
    spec: &StateFeedbackSpec,
    options: &SolveOptions,
) -> Result<StateFeedbackDesign> {
    let (n, _) = validate(vertices, spec)?;
    let t = match &spec.scaling {
        StateScaling::None => vec![1.0; n],
        StateScaling::Diagonal(t) => {
            if t.len() != n {
                return Err(LmiError::ShapeMismatch {
                    op: "state scaling".into(),
                    left: (n, 1),
                    right: (t.len(), 1),
                });
            }
            if let Some(v) = t.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
                return Err(LmiError::InvalidArgument {
                    what: "state scaling".into(),
                    reason: format!("entries must be finite and > 0, got {v}"),
                });
            }
            t.clone()
        }
        StateScaling::Auto => auto_scaling(vertices, spec),
    };
    design_in_scaled_coordinates(vertices, spec, &t, options)
}

/// `t_i = √X_ii` of the LQ-optimal `X` (estimated from the Riccati equation, see
/// [`super::scaling`]) for the plain LQ design; no scaling for other specifications, where
/// the LQ optimum is a poor guide to the solution's scale (measured on the book's designs:
/// fewer iterations for the pole-region design, more for the saturation design).
fn auto_scaling(vertices: &[Vertex], spec: &StateFeedbackSpec) -> Vec<f64> {
    let n = vertices[0].a.nrows();
    let plain_lq = vertices.len() == 1 && spec.regions.is_empty() && spec.input_bound.is_none();
    match (&spec.lq, plain_lq) {
        (Some(lq), true) => {
            super::scaling::lq_scaling(&vertices[0].a, &vertices[0].b, &lq.q, &lq.r)
                .unwrap_or_else(|| vec![1.0; n])
        }
        _ => vec![1.0; n],
    }
}

/// The design in the coordinates `x = T x̂`, `T = diag(t)`; results mapped back.
fn design_in_scaled_coordinates(
    vertices: &[Vertex],
    spec: &StateFeedbackSpec,
    t: &[f64],
    options: &SolveOptions,
) -> Result<StateFeedbackDesign> {
    let n = vertices[0].a.nrows();
    let m = vertices[0].b.ncols();
    let tm = Mat::from_diagonal(&pendulab_lti::Vector::from_column_slice(t));
    let tinv = Mat::from_diagonal(&pendulab_lti::Vector::from_iterator(
        n,
        t.iter().map(|v| 1.0 / v),
    ));
    let eps = spec.margin;
    let scaled = t.iter().any(|v| *v != 1.0);
    // Strict inequalities: in the plant's coordinates `F ≻ 0` is `F ⪰ εI`. In the scaled
    // coordinates the congruence maps εI to ε·D (D = T⁻² on the state blocks, I elsewhere),
    // which keeps the feasible set exactly that of the unscaled problem.
    let t2inv = &tinv * &tinv;
    let margin_blocks = |k: usize, extra: usize| -> Expr {
        let mut d = Mat::zeros(k * n + extra, k * n + extra);
        for b in 0..k {
            d.view_mut((b * n, b * n), (n, n)).copy_from(&t2inv);
        }
        for i in k * n..k * n + extra {
            d[(i, i)] = 1.0;
        }
        Expr::constant(&(d * eps))
    };
    let mut p = Problem::new();
    let x = p.symmetric("X", n);
    let l = p.matrix("L", m, n);
    let negative = |p: &mut Problem, name: &str, f: &Expr, k: usize, extra: usize| {
        if scaled {
            p.negative_semidefinite(name, &(f + &margin_blocks(k, extra)))
        } else {
            p.negative_definite(name, f, eps)
        }
    };
    if scaled {
        p.positive_semidefinite("X ≻ 0", &(&x - &margin_blocks(1, 0)))?;
    } else {
        p.positive_definite("X ≻ 0", &x, eps)?;
    }
    let weights = match &spec.lq {
        Some(lq) => Some((weight_factor("Q", &lq.q)? * &tm, psd_sqrt("R", &lq.r)?)),
        None => None,
    };
    let needs_stability = weights.is_none() && !spec.regions.iter().any(implies_stability);
    for (k, v) in vertices.iter().enumerate() {
        let a_hat = &tinv * &v.a * &tm;
        let b_hat = &tinv * &v.b;
        let y = &a_hat * &x + &b_hat * &l;
        if let Some((cq, rh)) = &weights {
            let rq = cq.nrows();
            let xc = &x * &Expr::constant(&cq.transpose());
            let lr = l.t() * rh;
            let lmi = Expr::block(&[
                &[&y.he(), &xc, &lr],
                &[
                    &xc.t(),
                    &Expr::identity(rq).scale(-1.0),
                    &Expr::zeros(rq, m),
                ],
                &[&lr.t(), &Expr::zeros(m, rq), &Expr::identity(m).scale(-1.0)],
            ]);
            negative(&mut p, &format!("LQ cost, vertex {k}"), &lmi, 1, rq + m)?;
        }
        for (j, r) in spec.regions.iter().enumerate() {
            let d = r.lmi(&x, &y)?;
            let blocks = d.nrows() / n;
            negative(&mut p, &format!("region {j}, vertex {k}"), &d, blocks, 0)?;
        }
        if needs_stability {
            negative(&mut p, &format!("stability, vertex {k}"), &y.he(), 1, 0)?;
        }
    }
    if let Some(ib) = &spec.input_bound {
        for (i, umax) in ib.u_max.iter().enumerate() {
            let li = l.sub_block(i, 0, 1, n);
            let e = Expr::block(&[&[&x, &li.t()], &[&li, &Expr::scalar(umax * umax)]]);
            p.positive_semidefinite(&format!("|u_{i}| ≤ {umax} on the ellipsoid"), &e)?;
        }
        for (k, x0) in ib.initial_states.iter().enumerate() {
            let x0h = &tinv * Mat::from_column_slice(n, 1, x0);
            let x0e = Expr::constant(&x0h);
            let e = Expr::block(&[&[&Expr::scalar(1.0), &x0e.t()], &[&x0e, &x]]);
            p.positive_semidefinite(&format!("initial state {k} in the ellipsoid"), &e)?;
        }
    }
    // tr X = tr(T X̂ T) = tr(T² X̂).
    let tr = (&(&tm * &tm) * &x).trace();
    if weights.is_some() {
        p.maximize(&tr)?;
    }
    let solution = p.solve(options)?;
    let relax = match spec.refinement {
        Refinement::None => None,
        Refinement::Feasibility { relax } => Some(relax),
        Refinement::WhenInaccurate { relax } => {
            (!(solution.status == Status::Solved && solution.all_checks_pass())).then_some(relax)
        }
    };
    let mut refined = None;
    if let (Some(relax), Some(t_star)) = (relax, solution.objective)
        && solution.status.is_solved()
        && t_star > 0.0
    {
        let mut q = p.clone();
        q.clear_objective();
        q.less_equal(
            "tr X ≥ (1 − relax) tr X*",
            &Expr::scalar((1.0 - relax) * t_star),
            &tr,
        )?;
        refined = Some(q.solve(options)?);
    }
    let final_sol = refined.as_ref().unwrap_or(&solution);
    let status = final_sol.status.clone();
    let feedback = if final_sol.all_checks_pass() {
        let xh = crate::linalg::sym(&final_sol.value(&x)?);
        let lh = final_sol.value(&l)?;
        let xv = crate::linalg::sym(&(&tm * &xh * &tm));
        let lv = &lh * &tm;
        let chol = xv.clone().cholesky().ok_or(LmiError::InvalidArgument {
            what: "X".into(),
            reason: "returned X is not positive definite".into(),
        })?;
        // K = −L X⁻¹  ⇔  Kᵀ = −X⁻¹ Lᵀ.
        let gain = -chol.solve(&lv.transpose()).transpose();
        let mut closed_loop_poles = Vec::with_capacity(vertices.len());
        for v in vertices {
            closed_loop_poles.push(pendulab_lti::linalg::eigenvalues(&(&v.a - &v.b * &gain))?);
        }
        let poles_in_regions = spec
            .regions
            .iter()
            .all(|r| closed_loop_poles.iter().flatten().all(|z| r.contains(*z)));
        Some(Feedback {
            gain,
            x: xv,
            l: lv,
            closed_loop_poles,
            poles_in_regions,
        })
    } else {
        None
    };
    Ok(StateFeedbackDesign {
        status,
        feedback,
        solution,
        refined,
    })
}

/// LMI LQ (guaranteed-cost) state feedback for `ẋ = Ax + Bu`: [`state_feedback`] with the
/// LQ condition only, maximising `tr X`, margin `ε = 1e-6`. The gain approaches the LQR
/// (Riccati) gain as the margin and the solver tolerance go to zero.
///
/// # Errors
/// As [`state_feedback`].
#[doc(alias = "lqr")]
pub fn lq_state_feedback(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    options: &SolveOptions,
) -> Result<StateFeedbackDesign> {
    state_feedback(&one_model(a, b), &lq_spec(q, r), options)
}

/// Multi-objective design: the LQ guaranteed cost plus pole regions (e.g. decay rate,
/// speed limit and damping sector), [`state_feedback`] on one model.
///
/// # Errors
/// As [`state_feedback`].
pub fn multiobjective_state_feedback(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    regions: &[Region],
    options: &SolveOptions,
) -> Result<StateFeedbackDesign> {
    robust_state_feedback(&one_model(a, b), q, r, regions, options)
}

/// Robust design over a polytope of plant models given by its vertices: the LQ guaranteed
/// cost and the pole regions imposed at every vertex with one common `X` and `L` (so the
/// bound and the regions hold for every model in the convex hull, by convexity of the LMIs
/// in `(A, B)`), [`state_feedback`].
///
/// # Errors
/// As [`state_feedback`].
pub fn robust_state_feedback(
    vertices: &[Vertex],
    q: &Mat,
    r: &Mat,
    regions: &[Region],
    options: &SolveOptions,
) -> Result<StateFeedbackDesign> {
    state_feedback(
        vertices,
        &StateFeedbackSpec {
            regions: regions.to_vec(),
            ..lq_spec(q, r)
        },
        options,
    )
}

/// LQ design under an input bound: the LQ guaranteed cost, `|u_i| ≤ u_max_i` on the
/// invariant ellipsoid containing the initial states, maximise `tr X`, then re-solve as a
/// feasibility problem with `tr X ≥ 0.94 tr X*` ([`Refinement::Feasibility`] with
/// `relax = 0.06`, the same 6 % the book allows in its gain-scheduling design) so that the
/// returned gain satisfies the bound with a strict margin.
///
/// # Errors
/// As [`state_feedback`].
pub fn saturated_state_feedback(
    a: &Mat,
    b: &Mat,
    q: &Mat,
    r: &Mat,
    bound: &InputBound,
    options: &SolveOptions,
) -> Result<StateFeedbackDesign> {
    state_feedback(
        &one_model(a, b),
        &StateFeedbackSpec {
            input_bound: Some(bound.clone()),
            refinement: Refinement::Feasibility { relax: 0.06 },
            ..lq_spec(q, r)
        },
        options,
    )
}

/// The polytope of one plant model `ẋ = Ax + Bu`: the single vertex `(A, B)`.
fn one_model(a: &Mat, b: &Mat) -> [Vertex; 1] {
    [Vertex {
        a: a.clone(),
        b: b.clone(),
    }]
}

/// The specification with the LQ guaranteed-cost condition of weights `(Q, R)` only (the
/// defaults of [`StateFeedbackSpec`] otherwise).
fn lq_spec(q: &Mat, r: &Mat) -> StateFeedbackSpec {
    StateFeedbackSpec {
        lq: Some(LqWeights {
            q: q.clone(),
            r: r.clone(),
        }),
        ..StateFeedbackSpec::default()
    }
}
