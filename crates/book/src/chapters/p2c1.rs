//! Part 2 ch. 1 — LMI and control: α-stability, the LMI LQ servo of the arm pendulum,
//! D-stability, polytopic robust design, input saturation and the gain-scheduled servo.
//!
//! Every LMI uses the margin ε = 1e-6 for strict inequalities (the M-files' `ep = 1e-6`). Gains are
//! reported in the book's convention `u = +K x` (pendulab's library uses `u = −K x`).

use super::common::*;
use crate::error::BookError;
use crate::output::{ExampleOutput, Value};
use crate::registry::{Example, RunContext};
use pendulab_lmi::synthesis::{
    GainScheduleSpec, LpvPlant, LqWeights, Region, ScheduledGain, Vertex, gain_scheduled_lq,
};
use pendulab_lmi::{Expr, Problem, SolveOptions, Status};
use pendulab_lti::Mat;
use pendulab_lti::design::lqr;
use pendulab_lti::linalg::eigenvalues;
use pendulab_plants::{ArmPendulum, RigSpec};
use pendulab_plot::{Channel, GainCurves, PoleZeroMap, RegionBound, SignalPanel, TimeResponse};
use pendulab_sim::controllers::{IntegrationRule, LqIntegralServo};
use pendulab_sim::{
    Controller, RunStatus, SampledLoop, SampledOptions, SampledRun, Signal, StayWithin,
};
use std::f64::consts::PI;

const EPS: f64 = 1e-6;
const DEG: f64 = 180.0 / PI;
const ARM: &str = "arm pendulum, book table 3.7";
const GAIN_NOTE: &str = "Gains in the book's convention u = +K x.";
/// What the α-region servo M-files' optimum determines and what it does not.
const ILL_DETERMINED_KT: &str = "trace(X) is certified; Kt = L X⁻¹ is not well determined by this objective: \
     near-optimal points with trace(X) within 1e-5 (relative) of the optimum give gains differing by 5–35 % \
     (pendulab-lmi's Clarabel backend and CVXPY + Clarabel stop there, \"almost solved\"; \
     tools/reference/p2c1_mfile_lmi_cvxpy.py), so the gain any solver reports for this M-file depends on where it stops.";

// ------------------------------------------------------------------ the M-files' LMIs, as written

/// How an M-file states an LMI: `F >= ep*eye` (`F ⪰ εI`), `F <= -ep*eye` (`F ⪯ −εI`) or
/// `F >= 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Rel {
    /// `F ⪰ εI`.
    GeEps,
    /// `F ⪯ −εI`.
    LeNegEps,
    /// `F ⪰ 0`.
    Ge0,
}

/// Affine matrix algebra shared by the solver's expressions ([`Expr`]) and plain matrices
/// ([`Mat`]): each M-file LMI is written once, generically, and both handed to the solver and
/// evaluated at the returned point (and at the unit directions, for the duality certificate).
trait Lin: Sized {
    fn cst(m: &Mat) -> Self;
    fn plus(&self, o: &Self) -> Self;
    fn minus(&self, o: &Self) -> Self;
    /// `m · self`.
    fn lmul(&self, m: &Mat) -> Self;
    /// `self · m`.
    fn rmul(&self, m: &Mat) -> Self;
    fn tr(&self) -> Self;
    fn sc(&self, f: f64) -> Self;
    fn blk(rows: &[&[&Self]]) -> Self;
}

impl Lin for Expr {
    fn cst(m: &Mat) -> Self {
        Expr::constant(m)
    }
    fn plus(&self, o: &Self) -> Self {
        self + o
    }
    fn minus(&self, o: &Self) -> Self {
        self - o
    }
    fn lmul(&self, m: &Mat) -> Self {
        &Expr::constant(m) * self
    }
    fn rmul(&self, m: &Mat) -> Self {
        self * &Expr::constant(m)
    }
    fn tr(&self) -> Self {
        self.t()
    }
    fn sc(&self, f: f64) -> Self {
        self.scale(f)
    }
    fn blk(rows: &[&[&Self]]) -> Self {
        Expr::block(rows)
    }
}

impl Lin for Mat {
    fn cst(m: &Mat) -> Self {
        m.clone()
    }
    fn plus(&self, o: &Self) -> Self {
        self + o
    }
    fn minus(&self, o: &Self) -> Self {
        self - o
    }
    fn lmul(&self, m: &Mat) -> Self {
        m * self
    }
    fn rmul(&self, m: &Mat) -> Self {
        self * m
    }
    fn tr(&self) -> Self {
        self.transpose()
    }
    fn sc(&self, f: f64) -> Self {
        self * f
    }
    fn blk(rows: &[&[&Self]]) -> Self {
        let nr: usize = rows.iter().map(|r| r[0].nrows()).sum();
        let nc: usize = rows[0].iter().map(|b| b.ncols()).sum();
        let mut m = Mat::zeros(nr, nc);
        let mut i = 0;
        for r in rows {
            let mut j = 0;
            for b in *r {
                m.view_mut((i, j), b.shape()).copy_from(*b);
                j += b.ncols();
            }
            i += r[0].nrows();
        }
        m
    }
}

/// The LMI problems of the p2c1 M-files (all maximise `trace(X)`; `obj = -trace(X)`).
#[derive(Debug, Clone)]
enum MfileLmi {
    /// `p2c122_ex4_adip_oc_servo.m`, `p2c122_ex4_adip_oc_multiobjective_servo.m`,
    /// `p2c13_ex5_adip_oc_{nominal,robust}_servo.m`: per model `(At, Bt)`, with
    /// `M = At X + Bt L`: `LMI_lq ⪯ −εI`, optionally `M' + M + 2αX ⪯ −εI`, the sector LMI
    /// `[k(M'+M), M−M'; M'−M, k(M'+M)] ⪯ −εI` and `M' + M + 2βX ⪰ εI`; `X ⪰ εI`.
    Servo {
        models: Vec<(Mat, Mat)>,
        q: Mat,
        r: Mat,
        alpha: Option<f64>,
        sector_k: Option<f64>,
        beta: Option<f64>,
    },
    /// `p2c14_ex6_adip_oc_saturation.m`: `OC1(L) ⪯ −εI`, `OC2(V) ⪯ −εI`,
    /// `MH = [X V'; V σ²] ⪰ 0`, `INI = [X x0; x0' 1] ⪰ 0`, `X ⪰ εI`.
    Saturation {
        a: Mat,
        b: Mat,
        q: Mat,
        r: Mat,
        sigma2: f64,
        x0: Mat,
    },
}

/// `sqrtm` of a diagonal weight (the M-files' Q and R are diagonal).
fn sqrt_diag(m: &Mat) -> Mat {
    Mat::from_fn(m.nrows(), m.ncols(), |i, j| {
        if i == j { m[(i, i)].sqrt() } else { 0.0 }
    })
}

/// The LQ cost LMI of the M-files: `[M'+M, X√Q, L'√R; √Q X, −I, 0; √R L, 0, −1]`.
fn lq_block<T: Lin>(a: &Mat, b: &Mat, q: &Mat, r: &Mat, x: &T, l: &T) -> T {
    let n = a.nrows();
    let m = x.lmul(a).plus(&l.lmul(b));
    let (sq, sr) = (sqrt_diag(q), sqrt_diag(r));
    T::blk(&[
        &[&m.tr().plus(&m), &x.rmul(&sq), &l.tr().rmul(&sr)],
        &[
            &x.lmul(&sq),
            &T::cst(&(-Mat::identity(n, n))),
            &T::cst(&Mat::zeros(n, 1)),
        ],
        &[
            &l.lmul(&sr),
            &T::cst(&Mat::zeros(1, n)),
            &T::cst(&(-Mat::identity(1, 1))),
        ],
    ])
}

impl MfileLmi {
    fn n(&self) -> usize {
        match self {
            MfileLmi::Servo { models, .. } => models[0].0.nrows(),
            MfileLmi::Saturation { a, .. } => a.nrows(),
        }
    }

    fn has_v(&self) -> bool {
        matches!(self, MfileLmi::Saturation { .. })
    }

