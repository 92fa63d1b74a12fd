//! The `control` facet of the extension module: `pendulab-control`'s designs and run-time
//! controllers behind `pendulab.control` (book Part 2 §2–§3).
//!
//! | Python (`_native`) | Rust | book |
//! |---|---|---|
//! | `control_sliding_surface(A, B, Q, form, weight)` | `sliding_mode::lq_sliding_surface` | Part 2 §3.2.3 |
//! | `control_sliding_mode(S, A, B, k2, delta)` | `SlidingModeController` | Part 2 §3.2.3 |
//! | `control_energy_pumping(k1, params)` | `swing_up::EnergyPumping` | Part 2 §3.2.3 |
//! | `control_energy_shaping(rig, params, **gains)` | `CartEnergyShaping`, `ArmEnergyShaping` | — |
//! | `control_nmpc_arm_swing_up(params, …)` | `nmpc::arm_swing_up_controller` (C/GMRES) | Part 2 §3.3 |
//! | `control_odq(A, B, C, dt, step, method, …)` | `quantizer::odq_analytic`, `odq_lp` | Part 2 §2.3.4 |
//! | `control_kalman(A, B, C, dt, G, Qn, Rn)` | `estimation::kalman_filter` | — |
//! | `control_build(spec, plant, ts)` | `spec::build_for` (the spec → controller factory) | `docs/model.md` §6 |
//! | `control_find_operating_point(sys, x0, …)` ([`trim`]) | `trim::find_operating_point` | — |
//! | `KalmanFilter`, `NonlinearFilter`, `control_filter_log`, … ([`kalman`]) | `kalman` | — |
//! | `control_linear_mpc`, `control_solve_qp`, `control_kkt_residuals` ([`mpc`]) | `mpc` | — |
//!
//! Run-time controllers come back as one class, `Controller`: `update(t, y)` returns the
//! command `u` for the measurement `y` at time `t` (s), as the sampled-data loop calls it.
//! Library sign throughout: `u = −K x`.

use nalgebra::DMatrix;
use numpy::PyArray1;
use pendulab_control::quantizer::{OdqLpOptions, OdqMethod, odq_analytic, odq_lp};
use pendulab_control::sliding_mode::{
    ReducedWeight, RegularForm, SlidingModeController, lq_sliding_surface,
};
use pendulab_control::swing_up::{
    ArmEnergyShaping, CartEnergyShaping, EnergyPumping, EnergyShapingGains,
};
use pendulab_control::{ControlError, estimation, nmpc};
use pendulab_lti::{Discrete, StateSpace as Ss};
use pendulab_plants::{ArmPendulum as ArmPlant, CartPendulum as CartPlant};
use pendulab_sim::Controller as SimController;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{
    OneD, complex_to_numpy, count, matrix, matrix_to_numpy, slice_to_numpy, vector,
};
use crate::errors::{Kind, from_error, new_err};
use crate::plants::{arm_params, cart_params, plant_error};

pub mod kalman;
pub mod mpc;
pub mod trim;

/// Adds this facet's functions and classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Controller>()?;
    m.add_function(wrap_pyfunction!(control_sliding_surface, m)?)?;
    m.add_function(wrap_pyfunction!(control_sliding_mode, m)?)?;
    m.add_function(wrap_pyfunction!(control_energy_pumping, m)?)?;
    m.add_function(wrap_pyfunction!(control_energy_shaping, m)?)?;
    m.add_function(wrap_pyfunction!(control_nmpc_arm_swing_up, m)?)?;
    m.add_function(wrap_pyfunction!(control_odq, m)?)?;
    m.add_function(wrap_pyfunction!(control_kalman, m)?)?;
    m.add_function(wrap_pyfunction!(control_build, m)?)?;
    m.add_function(wrap_pyfunction!(trim::control_find_operating_point, m)?)?;
    m.add_class::<kalman::NativeKalmanFilter>()?;
    m.add_class::<kalman::NativeNonlinearFilter>()?;
    m.add_function(wrap_pyfunction!(kalman::control_filter_log, m)?)?;
    m.add_function(wrap_pyfunction!(kalman::control_quantization_variance, m)?)?;
    m.add_function(wrap_pyfunction!(kalman::control_encoder_covariance, m)?)?;
    m.add_function(wrap_pyfunction!(kalman::control_nees, m)?)?;
    m.add_class::<mpc::NativeLinearMpc>()?;
    m.add_function(wrap_pyfunction!(mpc::control_linear_mpc, m)?)?;
    m.add_function(wrap_pyfunction!(mpc::control_solve_qp, m)?)?;
    m.add_function(wrap_pyfunction!(mpc::control_kkt_residuals, m)?)?;
    Ok(())
}

