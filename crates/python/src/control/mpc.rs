//! Constrained linear MPC and its QP method (`pendulab_control::mpc`) behind
//! `pendulab.control`:
//!
//! | Python (`_native`) | Rust |
//! |---|---|
//! | `control_linear_mpc(A, B, horizon, Q, R, …, sys, dt)` → `LinearMpc` | `LinearMpc::new`, `LinearMpc::sampled` |
//! | `LinearMpc.step(x, u_prev, warm)` | `LinearMpc::solve` (first move of the plan) |
//! | `control_solve_qp(H, g, G, w, …)` | `DualActiveSetQp` |
//! | `control_kkt_residuals(H, g, G, w, x, λ)` | `kkt_residuals` |
//!
//! An infeasible QP raises `pendulab.InfeasibleError` (`status = "infeasible"`, the Farkas
//! certificate `y ≥ 0`, `yᵀG = 0`, `yᵀw < 0` in `certificate`, `certificate_valid` from a
//! check of those three conditions); the iteration limit raises `pendulab.LinAlgError`
//! (`variant = "MaxIterations"`).

use nalgebra::DMatrix;
use pendulab_control::mpc::{
    DualActiveSetQp, KktResiduals, LinearMpc, MpcSettings, QpOptions, QpStatus, StateBound,
    Terminal, WarmStart, kkt_residuals,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::ce;
use crate::convert::{OneD, count, matrix, matrix_to_numpy, slice_to_numpy, vector};
use crate::errors::{Kind, new_err};
use crate::lti::system::{StateSpace, Sys};

/// A 1-d `float64` array returned to Python.
type Vector<'py> = Bound<'py, numpy::PyArray1<f64>>;

fn vec_of(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    Ok(vector(obj, what)?.as_slice().to_vec())
}

/// A bound vector of length `n`: `None` → `fill`, a scalar → repeated, else as given (±inf
/// allowed: no bound).
fn bounds(obj: Option<&Bound<'_, PyAny>>, what: &str, n: usize, fill: f64) -> PyResult<Vec<f64>> {
    let Some(obj) = obj else {
        return Ok(vec![fill; n]);
    };
    let v: Vec<f64> = if let Ok(x) = obj.extract::<f64>() {
        vec![x; n]
    } else if let Ok(v) = obj.extract::<Vec<f64>>() {
        v
    } else {
        vec_of(obj, what)?
    };
    if let Some(k) = v.iter().position(|x| x.is_nan()) {
        return Err(new_err(
            Kind::NotFinite,
            format!("{what} has NaN at index {k} (0-based); use ±inf for no bound"),
            Some("NonFinite"),
        ));
    }
    Ok(v)
}

/// A QP status's name.
fn status_name(s: Option<QpStatus>) -> &'static str {
    match s {
        Some(QpStatus::Solved) => "solved",
        Some(QpStatus::Infeasible) => "infeasible",
        Some(QpStatus::MaxIterations) => "max_iterations",
        None => "none",
    }
}

/// The error of an unsolved QP: `InfeasibleError` with the certificate, or `LinAlgError`.
fn unsolved(py: Python<'_>, qp: &DualActiveSetQp, g_mat: &DMatrix<f64>, w: &[f64]) -> PyErr {
    let status = qp.status();
    if status == Some(QpStatus::Infeasible) {
        let y = qp.certificate().unwrap_or(&[]).to_vec();
        // Check y ≥ 0, yᵀG = 0 (relative to the size of the terms), yᵀw < 0.
        let yv = nalgebra::DVector::from_column_slice(&y);
        let ytg = g_mat.transpose() * &yv;
        let scale = g_mat.abs().max() * y.iter().map(|v| v.abs()).sum::<f64>();
        let ytw: f64 = y.iter().zip(w).map(|(a, b)| a * b).sum();
        let valid = y.len() == w.len()
            && y.iter().all(|&v| v >= 0.0)
            && ytg.amax() <= 1e-9 * scale.max(f64::MIN_POSITIVE)
            && ytw < 0.0;
        let err = new_err(
            Kind::Infeasible,
            format!(
                "the QP is infeasible: the constraints G x ≤ w admit no point (Farkas certificate y with yᵀw = {ytw:e} after {} iterations)",
                qp.iterations()
            ),
            Some("QpInfeasible"),
        );
        let v = err.value(py);
        let _ = v.setattr("status", "infeasible");
        let _ = v.setattr("certificate_valid", valid);
        let _ = v.setattr("certificate", slice_to_numpy(py, &y));
        return err;
    }
    new_err(
        Kind::LinAlg,
        format!(
            "the QP method stopped at its iteration limit ({} iterations) without an optimal point; raise max_iterations",
            qp.iterations()
        ),
        Some("MaxIterations"),
    )
}