    /// Every LMI of the M-file, in its order, under its name, as `(name, relation, F)`.
    fn blocks<T: Lin>(&self, x: &T, l: &T, v: Option<&T>) -> Vec<(String, Rel, T)> {
        let n = self.n();
        let mut out = vec![("X >= ep*eye(n)".to_string(), Rel::GeEps, x.sc(1.0))];
        match self {
            MfileLmi::Servo {
                models,
                q,
                r,
                alpha,
                sector_k,
                beta,
            } => {
                for (i, (a, b)) in models.iter().enumerate() {
                    let tag = if models.len() > 1 {
                        format!(" (vertex {})", i + 1)
                    } else {
                        String::new()
                    };
                    let m = x.lmul(a).plus(&l.lmul(b));
                    let he = m.tr().plus(&m);
                    out.push((
                        format!("LMI_lq{tag}"),
                        Rel::LeNegEps,
                        lq_block(a, b, q, r, x, l),
                    ));
                    if let Some(al) = alpha {
                        out.push((
                            format!("LMI_alp{tag}"),
                            Rel::LeNegEps,
                            he.plus(&x.sc(2.0 * al)),
                        ));
                    }
                    if let Some(k) = sector_k {
                        let d = m.minus(&m.tr());
                        out.push((
                            format!("LMI3 (sector){tag}"),
                            Rel::LeNegEps,
                            T::blk(&[&[&he.sc(*k), &d], &[&d.sc(-1.0), &he.sc(*k)]]),
                        ));
                    }
                    if let Some(be) = beta {
                        out.push((
                            format!("LMI_bet{tag}"),
                            Rel::GeEps,
                            he.plus(&x.sc(2.0 * be)),
                        ));
                    }
                }
            }
            MfileLmi::Saturation {
                a,
                b,
                q,
                r,
                sigma2,
                x0,
            } => {
                out.push(("OC1".into(), Rel::LeNegEps, lq_block(a, b, q, r, x, l)));
                if let Some(v) = v {
                    out.push(("OC2".into(), Rel::LeNegEps, lq_block(a, b, q, r, x, v)));
                    out.push((
                        "MH".into(),
                        Rel::Ge0,
                        T::blk(&[
                            &[x, &v.tr()],
                            &[v, &T::cst(&Mat::from_element(1, 1, *sigma2))],
                        ]),
                    ));
                }
                out.push((
                    "INI".into(),
                    Rel::Ge0,
                    T::blk(&[
                        &[x, &T::cst(x0)],
                        &[&T::cst(&x0.transpose()), &T::cst(&Mat::identity(1, 1))],
                    ]),
                ));
                let _ = n;
            }
        }
        out
    }
}

/// The constraint as the solver sees it, `G ⪰ 0`: `F − εI`, `−F − εI` or `F`.
fn normalised(rel: Rel, f: &Mat) -> Mat {
    let k = f.nrows();
    match rel {
        Rel::GeEps => f - Mat::identity(k, k) * EPS,
        Rel::LeNegEps => -f - Mat::identity(k, k) * EPS,
        Rel::Ge0 => f.clone(),
    }
}

/// An M-file LMI solved: the M-file's variables and the optimum's certificate, recomputed here
/// from the M-file's LMIs at the returned point (not taken from the solver).
#[derive(Debug, Clone)]
struct MfileSolution {
    /// `X = double(X)`.
    x: Mat,
    /// `L = double(L)`.
    l: Mat,
    /// `V = double(V)` (saturation only).
    v: Option<Mat>,
    /// Solver status (Solved, or AlmostSolved reported as "inaccurate").
    status: Status,
    /// Which method solved it.
    backend: pendulab_lmi::Backend,
    /// `trace(X)`, the maximised objective.
    trace_x: f64,
    /// `Σ_j ⟨Z_j, G_j(0)⟩`: the dual objective, an upper bound on the optimum when the
    /// stationarity residual is zero.
    dual_bound: f64,
    /// `Σ_j ⟨Z_j, G_j(x*)⟩`: the duality gap at the returned point.
    gap: f64,
    /// `max_v |c_v + Σ_j ⟨Z_j, G_{j,v}⟩| / max(1, ‖Z‖)`: dual stationarity, relative.
    stationarity: f64,
    /// Smallest eigenvalue of each `Z_j` (dual feasibility), the smallest over all LMIs.
    min_dual_eig: f64,
    /// Per LMI (M-file name), the smallest eigenvalue of `G_j(x*)` (≥ 0: satisfied with the
    /// M-file's margin).
    margins: Vec<(String, f64)>,
}

impl MfileSolution {
    /// The smallest eigenvalue of the M-file's LMIs at the point, over all of them.
    fn min_margin(&self) -> f64 {
        self.margins
            .iter()
            .map(|m| m.1)
            .fold(f64::INFINITY, f64::min)
    }

    /// `Kt = L*inv(X)` (the book's sign, u = +Kt x).
    fn kt(&self, id: &str) -> Result<Mat, BookError> {
        let xi = self
            .x
            .clone()
            .try_inverse()
            .ok_or_else(|| fail(id, "X is singular"))?;
        Ok(&self.l * xi)
    }

    /// The status and certificate in one sentence for the output notes.
    fn note(&self, what: &str) -> String {
        let st = match self.status {
            Status::Solved => "solved".to_string(),
            Status::AlmostSolved => "INACCURATE (solved to reduced accuracy only)".to_string(),
            ref s => format!("{s:?}"),
        };
        format!(
            "{what}: the M-file's problem, maximise trace(X), {} LMIs as written there (ε = 1e-6); \
             solver status {st} ({:?}). Certificate recomputed from the M-file's LMIs at the returned point: \
             trace(X) = {:.8}, dual bound = {:.8}, duality gap = {:.2e}, dual stationarity residual = {:.1e}, \
             smallest LMI eigenvalue (after the margin) = {:.2e}, smallest dual eigenvalue = {:.1e}.",
            self.margins.len(),
            self.backend,
            self.trace_x,
            self.dual_bound,
            self.gap,
            self.stationarity,
            self.min_margin(),
            self.min_dual_eig
        )
    }
}

/// `⟨A, B⟩ = tr(AᵀB)`.
fn inner(a: &Mat, b: &Mat) -> f64 {
    a.iter().zip(b.iter()).map(|(x, y)| x * y).sum()
}

/// Smallest eigenvalue of a symmetric matrix (its symmetric part).
fn min_eig(m: &Mat) -> f64 {
    let s = (m + m.transpose()) * 0.5;
    nalgebra::SymmetricEigen::new(s)
        .eigenvalues
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min)
}

/// The M-file's variables `X`, `L` (`V`) and LMIs on a fresh problem, with the constraints'
/// ids in the M-file's order.
#[allow(clippy::type_complexity)]
fn mfile_problem(
    id: &str,
    spec: &MfileLmi,
) -> Result<
    (
        Problem,
        Expr,
        Expr,
        Option<Expr>,
        Vec<pendulab_lmi::ConstraintId>,
    ),
    BookError,
> {
    let n = spec.n();
    let mut p = Problem::new();
    let x = p.symmetric("X", n);
    let l = p.matrix("L", 1, n);
    let v = spec.has_v().then(|| p.matrix("V", 1, n));
    let mut ids = Vec::new();
    for (name, rel, f) in &spec.blocks(&x, &l, v.as_ref()) {
        let cid = match rel {
            Rel::GeEps => p.positive_definite(name, f, EPS),
            Rel::LeNegEps => p.negative_definite(name, f, EPS),
            Rel::Ge0 => p.positive_semidefinite(name, f),
        }
        .ctx(id)?;
        ids.push(cid);
    }
    Ok((p, x, l, v, ids))
}

/// A point of the M-file's feasibility solve (`solvesdp(CON)` with no objective).
#[derive(Debug, Clone)]
struct FeasiblePoint {
    x: Mat,
    l: Mat,
    v: Option<Mat>,
    status: Status,
    backend: pendulab_lmi::Backend,
    /// Per constraint (M-file name), the smallest eigenvalue after the margin (for the trace
    /// cap, `cap − trace(X)`), recomputed from the M-file's LMIs at the point.
    margins: Vec<(String, f64)>,
}

/// `p2c14_ex6_adip_oc_saturation.m` lines 77-78: the same LMIs plus `trace(X) <= cap`, solved
/// with no objective: whichever feasible point the interior-point method stops at.
fn feasible_point(
    id: &str,
    spec: &MfileLmi,
    cap: f64,
    options: &SolveOptions,
) -> Result<FeasiblePoint, BookError> {
    let (mut p, x, l, v, _) = mfile_problem(id, spec)?;
    let cap_name = "trace(X) <= -double(OBV)";
    p.less_equal(cap_name, &x.trace(), &Expr::scalar(cap))
        .ctx(id)?;
    let sol = p.solve(options).ctx(id)?;
    if !sol.status.is_solved() {
        return Err(fail(
            id,
            format!(
                "the M-file's feasibility solve was not solved: {:?}",
                sol.status
            ),
        ));
    }
    let xv = sol.value(&x).ctx(id)?;
    let xv = (&xv + xv.transpose()) * 0.5;
    let lv = sol.value(&l).ctx(id)?;
    let vv = match &v {
        Some(v) => Some(sol.value(v).ctx(id)?),
        None => None,
    };
    let mut margins: Vec<(String, f64)> = spec
        .blocks(&xv, &lv, vv.as_ref())
        .iter()
        .map(|(name, rel, f)| (name.clone(), min_eig(&normalised(*rel, f))))
        .collect();
    margins.push((cap_name.into(), cap - xv.trace()));
    Ok(FeasiblePoint {
        x: xv,
        l: lv,
        v: vv,
        status: sol.status.clone(),
        backend: sol.backend,
        margins,
    })
}

