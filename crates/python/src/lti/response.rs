//! Time and frequency responses: `lsim`, `step`, `impulse`, `initial`, `freqresp`, `bode`
//! (pendulab-lti's `response` and `frequency_response` modules).
//!
//! Layout: time responses follow MATLAB and python-control's `control.matlab` (one row per
//! time sample): `y` is `(len, p)`, `x` `(len, n)`, `u` `(len, m)`; `step`/`impulse` add a
//! last axis for the input channel, `(len, p, m)`, squeezed to `(len,)` for SISO systems.
//! Frequency responses follow python-control: `(p, m, len(omega))`, squeezed to
//! `(len(omega),)` for SISO systems.

use super::nogil;
use super::results::{obj, result_class};
use super::system::{Sys, system, with_sys};
use crate::convert::{
    OneD, array3_to_numpy, complex_array3_to_numpy, matrix, slice_to_numpy, vector,
};
use crate::errors::{Kind, lti, new_err};
use numpy::IntoPyArray;
use numpy::ndarray::{Array2, ShapeBuilder};
use pendulab_lti::response::{self, InputHold, LsimOptions};
use pendulab_lti::{Mat, Trajectory};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyFloat, PyInt};

result_class!(
    LsimResult, "LsimResult",
    "A simulated response; unpacks as MATLAB's and control.matlab's `yout, T, xout`.",
    array none,
    unpack {
        y as "y": "Outputs, one row per sample (len × p; len for one output).",
        t as "t": "Sample times in seconds (len).",
        x as "x": "States, one row per sample (len × n).",
    }
    also {
        u as "u": "Inputs, one row per sample (len × m).",
    }
);

result_class!(
    TimeResponse, "TimeResponse",
    "Responses per input channel (step, impulse, initial); unpacks as control.matlab's `yout, T`.",
    array none,
    unpack {
        y as "y": "Outputs (len × p × m; len for a SISO system; len × p for initial).",
        t as "t": "Sample times in seconds (len).",
    }
    also {
        x as "x": "States (len × n × m; len × n for initial).",
    }
);

/// A column-major `len × k` matrix as a `(len, k)` float64 array without copying (Fortran
/// order: column j is signal j).
fn signals(py: Python<'_>, m: Mat) -> PyResult<Py<PyAny>> {
    let shape = (m.nrows(), m.ncols()).f();
    let data: Vec<f64> = m.data.into();
    let array = Array2::from_shape_vec(shape, data)
        .map_err(|e| new_err(Kind::Shape, format!("response layout: {e}"), None))?;
    Ok(array.into_pyarray(py).into_any().unbind())
}

/// As [`signals`], but one signal as a 1-d `(len,)` array (python-control's squeeze).
fn single_or_signals(py: Python<'_>, m: Mat) -> PyResult<Py<PyAny>> {
    if m.ncols() == 1 {
        let data: Vec<f64> = m.data.into();
        Ok(data.into_pyarray(py).into_any().unbind())
    } else {
        signals(py, m)
    }
}

fn hold(name: &str) -> PyResult<InputHold> {
    match name.to_ascii_lowercase().as_str() {
        "foh" => Ok(InputHold::Foh),
        "zoh" => Ok(InputHold::Zoh),
        other => Err(new_err(
            Kind::InvalidArgument,
            format!("hold must be 'foh' or 'zoh', got {other:?}"),
            None,
        )),
    }
}

