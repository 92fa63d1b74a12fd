//! The `lmi` facet of the extension module: the LMI syntheses of `pendulab_lmi::synthesis`
//! behind `pendulab.lmi` (book Part 2 §1).
//!
//! | Python | Rust | book |
//! |---|---|---|
//! | `alpha_stability(A, alpha)` | `alpha_stability` | Part 2 §1.1.2, example 1.1 |
//! | `max_decay_rate(A)` | `max_decay_rate` | Part 2 §1.2.1 |
//! | `lq(A, B, Q, R)` | `lq_state_feedback` | Part 2 §1.2.2, example 1.4 |
//! | `d_stability(A, B, Q, R, regions)` | `multiobjective_state_feedback` | Part 2 §1.2.2 |
//! | `robust(vertices, Q, R, regions)` | `robust_state_feedback` | Part 2 §1.3, example 1.5 |
//! | `saturated(A, B, Q, R, u_max, x0s)` | `saturated_state_feedback` | Part 2 §1.4, example 1.6 |
//! | `state_feedback(vertices, …)` | `state_feedback` | the general specification |
//! | `gain_scheduled(A0, A1, B0, B1, Q, R, …)` | `gain_scheduled_lq` | Part 2 §1.5, example 1.7 |
//!
//! Every design is solved by Clarabel with `SolveOptions::default()`, the GIL released. The
//! control law is `u = −K x` (the book's `K̃ = L X⁻¹` is `−K`). A design whose LMIs have no
//! solution (or that the solver leaves unsolved, or whose solution fails its recheck) raises
//! `pendulab.InfeasibleError` with the solver's `status`; malformed data raises the
//! `ShapeError` / `NotFiniteError` / `InvalidArgumentError` of the Rust message.

use nalgebra::DMatrix;
use numpy::PyArray2;
use pendulab_lmi::synthesis::{
    self, GainSchedule, GainScheduleSpec, InputBound, LpvPlant, LqWeights, Refinement, Region,
    ScheduledGain, StateFeedbackDesign, StateFeedbackSpec, Vertex,
};
use pendulab_lmi::{LmiError, Solution, SolveOptions, Status};
use pyo3::prelude::*;
use pyo3::types::{PyList, PyTuple};

use crate::convert::{OneD, complex_to_numpy, matrix, matrix_to_numpy, vector};
use crate::errors::{Kind, exception_type, from_error, new_err};

/// Adds this facet's functions and classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(lmi_alpha_stability, m)?)?;
    m.add_function(wrap_pyfunction!(lmi_max_decay_rate, m)?)?;
    m.add_function(wrap_pyfunction!(lmi_lq, m)?)?;
    m.add_function(wrap_pyfunction!(lmi_d_stability, m)?)?;
    m.add_function(wrap_pyfunction!(lmi_robust, m)?)?;
    m.add_function(wrap_pyfunction!(lmi_saturated, m)?)?;
    m.add_function(wrap_pyfunction!(lmi_state_feedback, m)?)?;
    m.add_function(wrap_pyfunction!(lmi_gain_scheduled, m)?)?;
    m.add_class::<LmiFeedback>()?;
    m.add_class::<Lyapunov>()?;
    m.add_class::<Schedule>()?;
    Ok(())
}

/// An [`LmiError`] as the `pendulab` exception of its kind (shapes → `ShapeError`, NaN/±Inf →
/// `NotFiniteError`, bad values → `InvalidArgumentError`, solver breakdown → `Error`).
pub fn lmi_error(e: &LmiError) -> PyErr {
    let kind = match e {
        LmiError::ShapeMismatch { .. } | LmiError::NotSquare { .. } => Kind::Shape,
        LmiError::NonFinite { .. } => Kind::NotFinite,
        LmiError::NotSymmetric { .. } | LmiError::InvalidArgument { .. } => Kind::InvalidArgument,
        LmiError::Lti(l) => return crate::errors::to_py(l),
        _ => Kind::Error,
    };
    from_error(kind, e)
}

/// The solver's outcome in words: `"solved"`, `"almost-solved"`, `"infeasible"`,
/// `"unbounded"`, `"max-iterations"`, `"max-time"` or `"numerical-trouble: <reason>"`.
pub fn status_text(s: &Status) -> String {
    match s {
        Status::Solved => "solved".into(),
        Status::AlmostSolved => "almost-solved".into(),
        Status::Infeasible { .. } => "infeasible".into(),
        Status::Unbounded { .. } => "unbounded".into(),
        Status::MaxIterations => "max-iterations".into(),
        Status::MaxTime => "max-time".into(),
        Status::NumericalTrouble { reason } => format!("numerical-trouble: {reason}"),
    }
}