/// Solves the M-file's LMI problem (maximise `trace(X)`) with `options` and certifies the
/// answer. An unsolved status is an error naming it; "almost solved" is returned with its
/// status (reported as inaccurate).
fn solve_mfile(
    id: &str,
    spec: &MfileLmi,
    options: &SolveOptions,
) -> Result<MfileSolution, BookError> {
    let n = spec.n();
    let (mut p, x, l, v, ids) = mfile_problem(id, spec)?;
    let blocks = spec.blocks(&x, &l, v.as_ref());
    p.maximize(&x.trace()).ctx(id)?;
    let sol = p.solve(options).ctx(id)?;
    if !sol.status.is_solved() {
        return Err(fail(
            id,
            format!("the M-file's LMI problem was not solved: {:?}", sol.status),
        ));
    }
    let xv = sol.value(&x).ctx(id)?;
    let xv = (&xv + xv.transpose()) * 0.5;
    let lv = sol.value(&l).ctx(id)?;
    let vv = match &v {
        Some(v) => Some(sol.value(v).ctx(id)?),
        None => None,
    };
    let duals: Vec<Mat> = ids
        .iter()
        .map(|c| {
            sol.dual(*c)
                .cloned()
                .ok_or_else(|| fail(id, "the solver returned no dual variables"))
        })
        .collect::<Result<_, _>>()?;
    // G_j at a point (X, L, V), in the solver's form.
    let g_at = |xm: &Mat, lm: &Mat, vm: Option<&Mat>| -> Vec<Mat> {
        spec.blocks(xm, lm, vm)
            .iter()
            .map(|(_, rel, f)| normalised(*rel, f))
            .collect()
    };
    let zero_x = Mat::zeros(n, n);
    let zero_r = Mat::zeros(1, n);
    let pair = |gs: &[Mat]| -> f64 { gs.iter().zip(&duals).map(|(g, z)| inner(g, z)).sum() };
    let g0 = g_at(&zero_x, &zero_r, vv.as_ref().map(|_| &zero_r));
    let dual_bound = pair(&g0);
    let g_star = g_at(&xv, &lv, vv.as_ref());
    let gap = pair(&g_star);
    // Stationarity c_v + Σ_j ⟨Z_j, G_j(E_v) − G_j(0)⟩ over every scalar variable.
    let zn = duals.iter().map(|z| z.norm()).fold(1.0, f64::max);
    let mut stat: f64 = 0.0;
    let mut dirs: Vec<(Mat, Mat, Option<Mat>, f64)> = Vec::new();
    for j in 0..n {
        for i in 0..=j {
            let mut e = Mat::zeros(n, n);
            e[(i, j)] = 1.0;
            e[(j, i)] = 1.0;
            let c = if i == j { 1.0 } else { 0.0 };
            dirs.push((e, zero_r.clone(), vv.as_ref().map(|_| zero_r.clone()), c));
        }
    }
    for j in 0..n {
        let mut e = Mat::zeros(1, n);
        e[(0, j)] = 1.0;
        dirs.push((
            zero_x.clone(),
            e.clone(),
            vv.as_ref().map(|_| zero_r.clone()),
            0.0,
        ));
        if vv.is_some() {
            dirs.push((zero_x.clone(), zero_r.clone(), Some(e), 0.0));
        }
    }
    for (ex, el, ev, c) in &dirs {
        let g = g_at(ex, el, ev.as_ref());
        stat = stat.max((c + pair(&g) - dual_bound).abs() / zn);
    }
    let margins = blocks
        .iter()
        .zip(&g_star)
        .map(|((name, _, _), g)| (name.clone(), min_eig(g)))
        .collect();
    let min_dual_eig = duals.iter().map(min_eig).fold(f64::INFINITY, f64::min);
    Ok(MfileSolution {
        trace_x: xv.trace(),
        x: xv,
        l: lv,
        v: vv,
        status: sol.status.clone(),
        backend: sol.backend,
        dual_bound,
        gap,
        stationarity: stat,
        min_dual_eig,
        margins,
    })
}

/// Reports the M-file's solution values (`X`, `L`, `trace_invX`, `trace_X`) and the
/// certificate values under their names.
fn report_solution(
    id: &str,
    s: &MfileSolution,
    trace_inv_name: &str,
    out: &mut ExampleOutput,
) -> Result<(), BookError> {
    let xi =
        s.x.clone()
            .try_inverse()
            .ok_or_else(|| fail(id, "X is singular"))?;
    out.value("X", Value::matrix(&s.x))
        .value("L", Value::Vector(row(&s.l)))
        .value(trace_inv_name, Value::Number(xi.trace()))
        .value("trace_X", Value::Number(s.trace_x))
        .value(
            "solved_to_tolerance",
            Value::Bool(s.status == Status::Solved),
        )
        .value("dual_bound", Value::Number(s.dual_bound))
        .value("duality_gap", Value::Number(s.gap))
        .value("dual_stationarity_residual", Value::Number(s.stationarity))
        .value(
            "lmi_min_eigenvalues",
            Value::Vector(s.margins.iter().map(|m| m.1).collect()),
        );
    Ok(())
}

/// The chapter's examples, in book order.
pub(crate) fn examples() -> Vec<Example> {
    vec![
        Example {
            id: "p2c112_ex1_alpha_stability",
            title: "α-stability of a 2×2 matrix by an LMI (α = 1)",
            section: "Part 2 §1.1.2",
            parameters: "A = [[0, 1], [−2.25, −2.25]], α = 1",
            needs_data: None,
            run: p2c112_ex1,
        },
        Example {
            id: "p2c121_ex3_alpha_stability_opt",
            title: "α-stability LMI: minimise ξ1 + ξ2",
            section: "Part 2 §1.2.1",
            parameters: "A = [[0, 1], [−2.25, −2.25]], α = 1",
            needs_data: None,
            run: p2c121_ex3,
        },
        Example {
            id: "p2c122_ex4_adip_oc_servo",
            title: "Arm pendulum LQ servo by an LMI (guaranteed cost)",
            section: "Part 2 §1.2.2",
            parameters: ARM,
            needs_data: None,
            run: p2c122_ex4_servo,
        },
        Example {
            id: "p2c122_ex4_adip_oc_multiobjective_servo",
            title: "Arm pendulum servo: LQ cost with D-stability region",
            section: "Part 2 §1.2.2",
            parameters: ARM,
            needs_data: None,
            run: p2c122_ex4_multiobjective,
        },
        Example {
            id: "p2c13_ex5_adip_lqr_servo",
            title: "Nominal Riccati LQ servo at the four parameter vertices",
            section: "Part 2 §1.3",
            parameters: "arm pendulum, a1 ∈ [3.41, 8.99], b1 ∈ [8.69, 22.91]",
            needs_data: None,
            run: p2c13_lqr,
        },
        Example {
            id: "p2c13_ex5_adip_oc_nominal_servo",
            title: "Nominal LMI servo (α = 2, β = 40) at the four parameter vertices",
            section: "Part 2 §1.3",
            parameters: "arm pendulum, a1 ∈ [3.41, 8.99], b1 ∈ [8.69, 22.91]",
            needs_data: None,
            run: p2c13_nominal,
        },
        Example {
            id: "p2c13_ex5_adip_oc_robust_servo",
            title: "Robust LMI servo over the four parameter vertices (α = 2, β = 40)",
            section: "Part 2 §1.3",
            parameters: "arm pendulum, a1 ∈ [3.41, 8.99], b1 ∈ [8.69, 22.91]",
            needs_data: None,
            run: p2c13_robust,
        },
        Example {
            id: "p2c14_ex6_adip_oc_saturation",
            title: "State feedback under |u| ≤ 0.1 V saturation by invariant-ellipsoid conditions (K and H)",
            section: "Part 2 §1.4",
            parameters: ARM,
            needs_data: None,
            run: p2c14_ex6,
        },
        Example {
            id: "p2c15_ex7_adip_lqr_servo",
            title: "LQ servo on the nonlinear arm pendulum, r = 60° then 0",
            section: "Part 2 §1.5",
            parameters: ARM,
            needs_data: None,
            run: p2c15_lqr,
        },
        Example {
            id: "p2c15_ex7_adip_oc_gs_servo",
            title: "Gain-scheduled LQ servo (SOS, ρ = 1 − cos θ1), r = 60° then 0",
            section: "Part 2 §1.5",
            parameters: ARM,
            needs_data: None,
            run: p2c15_gs,
        },
    ]
}

fn a_ex1() -> Mat {
    Mat::from_row_slice(2, 2, &[0.0, 1.0, -2.25, -2.25])
}

/// `P = [[ξ1, ξ2], [ξ2, 1]] ≻ 0`, `AᵀP + PA + 2αP ≺ 0` on a fresh problem.
fn alpha_problem(id: &str) -> Result<(Problem, Expr, Expr, Expr), BookError> {
    let a = a_ex1();
    let mut p = Problem::new();
    let xi1 = p.scalar("xi1");
    let xi2 = p.scalar("xi2");
    let pm = Expr::block(&[&[&xi1, &xi2], &[&xi2, &Expr::scalar(1.0)]]);
    p.positive_definite("P ≻ 0", &pm, EPS).ctx(id)?;
    p.negative_definite(
        "AᵀP + PA + 2αP ≺ 0",
        &((&a.transpose() * &pm).he() + pm.scale(2.0)),
        EPS,
    )
    .ctx(id)?;
    Ok((p, pm, xi1, xi2))
}