/// `T` as a time vector (required: pendulab does not choose a simulation horizon).
fn times(t: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<f64>> {
    match t {
        Some(t) if !t.is_none() => Ok(vector(t, "T")?.data.into()),
        _ => Err(new_err(
            Kind::InvalidArgument,
            "T: the time vector is required (uniformly spaced, in seconds)".into(),
            None,
        )),
    }
}

/// The time samples of `step`, `impulse` and `initial`: `T` as given (a uniformly spaced
/// vector), a number `T` as the final time, or `None` for pendulab-lti's default final time
/// (`response_times`: `0 … T` by `T/1000`, a discrete system by its `dt`), as MATLAB's
/// `step(sys, tFinal)` and python-control's `T`.
fn response_grid(s: &Sys, t: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<f64>> {
    let t_final = match t {
        Some(t) if !t.is_none() && is_real_scalar(t) => {
            let v: f64 = t.extract()?;
            if !(v.is_finite() && v > 0.0) {
                return Err(new_err(
                    Kind::InvalidArgument,
                    format!("T = {v}: a final time must be finite and > 0 seconds"),
                    None,
                ));
            }
            Some(v)
        }
        Some(t) if !t.is_none() => return times(Some(t)),
        _ => None,
    };
    with_sys!(s, s => response::response_times(s, t_final, None)).map_err(lti)
}

/// A Python or NumPy real number (not a bool, not an array of one or more dimensions).
fn is_real_scalar(obj: &Bound<'_, PyAny>) -> bool {
    if obj.is_instance_of::<PyBool>() {
        return false;
    }
    obj.is_instance_of::<PyFloat>()
        || obj.is_instance_of::<PyInt>()
        || (obj.hasattr("dtype").unwrap_or(false)
            && obj
                .getattr("ndim")
                .and_then(|d| d.extract::<usize>())
                .is_ok_and(|d| d == 0)
            && obj.extract::<f64>().is_ok())
}

fn is_zero_scalar(obj: &Bound<'_, PyAny>) -> bool {
    (obj.is_exact_instance_of::<PyFloat>() || obj.is_exact_instance_of::<PyInt>())
        && obj.extract::<f64>().is_ok_and(|v| v == 0.0)
}

/// `lsim(sys, U=0., T=None, X0=0., hold='foh')` (MATLAB `lsim`, control.matlab `lsim`): the
/// response to the input samples `U` (`(len, m)`, or `(len,)` for one input; `0` for none) at
/// the uniformly spaced times `T` (s) from the state `X0` at `T[0]`.
///
/// Exact: a continuous system is simulated by its exact discretisation for the input hold,
/// `'foh'` (linear between samples, python-control's choice) or `'zoh'` (constant over each
/// interval); a discrete system is iterated (`T` spaced by its `dt`). Returns `LsimResult`
/// (`yout, T, xout = lsim(...)`, plus `.u`).
///
/// With `return_x=False` (python-control's keyword) the states are not recorded: `xout` is
/// `None`, `u` is `U` as given, and the outputs (equal bit for bit to those with states) come
/// from pendulab-lti's `lsim_outputs`, written straight into the returned array; a float64
/// contiguous `U` of one input and `T` are read in place.
///
/// Raises `pendulab.InvalidArgumentError` (variant `NonUniformTime`) for unevenly spaced `T`,
/// `pendulab.ShapeError` for `U`/`X0` of the wrong shape, `pendulab.NotFiniteError` for
/// NaN/Inf.
#[pyfunction]
#[pyo3(signature = (sys, U = None, T = None, X0 = None, hold = "foh", return_x = true))]
#[allow(non_snake_case)]
pub fn lsim(
    sys: &Bound<'_, PyAny>,
    U: Option<&Bound<'_, PyAny>>,
    T: Option<&Bound<'_, PyAny>>,
    X0: Option<&Bound<'_, PyAny>>,
    hold: &str,
    return_x: bool,
) -> PyResult<LsimResult> {
    let py = sys.py();
    let s = system(sys)?;
    if !return_x {
        return lsim_outputs(py, &s, U, T, X0, self::hold(hold)?);
    }
    let t = times(T)?;
    let nu = with_sys!(&s, s => s.nu());
    let u = match U {
        Some(u) if !u.is_none() && !is_zero_scalar(u) => matrix(u, "U", OneD::Column)?,
        _ => Mat::zeros(t.len(), nu),
    };
    let x0 = match X0 {
        Some(x) if !x.is_none() && !is_zero_scalar(x) => Some(vector(x, "X0")?),
        _ => None,
    };
    let options = LsimOptions {
        hold: self::hold(hold)?,
    };
    let traj = nogil(
        py,
        || with_sys!(&s, s => response::lsim(s, &u, &t, x0.as_ref().map(|v| v.as_slice()), &options)),
    )?;
    drop(u);
    LsimResult::from_trajectory(py, traj)
}

/// A float64, C-contiguous 1-d array read in place (`None`: another kind of object).
fn contiguous_1d<'py>(obj: &Bound<'py, PyAny>) -> Option<numpy::PyReadonlyArray1<'py, f64>> {
    use numpy::PyArrayMethods;
    let a = obj.cast::<numpy::PyArray1<f64>>().ok()?;
    let r = a.try_readonly().ok()?;
    r.as_slice().is_ok().then_some(r)
}

