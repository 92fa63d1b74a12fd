//! The M-files' LMIs as written (`F >= ep*eye`, `F <= -ep*eye`, `F >= 0`), solved as the
//! M-files state them, with the solution's margins and certificate reported (Part 2 §1.2–§1.4).

use super::*;

/// How an M-file states an LMI: `F >= ep*eye` (`F ⪰ εI`), `F <= -ep*eye` (`F ⪯ −εI`) or
/// `F >= 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Rel {
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
pub(super) trait Lin: Sized {
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
pub(super) enum MfileLmi {
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
pub(super) fn sqrt_diag(m: &Mat) -> Mat {
    Mat::from_fn(m.nrows(), m.ncols(), |i, j| {
        if i == j { m[(i, i)].sqrt() } else { 0.0 }
    })
}

/// The LQ cost LMI of the M-files: `[M'+M, X√Q, L'√R; √Q X, −I, 0; √R L, 0, −1]`.
pub(super) fn lq_block<T: Lin>(a: &Mat, b: &Mat, q: &Mat, r: &Mat, x: &T, l: &T) -> T {
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
pub(super) fn normalised(rel: Rel, f: &Mat) -> Mat {
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
pub(super) struct MfileSolution {
    /// `X = double(X)`.
    pub(super) x: Mat,
    /// `L = double(L)`.
    pub(super) l: Mat,
    /// `V = double(V)` (saturation only).
    pub(super) v: Option<Mat>,
    /// Solver status (Solved, or AlmostSolved reported as "inaccurate").
    pub(super) status: Status,
    /// Which method solved it.
    pub(super) backend: pendulab_lmi::Backend,
    /// `trace(X)`, the maximised objective.
    pub(super) trace_x: f64,
    /// `Σ_j ⟨Z_j, G_j(0)⟩`: the dual objective, an upper bound on the optimum when the
    /// stationarity residual is zero.
    pub(super) dual_bound: f64,
    /// `Σ_j ⟨Z_j, G_j(x*)⟩`: the duality gap at the returned point.
    pub(super) gap: f64,
    /// `max_v |c_v + Σ_j ⟨Z_j, G_{j,v}⟩| / max(1, ‖Z‖)`: dual stationarity, relative.
    pub(super) stationarity: f64,
    /// Smallest eigenvalue of each `Z_j` (dual feasibility), the smallest over all LMIs.
    pub(super) min_dual_eig: f64,
    /// Per LMI (M-file name), the smallest eigenvalue of `G_j(x*)` (≥ 0: satisfied with the
    /// M-file's margin).
    pub(super) margins: Vec<(String, f64)>,
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
    pub(super) fn kt(&self, id: &str) -> Result<Mat, BookError> {
        let xi = self
            .x
            .clone()
            .try_inverse()
            .ok_or_else(|| fail(id, "X is singular"))?;
        Ok(&self.l * xi)
    }

    /// The status and certificate in one sentence for the output notes.
    pub(super) fn note(&self, what: &str) -> String {
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
pub(super) fn inner(a: &Mat, b: &Mat) -> f64 {
    a.iter().zip(b.iter()).map(|(x, y)| x * y).sum()
}

/// Smallest eigenvalue of a symmetric matrix (its symmetric part).
pub(super) fn min_eig(m: &Mat) -> f64 {
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
pub(super) fn mfile_problem(
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
pub(super) struct FeasiblePoint {
    pub(super) x: Mat,
    pub(super) l: Mat,
    pub(super) v: Option<Mat>,
    pub(super) status: Status,
    pub(super) backend: pendulab_lmi::Backend,
    /// Per constraint (M-file name), the smallest eigenvalue after the margin (for the trace
    /// cap, `cap − trace(X)`), recomputed from the M-file's LMIs at the point.
    pub(super) margins: Vec<(String, f64)>,
}

/// `p2c14_ex6_adip_oc_saturation.m` lines 77-78: the same LMIs plus `trace(X) <= cap`, solved
/// with no objective: whichever feasible point the interior-point method stops at.
pub(super) fn feasible_point(
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
pub(super) fn solve_mfile(
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
pub(super) fn report_solution(
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

/// The committed run of `tools/reference/p2c1_mfile_lmi_cvxpy.py`: the p2c1 M-files' LMIs
/// transcribed into CVXPY 1.9.3 and solved by Clarabel 0.11.1 (Python build) and CVXOPT 1.3.3.
const CVXPY_RUN: &str = include_str!("../../../tests/fixtures/p2c1_mfile_lmi.json");

/// The CVXPY run, parsed.
pub(super) fn cvxpy_run(id: &str) -> Result<serde_json::Value, BookError> {
    serde_json::from_str(CVXPY_RUN).map_err(|e| fail(id, format!("the CVXPY run: {e}")))
}

/// What the CVXPY run's Clarabel solve of example `id`'s M-file problem gives: its status
/// (`optimal` or `optimal_inaccurate`) and record (`trace_X`, `trace_invX`, `K`, `X`, `L`, …).
pub(super) fn cvxpy_clarabel(id: &str) -> Result<(String, serde_json::Value), BookError> {
    let all = cvxpy_run(id)?;
    let rec = all[id]["CLARABEL"].clone();
    let status = rec["status"]
        .as_str()
        .ok_or_else(|| fail(id, "the CVXPY run has no Clarabel solve of this M-file"))?
        .to_string();
    Ok((status, rec))
}

/// A number, a row or a matrix of a CVXPY record as a [`Value`].
pub(super) fn json_value(id: &str, v: &serde_json::Value) -> Result<Value, BookError> {
    let bad = || fail(id, format!("the CVXPY run: {v} is not a number array"));
    let nums = |a: &serde_json::Value| -> Result<Vec<f64>, BookError> {
        a.as_array()
            .ok_or_else(bad)?
            .iter()
            .map(|x| x.as_f64().ok_or_else(bad))
            .collect()
    };
    if let Some(x) = v.as_f64() {
        return Ok(Value::Number(x));
    }
    let a = v.as_array().ok_or_else(bad)?;
    if a.first().is_some_and(|r| r.is_array()) {
        Ok(Value::Matrix(a.iter().map(nums).collect::<Result<_, _>>()?))
    } else {
        Ok(Value::Vector(nums(v)?))
    }
}

/// The source of a reference from the CVXPY run.
pub(super) fn cvxpy_source(stem: &str, lines: &str, status: &str) -> String {
    format!(
        "{stem}.m {lines}, the M-file's LMIs in CVXPY 1.9.3 solved by Clarabel 0.11.1 ({status}; \
         tools/reference/p2c1_mfile_lmi_cvxpy.py)"
    )
}