fn p2c112_ex1(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c112_ex1_alpha_stability";
    let (p, pm, _, _) = alpha_problem(id)?;
    let sol = p.solve(&SolveOptions::default()).ctx(id)?;
    let feasible = sol.status == Status::Solved && sol.all_checks_pass();
    let mut out = ExampleOutput::default();
    out.value("feasible", Value::Bool(feasible));
    if feasible {
        out.value("P", Value::matrix(&sol.value(&pm).ctx(id)?));
    }
    let ev = sorted(eigenvalues(&a_ex1()).ctx(id)?);
    out.value("eigenvalues_A", Value::Complex(ev.clone()));
    // The M-file displays P (line 21), the solver's feasible point: any P in the feasible set
    // answers the question, so the book's printed P (not known here) cannot be a reference.
    out.notes.push(
        "α-stability: every eigenvalue of A has Re λ < −α = −1 (here −1.125 ± 0.992j), so a P exists."
            .into(),
    );
    save_figure(
        ctx,
        &mut out,
        id,
        "poles",
        Ok(PoleZeroMap::new()
            .region("Re s < −α (α = 1)", &[RegionBound::DecayRate(1.0)])
            .poles("eigenvalues of A", &ev)
            .title("p2c112_ex1: eigenvalues of A and the α-stability region")
            .figure()),
    )?;
    Ok(out)
}

fn p2c121_ex3(_ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c121_ex3_alpha_stability_opt";
    let (mut p, _, xi1, xi2) = alpha_problem(id)?;
    p.minimize(&(&xi1 + &xi2)).ctx(id)?;
    let sol = p.solve(&SolveOptions::default()).ctx(id)?;
    if sol.status != Status::Solved {
        return Err(fail(id, format!("solver status {:?}", sol.status)));
    }
    let v = |e: &Expr| -> Result<f64, BookError> { Ok(sol.value(e).ctx(id)?[(0, 0)]) };
    let (x1, x2) = (v(&xi1)?, v(&xi2)?);
    let mut out = ExampleOutput::default();
    // p2c121_ex3_alpha_stability_opt.m lines 23-25: P = double(P), c'*xi.
    out.value("P", Value::Matrix(vec![vec![x1, x2], vec![x2, 1.0]]));
    out.value("optimum", Value::Number(x1 + x2))
        .value("xi1", Value::Number(x1))
        .value("xi2", Value::Number(x2));
    // Printed to 3 decimals: tolerance half a unit of the last digit.
    out.reference("optimum", Value::Number(2.929), "book, example 1.3", 5e-4)
        .reference("xi1", Value::Number(1.911), "book, example 1.3", 5e-4)
        .reference("xi2", Value::Number(1.019), "book, example 1.3", 5e-4);
    Ok(out)
}

/// `Q = diag(0.1, 1, 0.001, 0.001, 4)`, `R = 1` of the arm servo.
fn servo_weights() -> (Mat, Mat) {
    (diag(&[0.1, 1.0, 0.001, 0.001, 4.0]), diag(&[1.0]))
}

/// The Riccati LQ servo gain on the augmented nominal model (library sign, 1 × 5).
fn riccati_servo_gain(
    id: &str,
    at: &Mat,
    bt: &Mat,
) -> Result<pendulab_lti::design::Lqr, BookError> {
    let (q, r) = servo_weights();
    let sys = pendulab_lti::StateSpace::continuous(
        at.clone(),
        bt.clone(),
        Mat::identity(5, 5),
        Mat::zeros(5, 1),
    )
    .ctx(id)?;
    lqr(&sys, &q, &r, None).ctx(id)
}

fn nominal_servo(id: &str) -> Result<(Mat, Mat), BookError> {
    let p = pendulab_plants::ArmPendulumParams::book();
    arm_servo_model(id, p.a1, p.b1)
}

/// The servo `u = −K₁ x − K₂ w` (library sign) on the nonlinear arm pendulum, quantised rig
/// preset, 1 ms, with reference `r` for θ₁.
fn arm_servo_run(
    id: &str,
    params: pendulab_plants::ArmPendulumParams,
    k: &Mat,
    r: Signal,
    t_final: f64,
) -> Result<SampledRun, BookError> {
    let k1 = k.columns(0, 4).into_owned();
    let k2 = k.columns(4, 1).into_owned();
    let cs = Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]);
    let c = LqIntegralServo::new(&k1, &k2, &cs, vec![r], 1e-3, IntegrationRule::ForwardEuler)
        .ctx(id)?;
    run_arm(id, params, c, t_final, &[0.0, 0.0, 0.0, 0.0])
}

fn run_arm<C: Controller>(
    id: &str,
    params: pendulab_plants::ArmPendulumParams,
    c: C,
    t_final: f64,
    x0: &[f64],
) -> Result<SampledRun, BookError> {
    let plant = ArmPendulum::new(params).ctx(id)?;
    // The rig's safety stop: the run ends when the pendulum falls past 90°.
    let mut fall = StayWithin::new(1, PI / 2.0);
    let mut l = SampledLoop::new(
        plant,
        c,
        SampledOptions {
            t_final,
            ..Default::default()
        },
    )
    .ctx(id)?
    .with_rig(quantized_rig(id, &RigSpec::arm())?)
    .ctx(id)?;
    l.run_with(x0, &mut fall).ctx(id)
}

/// The time the pendulum fell (the run was stopped), if it did.
fn fell_at(run: &SampledRun) -> Option<f64> {
    match run.status {
        RunStatus::Stopped { t } => Some(t),
        RunStatus::Completed => None,
    }
}

/// θ₁, θ₂ (degrees) and u panels of arm runs.
fn arm_response(
    title: &str,
    runs: &[(&str, &SampledRun)],
    reference: Option<f64>,
) -> Result<pendulab_plot::Figure, pendulab_plot::PlotError> {
    let mut tr = TimeResponse::new().title(title);
    for (name, run) in runs {
        tr = tr.run(*name, &run.trajectory);
    }
    let mut th1 = SignalPanel::new(Channel::State(0), "θ1 [deg]").scaled(DEG);
    if let Some(r) = reference {
        th1 = th1.reference(r, Some("reference"));
    }
    tr.panel(th1)
        .panel(SignalPanel::new(Channel::State(1), "θ2 [deg]").scaled(DEG))
        .panel(SignalPanel::new(Channel::Input(0), "u [V]"))
        .figure()
}

/// The book's `Kt` (u = +Kt x) as the library gain (u = −K x).
fn library_gain(kt: &Mat) -> Mat {
    -kt
}

/// `eig(At + Bt*Kt)`, sorted.
fn poles_of(
    id: &str,
    a: &Mat,
    b: &Mat,
    kt: &Mat,
) -> Result<Vec<pendulab_lti::Complex64>, BookError> {
    Ok(sorted(eigenvalues(&(a + b * kt)).ctx(id)?))
}

/// The LMI servo of the p2c122 M-files on the nominal model, with its `Kt`, poles and the
/// Riccati comparison (`Kt_LQ = -lqr(At, Bt, Q, R)`, `poles_LQ`).
fn lmi_servo_values(
    id: &str,
    spec: &MfileLmi,
    at: &Mat,
    bt: &Mat,
    out: &mut ExampleOutput,
) -> Result<(MfileSolution, Mat, Mat), BookError> {
    let s = solve_mfile(id, spec, &SolveOptions::default())?;
    let kt = s.kt(id)?;
    report_solution(id, &s, "trace_invX", out)?;
    let poles = poles_of(id, at, bt, &kt)?;
    let lq = riccati_servo_gain(id, at, bt)?;
    let kt_lq = library_gain(&lq.gain);
    out.value("Kt", Value::Vector(row(&kt)))
        .value("K1", Value::Vector(row(&kt)[..4].to_vec()))
        .value("K2", Value::Number(kt[(0, 4)]))
        .value("poles", Value::Complex(poles))
        .value("Kt_LQ", Value::Vector(row(&kt_lq)))
        .value("poles_LQ", Value::Complex(poles_of(id, at, bt, &kt_lq)?));
    Ok((s, kt, kt_lq))
}

fn p2c122_ex4_servo(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c122_ex4_adip_oc_servo";
    let (at, bt) = nominal_servo(id)?;
    let (q, r) = servo_weights();
    // p2c122_ex4_adip_oc_servo.m lines 31-50: X ⪰ εI, LMI1 ⪯ −εI, obj = −trace(X).
    let spec = MfileLmi::Servo {
        models: vec![(at.clone(), bt.clone())],
        q,
        r,
        alpha: None,
        sector_k: None,
        beta: None,
    };
    let mut out = ExampleOutput::default();
    let (s, kt, kt_lq) = lmi_servo_values(id, &spec, &at, &bt, &mut out)?;
    let rel = (&kt - &kt_lq).norm() / kt_lq.norm();
    out.value("relative_difference_Kt_Kt_LQ", Value::Number(rel));
    out.notes.push(GAIN_NOTE.into());
    out.notes
        .push(s.note("p2c122_ex4_adip_oc_servo.m lines 36-50, solved once as there (no re-solve)"));
    out.notes.push(format!(
        "Kt = L X⁻¹ against the Riccati gain Kt_LQ = −lqr(At, Bt, Q, R): relative difference {rel:.1e} \
         (X⁻¹ = P up to the margin ε)."
    ));
    if ctx.out_dir.is_some() {
        save_servo_comparison(
            ctx,
            &mut out,
            id,
            "p2c122_ex4: LMI LQ servo vs Riccati LQ servo, r = 30°",
            "LMI",
            &library_gain(&kt),
            &library_gain(&kt_lq),
        )?;
    }
    Ok(out)
}

