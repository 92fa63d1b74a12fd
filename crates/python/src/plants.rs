//! The `plants` facet of the extension module: the book's cart-type and arm-type pendulums
//! (`pendulab-plants`) behind `pendulab.plants`.
//!
//! Parameters cross as dicts of the book's symbols (table 3.5: `a_c, b_c, m_p, l_p, L_p, J_p,
//! mu_p, g`; table 3.7: `a1, b1, L1, m2, l2, L2, J2, mu2, g`); missing entries take the book's
//! values, unknown names and invalid values (checked by the Rust `new`) raise
//! `pendulab.InvalidArgumentError` naming the parameter. States are `[z, θ, ż, θ̇]` (cart) and
//! `[θ₁, θ₂, θ̇₁, θ̇₂]` (arm), SI units, angles from the upward vertical; the input is the
//! motor voltage (V).

use std::collections::HashMap;

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

use pendulab_lti::{Continuous, StateSpace};
use pendulab_plants::{
    ArmEquilibrium, ArmLpv, ArmPendulum as ArmPlant, ArmPendulumParams, ArmPendulumState,
    CartEquilibrium, CartPendulum as CartPlant, CartPendulumParams, CartPendulumState, Jacobian,
    PlantError, Posture,
};
use pendulab_sim::SimError;

use crate::convert::{matrix_to_numpy, slice_to_numpy, vector};
use crate::errors::{Kind, from_error, new_err};

/// Adds this facet's classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<CartPendulum>()?;
    m.add_class::<ArmPendulum>()?;
    m.add_function(wrap_pyfunction!(simulate_json, m)?)?;
    Ok(())
}

/// Parses one spec from its JSON text, naming the argument in the error.
pub fn spec<T: serde::de::DeserializeOwned>(json: &str, what: &str) -> PyResult<T> {
    serde_json::from_str(json)
        .map_err(|e| new_err(Kind::InvalidArgument, format!("{what}: {e}"), Some("Spec")))
}

/// The one simulate path (`pendulab_control::scenario::simulate`) on specs given as JSON
/// text: `plant` a `PlantSpec` (or just `"cart"` / `"arm"`: the book's rig), `controller` a
/// `ControllerSpec`, `scenario` a `ScenarioSpec` (`docs/model.md` §6). Runs with the GIL
/// released; returns a dict of float64 arrays (`t` (N,), `x` (N, 4), `u`, `command` (N,),
/// `y` (N, 4), `reference` (N,)), `ts`, `switch_times` and `summary` (a dict).
///
/// Raises `pendulab.InvalidArgumentError` for a spec that does not parse or validate (the
/// message names the key), `pendulab.Error` for a failed run.
#[pyfunction]
fn simulate_json<'py>(
    py: Python<'py>,
    plant: &str,
    controller: &str,
    scenario: &str,
) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    use pendulab_control::scenario::simulate;
    let plant = plant_spec(plant)?;
    let controller: pendulab_control::spec::ControllerSpec = spec(controller, "controller")?;
    let scenario: pendulab_sim::scenario::ScenarioSpec = spec(scenario, "scenario")?;
    let run = py
        .detach(|| simulate(&plant, &controller, &scenario))
        .map_err(|e| from_error(Kind::InvalidArgument, &e))?;
    run_dict(py, &run)
}

/// A simulated run as the dict `simulate_json` returns (see there).
///
/// # Errors
/// Only if NumPy cannot allocate the arrays.
pub fn run_dict<'py>(
    py: Python<'py>,
    run: &pendulab_control::scenario::Run,
) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    let rows = |v: &[Vec<f64>]| -> PyResult<Bound<'py, PyArray2<f64>>> {
        let w = v.first().map_or(0, Vec::len);
        let flat: Vec<f64> = v.iter().flatten().copied().collect();
        numpy::IntoPyArray::into_pyarray(flat, py).reshape([v.len(), w])
    };
    let d = pyo3::types::PyDict::new(py);
    d.set_item("t", slice_to_numpy(py, &run.t))?;
    d.set_item("x", rows(&run.x)?)?;
    d.set_item("u", slice_to_numpy(py, &run.u))?;
    d.set_item("command", slice_to_numpy(py, &run.command))?;
    d.set_item("y", rows(&run.y)?)?;
    d.set_item("reference", slice_to_numpy(py, &run.reference))?;
    d.set_item("ts", run.ts)?;
    d.set_item("switch_times", run.switch_times.clone())?;
    let s = &run.summary;
    let summary = pyo3::types::PyDict::new(py);
    summary.set_item("settling_time", s.settling_time)?;
    summary.set_item("overshoot_percent", s.overshoot_percent)?;
    summary.set_item("peak_input", s.peak_input)?;
    summary.set_item("peak_command", s.peak_command)?;
    summary.set_item("time_in_saturation", s.time_in_saturation)?;
    summary.set_item("max_angle_deviation", s.max_angle_deviation)?;
    summary.set_item("left_angle_window", s.left_angle_window)?;
    summary.set_item("left_travel", s.left_travel)?;
    summary.set_item("final_state", s.final_state.clone())?;
    d.set_item("summary", summary)?;
    Ok(d)
}

