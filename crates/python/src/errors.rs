//! The `pendulab.Error` exception hierarchy and the mapping of the Rust crates' typed errors
//! onto it (the Rust message is kept word for word).
//!
//! ```text
//! Exception
//! └── pendulab.Error                       every error raised by pendulab
//!     ├── pendulab.ShapeError              (also ValueError)  wrong shape, not square, not SISO
//!     ├── pendulab.NotFiniteError          (also ValueError)  NaN or ±Inf in an argument
//!     ├── pendulab.InvalidArgumentError    (also ValueError)  bad value: not symmetric, not
//!     │                                    semidefinite, sample time, non-uniform time, …
//!     ├── pendulab.LinAlgError             (also numpy.linalg.LinAlgError, a ValueError)
//!     │   │                                singular, ill-conditioned, no convergence, inaccurate,
//!     │   │                                no unique solution, no real logarithm, pole at s = 0
//!     │   ├── pendulab.NotStabilizableError  no stabilising Riccati solution (not
//!     │   │                                  stabilisable, not detectable, boundary eigenvalue)
//!     │   └── pendulab.NotControllableError  poles cannot be assigned
//!     └── pendulab.InfeasibleError         an LMI or SOS synthesis has no solution (or the
//!                                          solver found none): attributes `status`,
//!                                          `certificate_valid`
//! ```
//!
//! So `except ValueError` catches every pendulab error of bad input or failed numerics, as
//! python-control users expect, and `except numpy.linalg.LinAlgError` catches the numerical
//! failures, as SciPy users expect. Errors converted from an [`LtiError`] carry the Rust
//! variant's name in the attribute `variant` (e.g. `"NotStabilizable"`).
//!
//! The classes are created once per interpreter (with `type(name, bases, namespace)`, since a
//! class with two bases cannot be declared with PyO3's `create_exception!`) and added to
//! `pendulab._native`; `pendulab` and `pendulab.errors` re-export them.

use pendulab_lti::LtiError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};

/// Which class of the hierarchy an error becomes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `pendulab.Error`: the base, for errors that fit no narrower class.
    Error,
    /// `pendulab.ShapeError`: an argument has the wrong number of dimensions or shape.
    Shape,
    /// `pendulab.NotFiniteError`: an argument holds NaN or ±Inf.
    NotFinite,
    /// `pendulab.InvalidArgumentError`: an argument's value is not allowed.
    InvalidArgument,
    /// `pendulab.LinAlgError`: a numerical method failed or the problem is singular.
    LinAlg,
    /// `pendulab.NotStabilizableError`: no stabilising (Riccati) solution exists.
    NotStabilizable,
    /// `pendulab.NotControllableError`: the pair (A, B) is not controllable.
    NotControllable,
    /// `pendulab.InfeasibleError`: an LMI/SOS synthesis found no solution.
    Infeasible,
}

impl Kind {
    /// Every kind, base first (the order in which the classes are created).
    pub const ALL: [Kind; 8] = [
        Kind::Error,
        Kind::Shape,
        Kind::NotFinite,
        Kind::InvalidArgument,
        Kind::LinAlg,
        Kind::NotStabilizable,
        Kind::NotControllable,
        Kind::Infeasible,
    ];