/// `pendulab.InfeasibleError` for a design `what` that ended in `status`, with the attributes
/// `status` (see [`status_text`]) and `certificate_valid` (a Farkas certificate checking out
/// to 1e-6, or `False` when the solver gave none).
fn infeasible(what: &str, status: &Status, solution: &Solution) -> PyErr {
    let text = status_text(status);
    let certificate_valid = match status {
        Status::Infeasible { certificate, .. } => certificate.is_valid(1e-6),
        _ => false,
    };
    let failed: Vec<&str> = solution
        .checks
        .iter()
        .filter(|c| !c.satisfied)
        .map(|c| c.name.as_str())
        .collect();
    let message = if failed.is_empty() {
        format!("{what}: no solution (solver status {text})")
    } else {
        format!(
            "{what}: no solution (solver status {text}; recheck failed: {})",
            failed.join(", ")
        )
    };
    Python::attach(|py| {
        let make = || -> PyResult<PyErr> {
            let e = exception_type(py, Kind::Infeasible)?.call1((message.clone(),))?;
            e.setattr("status", text.clone())?;
            e.setattr("certificate_valid", certificate_valid)?;
            Ok(PyErr::from_value(e))
        };
        make().unwrap_or_else(|e| e)
    })
}

/// A pole region from Python: `("decay_rate", α)`, `("speed_limit", β)`, `("sector", θ)`,
/// `("disk", center, radius)` or `("general", L, M)` (Chilali–Gahinet, see [`Region`]).
fn region(obj: &Bound<'_, PyAny>, index: usize) -> PyResult<Region> {
    let what = format!("regions[{index}]");
    let bad = |msg: String| new_err(Kind::InvalidArgument, format!("{what}: {msg}"), None);
    let t = obj.cast::<PyTuple>().map_err(|_| {
        bad("must be a tuple such as (\"decay_rate\", alpha), (\"speed_limit\", beta), (\"sector\", theta), (\"disk\", center, radius) or (\"general\", L, M)".into())
    })?;
    let kind: String = t
        .get_item(0)
        .and_then(|k| k.extract())
        .map_err(|_| bad("the first entry must be the region's name".into()))?;
    let number = |i: usize| -> PyResult<f64> {
        t.get_item(i)
            .and_then(|v| v.extract::<f64>())
            .map_err(|_| bad(format!("{kind} needs a number at position {i}")))
    };
    let arity = |n: usize| -> PyResult<()> {
        if t.len() == n {
            Ok(())
        } else {
            Err(bad(format!(
                "{kind} takes {} value(s), got {}",
                n - 1,
                t.len() - 1
            )))
        }
    };
    Ok(match kind.as_str() {
        "decay_rate" => {
            arity(2)?;
            Region::DecayRate { alpha: number(1)? }
        }
        "speed_limit" => {
            arity(2)?;
            Region::SpeedLimit { beta: number(1)? }
        }
        "sector" => {
            arity(2)?;
            Region::Sector { theta: number(1)? }
        }
        "disk" => {
            arity(3)?;
            Region::Disk {
                center: number(1)?,
                radius: number(2)?,
            }
        }
        "general" => {
            arity(3)?;
            Region::General {
                l: matrix(&t.get_item(1)?, &format!("{what} L"), OneD::Row)?,
                m: matrix(&t.get_item(2)?, &format!("{what} M"), OneD::Row)?,
            }
        }
        other => {
            return Err(bad(format!(
                "unknown region {other:?} (decay_rate, speed_limit, sector, disk, general)"
            )));
        }
    })
}

