//! The `ident` facet of the extension module: `pendulab-ident`'s least-squares and feature
//! methods (book Part 1 §3.2, §3.3) behind `pendulab.ident`, on arrays or a dataset parsed from
//! CSV text.
//!
//! | Python (`_native`) | Rust | estimates |
//! |---|---|---|
//! | `ident_dataset(source, text, time_unit)` | `Dataset::from_csv_str` | the columns |
//! | `ident_drive_ls("cart" / "arm", ts, y, v, …)` | `cart_drive_ls`, `arm_drive_ls` (+ `validate_drive`) | `a`, `b` |
//! | `ident_cart_pendulum_ls(ts, z, phi, …)` | `cart_pendulum_ls` (+ `validate_cart_pendulum`) | `J_p`, `μ_p` |
//! | `ident_arm_pendulum_ls(ts, phi1, phi2, …)` | `arm_pendulum_ls` (+ `validate_arm_pendulum`) | `α₂`, `J₂`, `μ₂` |
//! | `ident_p_step(t, y, …)` | `p_step` (+ `validate_p_step`) | `a`, `b`, `T_p`, overshoot |
//! | `ident_arx(u, y, ts, na, nb, nk, max_order, u_val, y_val)` | `blackbox::arx`, `arx_order_selection` (+ `Arx::fit_percent`) | `A`, `B` polynomials, AIC table |
//! | `ident_moesp(u, y, ts, order, horizon, u_val, y_val, max_order)` | `blackbox::moesp` (+ `Moesp::fit_percent`) | `A`, `B`, `C`, `D`, singular values |
//! | `ident_free_oscillation(t, y, m, l, g, …)` | `free_oscillation`, `pendulum_from_oscillation` (+ `validate_free_pendulum`, `validate_oscillation`) | `J`, `μ`, period, decay ratio |
//!
//! Each returns a dict: the estimates, the least-squares diagnostics (`std_error`,
//! `condition`, `residual_rms`), `failed_checks` (the messages of the library's plausibility
//! checks — the record against the options, the known constants' ranges, the estimates'
//! plausibility and resolution — empty when every check passes) and `fit` (the validation's MATLAB `compare`
//! percentage, or the message of why it could not run). `pendulab.ident.identify` strings them
//! together as `pendulab identify` does.

use numpy::PyArray1;
use pendulab_ident::{
    ArmPendulumConstants, CartPendulumConstants, Dataset, Differentiator, FilterHold, IdentError,
    LeastSquares, LsOptions, OscillationOptions, PStepOptions, PeriodCorrection, Prefilter,
    TimeUnit, Validation, arm_drive_ls, arm_pendulum_ls, cart_drive_ls, cart_pendulum_ls,
    free_oscillation, p_step, pendulum_from_oscillation, validate_arm_pendulum,
    validate_cart_pendulum, validate_drive, validate_free_pendulum, validate_oscillation,
    validate_p_step,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{count, matrix_to_numpy, optional_count, slice_to_numpy, vector};
use crate::errors::{Kind, from_error, new_err};
use crate::lti::system::{StateSpace, Sys};
use pendulab_ident::{
    ArxOrders, Experiment, IoRecord, MoespOptions, arx, arx_order_selection, moesp,
};
use pyo3::types::PyList;

/// Adds this facet's functions and classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NativeDataset>()?;
    m.add_function(wrap_pyfunction!(ident_dataset, m)?)?;
    m.add_function(wrap_pyfunction!(ident_drive_ls, m)?)?;
    m.add_function(wrap_pyfunction!(ident_cart_pendulum_ls, m)?)?;
    m.add_function(wrap_pyfunction!(ident_arm_pendulum_ls, m)?)?;
    m.add_function(wrap_pyfunction!(ident_p_step, m)?)?;
    m.add_function(wrap_pyfunction!(ident_free_oscillation, m)?)?;
    m.add_function(wrap_pyfunction!(ident_arx, m)?)?;
    m.add_function(wrap_pyfunction!(ident_moesp, m)?)?;
    Ok(())
}

/// An [`IdentError`] as the `pendulab` exception of its kind: lengths and sample counts →
/// `ShapeError`, NaN/±Inf → `NotFiniteError`, the rest (bad CSV, missing column, uneven time,
/// implausible or unresolved estimates, …) → `InvalidArgumentError`.
pub fn ident_error(e: &IdentError) -> PyErr {
    let kind = match e {
        IdentError::LengthMismatch { .. } | IdentError::TooFewSamples { .. } => Kind::Shape,
        IdentError::NonFinite { .. } | IdentError::NonFiniteResult { .. } => Kind::NotFinite,
        IdentError::Lti(l) => return crate::errors::to_py(l),
        _ => Kind::InvalidArgument,
    };
    from_error(kind, e)
}