    /// The Python class name.
    pub fn class_name(self) -> &'static str {
        match self {
            Kind::Error => "Error",
            Kind::Shape => "ShapeError",
            Kind::NotFinite => "NotFiniteError",
            Kind::InvalidArgument => "InvalidArgumentError",
            Kind::LinAlg => "LinAlgError",
            Kind::NotStabilizable => "NotStabilizableError",
            Kind::NotControllable => "NotControllableError",
            Kind::Infeasible => "InfeasibleError",
        }
    }

    fn doc(self) -> &'static str {
        match self {
            Kind::Error => "Base class of every error pendulab raises.",
            Kind::Shape => {
                "An argument has the wrong number of dimensions or the wrong shape (also a ValueError)."
            }
            Kind::NotFinite => "An argument holds NaN or an infinity (also a ValueError).",
            Kind::InvalidArgument => {
                "An argument's value is not allowed: not symmetric, not semidefinite, a bad sample time, ... (also a ValueError)."
            }
            Kind::LinAlg => {
                "A numerical method failed or the problem is singular (also a numpy.linalg.LinAlgError, hence a ValueError)."
            }
            Kind::NotStabilizable => {
                "No stabilising solution exists: (A, B) not stabilisable, (Q, A) not detectable, or eigenvalues on the stability boundary."
            }
            Kind::NotControllable => {
                "The pair (A, B) is not controllable: poles cannot be assigned."
            }
            Kind::Infeasible => {
                "An LMI or SOS synthesis has no solution, or the solver found none: `status` names the solver's outcome, `certificate_valid` whether a Farkas certificate of infeasibility checks out."
            }
        }
    }

    fn index(self) -> usize {
        Kind::ALL.iter().position(|k| *k == self).unwrap_or(0)
    }

    /// The class's bases: `Error` for the narrower classes, plus `ValueError` or
    /// `numpy.linalg.LinAlgError`.
    fn bases<'py>(self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        // `Error` is looked up only by the narrower classes: its own lock is held while it
        // is being created.
        let error = || exception_type(py, Kind::Error);
        let value_error = py.get_type::<pyo3::exceptions::PyValueError>();
        match self {
            Kind::Error => PyTuple::new(py, [py.get_type::<pyo3::exceptions::PyException>()]),
            Kind::Infeasible => PyTuple::new(py, [error()?]),
            Kind::Shape | Kind::NotFinite | Kind::InvalidArgument => {
                PyTuple::new(py, [error()?, value_error])
            }
            Kind::LinAlg => {
                let numpy_linalg = py
                    .import("numpy.linalg")?
                    .getattr("LinAlgError")?
                    .cast_into::<PyType>()?;
                PyTuple::new(py, [error()?, numpy_linalg])
            }
            Kind::NotStabilizable | Kind::NotControllable => {
                PyTuple::new(py, [exception_type(py, Kind::LinAlg)?])
            }
        }
    }
}

static TYPES: [PyOnceLock<Py<PyType>>; 8] = [
    PyOnceLock::new(),
    PyOnceLock::new(),
    PyOnceLock::new(),
    PyOnceLock::new(),
    PyOnceLock::new(),
    PyOnceLock::new(),
    PyOnceLock::new(),
    PyOnceLock::new(),
];