/// A [`ControlError`] as the `pendulab` exception of its kind: sizes → `ShapeError`, NaN/±Inf
/// → `NotFiniteError`, a singular matrix or a search that does not converge → `LinAlgError`
/// (attribute `variant`: `"Singular"`, `"NoConvergence"`), the LTI core's errors as
/// [`crate::errors::to_py`], the simulation layer's as [`crate::plants::sim_error`], anything
/// else `InvalidArgumentError`.
pub fn control_error(e: &ControlError) -> PyErr {
    let (kind, variant) = match e {
        ControlError::DimensionMismatch { .. } | ControlError::ShapeMismatch { .. } => {
            (Kind::Shape, None)
        }
        ControlError::NonFinite { .. } => (Kind::NotFinite, Some("NonFinite")),
        ControlError::Singular { .. } => (Kind::LinAlg, Some("Singular")),
        ControlError::NoConvergence { .. } => (Kind::LinAlg, Some("NoConvergence")),
        ControlError::Lti(l) => return crate::errors::to_py(l),
        ControlError::Sim(s) => return crate::plants::sim_error(s),
        _ => (Kind::InvalidArgument, None),
    };
    new_err(kind, crate::errors::message_with_sources(e), variant)
}

/// A `pendulab-control` result with its error as [`control_error`] gives it.
///
/// # Errors
/// The converted error.
pub fn ce<T>(r: pendulab_control::Result<T>) -> PyResult<T> {
    r.map_err(|e| control_error(&e))
}

fn bad(message: String) -> PyErr {
    new_err(Kind::InvalidArgument, message, None)
}

/// A run-time controller (`pendulab_sim::Controller`): `update(t, y)` → command `u`.
#[pyclass(name = "Controller", module = "pendulab.control", unsendable)]
pub struct Controller {
    inner: Box<dyn SimController>,
    kind: String,
    u: Vec<f64>,
}

impl Controller {
    fn new(kind: &str, inner: Box<dyn SimController>) -> Self {
        let nu = inner.nu();
        Self {
            inner,
            kind: kind.into(),
            u: vec![0.0; nu],
        }
    }
}

#[pymethods]
impl Controller {
    /// The command `u` (length `nu`) for the measurement `y` (length `ny`) at time `t` (s).
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        t: f64,
        y: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let y = vector(y, "y")?;
        if y.len() != self.inner.ny() {
            return Err(new_err(
                Kind::Shape,
                format!("y must have {} entries, got {}", self.inner.ny(), y.len()),
                None,
            ));
        }
        if !t.is_finite() {
            return Err(new_err(
                Kind::NotFinite,
                format!("t = {t} must be finite"),
                None,
            ));
        }
        self.inner.update(t, y.as_slice(), &mut self.u);
        Ok(slice_to_numpy(py, &self.u))
    }
    /// Back to the initial internal state.
    fn reset(&mut self) {
        self.inner.reset();
    }
    /// Number of measurements.
    #[getter]
    fn ny(&self) -> usize {
        self.inner.ny()
    }
    /// Number of commands.
    #[getter]
    fn nu(&self) -> usize {
        self.inner.nu()
    }
    /// The sample time (s) the controller expects, or `None` (any).
    #[getter]
    fn sample_time(&self) -> Option<f64> {
        self.inner.sample_time()
    }
    /// The times (s) at which a switching controller changed mode so far.
    #[getter]
    fn switch_times(&self) -> Vec<f64> {
        self.inner.switch_times().to_vec()
    }
    fn __repr__(&self) -> String {
        format!(
            "Controller({}, ny={}, nu={})",
            self.kind,
            self.inner.ny(),
            self.inner.nu()
        )
    }
}