fn kkt_dict<'py>(py: Python<'py>, k: &KktResiduals) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("stationarity", k.stationarity)?;
    d.set_item("primal", k.primal)?;
    d.set_item("dual", k.dual)?;
    d.set_item("complementarity", k.complementarity)?;
    Ok(d)
}

/// The condensed MPC ([`LinearMpc`]) with the state of the last `step`.
#[pyclass(name = "LinearMpc", module = "pendulab._native")]
pub struct NativeLinearMpc {
    mpc: LinearMpc,
    u_prev: Vec<f64>,
    solved: bool,
}

fn qp_options(tolerance: f64, max_iterations: usize) -> QpOptions {
    QpOptions {
        tolerance,
        max_iterations,
    }
}

/// `control_linear_mpc(A, B, horizon, Q, R, P=None, u_min=None, u_max=None, du_max=None,
/// state_bounds=None, tolerance=1e-9, max_iterations=0, sys=None, dt=None)`: the MPC of
/// `x⁺ = A x + B u` or, with `sys` (a continuous `pendulab.StateSpace`) and `dt` (s), of its
/// ZOH sampling (`A`, `B` then `None`). `P = None`: the DARE solution; `u_max` alone also sets
/// `u_min = −u_max`; `state_bounds` a list of `(index, min, max)`.
#[pyfunction]
#[pyo3(signature = (A, B, horizon, Q, R, P = None, u_min = None, u_max = None, du_max = None,
    state_bounds = None, tolerance = 1e-9, max_iterations = 0, sys = None, dt = None))]
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn control_linear_mpc(
    A: Option<&Bound<'_, PyAny>>,
    B: Option<&Bound<'_, PyAny>>,
    #[pyo3(from_py_with = count)] horizon: usize,
    Q: &Bound<'_, PyAny>,
    R: &Bound<'_, PyAny>,
    P: Option<&Bound<'_, PyAny>>,
    u_min: Option<&Bound<'_, PyAny>>,
    u_max: Option<&Bound<'_, PyAny>>,
    du_max: Option<&Bound<'_, PyAny>>,
    state_bounds: Option<Vec<(usize, f64, f64)>>,
    tolerance: f64,
    #[pyo3(from_py_with = count)] max_iterations: usize,
    sys: Option<&Bound<'_, PyAny>>,
    dt: Option<f64>,
) -> PyResult<NativeLinearMpc> {
    let continuous = match (sys, dt) {
        (Some(s), Some(_)) => {
            let s = s.cast::<StateSpace>().map_err(|_| {
                new_err(
                    Kind::InvalidArgument,
                    "sys must be a pendulab.StateSpace".into(),
                    None,
                )
            })?;
            match &s.get().sys {
                Sys::Continuous(c) => Some(c.clone()),
                Sys::Discrete(_) => {
                    return Err(new_err(
                        Kind::InvalidArgument,
                        "sys must be continuous-time (dt = 0); give a discrete model's A, B directly".into(),
                        None,
                    ));
                }
            }
        }
        (None, None) => None,
        _ => {
            return Err(new_err(
                Kind::InvalidArgument,
                "give both sys and dt, or neither".into(),
                None,
            ));
        }
    };
    let (a, b) = match (&continuous, A, B) {
        (Some(c), _, _) => (c.a().clone(), c.b().clone()),
        (None, Some(a), Some(b)) => (matrix(a, "A", OneD::Row)?, matrix(b, "B", OneD::Column)?),
        _ => {
            return Err(new_err(
                Kind::InvalidArgument,
                "give A and B (or sys and dt)".into(),
                None,
            ));
        }
    };
    let nu = b.ncols();
    let u_hi = bounds(u_max, "u_max", nu, f64::INFINITY)?;
    let u_lo = match u_min {
        None if u_max.is_some() => u_hi.iter().map(|v| -v).collect(),
        _ => bounds(u_min, "u_min", nu, f64::NEG_INFINITY)?,
    };
    let settings = MpcSettings {
        horizon,
        q: matrix(Q, "Q", OneD::Row)?,
        r: matrix(R, "R", OneD::Row)?,
        terminal: match P {
            Some(p) => Terminal::Weight(matrix(p, "P", OneD::Row)?),
            None => Terminal::Dare,
        },
        u_min: u_lo,
        u_max: u_hi,
        du_max: match du_max {
            Some(d) => Some(bounds(Some(d), "du_max", nu, f64::INFINITY)?),
            None => None,
        },
        state_bounds: state_bounds
            .unwrap_or_default()
            .into_iter()
            .map(|(index, min, max)| StateBound { index, min, max })
            .collect(),
        qp: qp_options(tolerance, max_iterations),
    };
    let mpc = match (&continuous, dt) {
        (Some(c), Some(dt)) => ce(LinearMpc::sampled(c, dt, &settings))?,
        _ => ce(LinearMpc::new(&a, &b, &settings))?,
    };
    Ok(NativeLinearMpc {
        u_prev: vec![0.0; mpc.nu()],
        mpc,
        solved: false,
    })
}