/// The Python class of `kind`, created on first use (module `pendulab`).
///
/// # Errors
/// Only if the interpreter cannot create a class (e.g. `numpy` cannot be imported).
pub fn exception_type(py: Python<'_>, kind: Kind) -> PyResult<Bound<'_, PyType>> {
    let ty = TYPES[kind.index()].get_or_try_init(py, || -> PyResult<Py<PyType>> {
        let namespace = PyDict::new(py);
        namespace.set_item("__module__", "pendulab")?;
        namespace.set_item("__doc__", kind.doc())?;
        let class =
            py.get_type::<PyType>()
                .call1((kind.class_name(), kind.bases(py)?, namespace))?;
        Ok(class.cast_into::<PyType>()?.unbind())
    })?;
    Ok(ty.bind(py).clone())
}

/// A `PyErr` of class `kind` with message `message`, optionally with the attribute
/// `variant` (the Rust error variant's name).
pub fn new_err(kind: Kind, message: String, variant: Option<&str>) -> PyErr {
    Python::attach(|py| {
        let make = || -> PyResult<PyErr> {
            let instance = exception_type(py, kind)?.call1((message.clone(),))?;
            if let Some(v) = variant {
                instance.setattr("variant", v)?;
            }
            Ok(PyErr::from_value(instance))
        };
        // Creating the class can fail only if numpy is missing; the message survives then.
        make().unwrap_or_else(|_| pyo3::exceptions::PyValueError::new_err(message.clone()))
    })
}

/// The class an [`LtiError`] becomes and the variant's name.
pub fn classify(err: &LtiError) -> (Kind, &'static str) {
    match err {
        LtiError::DimensionMismatch { .. } => (Kind::Shape, "DimensionMismatch"),
        LtiError::NotSquare { .. } => (Kind::Shape, "NotSquare"),
        LtiError::NotSiso { .. } => (Kind::Shape, "NotSiso"),
        LtiError::NonFinite { .. } => (Kind::NotFinite, "NonFinite"),
        LtiError::NotSymmetric { .. } => (Kind::InvalidArgument, "NotSymmetric"),
        LtiError::NotPositiveSemidefinite { .. } => {
            (Kind::InvalidArgument, "NotPositiveSemidefinite")
        }
        LtiError::NotPositiveDefinite { .. } => (Kind::InvalidArgument, "NotPositiveDefinite"),
        LtiError::InvalidSampleTime(_) => (Kind::InvalidArgument, "InvalidSampleTime"),
        LtiError::SampleTimeMismatch(..) => (Kind::InvalidArgument, "SampleTimeMismatch"),
        LtiError::NonUniformTime { .. } => (Kind::InvalidArgument, "NonUniformTime"),
        LtiError::Improper { .. } => (Kind::InvalidArgument, "Improper"),
        LtiError::InvalidArgument(_) => (Kind::InvalidArgument, "InvalidArgument"),
        LtiError::NotStabilizable { .. } => (Kind::NotStabilizable, "NotStabilizable"),
        LtiError::NotDetectable { .. } => (Kind::NotStabilizable, "NotDetectable"),
        LtiError::BoundaryEigenvalue { .. } => (Kind::NotStabilizable, "BoundaryEigenvalue"),
        LtiError::NotControllable { .. } => (Kind::NotControllable, "NotControllable"),
        LtiError::IllConditioned { .. } => (Kind::LinAlg, "IllConditioned"),
        LtiError::Singular { .. } => (Kind::LinAlg, "Singular"),
        LtiError::NoUniqueSolution { .. } => (Kind::LinAlg, "NoUniqueSolution"),
        LtiError::NoConvergence { .. } => (Kind::LinAlg, "NoConvergence"),
        LtiError::Inaccurate { .. } => (Kind::LinAlg, "Inaccurate"),
        LtiError::NoRealLogarithm { .. } => (Kind::LinAlg, "NoRealLogarithm"),
        LtiError::PoleAtEvaluationPoint { .. } => (Kind::LinAlg, "PoleAtEvaluationPoint"),
        LtiError::SynthesisAssumption { .. } => (Kind::InvalidArgument, "SynthesisAssumption"),
        LtiError::HinfInfeasible { .. } => (Kind::Infeasible, "HinfInfeasible"),
        // `LtiError` is non-exhaustive: a variant added later is a plain `pendulab.Error`.
        _ => (Kind::Error, "Other"),
    }
}

/// An [`LtiError`] as the Python exception of its class (see [`classify`]), with the Rust
/// message and the attribute `variant`.
pub fn to_py(err: &LtiError) -> PyErr {
    let (kind, variant) = classify(err);
    new_err(kind, err.to_string(), Some(variant))
}

/// Any other crate's error (sim, control, plants, …) as the Python exception of class `kind`.
/// The message is the error's `Display` followed by each `source()` whose text it does not
/// already contain, joined by `": "`.
pub fn from_error<E: std::error::Error + ?Sized>(kind: Kind, e: &E) -> PyErr {
    new_err(kind, message_with_sources(e), None)
}

/// `Display` of `e`, then the texts of its source chain not already contained in it.
pub fn message_with_sources<E: std::error::Error + ?Sized>(e: &E) -> String {
    let mut message = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        let text = s.to_string();
        if !message.contains(&text) {
            message.push_str(": ");
            message.push_str(&text);
        }
        source = s.source();
    }
    message
}

/// `map_err` helper: `lti_call().map_err(lti)?`.
pub fn lti(err: LtiError) -> PyErr {
    to_py(&err)
}

/// Adds the exception classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    for kind in Kind::ALL {
        m.add(kind.class_name(), exception_type(m.py(), kind)?)?;
    }
    Ok(())
}