/// `lsim(..., return_x=False)`: the outputs only (pendulab-lti `lsim_outputs`).
#[allow(non_snake_case)]
fn lsim_outputs(
    py: Python<'_>,
    s: &super::system::Sys,
    U: Option<&Bound<'_, PyAny>>,
    T: Option<&Bound<'_, PyAny>>,
    X0: Option<&Bound<'_, PyAny>>,
    hold: InputHold,
) -> PyResult<LsimResult> {
    use numpy::{PyArray1, PyArrayMethods};
    let (nu, ny) = with_sys!(s, s => (s.nu(), s.ny()));
    let t_obj = match T {
        Some(t) if !t.is_none() => t.clone(),
        _ => return Err(times(None).expect_err("T is required")),
    };
    let t_view = contiguous_1d(&t_obj);
    let t_owned: Vec<f64>;
    let t: &[f64] = match &t_view {
        Some(r) => r.as_slice()?,
        None => {
            t_owned = times(Some(&t_obj))?;
            &t_owned
        }
    };
    let len = t.len();
    let u_view = match U {
        Some(u) if nu == 1 => contiguous_1d(u),
        _ => None,
    };
    let u_owned: Vec<f64>;
    let u: &[f64] = match (&u_view, U) {
        (Some(r), _) => r.as_slice()?,
        (None, Some(u)) if !u.is_none() && !is_zero_scalar(u) => {
            u_owned = matrix(u, "U", OneD::Column)?.data.into();
            &u_owned
        }
        _ => {
            u_owned = vec![0.0; len * nu];
            &u_owned
        }
    };
    let x0 = match X0 {
        Some(x) if !x.is_none() && !is_zero_scalar(x) => Some(vector(x, "X0")?),
        _ => None,
    };
    let x0 = x0.as_ref().map(|v| v.as_slice());
    let options = LsimOptions { hold };
    let y: Py<PyAny> = if ny == 1 {
        let y = PyArray1::<f64>::zeros(py, len, false);
        {
            let mut w = y.readwrite();
            let ys = w.as_slice_mut()?;
            nogil(
                py,
                || with_sys!(s, s => response::lsim_outputs(s, u, t, x0, &options, ys)),
            )?;
        }
        y.into_any().unbind()
    } else {
        let mut ys = vec![0.0; len * ny];
        nogil(
            py,
            || with_sys!(s, s => response::lsim_outputs(s, u, t, x0, &options, &mut ys)),
        )?;
        signals(py, Mat::from_vec(len, ny, ys))?
    };
    let t_out = match t_view {
        Some(_) => t_obj.unbind(),
        None => slice_to_numpy(py, t).into_any().unbind(),
    };
    Ok(LsimResult {
        y,
        t: t_out,
        x: py.None(),
        u: U.map_or_else(|| py.None(), |u| u.clone().unbind()),
    })
}