/// Runs the nonlinear arm servo with the designed gain `k` and the Riccati gain `k_lq` for a
/// 30° step and writes both responses (titled `title`, the design labelled `label`) and an
/// animation of the design's run.
fn save_servo_comparison(
    ctx: &RunContext,
    out: &mut ExampleOutput,
    id: &str,
    title: &str,
    label: &str,
    k: &Mat,
    k_lq: &Mat,
) -> Result<(), BookError> {
    let step = Signal::step(0.0, 30f64.to_radians()).ctx(id)?;
    let params = pendulab_plants::ArmPendulumParams::book();
    let run = arm_servo_run(id, params, k, step.clone(), 6.0)?;
    let lq_run = arm_servo_run(id, params, k_lq, step, 6.0)?;
    save_figure(
        ctx,
        out,
        id,
        "response",
        arm_response(title, &[(label, &run), ("Riccati LQ", &lq_run)], Some(30.0)),
    )?;
    save_animation(ctx, out, id, "animation", || {
        run_animation(Rig::Arm, &run.trajectory, id)
    })
}

fn multiobjective_regions() -> [Region; 3] {
    [
        Region::DecayRate { alpha: 2.0 },
        Region::SpeedLimit { beta: 16.0 },
        Region::Sector {
            theta: std::f64::consts::FRAC_PI_4,
        },
    ]
}

fn p2c122_ex4_multiobjective(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c122_ex4_adip_oc_multiobjective_servo";
    let (at, bt) = nominal_servo(id)?;
    let (q, r) = servo_weights();
    // p2c122_ex4_adip_oc_multiobjective_servo.m lines 36-39: St = 1.5, α = 3/St, β = 8α,
    // θ = π/4, k = tan θ; lines 45-58: LMI1, LMI2 ⪯ −εI, LMI3 ⪯ −εI, LMI4 ⪰ εI.
    let alpha = 3.0 / 1.5;
    let beta = 8.0 * alpha;
    let theta = std::f64::consts::FRAC_PI_4;
    let spec = MfileLmi::Servo {
        models: vec![(at.clone(), bt.clone())],
        q,
        r,
        alpha: Some(alpha),
        sector_k: Some(theta.tan()),
        beta: Some(beta),
    };
    let mut out = ExampleOutput::default();
    let (s, kt, kt_lq) = lmi_servo_values(id, &spec, &at, &bt, &mut out)?;
    let poles = poles_of(id, &at, &bt, &kt)?;
    let regions = multiobjective_regions();
    let inside = poles
        .iter()
        .all(|z| regions.iter().all(|reg| reg.contains(*z)));
    out.value("poles_in_region", Value::Bool(inside));
    out.notes.push(GAIN_NOTE.into());
    out.notes.push(s.note(
        "p2c122_ex4_adip_oc_multiobjective_servo.m lines 41-62, solved once as there (no re-solve)",
    ));
    out.notes.push(ILL_DETERMINED_KT.into());
    out.notes.push(
        "Region: Re λ < −α = −2, Re λ > −β = −16, sector |Im λ| < tan(π/4)(−Re λ), the sector LMI written \
         with k = tan θ as in the M-file (line 50)."
            .into(),
    );
    if ctx.out_dir.is_some() {
        let lq_poles = poles_of(id, &at, &bt, &kt_lq)?;
        save_figure(
            ctx,
            &mut out,
            id,
            "poles",
            Ok(PoleZeroMap::new()
                .region(
                    "design region",
                    &[
                        RegionBound::DecayRate(alpha),
                        RegionBound::SpeedLimit(beta),
                        RegionBound::Sector(theta),
                    ],
                )
                .poles("multi-objective LMI", &poles)
                .poles("Riccati LQ", &lq_poles)
                .title("p2c122_ex4: closed-loop poles and the D-stability region")
                .figure()),
        )?;
        save_servo_comparison(
            ctx,
            &mut out,
            id,
            "p2c122_ex4: multi-objective servo vs LQ servo, r = 30°",
            "multi-objective LMI",
            &library_gain(&kt),
            &library_gain(&kt_lq),
        )?;
    }
    Ok(out)
}

/// The four vertices `(a1, b1)` of the p2c13 M-files (lines 37-47 of
/// `p2c13_ex5_adip_lqr_servo.m`): the nominal values × [0.55, 1.45], in `mvert(2)`'s column
/// order (ρ1 min/ρ2 min, ρ1 max/ρ2 min, ρ1 min/ρ2 max, ρ1 max/ρ2 max).
fn vertex_params() -> Vec<(f64, f64)> {
    let p = pendulab_plants::ArmPendulumParams::book();
    let (lo, hi) = (0.55, 1.45);
    // mvert(2) = [0 1 0 1; 0 0 1 1]; vertex = range(1) + diff(range) * ve.
    let ve = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
    ve.iter()
        .map(|&(e1, e2)| {
            (
                p.a1 * lo + (p.a1 * hi - p.a1 * lo) * e1,
                p.b1 * lo + (p.b1 * hi - p.b1 * lo) * e2,
            )
        })
        .collect()
}

/// `vertex` as the M-files display it: row 1 the a1 values, row 2 the b1 values.
fn vertex_value() -> Value {
    let v = vertex_params();
    Value::Matrix(vec![
        v.iter().map(|p| p.0).collect(),
        v.iter().map(|p| p.1).collect(),
    ])
}

fn vertices(id: &str) -> Result<Vec<Vertex>, BookError> {
    vertex_params()
        .into_iter()
        .map(|(a1, b1)| arm_servo_model(id, a1, b1).map(|(a, b)| Vertex { a, b }))
        .collect()
}

/// Values, notes and figures shared by the three p2c13 examples for a gain `k` (library sign).
fn p2c13_report(
    ctx: &RunContext,
    id: &str,
    gain_name: &str,
    k: &Mat,
    regions: bool,
    out: &mut ExampleOutput,
) -> Result<(), BookError> {
    let verts = vertices(id)?;
    let mut maxre = Vec::new();
    let mut all_poles = Vec::new();
    for v in &verts {
        let p = sorted(eigenvalues(&(&v.a - &v.b * k)).ctx(id)?);
        maxre.push(max_re(&p));
        all_poles.push(p);
    }
    let kb = book_row(k);
    out.value(gain_name, Value::Vector(kb.clone()))
        .value("K1", Value::Vector(kb[..4].to_vec()))
        .value("K2", Value::Number(kb[4]))
        .value("max_real_pole_per_vertex", Value::Vector(maxre.clone()))
        .value(
            "stable_at_all_vertices",
            Value::Bool(maxre.iter().all(|r| *r < 0.0)),
        );
    out.notes.push(GAIN_NOTE.into());
    out.notes.push(
        "Vertices (a1, b1) in mvert(2)'s order, as the M-files number them: (3.41, 8.69), (8.99, 8.69), (3.41, 22.91), (8.99, 22.91)."
            .into(),
    );
    if ctx.out_dir.is_none() {
        return Ok(());
    }
    let mut map = PoleZeroMap::new();
    if regions {
        map = map.region(
            "α = 2, β = 40",
            &[RegionBound::DecayRate(2.0), RegionBound::SpeedLimit(40.0)],
        );
    }
    for ((a1, b1), p) in vertex_params().iter().zip(&all_poles) {
        map = map.poles(format!("a1 = {a1:.2}, b1 = {b1:.2}"), p);
    }
    save_figure(
        ctx,
        out,
        id,
        "poles",
        Ok(map
            .title(format!("{id}: closed-loop poles at the four vertices"))
            .figure()),
    )?;
    // Nonlinear runs at the vertices, r = 30°, 6 s (an unstable vertex swings away; the
    // ±5 V amplifier bounds it).
    let step = Signal::step(0.0, 30f64.to_radians()).ctx(id)?;
    let mut runs = Vec::new();
    for (a1, b1) in vertex_params() {
        let params = pendulab_plants::ArmPendulumParams {
            a1,
            b1,
            ..pendulab_plants::ArmPendulumParams::book()
        };
        runs.push((
            format!("a1 = {a1:.2}, b1 = {b1:.2}"),
            arm_servo_run(id, params, k, step.clone(), 6.0)?,
        ));
    }
    let refs: Vec<(&str, &SampledRun)> = runs.iter().map(|(n, r)| (n.as_str(), r)).collect();
    save_figure(
        ctx,
        out,
        id,
        "response",
        arm_response(
            &format!("{id}: r = 30° at the four vertices"),
            &refs,
            Some(30.0),
        ),
    )?;
    // Animation at the vertex the nominal LQ servo cannot hold (a1 max, b1 min).
    save_animation(ctx, out, id, "animation", || {
        run_animation(Rig::Arm, &runs[1].1.trajectory, id)
    })?;
    Ok(())
}