fn regions(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<Region>> {
    let Some(obj) = obj else {
        return Ok(Vec::new());
    };
    obj.try_iter()?
        .enumerate()
        .map(|(i, r)| region(&r?, i))
        .collect()
}

/// The plant models: a list of `(A, B)` pairs (vertices of a polytope).
fn vertices(obj: &Bound<'_, PyAny>) -> PyResult<Vec<Vertex>> {
    obj.try_iter()?
        .enumerate()
        .map(|(i, v)| {
            let v = v?;
            let pair = v.cast::<PyTuple>().map_err(|_| {
                new_err(
                    Kind::InvalidArgument,
                    format!("vertices[{i}] must be an (A, B) tuple"),
                    None,
                )
            })?;
            if pair.len() != 2 {
                return Err(new_err(
                    Kind::Shape,
                    format!(
                        "vertices[{i}] must be an (A, B) pair, got {} entries",
                        pair.len()
                    ),
                    None,
                ));
            }
            Ok(Vertex {
                a: matrix(&pair.get_item(0)?, &format!("vertices[{i}] A"), OneD::Row)?,
                b: matrix(
                    &pair.get_item(1)?,
                    &format!("vertices[{i}] B"),
                    OneD::Column,
                )?,
            })
        })
        .collect()
}

fn weights(q: &Bound<'_, PyAny>, r: &Bound<'_, PyAny>) -> PyResult<LqWeights> {
    Ok(LqWeights {
        q: matrix(q, "Q", OneD::Row)?,
        r: matrix(r, "R", OneD::Row)?,
    })
}

fn input_bound(u_max: &Bound<'_, PyAny>, x0s: &Bound<'_, PyAny>) -> PyResult<InputBound> {
    let u_max = vector(u_max, "u_max")?.as_slice().to_vec();
    let x0 = matrix(x0s, "x0s", OneD::Row)?;
    Ok(InputBound {
        u_max,
        initial_states: x0.row_iter().map(|r| r.iter().copied().collect()).collect(),
    })
}

/// The gain and certificate of a state-feedback LMI design (`u = −K x`).
///
/// `K` (m × n), the Lyapunov matrix `X ≻ 0` (`V(x) = xᵀ X⁻¹ x`), `L = −K X`, the closed-loop
/// poles `eig(A − B K)` of each vertex (a list of complex arrays), `poles_in_regions`, the
/// solver's `status`, `objective` (`tr X` when maximised) and `iterations`. Unpacks as
/// `K, X, L`.
#[pyclass(name = "LmiFeedback", module = "pendulab.lmi", frozen)]
pub struct LmiFeedback {
    design: StateFeedbackDesign,
}

impl LmiFeedback {
    fn feedback(&self) -> &synthesis::Feedback {
        // Only designs with a feedback are wrapped (see `feedback_result`).
        self.design
            .feedback
            .as_ref()
            .expect("LmiFeedback holds a solved design")
    }
}

#[pymethods]
impl LmiFeedback {
    /// The gain `K` (m × n), `u = −K x`.
    #[getter(K)]
    fn k<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix_to_numpy(py, &self.feedback().gain)
    }
    /// The Lyapunov matrix `X ≻ 0` (n × n); `P = X⁻¹` certifies the closed loop.
    #[getter(X)]
    fn x<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix_to_numpy(py, &self.feedback().x)
    }
    /// `L = −K X` (m × n), the second decision variable.
    #[getter(L)]
    fn l<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix_to_numpy(py, &self.feedback().l)
    }
    /// The closed-loop poles `eig(A − B K)` of each vertex, a list of complex arrays.
    #[getter]
    fn poles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        PyList::new(
            py,
            self.feedback()
                .closed_loop_poles
                .iter()
                .map(|p| complex_to_numpy(py, p)),
        )
    }
    /// Whether every closed-loop pole of every vertex lies in every requested region.
    #[getter]
    fn poles_in_regions(&self) -> bool {
        self.feedback().poles_in_regions
    }
    /// The solver's outcome (`"solved"` or `"almost-solved"`) of the solve that gave `K`.
    #[getter]
    fn status(&self) -> String {
        let s = self
            .design
            .refined
            .as_ref()
            .unwrap_or(&self.design.solution);
        status_text(&s.status)
    }
    /// The objective at the optimum (`tr X` for the LQ designs), before any refinement.
    #[getter]
    fn objective(&self) -> Option<f64> {
        self.design.solution.objective
    }
    /// Interior-point iterations of the optimisation (plus the refinement's, if any).
    #[getter]
    fn iterations(&self) -> u32 {
        self.design.solution.iterations + self.design.refined.as_ref().map_or(0, |r| r.iterations)
    }
    /// The guaranteed LQ cost bound `x₀ᵀ X⁻¹ x₀` from the initial state `x0`.
    fn cost_bound(&self, x0: &Bound<'_, PyAny>) -> PyResult<f64> {
        let x0 = vector(x0, "x0")?;
        self.feedback()
            .cost_bound(x0.as_slice())
            .map_err(|e| lmi_error(&e))
    }
    fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let t = PyTuple::new(py, [self.k(py), self.x(py), self.l(py)])?;
        Ok(t.into_any().try_iter()?.into_any())
    }
    fn __len__(&self) -> usize {
        3
    }
    fn __repr__(&self) -> String {
        format!(
            "LmiFeedback(K={:?}, status={:?})",
            self.feedback().gain.as_slice(),
            self.status()
        )
    }
}