/// The plant of a front-end call: `"cart"` / `"arm"` (the book's rig, `PlantSpec::book`) or a
/// `PlantSpec` as JSON text.
///
/// # Errors
/// `InvalidArgumentError` naming the unknown plant or the spec's bad key.
pub fn plant_spec(plant: &str) -> PyResult<pendulab_plants::spec::PlantSpec> {
    use pendulab_plants::rig::PlantKind;
    use pendulab_plants::spec::PlantSpec;
    if plant.trim_start().starts_with('{') {
        spec(plant, "plant")
    } else {
        Ok(PlantSpec::book(
            PlantKind::parse(plant).map_err(|e| from_error(Kind::InvalidArgument, &e))?,
        ))
    }
}

/// A [`PlantError`] as `pendulab.InvalidArgumentError` (bad parameter or operating point).
pub fn plant_error(e: &PlantError) -> PyErr {
    from_error(Kind::InvalidArgument, e)
}

/// A [`SimError`] as the `pendulab` exception of its kind: wrong lengths → `ShapeError`,
/// NaN/±Inf inputs → `NotFiniteError`, a state that blows up or an integrator that gives up
/// → `pendulab.Error`, other bad arguments → `InvalidArgumentError`.
pub fn sim_error(e: &SimError) -> PyErr {
    let kind = match e {
        SimError::DimensionMismatch { .. } => Kind::Shape,
        SimError::NonFiniteInitialState { .. } | SimError::NonFiniteCommand { .. } => {
            Kind::NotFinite
        }
        SimError::NonFiniteState { .. }
        | SimError::StepSizeUnderflow { .. }
        | SimError::MaxStepsExceeded { .. } => Kind::Error,
        _ => Kind::InvalidArgument,
    };
    from_error(kind, e)
}

/// A plant's parameter struct with its fields listed once, by the book's symbols: the list
/// both applies a dict of values ([`params_from`]) and reads them back ([`params_dict`]).
pub trait ParamFields: Clone {
    /// The model's name in error messages.
    const MODEL: &'static str;
    /// The book's values (table 3.5 or 3.7).
    fn book() -> Self;
    /// Every parameter: (the book's symbol, the field).
    fn fields(&mut self) -> Vec<(&'static str, &mut f64)>;
}

impl ParamFields for CartPendulumParams {
    const MODEL: &'static str = "cart pendulum";
    fn book() -> Self {
        CartPendulumParams::book()
    }
    fn fields(&mut self) -> Vec<(&'static str, &mut f64)> {
        vec![
            ("a_c", &mut self.a_c),
            ("b_c", &mut self.b_c),
            ("m_p", &mut self.m_p),
            ("l_p", &mut self.l_p),
            ("L_p", &mut self.L_p),
            ("J_p", &mut self.J_p),
            ("mu_p", &mut self.mu_p),
            ("g", &mut self.g),
        ]
    }
}

impl ParamFields for ArmPendulumParams {
    const MODEL: &'static str = "arm pendulum";
    fn book() -> Self {
        ArmPendulumParams::book()
    }
    fn fields(&mut self) -> Vec<(&'static str, &mut f64)> {
        vec![
            ("a1", &mut self.a1),
            ("b1", &mut self.b1),
            ("L1", &mut self.L1),
            ("m2", &mut self.m2),
            ("l2", &mut self.l2),
            ("L2", &mut self.L2),
            ("J2", &mut self.J2),
            ("mu2", &mut self.mu2),
            ("g", &mut self.g),
        ]
    }
}

/// The book's parameters with `values` applied (not yet validated: the Rust `new` checks
/// them, so a NaN is refused there with its "must be finite" message).
///
/// # Errors
/// `InvalidArgumentError` for a name that is not a parameter, listing the known ones.
pub fn params_from<P: ParamFields>(values: Option<&HashMap<String, f64>>) -> PyResult<P> {
    let mut p = P::book();
    let mut fields = p.fields();
    for (k, v) in values.into_iter().flatten() {
        match fields.iter_mut().find(|(n, _)| n == k) {
            Some((_, f)) => **f = *v,
            None => {
                let known: Vec<&str> = fields.iter().map(|(n, _)| *n).collect();
                return Err(new_err(
                    Kind::InvalidArgument,
                    format!(
                        "{}: unknown parameter {k:?} (known: {})",
                        P::MODEL,
                        known.join(", ")
                    ),
                    None,
                ));
            }
        }
    }
    drop(fields);
    Ok(p)
}

/// The parameters as a dict of the book's symbols (SI units), in the book's order.
///
/// # Errors
/// Only if Python cannot build the dict.
pub fn params_dict<'py, P: ParamFields>(
    py: Python<'py>,
    p: &P,
) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    let mut p = p.clone();
    let d = pyo3::types::PyDict::new(py);
    for (n, v) in p.fields() {
        d.set_item(n, *v)?;
    }
    Ok(d)
}