fn p2c13_lqr(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c13_ex5_adip_lqr_servo";
    let (at, bt) = nominal_servo(id)?;
    let lq = riccati_servo_gain(id, &at, &bt)?;
    let mut out = ExampleOutput::default();
    // p2c13_ex5_adip_lqr_servo.m line 33: Kt_LQ = -lqr(At_nominal, Bt_nominal, Q, R).
    out.value(
        "ve",
        Value::Matrix(vec![vec![0.0, 1.0, 0.0, 1.0], vec![0.0, 0.0, 1.0, 1.0]]),
    )
    .value("vertex", vertex_value());
    p2c13_report(ctx, id, "Kt_LQ", &lq.gain, false, &mut out)?;
    out.notes.push(
        "The nominal Riccati LQ servo is unstable at the second vertex (a1, b1) = (8.99, 8.69); the book's printed numbers for this example are not known here, so no badge claims them."
            .into(),
    );
    Ok(out)
}

/// The p2c13 LMI servo (nominal model only, or all four vertices): α = 3/St = 2,
/// β = 20α = 40, `obj = -trace(X)`.
fn p2c13_lmi(ctx: &RunContext, id: &str, robust: bool) -> Result<ExampleOutput, BookError> {
    let (q, r) = servo_weights();
    let models: Vec<(Mat, Mat)> = if robust {
        vertices(id)?.into_iter().map(|v| (v.a, v.b)).collect()
    } else {
        vec![nominal_servo(id)?]
    };
    let alpha = 3.0 / 1.5;
    let spec = MfileLmi::Servo {
        models,
        q,
        r,
        alpha: Some(alpha),
        sector_k: None,
        beta: Some(20.0 * alpha),
    };
    let s = solve_mfile(id, &spec, &SolveOptions::default())?;
    let kt = s.kt(id)?;
    let mut out = ExampleOutput::default();
    // The M-files display trace(inv(X)) as `trase_invX` (sic).
    report_solution(id, &s, "trase_invX", &mut out)?;
    out.value(
        "ve",
        Value::Matrix(vec![vec![0.0, 1.0, 0.0, 1.0], vec![0.0, 0.0, 1.0, 1.0]]),
    )
    .value("vertex", vertex_value());
    p2c13_report(ctx, id, "Kt", &library_gain(&kt), true, &mut out)?;
    out.notes.push(s.note(if robust {
        "p2c13_ex5_adip_oc_robust_servo.m lines 47-79 (common X, L at the four vertices), solved once as there (no re-solve)"
    } else {
        "p2c13_ex5_adip_oc_nominal_servo.m lines 31-58 (nominal model), solved once as there (no re-solve)"
    }));
    out.notes.push(
        "Region as in the M-file: M'+M+2αX ⪯ −εI (Re λ < −2) and M'+M+2βX ⪰ εI (Re λ > −40, a half-plane)."
            .into(),
    );
    if !robust {
        out.notes.push(ILL_DETERMINED_KT.into());
    }
    Ok(out)
}

fn p2c13_nominal(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    p2c13_lmi(ctx, "p2c13_ex5_adip_oc_nominal_servo", false)
}

fn p2c13_robust(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c13_ex5_adip_oc_robust_servo";
    let mut out = p2c13_lmi(ctx, id, true)?;
    out.notes.push(
        "Stable at all four vertices. The optimum is well conditioned: CVXPY + Clarabel \
         (tools/reference/p2c1_mfile_lmi_cvxpy.py) agrees on trace(X) to 2e-7 and on Kt to 1e-4."
            .into(),
    );
    Ok(out)
}

/// `u = Kx` (the book's sign) through the M-file's saturation block `±sat` (the Simulink
/// models `adip_saturation_sim` / `adip_saturation2_sim`: Matrix Gain `K` → Saturation
/// `[-sat, sat]` → plant; `u` is logged before, `v` after the saturation).
#[derive(Debug, Clone)]
struct SaturatedGain {
    k: [f64; 4],
    sat: f64,
}

impl Controller for SaturatedGain {
    fn ny(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    fn reset(&mut self) {}
    fn sample_time(&self) -> Option<f64> {
        Some(1e-3)
    }
    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        let v: f64 = self.k.iter().zip(y).map(|(k, x)| k * x).sum();
        u[0] = v.clamp(-self.sat, self.sat);
    }
}

/// A number already reported in `out` (NaN when missing).
fn num_of(out: &ExampleOutput, name: &str) -> f64 {
    match out.get(name) {
        Some(Value::Number(x)) => *x,
        _ => f64::NAN,
    }
}

fn p2c14_ex6(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c14_ex6_adip_oc_saturation";
    let plant = ArmPendulum::book();
    let lin = plant
        .linearize(pendulab_plants::ArmEquilibrium::upright(0.0))
        .ctx(id)?;
    // p2c14_ex6_adip_oc_saturation.m lines 28-67.
    let q = diag(&[20.0, 10.0, 0.1, 0.1]);
    let r = diag(&[1.0]);
    let sigma2: f64 = 0.1 * 0.1;
    let x0v = [10f64.to_radians(), 0.0, 0.0, 0.0];
    let spec = MfileLmi::Saturation {
        a: lin.a().clone(),
        b: lin.b().clone(),
        q,
        r,
        sigma2,
        x0: Mat::from_column_slice(4, 1, &x0v),
    };
    // Lines 69-74: maximise trace(X) (OBV = -trace(X)), display double(OBV).
    let s = solve_mfile(id, &spec, &SolveOptions::default())?;
    let inv = |x: &Mat| -> Result<Mat, BookError> {
        x.clone()
            .try_inverse()
            .ok_or_else(|| fail(id, "X is singular"))
    };
    let k_max = s.kt(id)?;
    let h_max = s.v.as_ref().ok_or_else(|| fail(id, "no V"))? * inv(&s.x)?;
    // Lines 77-92: the same LMIs with trace(X) <= -double(OBV), no objective; the M-file's
    // X, K = L*inv(X), H = V*inv(X), eig(A+B*K), trace_invX and trace_X are of this point.
    let f = feasible_point(id, &spec, s.trace_x, &SolveOptions::default())?;
    let xi = inv(&f.x)?;
    let k = &f.l * &xi;
    let v = f.v.clone().ok_or_else(|| fail(id, "no V"))?;
    let h = &v * &xi;
    let poles = poles_of(id, lin.a(), lin.b(), &k)?;
    let sat = sigma2.sqrt();
    let mut out = ExampleOutput::default();
    out.value("OBV", Value::Number(-s.trace_x))
        .value("dual_bound", Value::Number(s.dual_bound))
        .value("duality_gap", Value::Number(s.gap))
        .value("dual_stationarity_residual", Value::Number(s.stationarity))
        .value(
            "lmi_min_eigenvalues_at_max_trace",
            Value::Vector(s.margins.iter().map(|m| m.1).collect()),
        )
        .value("K_at_max_trace", Value::Vector(row(&k_max)))
        .value("H_at_max_trace", Value::Vector(row(&h_max)))
        .value("X", Value::matrix(&f.x))
        .value("L", Value::Vector(row(&f.l)))
        .value("V", Value::Vector(row(&v)))
        .value("K", Value::Vector(row(&k)))
        .value("H", Value::Vector(row(&h)))
        .value("poles", Value::Complex(poles))
        .value("trace_invX", Value::Number(xi.trace()))
        .value("trace_X", Value::Number(f.x.trace()))
        .value(
            "solved_to_tolerance",
            Value::Bool(f.status == Status::Solved),
        )
        .value(
            "lmi_min_eigenvalues",
            Value::Vector(f.margins.iter().map(|m| m.1).collect()),
        )
        .value("sat", Value::Number(sat));
    // Simulations (lines 95-97): the exact-state model (adip_saturation_sim) and the model
    // with D/A and encoder resolution (adip_saturation2_sim, the one the M-file runs), 10 s.
    let kk = [k[(0, 0)], k[(0, 1)], k[(0, 2)], k[(0, 3)]];
    let sim_on = |rig: bool| -> Result<SampledRun, BookError> {
        let c = SaturatedGain { k: kk, sat };
        let mut l = SampledLoop::new(
            plant,
            c,
            SampledOptions {
                t_final: 10.0,
                ..Default::default()
            },
        )
        .ctx(id)?;
        if rig {
            l = l.with_rig(quantized_rig(id, &RigSpec::arm())?).ctx(id)?;
        }
        l.run(&x0v).ctx(id)
    };
    let mut runs = Vec::new();
    for (tag, rig) in [("", false), ("_quantised_rig", true)] {
        let run = sim_on(rig)?;
        let t = run.trajectory.t();
        // u = K x along the run (before the saturation; from the plant's states), v applied.
        let xs: Vec<Vec<f64>> = (0..4)
            .map(|j| run.trajectory.x_signal(j).to_vec())
            .collect();
        let u: Vec<f64> = (0..t.len())
            .map(|i| (0..4).map(|j| kk[j] * xs[j][i]).sum())
            .collect();
        let vv = run.trajectory.u_signal(0);
        let sat_time = u
            .iter()
            .zip(t.windows(2))
            .filter(|(u, _)| u.abs() > sat)
            .map(|(_, w)| w[1] - w[0])
            .sum::<f64>();
        out.value(
            &format!("max_abs_u{tag}"),
            Value::Number(max_abs_after(t, &u, 0.0)),
        )
        .value(
            &format!("max_abs_v{tag}"),
            Value::Number(max_abs_after(t, vv, 0.0)),
        )
        .value(&format!("saturated_seconds{tag}"), Value::Number(sat_time))
        .value(
            &format!("final_state{tag}"),
            Value::Vector(run.diagnostics.final_state.clone()),
        );
        runs.push((run, u));
    }
    out.notes.push("Gains in the book's convention u = +K x; H = V X⁻¹ is the auxiliary gain of the invariant-ellipsoid conditions.".into());
    out.notes
        .push(s.note("p2c14_ex6_adip_oc_saturation.m lines 50-74 (first solve, OBV)"));
    out.notes.push(format!(
        "Then, as the M-file does (lines 77-78), the same LMIs with trace(X) ≤ −OBV = {:.6} and no objective, \
         solver status {} ({:?}): a bound every feasible X meets, so this solve returns whichever interior \
         point the method stops at (trace(X) = {:.4} here; pendulab-lmi's Clarabel backend and CVXPY + Clarabel \
         stop elsewhere, with K differing by tens of %, tools/reference/p2c1_mfile_lmi_cvxpy.py). X, K, H, poles, \
         trace_invX and trace_X are of this point, as in the M-file; smallest LMI eigenvalue there (after the \
         margin) {:.2e}. At the max-trace point itself K_at_max_trace is extreme (X nearly singular), H_at_max_trace \
         is well determined.",
        s.trace_x,
        if f.status == Status::Solved { "solved" } else { "INACCURATE" },
        f.backend,
        f.x.trace(),
        f.margins.iter().map(|m| m.1).fold(f64::INFINITY, f64::min),
    ));
    out.notes.push(format!(
        "The LMIs bound |H x| ≤ sat = {sat} V on the ellipsoid xᵀX⁻¹x ≤ 1 containing x0 (MH, INI) and give both A + BK and \
         A + BH the LQ bound (OC1, OC2), so sat(Kx) ∈ co{{Kx, Hx}} there: K itself is allowed to saturate. From θ1(0) = 10° \
         u = K x reaches {:.3} V and is clipped to ±{sat} V for {:.2} s (exact state; {:.3} V and {:.2} s on the quantised rig).",
        num_of(&out, "max_abs_u"),
        num_of(&out, "saturated_seconds"),
        num_of(&out, "max_abs_u_quantised_rig"),
        num_of(&out, "saturated_seconds_quantised_rig"),
    ));
    if ctx.out_dir.is_some() {
        let (run, _) = &runs[0];
        let (rig_run, _) = &runs[1];
        let fig = TimeResponse::new()
            .title("p2c14_ex6: saturation design (book's K, |v| ≤ 0.1 V), θ1(0) = 10°")
            .run("exact state", &run.trajectory)
            .run("quantised rig", &rig_run.trajectory)
            .panel(SignalPanel::new(Channel::State(0), "θ1 [deg]").scaled(DEG))
            .panel(SignalPanel::new(Channel::State(1), "θ2 [deg]").scaled(DEG))
            .panel(
                SignalPanel::new(Channel::Input(0), "v = sat(Kx) [V]")
                    .reference(sat, Some("±sat"))
                    .reference(-sat, None),
            )
            .figure();
        save_figure(ctx, &mut out, id, "response", fig)?;
        save_animation(ctx, &mut out, id, "animation", || {
            run_animation(Rig::Arm, &rig_run.trajectory, id)
        })?;
    }
    Ok(out)
}