fn feedback_result(what: &str, design: StateFeedbackDesign) -> PyResult<LmiFeedback> {
    if design.feedback.is_none() {
        let s = design.refined.as_ref().unwrap_or(&design.solution);
        return Err(infeasible(what, &design.status, s));
    }
    Ok(LmiFeedback { design })
}

fn solve_options() -> SolveOptions {
    SolveOptions::default()
}

/// `(A, B)` of one plant model (`B` of one input may be 1-d).
#[allow(non_snake_case)]
fn plant(A: &Bound<'_, PyAny>, B: &Bound<'_, PyAny>) -> PyResult<(DMatrix<f64>, DMatrix<f64>)> {
    Ok((matrix(A, "A", OneD::Row)?, matrix(B, "B", OneD::Column)?))
}

/// Runs the design `f` with the GIL released; `what` names it in `InfeasibleError`.
fn design(
    py: Python<'_>,
    what: &str,
    f: impl FnOnce() -> pendulab_lmi::Result<StateFeedbackDesign> + Send,
) -> PyResult<LmiFeedback> {
    feedback_result(what, py.detach(f).map_err(|e| lmi_error(&e))?)
}

/// `lq(A, B, Q, R)`: the LMI LQ (guaranteed-cost) state feedback (book Part 2 §1.2.2):
/// `X ≻ 0`, `[[He(AX + BL), X C_qᵀ, Lᵀ R^½], [C_q X, −I, 0], [R^½ L, 0, −I]] ≺ 0`
/// (`Q = C_qᵀ C_q`), maximise `tr X`; `K = −L X⁻¹` approaches the LQR gain.
#[pyfunction]
#[pyo3(signature = (A, B, Q, R))]
#[allow(non_snake_case)]
fn lmi_lq(
    py: Python<'_>,
    A: &Bound<'_, PyAny>,
    B: &Bound<'_, PyAny>,
    Q: &Bound<'_, PyAny>,
    R: &Bound<'_, PyAny>,
) -> PyResult<LmiFeedback> {
    let (a, b) = plant(A, B)?;
    let w = weights(Q, R)?;
    design(py, "LMI LQ design", || {
        synthesis::lq_state_feedback(&a, &b, &w.q, &w.r, &solve_options())
    })
}

/// `d_stability(A, B, Q, R, regions)`: the LQ guaranteed cost with the closed-loop poles in
/// every region (Chilali–Gahinet; book Part 2 §1.2.2).
#[pyfunction]
#[pyo3(signature = (A, B, Q, R, regions))]
#[allow(non_snake_case)]
fn lmi_d_stability(
    py: Python<'_>,
    A: &Bound<'_, PyAny>,
    B: &Bound<'_, PyAny>,
    Q: &Bound<'_, PyAny>,
    R: &Bound<'_, PyAny>,
    regions: &Bound<'_, PyAny>,
) -> PyResult<LmiFeedback> {
    let (a, b) = plant(A, B)?;
    let w = weights(Q, R)?;
    let regs = self::regions(Some(regions))?;
    design(py, "D-stability design", || {
        synthesis::multiobjective_state_feedback(&a, &b, &w.q, &w.r, &regs, &solve_options())
    })
}

/// `robust(vertices, Q, R, regions=())`: one gain for every plant in the convex hull of the
/// `(A, B)` vertices (book Part 2 §1.3).
#[pyfunction]
#[pyo3(signature = (vertices, Q, R, regions = None))]
#[allow(non_snake_case)]
fn lmi_robust(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    Q: &Bound<'_, PyAny>,
    R: &Bound<'_, PyAny>,
    regions: Option<&Bound<'_, PyAny>>,
) -> PyResult<LmiFeedback> {
    let v = self::vertices(vertices)?;
    let w = weights(Q, R)?;
    let regs = self::regions(regions)?;
    design(py, "robust design", || {
        synthesis::robust_state_feedback(&v, &w.q, &w.r, &regs, &solve_options())
    })
}

