//! `control_find_operating_point`: `pendulab_control::trim::find_operating_point` on a shipped
//! plant or a user's callables ([`crate::callable::Model`]), with python-control's keywords.
//!
//! | python-control 0.10 / MATLAB `operspec` | Rust [`TrimSpec`] |
//! |---|---|
//! | `x0` (guess; `ix`: held) / `operspec.States.Known` | `x`, `fixed_states` |
//! | `u0` (held unless `y0` is given; `iu`: held) / `Inputs.Known` | `u`, `fixed_inputs` |
//! | `y0` with `iy` (default all) / `Outputs.Known` | `outputs` |
//! | `idx` (derivatives that must vanish; default all) / `States.SteadyState` | complement in `free_derivatives` |
//! | `t` | `t` |

use pendulab_control::trim::{TrimOptions, TrimSpec, TrimStatus, find_operating_point};
use pendulab_sim::Dynamics;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::control_error;
use crate::callable::Model;
use crate::convert::{count, slice_to_numpy, vector};
use crate::errors::{Kind, new_err};

/// Checks that every index is below `n`, naming the keyword.
fn indices(what: &str, idx: &[usize], n: usize) -> PyResult<()> {
    match idx.iter().find(|&&i| i >= n) {
        Some(i) => Err(new_err(
            Kind::InvalidArgument,
            format!("{what}: index {i} is out of range (there are {n})"),
            None,
        )),
        None => Ok(()),
    }
}

/// `control_find_operating_point(sys, x0, u0=None, y0=None, t=0.0, iu=None, iy=None,
/// ix=None, idx=None, h=None, tol=1e-10, max_iterations=100, dx0=None)`: the operating point
/// of `sys` (a plant object, `"cart"`/`"arm"`, or a callable `f(x, u)` with the output map
/// `h`) by Levenberg–Marquardt (module table for the keywords; `dx0`: the held derivatives'
/// targets, `TrimSpec::derivative_targets`). Returns a dict `x, u, y, dx, residual,
/// iterations, status` (`"isolated"` or `"family"`), `family_dimension`.
#[pyfunction]
#[pyo3(signature = (sys, x0, u0 = None, y0 = None, t = 0.0, iu = None, iy = None, ix = None,
    idx = None, h = None, tol = 1e-10, max_iterations = 100, dx0 = None))]
#[allow(clippy::too_many_arguments)]
pub fn control_find_operating_point<'py>(
    py: Python<'py>,
    sys: &Bound<'py, PyAny>,
    x0: &Bound<'py, PyAny>,
    u0: Option<&Bound<'py, PyAny>>,
    y0: Option<&Bound<'py, PyAny>>,
    t: f64,
    iu: Option<Vec<usize>>,
    iy: Option<Vec<usize>>,
    ix: Option<Vec<usize>>,
    idx: Option<Vec<usize>>,
    h: Option<&Bound<'py, PyAny>>,
    tol: f64,
    #[pyo3(from_py_with = count)] max_iterations: usize,
    dx0: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let x = vector(x0, "x0")?.as_slice().to_vec();
    let mut u = match u0 {
        Some(u) => vector(u, "u0")?.as_slice().to_vec(),
        None => Vec::new(),
    };
    let model = Model::from_py(sys, h, &x, &u)?;
    if u0.is_none() {
        u = vec![0.0; model.nu()];
    }
    let (nx, nu, ny) = (model.nx(), model.nu(), model.ny());
    let mut spec = TrimSpec::new(&x, &u);
    spec.t = t;
    spec.fixed_states = ix.unwrap_or_default();
    // python-control: without y0 the inputs are held at u0 unless iu says otherwise.
    spec.fixed_inputs = match iu {
        Some(iu) => iu,
        None if y0.is_none() => (0..nu).collect(),
        None => Vec::new(),
    };
    match y0 {
        Some(y0) => {
            let y = vector(y0, "y0")?;
            if y.len() != ny {
                return Err(new_err(
                    Kind::Shape,
                    format!(
                        "y0 must have one entry per output of h ({ny}), got {}",
                        y.len()
                    ),
                    None,
                ));
            }
            let iy = iy.unwrap_or_else(|| (0..ny).collect());
            indices("iy", &iy, ny)?;
            spec.outputs = iy.iter().map(|&j| (j, y[j])).collect();
        }
        None if iy.is_some() => {
            return Err(new_err(
                Kind::InvalidArgument,
                "iy lists outputs to hold but y0 gives no values".into(),
                None,
            ));
        }
        None => {}
    }
    if let Some(idx) = idx {
        indices("idx", &idx, nx)?;
        spec.free_derivatives = (0..nx).filter(|i| !idx.contains(i)).collect();
    }
    if let Some(dx0) = dx0 {
        let dx = vector(dx0, "dx0")?;
        if dx.len() != nx {
            return Err(new_err(
                Kind::Shape,
                format!("dx0 must have one entry per state ({nx}), got {}", dx.len()),
                None,
            ));
        }
        spec.derivative_targets = dx.as_slice().to_vec();
    }
    let options = TrimOptions {
        tolerance: tol,
        max_iterations,
        ..TrimOptions::default()
    };
    let errors = model.errors();
    errors.clear();
    let op = errors.or(find_operating_point(&model, &spec, &options), control_error)?;
    let d = PyDict::new(py);
    d.set_item("x", slice_to_numpy(py, &op.x))?;
    d.set_item("u", slice_to_numpy(py, &op.u))?;
    d.set_item("y", slice_to_numpy(py, &op.y))?;
    d.set_item("dx", slice_to_numpy(py, &op.dx))?;
    d.set_item("residual", op.residual)?;
    d.set_item("iterations", op.iterations)?;
    let (status, dim) = match op.status {
        TrimStatus::Isolated => ("isolated", 0),
        TrimStatus::Family { dimension } => ("family", dimension),
    };
    d.set_item("status", status)?;
    d.set_item("family_dimension", dim)?;
    Ok(d)
}