/// The cart's parameters: the book's (table 3.5) with `values` applied (not yet validated).
///
/// # Errors
/// `InvalidArgumentError` for a name that is not a parameter.
pub fn cart_params(values: Option<&HashMap<String, f64>>) -> PyResult<CartPendulumParams> {
    params_from(values)
}

/// The arm's parameters: the book's (table 3.7) with `values` applied (not yet validated).
///
/// # Errors
/// `InvalidArgumentError` for a name that is not a parameter.
pub fn arm_params(values: Option<&HashMap<String, f64>>) -> PyResult<ArmPendulumParams> {
    params_from(values)
}

/// `"upright"` or `"hanging"`.
fn posture(s: &str) -> PyResult<Posture> {
    match s {
        "upright" => Ok(Posture::Upright),
        "hanging" => Ok(Posture::Hanging),
        _ => Err(new_err(
            Kind::InvalidArgument,
            format!("posture {s:?}: expected \"upright\" or \"hanging\""),
            None,
        )),
    }
}

/// A state argument of four finite numbers.
fn state4(x: &Bound<'_, PyAny>, what: &str) -> PyResult<[f64; 4]> {
    let v = vector(x, what)?;
    if v.len() != 4 {
        return Err(new_err(
            Kind::Shape,
            format!("{what} must have 4 entries, got {}", v.len()),
            None,
        ));
    }
    Ok([v[0], v[1], v[2], v[3]])
}

/// A finite scalar input (V).
fn voltage(u: f64) -> PyResult<f64> {
    if u.is_finite() {
        Ok(u)
    } else {
        Err(new_err(
            Kind::NotFinite,
            format!("u = {u} must be finite"),
            None,
        ))
    }
}

/// `(A, B, C, D)` as float64 arrays.
type Abcd<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
);

/// `(A, B, C, D)` of a state-space model as float64 arrays.
fn abcd<'py>(py: Python<'py>, sys: &StateSpace<Continuous>) -> Abcd<'py> {
    (
        matrix_to_numpy(py, sys.a()),
        matrix_to_numpy(py, sys.b()),
        matrix_to_numpy(py, sys.c()),
        matrix_to_numpy(py, sys.d()),
    )
}

/// `(A, B)` as float64 arrays.
type Ab<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>);

/// `(A (4, 4), B (4, 1))` of a Jacobian.
fn jacobian_arrays<'py>(py: Python<'py>, j: &Jacobian<4>) -> Ab<'py> {
    (
        matrix_to_numpy(py, &j.a_matrix()),
        matrix_to_numpy(py, &j.b_matrix()),
    )
}