fn ie<T>(r: pendulab_ident::Result<T>) -> PyResult<T> {
    r.map_err(|e| ident_error(&e))
}

/// A measured record: named, equally long columns with a time column `t` (seconds, or
/// milliseconds as declared), parsed by `pendulab_ident::Dataset`.
#[pyclass(name = "Dataset", module = "pendulab.ident", frozen)]
pub struct NativeDataset {
    data: Dataset,
}

#[pymethods]
impl NativeDataset {
    /// The column names, in file order.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.data.names().to_vec()
    }
    /// Where the data came from (the file name or the given source).
    #[getter]
    fn source(&self) -> String {
        self.data.source().to_string()
    }
    /// Column `name` as a float64 array (the time column in seconds).
    fn column<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(slice_to_numpy(py, ie(self.data.column(name))?))
    }
    /// The time column in seconds.
    fn time<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(slice_to_numpy(py, ie(self.data.time())?))
    }
    /// The uniform sample time (s); raises if the time column is not uniformly spaced.
    fn uniform_step(&self) -> PyResult<f64> {
        ie(self.data.uniform_step())
    }
    /// Raises if the time step is implausible for the declared unit.
    fn check_time_unit(&self) -> PyResult<()> {
        ie(self.data.check_time_unit())
    }
    /// The samples with `t0 ≤ t ≤ t1` (either end `None`: open), seconds.
    #[pyo3(signature = (t0 = None, t1 = None))]
    fn window(&self, t0: Option<f64>, t1: Option<f64>) -> PyResult<NativeDataset> {
        Ok(NativeDataset {
            data: ie(self.data.window(t0, t1))?,
        })
    }
    fn __len__(&self) -> usize {
        self.data.len()
    }
    fn __repr__(&self) -> String {
        format!(
            "Dataset({:?}, {} samples, columns {:?})",
            self.data.source(),
            self.data.len(),
            self.data.names()
        )
    }
}

/// `ident_dataset(source, text, time_unit=None)`: CSV text with a header line (as the files of
/// `data/rig/`) parsed into a [`NativeDataset`]; `time_unit` `"s"` or `"ms"` overrides what
/// the header declares (`t_ms`, `t[ms]`, `t (ms)` are milliseconds).
#[pyfunction]
#[pyo3(signature = (source, text, time_unit = None))]
fn ident_dataset(source: &str, text: &str, time_unit: Option<&str>) -> PyResult<NativeDataset> {
    let mut data = ie(Dataset::from_csv_str(source, text))?;
    if let Some(u) = time_unit {
        let unit = match u {
            "s" => TimeUnit::Seconds,
            "ms" => TimeUnit::Milliseconds,
            other => {
                return Err(new_err(
                    Kind::InvalidArgument,
                    format!("time_unit {other:?}: expected \"s\" or \"ms\""),
                    None,
                ));
            }
        };
        data = ie(data.with_time_unit(unit))?;
    }
    Ok(NativeDataset { data })
}