/// `saturated(A, B, Q, R, u_max, x0s)`: the LQ guaranteed cost with `|u_i| ≤ u_max_i` on the
/// invariant ellipsoid `{xᵀ X⁻¹ x ≤ 1}` containing every row of `x0s` (book Part 2 §1.4).
#[pyfunction]
#[pyo3(signature = (A, B, Q, R, u_max, x0s))]
#[allow(non_snake_case)]
fn lmi_saturated(
    py: Python<'_>,
    A: &Bound<'_, PyAny>,
    B: &Bound<'_, PyAny>,
    Q: &Bound<'_, PyAny>,
    R: &Bound<'_, PyAny>,
    u_max: &Bound<'_, PyAny>,
    x0s: &Bound<'_, PyAny>,
) -> PyResult<LmiFeedback> {
    let (a, b) = plant(A, B)?;
    let w = weights(Q, R)?;
    let bound = input_bound(u_max, x0s)?;
    design(py, "saturation design", || {
        synthesis::saturated_state_feedback(&a, &b, &w.q, &w.r, &bound, &solve_options())
    })
}

/// `state_feedback(vertices, Q=None, R=None, regions=(), u_max=None, x0s=None,
/// refinement="when-inaccurate", relax=0.01, margin=1e-6)`: the general specification
/// (`pendulab_lmi::synthesis::state_feedback`); without `Q`, `R` a feasibility problem.
#[pyfunction]
#[pyo3(signature = (vertices, Q = None, R = None, regions = None, u_max = None, x0s = None,
                    refinement = "when-inaccurate", relax = 0.01, margin = 1e-6))]
#[allow(non_snake_case, clippy::too_many_arguments)]
fn lmi_state_feedback(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    Q: Option<&Bound<'_, PyAny>>,
    R: Option<&Bound<'_, PyAny>>,
    regions: Option<&Bound<'_, PyAny>>,
    u_max: Option<&Bound<'_, PyAny>>,
    x0s: Option<&Bound<'_, PyAny>>,
    refinement: &str,
    relax: f64,
    margin: f64,
) -> PyResult<LmiFeedback> {
    let v = self::vertices(vertices)?;
    let lq = match (Q, R) {
        (Some(q), Some(r)) => Some(weights(q, r)?),
        (None, None) => None,
        _ => {
            return Err(new_err(
                Kind::InvalidArgument,
                "Q and R go together: give both or neither".into(),
                None,
            ));
        }
    };
    let input_bound = match (u_max, x0s) {
        (Some(u), Some(x)) => Some(input_bound(u, x)?),
        (None, None) => None,
        _ => {
            return Err(new_err(
                Kind::InvalidArgument,
                "u_max and x0s go together: give both or neither".into(),
                None,
            ));
        }
    };
    let refinement = match refinement {
        "none" => Refinement::None,
        "feasibility" => Refinement::Feasibility { relax },
        "when-inaccurate" => Refinement::WhenInaccurate { relax },
        other => {
            return Err(new_err(
                Kind::InvalidArgument,
                format!(
                    "refinement {other:?}: expected \"none\", \"feasibility\" or \"when-inaccurate\""
                ),
                None,
            ));
        }
    };
    let spec = StateFeedbackSpec {
        lq,
        regions: self::regions(regions)?,
        input_bound,
        refinement,
        margin,
        ..StateFeedbackSpec::default()
    };
    design(py, "state-feedback design", || {
        synthesis::state_feedback(&v, &spec, &solve_options())
    })
}

/// A Lyapunov certificate `P` of α-stability (`AᵀP + PA + 2αP ≺ 0`, `P ≻ 0`) and the decay
/// rate `alpha` it certifies; `solves` counts the LMI solves (bisection).
#[pyclass(name = "Lyapunov", module = "pendulab.lmi", frozen)]
pub struct Lyapunov {
    p: DMatrix<f64>,
    /// The certified decay rate α (1/s).
    #[pyo3(get)]
    alpha: f64,
    /// Number of LMI solves.
    #[pyo3(get)]
    solves: usize,
    /// The solver's outcome of the (last feasible) solve.
    #[pyo3(get)]
    status: String,
}