/// `control_sliding_surface(A, B, Q, form="book", weight="exact")`: the LQ-optimal switching
/// surface `σ = Sᵀx` (book Part 2 §3.2.3): regular form `x̄ = Tx` (`"book"`: the shear on the
/// last state, `"orthogonal"`: a Householder reflection), reduced Riccati equation with the
/// weight `"exact"` (`Q̄₁₁ − Q̄₁₂Q̄₂₂⁻¹Q̄₁₂ᵀ`) or `"book-script"` (`Q̄₁₁`). Returns a dict
/// `S, T, K, P, residual, sliding_poles, STb`.
#[pyfunction]
#[pyo3(signature = (A, B, Q, form = "book", weight = "exact"))]
#[allow(non_snake_case)]
fn control_sliding_surface<'py>(
    py: Python<'py>,
    A: &Bound<'py, PyAny>,
    B: &Bound<'py, PyAny>,
    Q: &Bound<'py, PyAny>,
    form: &str,
    weight: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let a = matrix(A, "A", OneD::Row)?;
    let b = matrix(B, "B", OneD::Column)?;
    let q = matrix(Q, "Q", OneD::Row)?;
    let form = match form {
        "book" => RegularForm::BookShear,
        "orthogonal" => RegularForm::Orthogonal,
        other => {
            return Err(bad(format!(
                "form {other:?}: expected \"book\" or \"orthogonal\""
            )));
        }
    };
    let weight = match weight {
        "exact" => ReducedWeight::Exact,
        "book-script" => ReducedWeight::BookScript,
        other => {
            return Err(bad(format!(
                "weight {other:?}: expected \"exact\" or \"book-script\""
            )));
        }
    };
    let s = ce(lq_sliding_surface(&a, &b, &q, form, weight))?;
    let d = PyDict::new(py);
    d.set_item("S", slice_to_numpy(py, &s.s))?;
    d.set_item("T", matrix_to_numpy(py, &s.transformation))?;
    d.set_item("K", matrix_to_numpy(py, &s.reduced_gain))?;
    d.set_item("P", matrix_to_numpy(py, &s.riccati))?;
    d.set_item("residual", s.residual)?;
    d.set_item("sliding_poles", complex_to_numpy(py, &s.sliding_poles))?;
    d.set_item("STb", s.s_transpose_b)?;
    Ok(d)
}

/// `control_sliding_mode(S, A, B, k2, delta=0.0)`: the sliding-mode law
/// `u = −(SᵀA x + K₂ σ/(|σ| + δ)) / (SᵀB)`, `σ = Sᵀx` (book Part 2 §3.2.3; `δ = 0`:
/// `sign σ`).
#[pyfunction]
#[pyo3(signature = (S, A, B, k2, delta = 0.0))]
#[allow(non_snake_case)]
fn control_sliding_mode(
    S: &Bound<'_, PyAny>,
    A: &Bound<'_, PyAny>,
    B: &Bound<'_, PyAny>,
    k2: f64,
    delta: f64,
) -> PyResult<Controller> {
    let s = vector(S, "S")?;
    let a = matrix(A, "A", OneD::Row)?;
    let b = matrix(B, "B", OneD::Column)?;
    let c = ce(SlidingModeController::new(s.as_slice(), &a, &b, k2, delta))?;
    Ok(Controller::new("sliding-mode", Box::new(c)))
}

fn cart_plant(params: Option<std::collections::HashMap<String, f64>>) -> PyResult<CartPlant> {
    CartPlant::new(cart_params(params.as_ref())?).map_err(|e| plant_error(&e))
}

fn arm_plant(params: Option<std::collections::HashMap<String, f64>>) -> PyResult<ArmPlant> {
    ArmPlant::new(arm_params(params.as_ref())?).map_err(|e| plant_error(&e))
}

/// `control_energy_pumping(k1=0.8, params=None)`: the book's energy-pumping swing-up of the
/// cart pendulum (Part 2 §3.2.3), on the cart with `params` (book table 3.5 by default).
#[pyfunction]
#[pyo3(signature = (k1 = 0.8, params = None))]
fn control_energy_pumping(
    k1: f64,
    params: Option<std::collections::HashMap<String, f64>>,
) -> PyResult<Controller> {
    let c = ce(EnergyPumping::new(&cart_plant(params)?, k1))?;
    Ok(Controller::new("energy-pumping", Box::new(c)))
}