/// The least-squares options of `pendulab identify`, the keyword arguments `**options` of
/// `ident_drive_ls`, `ident_cart_pendulum_ls` and `ident_arm_pendulum_ls`: `filter`
/// `"causal"` (default), `"zero-phase"` or `"none"`, the time constant `tf` (s, default
/// 0.075) of `1/(T_f s + 1)³`, its discretisation `hold` (`"zoh"` default, `"foh"`), and the
/// differentiator (three-point, or Savitzky–Golay of `savgol` samples and order
/// `savgol_order`, default 3).
///
/// # Errors
/// `TypeError` for another keyword or a value of the wrong type (as Python does);
/// `InvalidArgumentError` for an unknown filter or hold.
fn ls_options(options: Option<&Bound<'_, PyDict>>) -> PyResult<LsOptions> {
    let (mut filter, mut tf, mut hold) = ("causal".to_owned(), 0.075, "zoh".to_owned());
    let (mut savgol, mut savgol_order) = (None::<usize>, 3usize);
    for (k, v) in options.into_iter().flat_map(|d| d.iter()) {
        match k.extract::<String>()?.as_str() {
            "filter" => filter = v.extract()?,
            "tf" => tf = v.extract()?,
            "hold" => hold = v.extract()?,
            "savgol" => savgol = v.extract()?,
            "savgol_order" => savgol_order = v.extract()?,
            other => {
                return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                    "unexpected keyword argument {other:?} (the least-squares options are filter, tf, hold, savgol, savgol_order)"
                )));
            }
        }
    }
    let hold = match hold.as_str() {
        "zoh" => FilterHold::Zoh,
        "foh" => FilterHold::Foh,
        other => {
            return Err(new_err(
                Kind::InvalidArgument,
                format!("hold {other:?}: expected \"zoh\" or \"foh\""),
                None,
            ));
        }
    };
    let prefilter = match filter.as_str() {
        "causal" => Prefilter::Causal { tf, hold },
        "zero-phase" => Prefilter::ZeroPhase { tf, hold },
        "none" => Prefilter::None,
        other => {
            return Err(new_err(
                Kind::InvalidArgument,
                format!("filter {other:?}: expected \"causal\", \"zero-phase\" or \"none\""),
                None,
            ));
        }
    };
    Ok(LsOptions {
        differentiator: match savgol {
            Some(window) => Differentiator::SavitzkyGolay {
                window,
                order: savgol_order,
            },
            None => Differentiator::ThreePoint,
        },
        prefilter,
    })
}

fn column(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    Ok(vector(obj, what)?.as_slice().to_vec())
}

/// The options' check of the record (enough samples for the differentiator and the filter, a
/// time constant suited to `ts`), as a list of at most one failure.
fn data_checks(opts: &LsOptions, ts: f64, n: usize) -> Vec<IdentError> {
    opts.check_data(ts, n).err().into_iter().collect()
}

fn messages(errors: Vec<IdentError>) -> Vec<String> {
    errors.iter().map(|e| e.to_string()).collect()
}

/// Runs `solve` and, when it succeeds, `validate` on its result, with the GIL released.
fn solve_then_validate<R: Send, V: Send>(
    py: Python<'_>,
    solve: impl FnOnce() -> pendulab_ident::Result<R> + Send,
    validate: impl FnOnce(&R) -> V + Send,
) -> (pendulab_ident::Result<R>, Option<V>) {
    py.detach(|| {
        let r = solve();
        let v = r.as_ref().ok().map(validate);
        (r, v)
    })
}

/// Puts a least-squares method's diagnostics, the failed checks and the validation into `d`.
fn put_ls_result(
    d: &Bound<'_, PyDict>,
    lsq: &LeastSquares,
    failed: Vec<IdentError>,
    fit: Option<pendulab_ident::Result<Validation>>,
) -> PyResult<()> {
    put_lsq(d, lsq)?;
    d.set_item("failed_checks", messages(failed))?;
    match fit {
        Some(fit) => put_fit(d, "fit", fit),
        None => Ok(()),
    }
}

/// Puts the least-squares diagnostics into `d`.
fn put_lsq(d: &Bound<'_, PyDict>, lsq: &LeastSquares) -> PyResult<()> {
    let py = d.py();
    d.set_item("names", lsq.names.clone())?;
    d.set_item("estimate", slice_to_numpy(py, &lsq.estimate))?;
    d.set_item("std_error", slice_to_numpy(py, &lsq.std_error))?;
    d.set_item("condition", lsq.condition)?;
    d.set_item("residual_rms", lsq.residual_rms)?;
    d.set_item("samples", lsq.samples)?;
    Ok(())
}

/// The validation as a dict (`fit_percent`, `rms_error`, `simulated`, `start`, `output`), or
/// its error's message under `error`.
fn put_fit(
    d: &Bound<'_, PyDict>,
    key: &str,
    v: pendulab_ident::Result<Validation>,
) -> PyResult<()> {
    let py = d.py();
    let f = PyDict::new(py);
    match v {
        Ok(v) => {
            f.set_item("fit_percent", v.fit_percent)?;
            f.set_item("rms_error", v.rms_error)?;
            f.set_item("simulated", slice_to_numpy(py, &v.simulated))?;
            f.set_item("start", v.start)?;
            f.set_item("output", v.output)?;
        }
        Err(e) => f.set_item("error", e.to_string())?,
    }
    d.set_item(key, f)
}