#[pymethods]
impl NativeLinearMpc {
    /// Solves the QP at the state `x` with the previous input `u_prev` (default: the move of
    /// the last `step`, zeros at first) starting from the working set `warm` (`"cold"`,
    /// `"same"`, `"shifted"`) and returns the first move `u₀`.
    #[pyo3(signature = (x, u_prev = None, warm = "shifted"))]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u_prev: Option<&Bound<'py, PyAny>>,
        warm: &str,
    ) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        let x = vec_of(x, "x")?;
        let u_prev = match u_prev {
            Some(u) => vec_of(u, "u_prev")?,
            None => self.u_prev.clone(),
        };
        let warm = match warm {
            "cold" => WarmStart::Cold,
            "same" => WarmStart::Same,
            "shifted" => WarmStart::Shifted,
            other => {
                return Err(new_err(
                    Kind::InvalidArgument,
                    format!("warm {other:?}: expected \"cold\", \"same\" or \"shifted\""),
                    None,
                ));
            }
        };
        self.solved = true;
        let status = ce(self.mpc.solve(&x, &u_prev, warm))?;
        if status != QpStatus::Solved {
            let (_, w) = self.mpc.last_qp_vectors();
            return Err(unsolved(py, self.mpc.qp(), self.mpc.constraint_matrix(), w));
        }
        let nu = self.mpc.nu();
        self.u_prev.copy_from_slice(&self.mpc.plan()[..nu]);
        Ok(slice_to_numpy(py, &self.u_prev))
    }

    /// Status of the last step (`"solved"`, `"infeasible"`, `"max_iterations"`, `"none"`).
    #[getter]
    fn status(&self) -> &'static str {
        if self.solved {
            status_name(self.mpc.qp().status())
        } else {
            "none"
        }
    }
    /// Active-set iterations of the last step.
    #[getter]
    fn iterations(&self) -> usize {
        self.mpc.qp().iterations()
    }
    /// Rows of `G U ≤ w` active at the last step's answer.
    #[getter]
    fn active_set(&self) -> Vec<usize> {
        self.mpc.qp().active_set().to_vec()
    }
    /// The plan `U = [u₀; …; u_{N−1}]` of the last step.
    #[getter]
    fn plan<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        slice_to_numpy(py, self.mpc.plan())
    }
    /// The multipliers `λ ≥ 0` of the last step.
    #[getter]
    fn multipliers<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        slice_to_numpy(py, self.mpc.qp().multipliers())
    }
    /// The condensed Hessian `H`.
    #[getter]
    #[allow(non_snake_case)]
    fn H<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        matrix_to_numpy(py, self.mpc.hessian())
    }
    /// The constraint matrix `G`.
    #[getter]
    #[allow(non_snake_case)]
    fn G<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        matrix_to_numpy(py, self.mpc.constraint_matrix())
    }
    /// The terminal weight `P` in use.
    #[getter]
    #[allow(non_snake_case)]
    fn P<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        matrix_to_numpy(py, self.mpc.terminal_weight())
    }
    /// `K = (R + BᵀPB)⁻¹BᵀPA`: the unconstrained first move is `−K x`.
    #[getter]
    #[allow(non_snake_case)]
    fn K<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        matrix_to_numpy(py, self.mpc.lq_gain())
    }
    /// `(nx, nu, horizon, rows_per_stage)`.
    #[getter]
    fn dims(&self) -> (usize, usize, usize, usize) {
        (
            self.mpc.nx(),
            self.mpc.nu(),
            self.mpc.horizon(),
            self.mpc.rows_per_stage(),
        )
    }
    /// The QP's `(g, w)` at `x` and `u_prev`.
    fn qp_vectors<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u_prev: &Bound<'py, PyAny>,
    ) -> PyResult<(Vector<'py>, Vector<'py>)> {
        let x = vec_of(x, "x")?;
        let u = vec_of(u_prev, "u_prev")?;
        let mut g = vec![0.0; self.mpc.hessian().nrows()];
        let mut w = vec![0.0; self.mpc.constraint_matrix().nrows()];
        ce(self.mpc.qp_vectors(&x, &u, &mut g, &mut w))?;
        Ok((slice_to_numpy(py, &g), slice_to_numpy(py, &w)))
    }
    /// The KKT residuals of the last step's answer (a dict).
    fn kkt<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let (g, w) = self.mpc.last_qp_vectors();
        let qp = self.mpc.qp();
        let k = ce(kkt_residuals(
            self.mpc.hessian(),
            g,
            self.mpc.constraint_matrix(),
            w,
            qp.solution(),
            qp.multipliers(),
        ))?;
        kkt_dict(py, &k)
    }
}