impl LsimResult {
    /// The arrays of a pendulab-lti trajectory (states and inputs without copying).
    fn from_trajectory(py: Python<'_>, traj: Trajectory) -> PyResult<Self> {
        let (t, x, u, y) = traj.into_parts();
        Ok(LsimResult {
            y: single_or_signals(py, y)?,
            t: slice_to_numpy(py, &t).into_any().unbind(),
            x: signals(py, x)?,
            u: signals(py, u)?,
        })
    }
}

result_class!(
    LsimSplit, "LsimSplit",
    "A response and its zero-input and zero-state parts (book Part 1 §4, eq. 4.24: y = y_zi + y_zs); unpacks as `zero_input, zero_state, total`.",
    array none,
    unpack {
        zero_input as "zero_input": "Response to X0 with U = 0 (LsimResult).",
        zero_state as "zero_state": "Response to U from the zero state (LsimResult).",
        total as "total": "Response to both, simulated as one run, not as the sum (LsimResult).",
    }
    also {}
);

/// `lsim_split(sys, U, T, X0, hold='foh')`: the response to `U` from `X0` and its zero-input
/// and zero-state parts, each simulated on its own (pendulab-lti `lsim_split`), so that
/// superposition can be checked. Arguments and errors as `lsim`.
#[pyfunction]
#[pyo3(signature = (sys, U, T, X0, hold = "foh"))]
#[allow(non_snake_case)]
pub fn lsim_split(
    sys: &Bound<'_, PyAny>,
    U: &Bound<'_, PyAny>,
    T: &Bound<'_, PyAny>,
    X0: &Bound<'_, PyAny>,
    hold: &str,
) -> PyResult<LsimSplit> {
    let py = sys.py();
    let s = system(sys)?;
    let t = times(Some(T))?;
    let u = matrix(U, "U", OneD::Column)?;
    let x0 = vector(X0, "X0")?;
    let options = LsimOptions {
        hold: self::hold(hold)?,
    };
    let split = nogil(
        py,
        || with_sys!(&s, s => response::lsim_split(s, &u, &t, x0.as_slice(), &options)),
    )?;
    let wrap = |traj| -> PyResult<Py<PyAny>> {
        Ok(Py::new(py, LsimResult::from_trajectory(py, traj)?)?.into_any())
    };
    Ok(LsimSplit {
        zero_input: wrap(split.zero_input)?,
        zero_state: wrap(split.zero_state)?,
        total: wrap(split.total)?,
    })
}

/// One 3-d array `(len, k, channels)` from per-channel trajectories (`pick` chooses x or y);
/// SISO responses (one signal, one channel) squeezed to `(len,)`.
fn per_channel(
    py: Python<'_>,
    runs: &[Trajectory],
    len: usize,
    k: usize,
    squeeze: bool,
    pick: fn(&Trajectory) -> &Mat,
) -> Py<PyAny> {
    if squeeze && runs.len() == 1 && k == 1 {
        return slice_to_numpy(py, pick(&runs[0]).as_slice())
            .into_any()
            .unbind();
    }
    array3_to_numpy(py, (len, k, runs.len()), |(s, i, j)| pick(&runs[j])[(s, i)])
        .into_any()
        .unbind()
}

fn channel_response(
    sys: &Bound<'_, PyAny>,
    t: Option<&Bound<'_, PyAny>>,
    impulse: bool,
) -> PyResult<TimeResponse> {
    let py = sys.py();
    let s = system(sys)?;
    let t = response_grid(&s, t)?;
    let runs = nogil(
        py,
        || with_sys!(&s, s => if impulse { response::impulse(s, &t) } else { response::step(s, &t) }),
    )?;
    let (nx, ny) = with_sys!(&s, s => (s.nx(), s.ny()));
    Ok(TimeResponse {
        y: per_channel(py, &runs, t.len(), ny, true, Trajectory::y),
        t: slice_to_numpy(py, &t).into_any().unbind(),
        x: per_channel(py, &runs, t.len(), nx, false, Trajectory::x),
    })
}