/// `ident_drive_ls(rig, ts, y, v, **options)`: the drive `ÿ = −a ẏ + b v` by least squares
/// (book Part 1 §3.2.2, eq. (3.31)): `rig` `"cart"` (y = z, `a_c`, `b_c`) or `"arm"`
/// (y = φ₁, `a₁`, `b₁`), sample time `ts` (s); `options` as [`ls_options`].
#[pyfunction]
#[pyo3(signature = (rig, ts, y, v, **options))]
fn ident_drive_ls<'py>(
    py: Python<'py>,
    rig: &str,
    ts: f64,
    y: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = ls_options(options)?;
    let (yname, cart) = match rig {
        "cart" => ("z", true),
        "arm" => ("phi1", false),
        other => {
            return Err(new_err(
                Kind::InvalidArgument,
                format!("rig {other:?}: expected \"cart\" or \"arm\""),
                None,
            ));
        }
    };
    let (y, v) = (column(y, yname)?, column(v, "v")?);
    let (r, fit) = solve_then_validate(
        py,
        || {
            if cart {
                cart_drive_ls(ts, &y, &v, &opts)
            } else {
                arm_drive_ls(ts, &y, &v, &opts)
            }
        },
        |d| validate_drive(ts, &y, &v, d.a, d.b, yname),
    );
    let r = ie(r)?;
    let d = PyDict::new(py);
    d.set_item("a", r.a)?;
    d.set_item("b", r.b)?;
    let mut failed = data_checks(&opts, ts, y.len());
    failed.extend(r.failed_checks(ts));
    put_ls_result(&d, &r.lsq, failed, fit)?;
    Ok(d)
}

/// `ident_cart_pendulum_ls(ts, z, phi, mp, lp, g, …)`: the cart pendulum's `J_p`, `μ_p` by
/// least squares with the known `m_p`, `l_p`, `g` (book Part 1 §3.2.2); `phi` is the angle
/// from the hanging rest (`φ = θ − π`); `options` as [`ls_options`].
#[pyfunction]
#[pyo3(signature = (ts, z, phi, mp = 0.107, lp = 0.230, g = 9.81, **options))]
#[allow(clippy::too_many_arguments)]
fn ident_cart_pendulum_ls<'py>(
    py: Python<'py>,
    ts: f64,
    z: &Bound<'py, PyAny>,
    phi: &Bound<'py, PyAny>,
    mp: f64,
    lp: f64,
    g: f64,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = ls_options(options)?;
    let c = CartPendulumConstants { mp, lp, g };
    let (z, phi) = (column(z, "z")?, column(phi, "phi")?);
    let (r, fit) = solve_then_validate(
        py,
        || cart_pendulum_ls(ts, &z, &phi, &c, &opts),
        |p| validate_cart_pendulum(ts, &z, &phi, p.jp, p.mup, &c),
    );
    let r = ie(r)?;
    let d = PyDict::new(py);
    d.set_item("Jp", r.jp)?;
    d.set_item("mup", r.mup)?;
    let mut failed = data_checks(&opts, ts, z.len());
    failed.extend(c.check_range().err());
    failed.extend(r.failed_checks(ts, &c));
    put_ls_result(&d, &r.lsq, failed, fit)?;
    Ok(d)
}

/// `ident_arm_pendulum_ls(ts, phi1, phi2, L1, m2, l2, g, …)`: the arm pendulum's `α₂`, `μ₂`
/// (and `J₂ = α₂ − m₂ l₂²`) by least squares with the known `L₁`, `m₂`, `l₂`, `g` (book Part 1
/// §3.3); `options` as [`ls_options`].
#[pyfunction]
#[pyo3(signature = (ts, phi1, phi2, L1 = 0.227, m2 = 0.096, l2 = 0.195, g = 9.81, **options))]
#[allow(clippy::too_many_arguments, non_snake_case)]
fn ident_arm_pendulum_ls<'py>(
    py: Python<'py>,
    ts: f64,
    phi1: &Bound<'py, PyAny>,
    phi2: &Bound<'py, PyAny>,
    L1: f64,
    m2: f64,
    l2: f64,
    g: f64,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = ls_options(options)?;
    let c = ArmPendulumConstants { l1: L1, m2, l2, g };
    let (p1, p2) = (column(phi1, "phi1")?, column(phi2, "phi2")?);
    let (r, fit) = solve_then_validate(
        py,
        || arm_pendulum_ls(ts, &p1, &p2, &c, &opts),
        |p| validate_arm_pendulum(ts, &p1, &p2, p.alpha2, p.mu2, &c),
    );
    let r = ie(r)?;
    let d = PyDict::new(py);
    d.set_item("J2", r.j2)?;
    d.set_item("mu2", r.mu2)?;
    d.set_item("alpha2", r.alpha2)?;
    let mut failed = data_checks(&opts, ts, p1.len());
    failed.extend(c.check_range().err());
    failed.extend(r.failed_checks(ts, &c));
    put_ls_result(&d, &r.lsq, failed, fit)?;
    Ok(d)
}