/// `control_solve_qp(H, g, G, w, warm_start=None, tolerance=1e-9, max_iterations=0)`:
/// `minimise ½xᵀHx + gᵀx s.t. Gx ≤ w` by the dual active-set method. Returns a dict `x`,
/// `multipliers`, `active_set`, `iterations`, `status`, `kkt` (the residuals of the answer).
#[pyfunction]
#[pyo3(signature = (H, g, G, w, warm_start = None, tolerance = 1e-9, max_iterations = 0))]
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn control_solve_qp<'py>(
    py: Python<'py>,
    H: &Bound<'py, PyAny>,
    g: &Bound<'py, PyAny>,
    G: &Bound<'py, PyAny>,
    w: &Bound<'py, PyAny>,
    warm_start: Option<Vec<usize>>,
    tolerance: f64,
    #[pyo3(from_py_with = count)] max_iterations: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let h = matrix(H, "H", OneD::Row)?;
    let gv = vec_of(g, "g")?;
    let a = matrix(G, "G", OneD::Row)?;
    let wv = vec_of(w, "w")?;
    let mut qp = ce(DualActiveSetQp::new(
        &h,
        &a,
        qp_options(tolerance, max_iterations),
    ))?;
    let status = ce(qp.solve(&gv, &wv, &warm_start.unwrap_or_default()))?;
    if status != QpStatus::Solved {
        return Err(unsolved(py, &qp, &a, &wv));
    }
    let k = ce(kkt_residuals(
        &h,
        &gv,
        &a,
        &wv,
        qp.solution(),
        qp.multipliers(),
    ))?;
    let d = PyDict::new(py);
    d.set_item("x", slice_to_numpy(py, qp.solution()))?;
    d.set_item("multipliers", slice_to_numpy(py, qp.multipliers()))?;
    d.set_item("active_set", qp.active_set().to_vec())?;
    d.set_item("iterations", qp.iterations())?;
    d.set_item("status", status_name(Some(status)))?;
    d.set_item("kkt", kkt_dict(py, &k)?)?;
    Ok(d)
}

/// `control_kkt_residuals(H, g, G, w, x, lam)`: the KKT residuals of `(x, λ)` for
/// `minimise ½xᵀHx + gᵀx s.t. Gx ≤ w` (a dict `stationarity`, `primal`, `dual`,
/// `complementarity`, each a largest absolute entry).
#[pyfunction]
#[allow(non_snake_case)]
pub fn control_kkt_residuals<'py>(
    py: Python<'py>,
    H: &Bound<'py, PyAny>,
    g: &Bound<'py, PyAny>,
    G: &Bound<'py, PyAny>,
    w: &Bound<'py, PyAny>,
    x: &Bound<'py, PyAny>,
    lam: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    let k = ce(kkt_residuals(
        &matrix(H, "H", OneD::Row)?,
        &vec_of(g, "g")?,
        &matrix(G, "G", OneD::Row)?,
        &vec_of(w, "w")?,
        &vec_of(x, "x")?,
        &vec_of(lam, "lam")?,
    ))?;
    kkt_dict(py, &k)
}