/// `control_energy_shaping(rig, params=None, gains=None)`: the energy-shaping swing-up of the
/// cart (`rig="cart"`) or arm (`"arm"`) pendulum with the rig's tuned gains
/// (`EnergyShapingGains::cart_rig` / `arm_rig`), each overridable in `gains` by its field name
/// (`k_energy`, `max_acceleration`, `energy_ratio`, `k_position`, `k_velocity`, `reference`,
/// `travel_limit`, `max_voltage`).
#[pyfunction]
#[pyo3(signature = (rig, params = None, gains = None))]
fn control_energy_shaping(
    rig: &str,
    params: Option<std::collections::HashMap<String, f64>>,
    gains: Option<std::collections::HashMap<String, f64>>,
) -> PyResult<Controller> {
    let mut g = match rig {
        "cart" => EnergyShapingGains::cart_rig(),
        "arm" => EnergyShapingGains::arm_rig(),
        other => return Err(bad(format!("rig {other:?}: expected \"cart\" or \"arm\""))),
    };
    for (k, v) in gains.into_iter().flatten() {
        let field = match k.as_str() {
            "k_energy" => &mut g.k_energy,
            "max_acceleration" => &mut g.max_acceleration,
            "energy_ratio" => &mut g.energy_ratio,
            "k_position" => &mut g.k_position,
            "k_velocity" => &mut g.k_velocity,
            "reference" => &mut g.reference,
            "travel_limit" => &mut g.travel_limit,
            "max_voltage" => &mut g.max_voltage,
            other => return Err(bad(format!("gains: unknown gain {other:?}"))),
        };
        *field = v;
    }
    let c: Box<dyn SimController> = if rig == "cart" {
        Box::new(ce(CartEnergyShaping::new(&cart_plant(params)?, g))?)
    } else {
        Box::new(ce(ArmEnergyShaping::new(&arm_plant(params)?, g))?)
    };
    Ok(Controller::new("energy-shaping", c))
}

/// `control_nmpc_arm_swing_up(params=None, u_max=2.5, ts=1e-3)`: the C/GMRES NMPC swing-up
/// of the arm pendulum with the book's setting (Part 2 §3.3: `Q = diag(1, 1, 0, 0)`,
/// `Q_f = diag(3, 1, 0, 0)`, horizon `T(t) = 0.5(1 − e^{−0.5t})`, `N = 25`), `|u| ≤ u_max`
/// (V), updated every `ts` (s). Measurement: the full state `[θ₁, θ₂, θ̇₁, θ̇₂]`.
#[pyfunction]
#[pyo3(signature = (params = None, u_max = 2.5, ts = 1e-3))]
fn control_nmpc_arm_swing_up(
    params: Option<std::collections::HashMap<String, f64>>,
    u_max: f64,
    ts: f64,
) -> PyResult<Controller> {
    let settings = nmpc::ArmSwingUpSettings {
        u_max,
        ts,
        ..nmpc::ArmSwingUpSettings::book()
    };
    let c = ce(nmpc::arm_swing_up_controller(arm_plant(params)?, &settings))?;
    Ok(Controller::new("nmpc", Box::new(c)))
}

fn discrete(
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    c: &Bound<'_, PyAny>,
    dt: f64,
) -> PyResult<Ss<Discrete>> {
    let a = matrix(a, "A", OneD::Row)?;
    let b = matrix(b, "B", OneD::Column)?;
    let c = matrix(c, "C", OneD::Row)?;
    let d = DMatrix::zeros(c.nrows(), b.ncols());
    Ss::discrete(a, b, c, d, dt).map_err(crate::errors::lti)
}