/// `([[A, 0], [0, 0]], [B; 0])`: the plant padded with the integrator state (its `−C` row is
/// set by the caller where the matrix is the constant term).
fn augment(a: &Mat, b: &Mat) -> (Mat, Mat) {
    let mut at = Mat::zeros(5, 5);
    at.view_mut((0, 0), (4, 4)).copy_from(a);
    let mut bt = Mat::zeros(5, 1);
    bt.view_mut((0, 0), (4, 1)).copy_from(b);
    (at, bt)
}

/// r = 60° for 0–6 s, then 0 (12 s).
fn gs_reference(id: &str) -> Result<Signal, BookError> {
    Signal::piecewise_constant(&[0.0, 6.0], &[60f64.to_radians(), 0.0]).ctx(id)
}

fn p2c15_lqr(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c15_ex7_adip_lqr_servo";
    let (at, bt) = nominal_servo(id)?;
    let lq = riccati_servo_gain(id, &at, &bt)?;
    let run = arm_servo_run(
        id,
        pendulab_plants::ArmPendulumParams::book(),
        &lq.gain,
        gs_reference(id)?,
        12.0,
    )?;
    // The constant gain on the frozen LPV models A(ρ), B(ρ), ρ = 1 − cos θ1, θ1 ∈ [0°, 65°].
    let lpv = ArmPendulum::book().lpv();
    let frozen = |th: f64| -> Result<f64, BookError> {
        let rho = 1.0 - th.to_radians().cos();
        let (mut a, b) = augment(&lpv.a(rho), &lpv.b(rho));
        a[(4, 0)] = -1.0;
        Ok(max_re(&eigenvalues(&(&a - &b * &lq.gain)).ctx(id)?))
    };
    let grid: Vec<f64> = (0..=65).map(f64::from).collect();
    let mut frozen_re = Vec::new();
    for th in &grid {
        frozen_re.push(frozen(*th)?);
    }
    let limit = grid
        .iter()
        .zip(&frozen_re)
        .find(|(_, r)| **r >= 0.0)
        .map(|(t, _)| *t);
    let t = run.trajectory.t();
    let th1 = run.trajectory.x_signal(0);
    let mut out = ExampleOutput::default();
    // p2c15_ex7_adip_lqr_servo.m lines 34-36: Kt, K1, K2.
    let kb = book_row(&lq.gain);
    out.value("Kt", Value::Vector(kb.clone()))
        .value("K1", Value::Vector(kb[..4].to_vec()))
        .value("K2", Value::Number(kb[4]))
        .value("max_real_pole_frozen_at_0deg", Value::Number(frozen_re[0]))
        .value(
            "max_real_pole_frozen_at_60deg",
            Value::Number(frozen_re[60]),
        )
        .value(
            "max_theta1_deg",
            Value::Number(max_abs_after(t, th1, 0.0) * DEG),
        )
        .value(
            "final_state",
            Value::Vector(run.diagnostics.final_state.clone()),
        );
    if let Some(tf) = fell_at(&run) {
        out.value("fell_at", Value::Number(tf));
    }
    out.notes.push(GAIN_NOTE.into());
    out.notes.push(format!(
        "Constant LQ servo gain designed at θ1 = 0, run on the nonlinear arm pendulum (quantised rig preset). \
         On the frozen models the constant gain loses stability from θ1 ≈ {}° on (max Re λ = {:.2} 1/s at 60°): \
         the motivation for the gain-scheduled design. {}",
        limit.map_or("—".to_string(), |t| format!("{t:.0}")),
        frozen_re[60],
        match fell_at(&run) {
            Some(tf) => format!("The pendulum fell at t = {tf:.2} s (run stopped at |θ2| > 90°)."),
            None => "The run completed.".to_string(),
        }
    ));
    save_figure(
        ctx,
        &mut out,
        id,
        "response",
        arm_response(
            "p2c15_ex7: LQ servo, r = 60° then 0",
            &[("LQ servo", &run)],
            None,
        ),
    )?;
    save_animation(ctx, &mut out, id, "animation", || {
        run_animation(Rig::Arm, &run.trajectory, id)
    })?;
    Ok(out)
}

/// The scheduled servo `u = −K(ρ) [x; w]`, `ρ = 1 − cos y₀`, `w_k = w_{k−1} + ts (r − y₀)`
/// (forward Euler, as [`LqIntegralServo`]), with `K(ρ) = −L(ρ) X(ρ)⁻¹` evaluated at every
/// sample on stack matrices (no allocation in `update`).
#[derive(Debug, Clone)]
struct ScheduledServo {
    x: [nalgebra::SMatrix<f64, 5, 5>; 3],
    l: [nalgebra::SMatrix<f64, 1, 5>; 3],
    r: Signal,
    ts: f64,
    w: f64,
    e_prev: f64,
}