/// `ident_p_step(t, y, step_time, target, kp)`: the drive from a P-control step response (book
/// Part 1 §3.2.1: peak time `T_p` and overshoot give `ω_n`, `ζ`, then `a`, `b`).
#[pyfunction]
#[pyo3(signature = (t, y, step_time, target, kp))]
fn ident_p_step<'py>(
    py: Python<'py>,
    t: &Bound<'py, PyAny>,
    y: &Bound<'py, PyAny>,
    step_time: f64,
    target: f64,
    kp: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let (t, y) = (column(t, "t")?, column(y, "y")?);
    let o = PStepOptions {
        step_time,
        target,
        k_p: kp,
    };
    let e = ie(p_step(&t, &y, &o))?;
    let d = PyDict::new(py);
    d.set_item("a", e.a)?;
    d.set_item("b", e.b)?;
    d.set_item("Tp", e.tp)?;
    d.set_item("overshoot", e.overshoot)?;
    d.set_item("overshoot_ratio", e.overshoot_ratio)?;
    d.set_item("omega_n", e.omega_n)?;
    d.set_item("zeta", e.zeta)?;
    d.set_item("peak_time", e.peak.t)?;
    d.set_item("peak_value", e.peak.value)?;
    put_fit(
        &d,
        "fit",
        validate_p_step(&t, &y, step_time, target, kp, e.a, e.b),
    )?;
    Ok(d)
}

/// `ident_free_oscillation(t, y, m, l, g, hysteresis=None, amplitude_correction=False,
/// ts=None)`: a pendulum's `J`, `μ` from its free oscillation (book Part 1 §3.2.1: mean period
/// and decay ratio of the peaks, with the known `m`, `l`, `g`); `ts` (s) is the sample time
/// the validations simulate at (default: the mean step of `t`). `failed_checks` holds the
/// known constants' range check: the cart pendulum's (`m_p = m`, `l_p = l`), or with `L1` the
/// arm pendulum's (`m₂ = m`, `l₂ = l`).
#[pyfunction]
#[pyo3(signature = (t, y, m, l, g = 9.81, hysteresis = None, amplitude_correction = false,
                    ts = None, L1 = None))]
#[allow(clippy::too_many_arguments, non_snake_case)]
fn ident_free_oscillation<'py>(
    py: Python<'py>,
    t: &Bound<'py, PyAny>,
    y: &Bound<'py, PyAny>,
    m: f64,
    l: f64,
    g: f64,
    hysteresis: Option<f64>,
    amplitude_correction: bool,
    ts: Option<f64>,
    L1: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let (t, y) = (column(t, "t")?, column(y, "y")?);
    let range = match L1 {
        None => CartPendulumConstants { mp: m, lp: l, g }.check_range(),
        Some(l1) => ArmPendulumConstants {
            l1,
            m2: m,
            l2: l,
            g,
        }
        .check_range(),
    };
    let osc = ie(free_oscillation(&t, &y, &OscillationOptions { hysteresis }))?;
    let correction = if amplitude_correction {
        PeriodCorrection::LargeAmplitude
    } else {
        PeriodCorrection::None
    };
    let p = ie(pendulum_from_oscillation(&osc, m, l, g, correction))?;
    let d = PyDict::new(py);
    d.set_item("J", p.j)?;
    d.set_item("mu", p.mu)?;
    d.set_item("period", osc.period)?;
    d.set_item("decay_ratio", osc.decay_ratio)?;
    d.set_item("omega_n", p.omega_n)?;
    d.set_item("zeta", p.zeta)?;
    d.set_item("corrected_period", p.period)?;
    d.set_item("std_errors", p.std_errors)?;
    d.set_item("period_std_error", osc.period_std_error)?;
    d.set_item("decay_ratio_std_error", osc.decay_ratio_std_error)?;
    d.set_item("peaks", osc.peaks.len())?;
    d.set_item(
        "peak_times",
        osc.peaks.iter().map(|k| k.t).collect::<Vec<_>>(),
    )?;
    d.set_item("hysteresis", osc.hysteresis)?;
    d.set_item("failed_checks", messages(range.err().into_iter().collect()))?;
    let mean_step = match (t.first(), t.last()) {
        (Some(a), Some(b)) if t.len() > 1 => (b - a) / (t.len() - 1) as f64,
        _ => 0.0,
    };
    let ts = ts.unwrap_or(mean_step);
    let start = osc.peaks.first().map_or(0, |p| p.first);
    put_fit(
        &d,
        "fit",
        validate_free_pendulum(ts, &y, start, p.j, p.mu, (m, l, g)),
    )?;
    put_fit(
        &d,
        "fit_linear",
        validate_oscillation(ts, &y, start, p.omega_n, p.zeta),
    )?;
    Ok(d)
}