/// Declares a plant's Python class: the methods both pendulums share (`new`, `params`,
/// `derivative`, `jacobian`, `linearize`, `upright_energy`, `__repr__`), written once, plus
/// the plant's own methods (`extra`). `coord` names the drive coordinate of the equilibrium
/// (`z` for the cart, `theta1` for the arm); `state` documents the state vector.
macro_rules! plant_class {
    (
        $(#[$doc:meta])*
        $class:ident($plant:ty, $params:ident, $eq:ident { $coord:ident }, state $state:literal,
            linearize $lin_doc:literal)
        { $($extra:tt)* }
    ) => {
        $(#[$doc])*
        #[pyclass(module = "pendulab._native", frozen)]
        pub struct $class {
            plant: $plant,
        }

        #[pymethods]
        impl $class {
            /// The plant with the book's parameters, each overridable in `params`.
            #[new]
            #[pyo3(signature = (params = None))]
            fn new(params: Option<HashMap<String, f64>>) -> PyResult<Self> {
                let p = $params(params.as_ref())?;
                Ok(Self {
                    plant: <$plant>::new(p).map_err(|e| plant_error(&e))?,
                })
            }

            /// The parameters as a dict of the book's symbols (SI units).
            #[getter]
            fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
                params_dict(py, self.plant.params())
            }

            #[doc = concat!("`ẋ = f(x, u)` at the state `x = ", $state, "` and the voltage `u` (V).")]
            fn derivative<'py>(
                &self,
                py: Python<'py>,
                x: &Bound<'py, PyAny>,
                u: f64,
            ) -> PyResult<Bound<'py, PyArray1<f64>>> {
                let f = self.plant.derivative_array(&state4(x, "x")?, voltage(u)?);
                Ok(slice_to_numpy(py, &f))
            }

            /// The analytic Jacobian `(A, B) = (∂f/∂x, ∂f/∂u)` at any point `(x, u)`.
            fn jacobian<'py>(
                &self,
                py: Python<'py>,
                x: &Bound<'py, PyAny>,
                u: f64,
            ) -> PyResult<Ab<'py>> {
                let j = self.plant.jacobian(&state4(x, "x")?, voltage(u)?);
                Ok(jacobian_arrays(py, &j))
            }

            #[doc = $lin_doc]
            #[pyo3(signature = (posture = "upright", $coord = 0.0, measured = false))]
            fn linearize<'py>(
                &self,
                py: Python<'py>,
                posture: &str,
                $coord: f64,
                measured: bool,
            ) -> PyResult<Abcd<'py>> {
                let eq = $eq {
                    $coord,
                    posture: self::posture(posture)?,
                };
                let sys = if measured {
                    self.plant.linearize_measured(eq)
                } else {
                    self.plant.linearize(eq)
                }
                .map_err(|e| plant_error(&e))?;
                Ok(abcd(py, &sys))
            }

            /// The upright rest's energy (J): `2 m_p g l_p` (cart), `2 α₅` (arm).
            #[getter]
            fn upright_energy(&self) -> f64 {
                self.plant.upright_energy()
            }

            fn __repr__(&self) -> String {
                format!(concat!(stringify!($class), "({:?})"), self.plant.params())
            }

            $($extra)*
        }
    };
}

plant_class!(
    /// The cart-type pendulum (book §3.1, table 3.5; `docs/model.md` §1).
    CartPendulum(CartPlant, cart_params, CartEquilibrium { z }, state "[z, θ, ż, θ̇]",
        linearize "The linearisation `(A, B, C, D)` at the rest `posture` (`\"upright\"` or \
                   `\"hanging\"`) with the cart at `z` (m), in deviation variables; `C = I` or, \
                   with `measured`, the encoder rows `[z, θ]`.")
    {
        /// `J = J_p + m_p l_p²` (kg m²), the pendulum's inertia about the pivot.
        #[getter]
        fn inertia_about_pivot(&self) -> f64 {
            self.plant.inertia_about_pivot()
        }

        /// The pendulum's energy `E = ½ J θ̇² + m_p g l_p (1 + cos θ)` (J) at `x`.
        fn energy(&self, x: &Bound<'_, PyAny>) -> PyResult<f64> {
            Ok(self
                .plant
                .energy(&CartPendulumState::from_array(state4(x, "x")?)))
        }
    }
);

plant_class!(
    /// The arm-type pendulum (book §3.3, table 3.7; `docs/model.md` §2).
    ArmPendulum(ArmPlant, arm_params, ArmEquilibrium { theta1 }, state "[θ₁, θ₂, θ̇₁, θ̇₂]",
        linearize "The linearisation `(A, B, C, D)` with the arm at rest at `theta1` (rad) and \
                   the pendulum at rest `posture`; `C = I` or, with `measured`, the encoder \
                   rows `[θ₁, θ₂]`.")
    {
        /// `(α₂, α₃, α₅) = (J₂ + m₂ l₂², m₂ L₁ l₂, m₂ l₂ g)`.
        #[getter]
        fn alphas(&self) -> (f64, f64, f64) {
            (
                self.plant.alpha2(),
                self.plant.alpha3(),
                self.plant.alpha5(),
            )
        }

        /// The LPV form `(A₀, A₁, B₀, B₁)` of the upright model: `A(ρ) = A₀ + ρ A₁`,
        /// `B(ρ) = B₀ + ρ B₁`, `ρ = 1 − cos θ₁` (book part 2 §1.5).
        #[allow(clippy::type_complexity)]
        fn lpv<'py>(&self, py: Python<'py>) -> Abcd<'py> {
            let ArmLpv { a0, a1, b0, b1 } = self.plant.lpv();
            (
                matrix_to_numpy(py, &a0),
                matrix_to_numpy(py, &a1),
                matrix_to_numpy(py, &b0),
                matrix_to_numpy(py, &b1),
            )
        }

        /// The pendulum's energy `E₂ = ½ α₂ θ̇₂² + α₅ (1 + cos θ₂)` (J) at `x`.
        fn energy(&self, x: &Bound<'_, PyAny>) -> PyResult<f64> {
            Ok(self
                .plant
                .pendulum_energy(&ArmPendulumState::from_array(state4(x, "x")?)))
        }
    }
);
