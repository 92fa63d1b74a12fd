//! A user's nonlinear model given as Python callables, as a `pendulab-sim` [`Dynamics`]: the
//! one wrapper behind `pendulab.control.find_operating_point` and the extended and unscented
//! Kalman filters.
//!
//! The model is `ẋ = f(x, u)` with the optional output map `y = h(x, u)` (continuous time,
//! time-invariant: `t` is not passed), `f` and `h` Python callables taking two 1-d `float64`
//! arrays and returning anything [`crate::convert::vector`] reads (a list, an array, a scalar
//! for one entry). They are called with the GIL held (the library calls stay on the calling
//! thread). [`Dynamics::derivative`] cannot fail, so a failing call is recorded in an
//! [`ErrorSlot`] and the output is filled with NaN, which stops the library's computation (a
//! non-finite evaluation is an error everywhere in `pendulab-control`); the caller then
//! reports the recorded error instead of the library's ([`ErrorSlot::or`]):
//!
//! - an exception raised by the callable propagates as that same Python exception;
//! - a result of the wrong length is a `pendulab.ShapeError` ("f(x, u) returned 3 values, the
//!   state has 4"), NaN or ±Inf a `pendulab.NotFiniteError` naming the entry, something that
//!   is not a vector a `pendulab.InvalidArgumentError`/`ShapeError`; each message names the
//!   point `(x, u)` at which it happened.
//!
//! [`Model`] joins the callables with the shipped plants (`pendulab.plants.CartPendulum`,
//! `ArmPendulum` objects or the names `"cart"` / `"arm"`), so each front-end function takes
//! either.

use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::Rc;

use pendulab_plants::{ArmPendulum as ArmPlant, CartPendulum as CartPlant};
use pendulab_sim::Dynamics;
use pyo3::prelude::*;

use crate::convert::{slice_to_numpy, vector};
use crate::errors::{Kind, new_err};
use crate::plants::{arm_params, cart_params, plant_error};

/// The first error a callable raised during a library call, shared between the model and the
/// front-end object that owns it.
#[derive(Debug, Clone, Default)]
pub struct ErrorSlot(Rc<RefCell<Option<PyErr>>>);

impl ErrorSlot {
    /// Records `e` unless an earlier error is already recorded.
    fn set(&self, e: PyErr) {
        let mut slot = self.0.borrow_mut();
        if slot.is_none() {
            *slot = Some(e);
        }
    }

    /// Whether an error is recorded.
    fn is_set(&self) -> bool {
        self.0.borrow().is_some()
    }

    /// Clears the slot before a library call.
    pub fn clear(&self) {
        self.0.borrow_mut().take();
    }

    /// The recorded error if there is one, else `result` with its error mapped by `map`: the
    /// callable's own failure takes precedence over the library's report of the NaN it caused.
    ///
    /// # Errors
    /// The recorded error, or `map(library error)`.
    pub fn or<T, E>(&self, result: Result<T, E>, map: impl FnOnce(&E) -> PyErr) -> PyResult<T> {
        if let Some(e) = self.0.borrow_mut().take() {
            return Err(e);
        }
        result.map_err(|e| map(&e))
    }
}

/// `ẋ = f(x, u)`, `y = h(x, u)` as Python callables (module documentation).
#[derive(Debug)]
pub struct PyDynamics {
    f: Py<PyAny>,
    h: Option<Py<PyAny>>,
    nx: usize,
    nu: usize,
    ny: usize,
    errors: ErrorSlot,
}