#[pymethods]
impl Lyapunov {
    /// `P ≻ 0` (n × n): `V(x) = xᵀ P x` decays at least like `e^{−2αt}`.
    #[getter(P)]
    fn p<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix_to_numpy(py, &self.p)
    }
    #[pyo3(signature = (dtype = None, copy = None))]
    fn __array__<'py>(
        &self,
        py: Python<'py>,
        dtype: Option<Bound<'py, PyAny>>,
        copy: Option<bool>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let _ = copy;
        let a = self.p(py).into_any();
        match dtype {
            None => Ok(a),
            Some(dt) => a.call_method1("astype", (dt,)),
        }
    }
    fn __repr__(&self) -> String {
        format!("Lyapunov(alpha={}, P={:?})", self.alpha, self.p.as_slice())
    }
}

/// `alpha_stability(A, alpha, margin=1e-6)`: find `P ⪰ εI` with `AᵀP + PA + 2αP ⪯ −εI`
/// (book Part 2 §1.1.2). Feasible iff every eigenvalue of `A` has `Re λ < −α`; raises
/// `pendulab.InfeasibleError` otherwise.
#[pyfunction]
#[pyo3(signature = (A, alpha, margin = 1e-6))]
#[allow(non_snake_case)]
fn lmi_alpha_stability(
    py: Python<'_>,
    A: &Bound<'_, PyAny>,
    alpha: f64,
    margin: f64,
) -> PyResult<Lyapunov> {
    let a = matrix(A, "A", OneD::Row)?;
    let r = py
        .detach(|| synthesis::alpha_stability(&a, alpha, margin, &solve_options()))
        .map_err(|e| lmi_error(&e))?;
    match (r.feasible, r.p) {
        (true, Some(p)) => Ok(Lyapunov {
            p,
            alpha,
            solves: 1,
            status: status_text(&r.solution.status),
        }),
        _ => Err(infeasible(
            &format!("α-stability (α = {alpha})"),
            &r.solution.status,
            &r.solution,
        )),
    }
}

/// `max_decay_rate(A, margin=1e-6, tol=1e-6)`: the largest α certified by a quadratic
/// Lyapunov function, by bisection to `tol` (book Part 2 §1.2.1); equals `−max Re λ(A)` up to
/// the margin and the tolerance.
#[pyfunction]
#[pyo3(signature = (A, margin = 1e-6, tol = 1e-6))]
#[allow(non_snake_case)]
fn lmi_max_decay_rate(
    py: Python<'_>,
    A: &Bound<'_, PyAny>,
    margin: f64,
    tol: f64,
) -> PyResult<Lyapunov> {
    let a = matrix(A, "A", OneD::Row)?;
    let r = py
        .detach(|| synthesis::max_decay_rate(&a, margin, tol, &solve_options()))
        .map_err(|e| lmi_error(&e))?;
    Ok(Lyapunov {
        p: r.p,
        alpha: r.alpha,
        solves: r.solves,
        status: "solved".into(),
    })
}

/// A gain schedule `K(ρ) = −L(ρ) X(ρ)⁻¹` (`u = −K(ρ) x`) from `gain_scheduled`: call it with
/// ρ for the gain. `X(ρ) = X₀ + ρX₁ + ρ²X₂`, `L(ρ) = L₀ + ρL₁ + ρ²L₂`; `gamma` bounds the cost
/// from `x₀` by `γ ‖x₀‖²` (book Part 2 §1.5, problem (1.62)); `gamma_star` is the minimised
/// bound; `optimum` the schedule at the γ minimum itself (not rechecked), or `None`.
#[pyclass(name = "Schedule", module = "pendulab.lmi", frozen)]
pub struct Schedule {
    sched: ScheduledGain,
    optimum: Option<ScheduledGain>,
    /// γ* of the minimisation.
    #[pyo3(get)]
    gamma_star: Option<f64>,
    /// The final solve's outcome.
    #[pyo3(get)]
    status: String,
}

fn coefficients<'py>(py: Python<'py>, c: &[DMatrix<f64>; 3]) -> PyResult<Bound<'py, PyTuple>> {
    PyTuple::new(py, c.iter().map(|m| matrix_to_numpy(py, m)))
}