/// An order argument that must be at least 1.
fn at_least_one(name: &str, v: Option<usize>) -> PyResult<()> {
    if v == Some(0) {
        return Err(new_err(
            Kind::InvalidArgument,
            format!("{name} must be at least 1"),
            None,
        ));
    }
    Ok(())
}

/// The validation record: `(u_val, y_val)` when given, else the estimation record.
fn validation_record(
    u: &[f64],
    y: &[f64],
    u_val: Option<&Bound<'_, PyAny>>,
    y_val: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Vec<f64>, Vec<f64>)> {
    match (u_val, y_val) {
        (Some(uv), Some(yv)) => Ok((column(uv, "u_val")?, column(yv, "y_val")?)),
        (None, None) => Ok((u.to_vec(), y.to_vec())),
        _ => Err(new_err(
            Kind::InvalidArgument,
            "give both u_val and y_val, or neither".into(),
            None,
        )),
    }
}

/// `ident_arx(u, y, ts, na=None, nb=None, nk=1, max_order=None, u_val=None, y_val=None)`: the
/// ARX model `A(q⁻¹) y(k) = B(q⁻¹) u(k − n_k) + e(k)` by least squares (`pendulab_ident::arx`;
/// `na`, `nb` default 2), or with `max_order` every `n_a, n_b ∈ 1…max_order` ranked by
/// `AIC = N ln V + 2d` (`arx_order_selection`). Returns a dict: `a` (`[1, a₁…]`), `b`, `na`,
/// `nb`, `nk`, `std_error`, `noise_variance`, `ts`, `model` (the discrete `StateSpace`),
/// `aic` (list of `{na, nb, nk, loss, aic}` or `None`) and `fit` (MATLAB `compare` percent on
/// `(u_val, y_val)`, default the estimation record).
#[pyfunction]
#[pyo3(signature = (u, y, ts, na = None, nb = None, nk = 1, max_order = None, u_val = None,
                    y_val = None))]