/// `step(sys, T=None)`: unit-step responses from a zero state, one per input channel (MATLAB
/// `step`), exact for continuous systems. `T` is the uniformly spaced time vector, or a
/// number, the final time (MATLAB's `step(sys, tFinal)`, python-control's `T`: samples
/// `0 … T` by `T/1000`, a discrete system's by its `dt`), or `None` for a final time from
/// the poles (7 time constants of the slowest mode; pendulab-lti `default_final_time`).
/// Returns `TimeResponse` (`yout, T = step(...)`), `y` of shape `(len, p, m)` (`(len,)` for
/// SISO), `x` `(len, n, m)`. Raises `pendulab.InvalidArgumentError` for a final time that
/// is not finite and > 0.
#[pyfunction]
#[pyo3(signature = (sys, T = None))]
#[allow(non_snake_case)]
pub fn step(sys: &Bound<'_, PyAny>, T: Option<&Bound<'_, PyAny>>) -> PyResult<TimeResponse> {
    channel_response(sys, T, false)
}

/// `impulse(sys, T)`: impulse responses, one per input channel (MATLAB `impulse`):
/// continuous, `y = C e^{A t} B e_j` (a feedthrough `D δ(t)` has no sample value); discrete,
/// the response to the unit-area pulse `u_j[0] = 1/dt`. `T` and shapes as `step`.
#[pyfunction]
#[pyo3(signature = (sys, T = None))]
#[allow(non_snake_case)]
pub fn impulse(sys: &Bound<'_, PyAny>, T: Option<&Bound<'_, PyAny>>) -> PyResult<TimeResponse> {
    channel_response(sys, T, true)
}

/// `initial(sys, T, X0)`: the zero-input response from `X0` at `T[0]` (MATLAB `initial`);
/// `T` as `step`'s (a vector, a final time, or `None`); `y` of shape `(len, p)` (`(len,)`
/// for one output), `x` `(len, n)`.
#[pyfunction]
#[pyo3(signature = (sys, T = None, X0 = None))]
#[allow(non_snake_case)]
pub fn initial(
    sys: &Bound<'_, PyAny>,
    T: Option<&Bound<'_, PyAny>>,
    X0: Option<&Bound<'_, PyAny>>,
) -> PyResult<TimeResponse> {
    let py = sys.py();
    let s = system(sys)?;
    let t = response_grid(&s, T)?;
    let x0 = match X0 {
        Some(x) if !x.is_none() => vector(x, "X0")?,
        _ => {
            return Err(new_err(
                Kind::InvalidArgument,
                "X0: the initial state is required".into(),
                None,
            ));
        }
    };
    let traj = nogil(
        py,
        || with_sys!(&s, s => response::initial(s, x0.as_slice(), &t)),
    )?;
    let (t, x, _u, y) = traj.into_parts();
    Ok(TimeResponse {
        y: single_or_signals(py, y)?,
        t: slice_to_numpy(py, &t).into_any().unbind(),
        x: signals(py, x)?,
    })
}

result_class!(
    FrequencyResponse, "FrequencyResponse",
    "Complex frequency response samples; unpacks as `response, omega`.",
    array none,
    unpack {
        response as "response": "G(jω) (continuous) or G(e^{jω dt}) (discrete), complex, shape (p, m, len(omega)); (len(omega),) for SISO.",
        omega as "omega": "Frequencies in rad/s.",
    }
    also {}
);

result_class!(
    BodeResult, "BodeResult",
    "Bode data; unpacks as `mag_db, phase_deg, omega` (magnitude in dB and unwrapped phase in degrees, unlike python-control's absolute magnitude and radians).",
    array none,
    unpack {
        mag_db as "mag_db": "20 log₁₀|G| in dB, shape (p, m, len(omega)); (len(omega),) for SISO.",
        phase_deg as "phase_deg": "∠G in degrees, unwrapped along omega (first value in (−180°, 180°]).",
        omega as "omega": "Frequencies in rad/s.",
    }
    also {}
);