/// `control_odq(A, B, C, dt, step, method="analytic", horizon=300, max_filter_gain=None)`:
/// the optimal dynamic quantizer (Azuma–Sugie; book Part 2 §2.3.4) of step `d` for the
/// strictly proper discrete system `(A, B, C)` (sample time `dt`): the closed form
/// (`"analytic"`) or the linear program over `horizon` samples (`"lp"`). Returns a dict: the
/// filter `(A_f, B_f, C_f)`, `design_cost`, `cost` and `static_cost` (worst-case output
/// deviation bounds), `filter_gain`, `method`.
#[pyfunction]
#[pyo3(signature = (A, B, C, dt, step, method = "analytic", horizon = 300, max_filter_gain = None))]
#[allow(non_snake_case, clippy::too_many_arguments)]
fn control_odq<'py>(
    py: Python<'py>,
    A: &Bound<'py, PyAny>,
    B: &Bound<'py, PyAny>,
    C: &Bound<'py, PyAny>,
    dt: f64,
    step: f64,
    method: &str,
    #[pyo3(from_py_with = count)] horizon: usize,
    max_filter_gain: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let sys = discrete(A, B, C, dt)?;
    let design = match method {
        "analytic" => py.detach(|| odq_analytic(&sys, step)),
        "lp" => {
            let o = OdqLpOptions {
                horizon,
                max_filter_gain,
                ..OdqLpOptions::default()
            };
            py.detach(|| odq_lp(&sys, step, &o))
        }
        other => {
            return Err(bad(format!(
                "method {other:?}: expected \"analytic\" or \"lp\""
            )));
        }
    };
    let design = ce(design)?;
    let (af, bf, cf) = design.quantizer.filter();
    let d = PyDict::new(py);
    d.set_item("A_f", matrix_to_numpy(py, af))?;
    d.set_item("B_f", matrix_to_numpy(py, bf))?;
    d.set_item("C_f", matrix_to_numpy(py, cf))?;
    d.set_item("design_cost", design.design_cost)?;
    d.set_item("cost", design.cost.bound)?;
    d.set_item("static_cost", design.static_cost.bound)?;
    d.set_item("filter_gain", design.filter_gain)?;
    d.set_item(
        "method",
        match design.method {
            OdqMethod::Analytic { .. } => "analytic",
            _ => "lp",
        },
    )?;
    Ok(d)
}

/// `control_kalman(A, B, C, dt, G, Qn, Rn)`: the steady-state Kalman filter of
/// `x⁺ = Ax + Bu + Gw`, `y = Cx + v`, `E[wwᵀ] = Q_n`, `E[vvᵀ] = R_n` (MATLAB `kalman`). Returns
/// a dict: predictor gain `L`, filter gain `M`, prior and posterior covariances `P`, `Z`, the
/// error poles and the DARE's relative residual.
#[pyfunction]
#[pyo3(signature = (A, B, C, dt, G, Qn, Rn))]
#[allow(non_snake_case, clippy::too_many_arguments)]
fn control_kalman<'py>(
    py: Python<'py>,
    A: &Bound<'py, PyAny>,
    B: &Bound<'py, PyAny>,
    C: &Bound<'py, PyAny>,
    dt: f64,
    G: &Bound<'py, PyAny>,
    Qn: &Bound<'py, PyAny>,
    Rn: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    let sys = discrete(A, B, C, dt)?;
    let g = matrix(G, "G", OneD::Column)?;
    let qn = matrix(Qn, "Qn", OneD::Row)?;
    let rn = matrix(Rn, "Rn", OneD::Row)?;
    let k = ce(py.detach(|| estimation::kalman_filter(&sys, &g, &qn, &rn)))?;
    let d = PyDict::new(py);
    d.set_item("L", matrix_to_numpy(py, &k.predictor_gain))?;
    d.set_item("M", matrix_to_numpy(py, &k.filter_gain))?;
    d.set_item("P", matrix_to_numpy(py, &k.prior_covariance))?;
    d.set_item("Z", matrix_to_numpy(py, &k.posterior_covariance))?;
    d.set_item("poles", complex_to_numpy(py, &k.error_poles))?;
    d.set_item("residual", k.residual)?;
    Ok(d)
}

/// `control_build(spec, plant, ts)`: the controller a `ControllerSpec` (JSON text) describes
/// for the plant (`"cart"`, `"arm"` or a `PlantSpec` as JSON), running at loop period `ts`
/// (s): the factory every front end uses (`pendulab_control::spec::build_for`).
#[pyfunction]
fn control_build(spec: &str, plant: &str, ts: f64) -> PyResult<Controller> {
    let spec: pendulab_control::spec::ControllerSpec = serde_json::from_str(spec).map_err(|e| {
        new_err(
            Kind::InvalidArgument,
            format!("controller: {e}"),
            Some("Spec"),
        )
    })?;
    let plant = crate::plants::plant_spec(plant)?;
    let built = pendulab_control::spec::build_for(&spec, &plant, ts)
        .map_err(|e| from_error(Kind::InvalidArgument, &e))?;
    Ok(Controller::new(built.kind, built.controller))
}