/// Checks that `obj` is callable, naming it.
fn check_callable(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<()> {
    if obj.is_callable() {
        Ok(())
    } else {
        Err(new_err(
            Kind::InvalidArgument,
            format!(
                "{what} must be a callable (x, u) -> array, got {}",
                obj.get_type().name()?
            ),
            None,
        ))
    }
}

/// Calls `func(x, u)` and reads the result as a vector of length `n` (`None`: any length).
fn call(
    py: Python<'_>,
    func: &Py<PyAny>,
    what: &str,
    x: &[f64],
    u: &[f64],
    n: Option<usize>,
) -> PyResult<Vec<f64>> {
    let out = func
        .bind(py)
        .call1((slice_to_numpy(py, x), slice_to_numpy(py, u)))?;
    let at = format!("{what} at x = {x:?}, u = {u:?}");
    let v = vector(&out, &at)?;
    if let Some(n) = n
        && v.len() != n
    {
        return Err(new_err(
            Kind::Shape,
            format!(
                "{what} returned {} values at x = {x:?}, u = {u:?}; expected {n}",
                v.len()
            ),
            None,
        ));
    }
    Ok(v.as_slice().to_vec())
}

impl PyDynamics {
    /// The model `f` (and `h`) with `nx` states and `nu` inputs, probed once at `(x, u)`
    /// (lengths `nx`, `nu`): `f` must return `nx` finite values there, and `h` fixes the
    /// output count `ny` by what it returns.
    ///
    /// # Errors
    /// `InvalidArgumentError` if `f` or `h` is not callable; the probe's errors (module
    /// documentation).
    pub fn new(
        f: &Bound<'_, PyAny>,
        h: Option<&Bound<'_, PyAny>>,
        x: &[f64],
        u: &[f64],
    ) -> PyResult<Self> {
        let py = f.py();
        check_callable(f, "f")?;
        let f = f.clone().unbind();
        call(py, &f, "f(x, u)", x, u, Some(x.len()))?;
        let (h, ny) = match h {
            Some(h) => {
                check_callable(h, "h")?;
                let h = h.clone().unbind();
                let ny = call(py, &h, "h(x, u)", x, u, None)?.len();
                (Some(h), ny)
            }
            None => (None, 0),
        };
        Ok(Self {
            f,
            h,
            nx: x.len(),
            nu: u.len(),
            ny,
            errors: ErrorSlot::default(),
        })
    }

    /// Calls `func` into `out`; on failure records the error and fills `out` with NaN.
    fn eval(&self, func: &Py<PyAny>, what: &str, x: &[f64], u: &[f64], out: &mut [f64]) {
        if self.errors.is_set() {
            out.fill(f64::NAN);
            return;
        }
        Python::attach(|py| match call(py, func, what, x, u, Some(out.len())) {
            Ok(v) => out.copy_from_slice(&v),
            Err(e) => {
                self.errors.set(e);
                out.fill(f64::NAN);
            }
        });
    }
}

impl Dynamics for PyDynamics {
    fn nx(&self) -> usize {
        self.nx
    }
    fn nu(&self) -> usize {
        self.nu
    }
    fn derivative(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        self.eval(&self.f, "f(x, u)", x, u, dx);
    }
    fn ny(&self) -> usize {
        self.ny
    }
    fn output(&self, _t: f64, x: &[f64], u: &[f64], y: &mut [f64]) {
        if let Some(h) = &self.h {
            self.eval(h, "h(x, u)", x, u, y);
        }
    }
}

/// A model the front-end functions accept: a shipped plant or Python callables.
#[derive(Debug)]
pub enum Model {
    /// The cart pendulum (state `[z, θ, ż, θ̇]`, input the voltage; no output map).
    Cart(CartPlant),
    /// The arm pendulum (state `[θ₁, θ₂, θ̇₁, θ̇₂]`, input the voltage; no output map).
    Arm(ArmPlant),
    /// A user's `f` and optional `h`.
    Callable(PyDynamics),
}

impl Model {
    /// The model `sys` stands for: a `pendulab.plants.CartPendulum` or `ArmPendulum` (its
    /// parameters), `"cart"` or `"arm"` (the book's), or a callable `f(x, u)` with the output
    /// map `h` (probed at `x`, `u`: `nx = len(x)`, `nu = len(u)`). `h` is refused with a
    /// plant, which has no output map.
    ///
    /// # Errors
    /// `InvalidArgumentError` for anything else, an unknown plant name or `h` with a plant;
    /// [`PyDynamics::new`]'s errors.
    pub fn from_py(
        sys: &Bound<'_, PyAny>,
        h: Option<&Bound<'_, PyAny>>,
        x: &[f64],
        u: &[f64],
    ) -> PyResult<Self> {
        let params = || -> PyResult<Option<HashMap<String, f64>>> {
            Ok(Some(sys.getattr("params")?.extract()?))
        };
        let plant = if let Ok(name) = sys.extract::<String>() {
            Some((name, None))
        } else if sys.is_instance_of::<crate::plants::CartPendulum>() {
            Some(("cart".to_string(), params()?))
        } else if sys.is_instance_of::<crate::plants::ArmPendulum>() {
            Some(("arm".to_string(), params()?))
        } else {
            None
        };
        let Some((name, params)) = plant else {
            return Ok(Model::Callable(PyDynamics::new(sys, h, x, u)?));
        };
        if h.is_some() {
            return Err(new_err(
                Kind::InvalidArgument,
                format!("h: the {name} plant has no output map; give h only with a callable f"),
                None,
            ));
        }
        match name.as_str() {
            "cart" => Ok(Model::Cart(
                CartPlant::new(cart_params(params.as_ref())?).map_err(|e| plant_error(&e))?,
            )),
            "arm" => Ok(Model::Arm(
                ArmPlant::new(arm_params(params.as_ref())?).map_err(|e| plant_error(&e))?,
            )),
            other => Err(new_err(
                Kind::InvalidArgument,
                format!(
                    "sys {other:?}: expected \"cart\", \"arm\", a pendulab.plants plant or a callable f(x, u)"
                ),
                None,
            )),
        }
    }

    /// The slot recording a callable's failure (a fresh, never-set slot for the plants).
    pub fn errors(&self) -> ErrorSlot {
        match self {
            Model::Callable(d) => d.errors.clone(),
            _ => ErrorSlot::default(),
        }
    }
}

/// Forwards every [`Dynamics`] method to the variant's model.
macro_rules! each {
    ($self:ident, $m:ident => $e:expr) => {
        match $self {
            Model::Cart($m) => $e,
            Model::Arm($m) => $e,
            Model::Callable($m) => $e,
        }
    };
}

impl Dynamics for Model {
    fn nx(&self) -> usize {
        each!(self, m => m.nx())
    }
    fn nu(&self) -> usize {
        each!(self, m => m.nu())
    }
    fn derivative(&self, t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        each!(self, m => m.derivative(t, x, u, dx))
    }
    fn ny(&self) -> usize {
        each!(self, m => m.ny())
    }
    fn output(&self, t: f64, x: &[f64], u: &[f64], y: &mut [f64]) {
        each!(self, m => m.output(t, x, u, y))
    }
}