/// The frequencies: `omega` if given, else pendulab-lti's automatic grid (one decade beyond
/// the poles and zeros, `points_per_decade` per decade, up to the Nyquist frequency).
pub(super) fn frequencies<D: pendulab_lti::TimeDomain>(
    s: &pendulab_lti::StateSpace<D>,
    omega: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<f64>> {
    match omega {
        Some(w) if !w.is_none() => Ok(vector(w, "omega")?.data.into()),
        _ => pendulab_lti::frequency_response::frequency_grid(s, 50).map_err(lti),
    }
}

/// `freqresp(sys, omega=None)`: the complex frequency response at `omega` (rad/s; chosen
/// from the poles and zeros if omitted), by Laub's Hessenberg method. Returns
/// `FrequencyResponse` (`response, omega`); `numpy.abs` / `numpy.angle` give magnitude and
/// phase.
///
/// Raises `pendulab.LinAlgError` (variant `PoleAtEvaluationPoint`) if a frequency hits a pole.
#[pyfunction]
#[pyo3(signature = (sys, omega = None))]
pub fn freqresp(
    sys: &Bound<'_, PyAny>,
    omega: Option<&Bound<'_, PyAny>>,
) -> PyResult<FrequencyResponse> {
    let py = sys.py();
    let s = system(sys)?;
    let w = with_sys!(&s, s => frequencies(s, omega))?;
    let f = nogil(
        py,
        || with_sys!(&s, s => pendulab_lti::frequency_response::freqresp(s, &w)),
    )?;
    let (ny, nu) = with_sys!(&s, s => (s.ny(), s.nu()));
    let response = if ny == 1 && nu == 1 {
        let v: Vec<_> = f.response.iter().map(|g| g[(0, 0)]).collect();
        crate::convert::complex_to_numpy(py, &v).into_any().unbind()
    } else {
        complex_array3_to_numpy(py, (ny, nu, w.len()), |(i, j, k)| f.response[k][(i, j)])
            .into_any()
            .unbind()
    };
    Ok(FrequencyResponse {
        response,
        omega: slice_to_numpy(py, &w).into_any().unbind(),
    })
}

/// `bode(sys, omega=None)`: magnitude (dB) and unwrapped phase (degrees) of every channel
/// (MATLAB `bode` data; no plot). Returns `BodeResult` (`mag_db, phase_deg, omega`).
#[pyfunction]
#[pyo3(signature = (sys, omega = None))]
pub fn bode(sys: &Bound<'_, PyAny>, omega: Option<&Bound<'_, PyAny>>) -> PyResult<BodeResult> {
    let py = sys.py();
    let s = system(sys)?;
    let w = with_sys!(&s, s => frequencies(s, omega))?;
    let (ny, nu) = with_sys!(&s, s => (s.ny(), s.nu()));
    let channels = nogil(py, || {
        let mut out = Vec::with_capacity(ny * nu);
        for i in 0..ny {
            for j in 0..nu {
                out.push(with_sys!(&s, s => pendulab_lti::frequency_response::bode_channel(s, &w, i, j))?);
            }
        }
        Ok::<_, pendulab_lti::LtiError>(out)
    })?;
    let pack = |pick: fn(&pendulab_lti::frequency_response::Bode) -> &Vec<f64>| -> Py<PyAny> {
        if ny == 1 && nu == 1 {
            slice_to_numpy(py, pick(&channels[0])).into_any().unbind()
        } else {
            array3_to_numpy(py, (ny, nu, w.len()), |(i, j, k)| {
                pick(&channels[i * nu + j])[k]
            })
            .into_any()
            .unbind()
        }
    };
    Ok(BodeResult {
        mag_db: pack(|b| &b.magnitude_db),
        phase_deg: pack(|b| &b.phase_deg),
        omega: obj(py, slice_to_numpy(py, &w))?,
    })
}