#[allow(clippy::too_many_arguments)]
fn ident_arx<'py>(
    py: Python<'py>,
    u: &Bound<'py, PyAny>,
    y: &Bound<'py, PyAny>,
    ts: f64,
    #[pyo3(from_py_with = optional_count)] na: Option<usize>,
    #[pyo3(from_py_with = optional_count)] nb: Option<usize>,
    #[pyo3(from_py_with = count)] nk: usize,
    #[pyo3(from_py_with = optional_count)] max_order: Option<usize>,
    u_val: Option<&Bound<'py, PyAny>>,
    y_val: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    at_least_one("na", na)?;
    at_least_one("nb", nb)?;
    at_least_one("max_order", max_order)?;
    if max_order.is_some() && (na.is_some() || nb.is_some()) {
        return Err(new_err(
            Kind::InvalidArgument,
            "give either na/nb or max_order, not both".into(),
            None,
        ));
    }
    let (u, y) = (column(u, "u")?, column(y, "y")?);
    let (uv, yv) = validation_record(&u, &y, u_val, y_val)?;
    let (r, fit) = solve_then_validate(
        py,
        || {
            let ex = [Experiment::new(&u, &y)];
            match max_order {
                Some(n) => arx_order_selection(&ex, ts, 1..=n, 1..=n, nk..=nk)
                    .map(|s| (s.model, Some(s.candidates))),
                None => arx(
                    &ex,
                    ts,
                    ArxOrders::new(na.unwrap_or(2), nb.unwrap_or(2), nk),
                )
                .map(|m| (m, None)),
            }
        },
        |(m, _)| m.fit_percent(&uv, &yv),
    );
    let (m, table) = ie(r)?;
    let fit =
        ie(fit.ok_or_else(|| new_err(Kind::InvalidArgument, "validation not run".into(), None))?)?;
    let d = PyDict::new(py);
    d.set_item("a", slice_to_numpy(py, &m.a))?;
    d.set_item("b", slice_to_numpy(py, &m.b))?;
    d.set_item("na", m.orders.na)?;
    d.set_item("nb", m.orders.nb)?;
    d.set_item("nk", m.orders.nk)?;
    d.set_item("std_error", slice_to_numpy(py, &m.std_error))?;
    d.set_item("noise_variance", m.noise_variance)?;
    d.set_item("ts", m.ts)?;
    let ss = ie(m.state_space())?;
    d.set_item("model", StateSpace::wrap(py, Sys::Discrete(ss))?)?;
    let aic = match table {
        Some(t) => {
            let rows = PyList::empty(py);
            for c in t {
                let r = PyDict::new(py);
                r.set_item("na", c.orders.na)?;
                r.set_item("nb", c.orders.nb)?;
                r.set_item("nk", c.orders.nk)?;
                r.set_item("loss", c.loss)?;
                r.set_item("aic", c.aic)?;
                rows.append(r)?;
            }
            rows.into_any()
        }
        None => py.None().into_bound(py),
    };
    d.set_item("aic", aic)?;
    d.set_item("fit", fit)?;
    Ok(d)
}

/// `ident_moesp(u, y, ts, order=None, horizon=10, u_val=None, y_val=None, max_order=None)`: a
/// discrete state-space model by PO-MOESP (`pendulab_ident::moesp`; with `order = None` the
/// order is the largest gap `σ_n/σ_{n+1}` of the singular values among
/// `n ∈ 1…min(max_order, horizon − 1)`, `MoespOptions::max_order`). Returns a dict: `model`
/// (the discrete `StateSpace`), `A`, `B`, `C`, `D`, `order`, `horizon`, `max_order`,
/// `singular_values`, `ts` and `fit` (MATLAB `compare` percent, simulated from the zero state
/// on `(u_val, y_val)`, default the estimation record).
#[pyfunction]
#[pyo3(signature = (u, y, ts, order = None, horizon = 10, u_val = None, y_val = None,
                    max_order = None))]
#[allow(clippy::too_many_arguments)]
fn ident_moesp<'py>(
    py: Python<'py>,
    u: &Bound<'py, PyAny>,
    y: &Bound<'py, PyAny>,
    ts: f64,
    #[pyo3(from_py_with = optional_count)] order: Option<usize>,
    #[pyo3(from_py_with = count)] horizon: usize,
    u_val: Option<&Bound<'py, PyAny>>,
    y_val: Option<&Bound<'py, PyAny>>,
    #[pyo3(from_py_with = optional_count)] max_order: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    at_least_one("order", order)?;
    let (u, y) = (column(u, "u")?, column(y, "y")?);
    let (uv, yv) = validation_record(&u, &y, u_val, y_val)?;
    let opts = MoespOptions {
        horizon,
        order,
        max_order,
    };
    let (r, fit) = solve_then_validate(
        py,
        || moesp(&[IoRecord::siso(&u, &y)], ts, opts),
        |s| s.fit_percent(&IoRecord::siso(&uv, &yv)),
    );
    let s = ie(r)?;
    let fit =
        ie(fit.ok_or_else(|| new_err(Kind::InvalidArgument, "validation not run".into(), None))?)?;
    let d = PyDict::new(py);
    d.set_item("A", matrix_to_numpy(py, s.model.a()))?;
    d.set_item("B", matrix_to_numpy(py, s.model.b()))?;
    d.set_item("C", matrix_to_numpy(py, s.model.c()))?;
    d.set_item("D", matrix_to_numpy(py, s.model.d()))?;
    d.set_item("order", s.order)?;
    d.set_item("horizon", horizon)?;
    d.set_item("max_order", max_order)?;
    d.set_item("singular_values", slice_to_numpy(py, &s.singular_values))?;
    d.set_item("ts", ts)?;
    d.set_item("fit", fit.first().copied().unwrap_or(f64::NAN))?;
    d.set_item("model", StateSpace::wrap(py, Sys::Discrete(s.model))?)?;
    Ok(d)
}