#[pymethods]
impl Schedule {
    /// `K(ρ)` (m × n). Raises `InvalidArgumentError` where `X(ρ)` is not positive definite.
    fn __call__<'py>(&self, py: Python<'py>, rho: f64) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let k = self.sched.gain(rho).map_err(|e| lmi_error(&e))?;
        Ok(matrix_to_numpy(py, &k))
    }
    /// `X(ρ)` (n × n).
    #[pyo3(name = "X")]
    fn x<'py>(&self, py: Python<'py>, rho: f64) -> Bound<'py, PyArray2<f64>> {
        matrix_to_numpy(py, &self.sched.x(rho))
    }
    /// `L(ρ)` (m × n).
    #[pyo3(name = "L")]
    fn l<'py>(&self, py: Python<'py>, rho: f64) -> Bound<'py, PyArray2<f64>> {
        matrix_to_numpy(py, &self.sched.l(rho))
    }
    /// `(X₀, X₁, X₂)`.
    #[getter]
    fn x_coefficients<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        coefficients(py, &self.sched.x_coefficients)
    }
    /// `(L₀, L₁, L₂)`.
    #[getter]
    fn l_coefficients<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        coefficients(py, &self.sched.l_coefficients)
    }
    /// γ achieved by this schedule.
    #[getter]
    fn gamma(&self) -> f64 {
        self.sched.gamma
    }
    /// The design range `(ρ_lo, ρ_hi)`.
    #[getter]
    fn rho_range(&self) -> (f64, f64) {
        self.sched.rho_range
    }
    /// The schedule at the γ minimum (not rechecked), or `None`.
    #[getter]
    fn optimum(&self) -> Option<Schedule> {
        self.optimum.as_ref().map(|o| Schedule {
            sched: o.clone(),
            optimum: None,
            gamma_star: self.gamma_star,
            status: "optimum".into(),
        })
    }
    fn __repr__(&self) -> String {
        format!(
            "Schedule(gamma={}, gamma_star={:?}, rho_range={:?})",
            self.sched.gamma, self.gamma_star, self.sched.rho_range
        )
    }
}

/// `gain_scheduled(A0, A1, B0, B1, Q, R, rho_range, rho0_range=None, rho_dot_bound=0.0,
/// margin=1e-6, gamma_relax=0.06, balance=True)`: gain-scheduled LQ for
/// `ẋ = (A₀ + ρA₁)x + (B₀ + ρB₁)u`, `|ρ̇| ≤ ν`, by SOS multipliers (book Part 2 §1.5; the
/// conditions in `pendulab_lmi::synthesis::gain_scheduled_lq`). Returns a callable
/// [`Schedule`]; raises `pendulab.InfeasibleError` when no rechecked schedule is found.
#[pyfunction]
#[pyo3(signature = (A0, A1, B0, B1, Q, R, rho_range, rho0_range = None, rho_dot_bound = 0.0,
                    margin = 1e-6, gamma_relax = 0.06, balance = true))]
#[allow(non_snake_case, clippy::too_many_arguments)]
fn lmi_gain_scheduled(
    py: Python<'_>,
    A0: &Bound<'_, PyAny>,
    A1: &Bound<'_, PyAny>,
    B0: &Bound<'_, PyAny>,
    B1: &Bound<'_, PyAny>,
    Q: &Bound<'_, PyAny>,
    R: &Bound<'_, PyAny>,
    rho_range: (f64, f64),
    rho0_range: Option<(f64, f64)>,
    rho_dot_bound: f64,
    margin: f64,
    gamma_relax: f64,
    balance: bool,
) -> PyResult<Schedule> {
    let plant = LpvPlant {
        a0: matrix(A0, "A0", OneD::Row)?,
        a1: matrix(A1, "A1", OneD::Row)?,
        b0: matrix(B0, "B0", OneD::Column)?,
        b1: matrix(B1, "B1", OneD::Column)?,
    };
    let spec = GainScheduleSpec {
        rho_range,
        rho0_range: rho0_range.unwrap_or(rho_range),
        rho_dot_bound,
        lq: weights(Q, R)?,
        margin,
        gamma_relax,
        balance,
    };
    let d: GainSchedule = py
        .detach(|| synthesis::gain_scheduled_lq(&plant, &spec, &solve_options()))
        .map_err(|e| lmi_error(&e))?;
    match d.schedule {
        Some(sched) => Ok(Schedule {
            sched,
            optimum: d.optimum,
            gamma_star: d.gamma_star,
            status: status_text(&d.status),
        }),
        None => {
            let s = d.refined.as_ref().unwrap_or(&d.optimization);
            Err(infeasible("gain-scheduled design", &d.status, s))
        }
    }
}