impl ScheduledServo {
    fn new(s: &ScheduledGain, r: Signal) -> Self {
        let x = std::array::from_fn(|i| {
            nalgebra::SMatrix::<f64, 5, 5>::from_fn(|a, b| s.x_coefficients[i][(a, b)])
        });
        let l = std::array::from_fn(|i| {
            nalgebra::SMatrix::<f64, 1, 5>::from_fn(|a, b| s.l_coefficients[i][(a, b)])
        });
        Self {
            x,
            l,
            r,
            ts: 1e-3,
            w: 0.0,
            e_prev: 0.0,
        }
    }
}

impl Controller for ScheduledServo {
    fn ny(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    fn reset(&mut self) {
        self.w = 0.0;
        self.e_prev = 0.0;
    }
    fn sample_time(&self) -> Option<f64> {
        Some(self.ts)
    }
    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        self.w += self.ts * self.e_prev;
        self.e_prev = self.r.value(t) - y[0];
        let rho = 1.0 - y[0].cos();
        let xm = self.x[0] + self.x[1] * rho + self.x[2] * (rho * rho);
        let lm = self.l[0] + self.l[1] * rho + self.l[2] * (rho * rho);
        let z = nalgebra::SVector::<f64, 5>::new(y[0], y[1], y[2], y[3], self.w);
        // u = −K z = L X⁻¹ z. X(ρ) ≻ 0 is certified on the design range; outside it (ρ up to
        // 2) a non-positive-definite X(ρ) gives no gain, and the command is 0.
        u[0] = match xm.cholesky() {
            Some(ch) => (lm * ch.solve(&z))[(0, 0)],
            None => 0.0,
        };
    }
}

fn p2c15_gs(ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    let id = "p2c15_ex7_adip_oc_gs_servo";
    let plant = ArmPendulum::book();
    let lpv = plant.lpv();
    let (mut a0, b0) = augment(&lpv.a0, &lpv.b0);
    a0[(4, 0)] = -1.0;
    let (a1, b1) = augment(&lpv.a1, &lpv.b1);
    let rho_bar = 1.0 - 65f64.to_radians().cos();
    let (q, r) = servo_weights();
    let spec = GainScheduleSpec {
        rho_range: (0.0, rho_bar),
        rho0_range: (0.0, rho_bar),
        rho_dot_bound: 0.75,
        lq: LqWeights { q, r },
        margin: EPS,
        gamma_relax: 0.06,
        balance: true,
    };
    let design = gain_scheduled_lq(
        &LpvPlant { a0, a1, b0, b1 },
        &spec,
        &SolveOptions::default(),
    )
    .ctx(id)?;
    let gamma = design
        .gamma_star
        .ok_or_else(|| fail(id, format!("γ minimisation failed: {:?}", design.status)))?;
    let sched = design.schedule.as_ref().ok_or_else(|| {
        fail(
            id,
            format!(
                "feasibility re-solve failed its rechecks: {:?}",
                design.status
            ),
        )
    })?;
    let k_opt_bar = design
        .optimum
        .as_ref()
        .map(|o| o.gain(rho_bar))
        .transpose()
        .ctx(id)?;
    let k0 = sched.gain(0.0).ctx(id)?;
    let kbar = sched.gain(rho_bar).ctx(id)?;
    let run = run_arm(
        id,
        pendulab_plants::ArmPendulumParams::book(),
        ScheduledServo::new(sched, gs_reference(id)?),
        12.0,
        &[0.0; 4],
    )?;
    let th1 = run.trajectory.x_signal(0);
    let dth1 = run.trajectory.x_signal(2);
    let rho: Vec<f64> = th1.iter().map(|t| 1.0 - t.cos()).collect();
    let rho_dot: Vec<f64> = th1.iter().zip(dth1).map(|(t, w)| t.sin() * w).collect();
    // θ1 just before r returns to 0 (the last sample before 6 s).
    let t = run.trajectory.t();
    let k6 = t.iter().rposition(|&ti| ti < 6.0 - 1e-9).unwrap_or(0);
    let e6 = (th1[k6] * DEG - 60.0).abs();
    let range = |v: &[f64]| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        vec![lo, hi]
    };
    let mut out = ExampleOutput::default();
    // p2c15_ex7_adip_oc_gs_servo.m line 120: gamma_obj = 1.06*double(gamma), displayed at
    // line 249; line 250 displays double(gamma) of the second (feasibility) solve.
    out.value("gamma", Value::Number(gamma))
        .value("gamma_obj", Value::Number(1.06 * gamma))
        .value("gamma_design", Value::Number(sched.gamma))
        .value("K_at_rho0", Value::Vector(book_row(&k0)))
        .value("K_at_rho_max", Value::Vector(book_row(&kbar)))
        .value("rho_range_seen", Value::Vector(range(&rho)))
        .value("rho_dot_range_seen", Value::Vector(range(&rho_dot)))
        .value("rho_design_range", Value::Vector(vec![0.0, rho_bar]))
        .value("tracking_error_at_6s_deg", Value::Number(e6))
        .value(
            "final_state",
            Value::Vector(run.diagnostics.final_state.clone()),
        );
    if let Some(k) = &k_opt_bar {
        out.value("K_at_rho_max_at_optimum", Value::Vector(book_row(k)));
    }
    // Book p. 164: "γ = 236 程度まで可解" — the M-file's gamma_obj (1.06 times its γ*),
    // printed as an integer: half a unit. (the 256-bit SDP optimum γ* ≈ 222 is not a
    // printed value; the tests check γ against it.)
    out.reference(
        "gamma_obj",
        Value::Number(236.0),
        "book p. 164 (γ = 236 程度)",
        0.5,
    );
    out.notes.push(GAIN_NOTE.into());
    out.notes.push(format!(
        "γ* = {gamma:.2}; the schedule used satisfies γ ≤ gamma_obj = 1.06 γ* = {:.2}. The book reports γ ≈ 236 from \
         SeDuMi: the 1.06 γ* cap of its second (feasibility) solve, from a γ* about 0.2 % above the optimum found here \
         (double-precision solvers stop high on this degenerate SDP; a 256-bit SDP solver gives γ* ≈ 222).",
        1.06 * gamma
    ));
    out.notes.push(
        "Solved in normalised parameters ρ = ρ̄ s, s ∈ [0, 1] (same feasible set); K(ρ̄) is well determined, K(0) is not (near-optimal solutions differ there)."
            .into(),
    );
    if ctx.out_dir.is_some() {
        // Gain curves K(θ1) against the constant LQ servo gain.
        let (at, bt) = nominal_servo(id)?;
        let lq = riccati_servo_gain(id, &at, &bt)?;
        let lq_book = book_row(&lq.gain);
        let th: Vec<f64> = (0..=130).map(|k| k as f64 * 0.5).collect();
        let mut ks: Vec<Vec<f64>> = vec![Vec::new(); 5];
        for t in &th {
            let k = sched.gain(1.0 - t.to_radians().cos()).ctx(id)?;
            for (j, v) in book_row(&k).into_iter().enumerate() {
                ks[j].push(v);
            }
        }
        let names = ["K11", "K12", "K13", "K14", "K2"];
        let mut gc = GainCurves::new("θ1 [deg]", &th)
            .legend_names("gain scheduling K(θ1)", "LQ (constant)")
            .title("p2c15_ex7: scheduled gains against the constant LQ servo gains");
        for j in 0..5 {
            gc = gc.gain(names[j], &ks[j], Some(lq_book[j]));
        }
        save_figure(ctx, &mut out, id, "gains", gc.figure())?;
        let lq_run = arm_servo_run(
            id,
            pendulab_plants::ArmPendulumParams::book(),
            &lq.gain,
            gs_reference(id)?,
            12.0,
        )?;
        save_figure(
            ctx,
            &mut out,
            id,
            "response",
            arm_response(
                "p2c15_ex7: gain-scheduled vs LQ servo, r = 60° then 0",
                &[("gain scheduled", &run), ("LQ", &lq_run)],
                None,
            ),
        )?;
        // ρ and ρ̇ along the run with the design ranges.
        let t = run.trajectory.t();
        let mut ax1 = pendulab_plot::Axes::new();
        ax1.ylabel("ρ = 1 − cos θ1 [-]");
        ax1.plot(t, &rho).label("ρ(t)");
        ax1.hline(rho_bar)
            .label("design range")
            .color(pendulab_plot::Color::RED)
            .dashed();
        ax1.hline(0.0).color(pendulab_plot::Color::RED).dashed();
        let mut ax2 = pendulab_plot::Axes::new();
        ax2.ylabel("dρ/dt [1/s]").xlabel("time [s]");
        ax2.plot(t, &rho_dot).label("dρ/dt");
        ax2.hline(0.75)
            .label("±0.75")
            .color(pendulab_plot::Color::RED)
            .dashed();
        ax2.hline(-0.75).color(pendulab_plot::Color::RED).dashed();
        save_figure(
            ctx,
            &mut out,
            id,
            "rho",
            Ok(pendulab_plot::Figure::column([ax1, ax2])
                .title("p2c15_ex7: scheduling parameter and its rate inside the design ranges")),
        )?;
        save_animation(ctx, &mut out, id, "animation", || {
            run_animation(Rig::Arm, &run.trajectory, id)
        })?;
    }
    Ok(out)
}
