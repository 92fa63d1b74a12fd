//! Batch runs on all cores that honour Ctrl-C: the work is cut into chunks, each chunk runs
//! on rayon's threads with the GIL released, and between chunks the calling thread takes the
//! GIL back and runs Python's signal handlers (`Python::check_signals`), so a `SIGINT`
//! raises `KeyboardInterrupt` within one chunk's time (about a tenth of a second for 1024
//! of the grid's 10 s runs on two cores).
//!
//! - `batch_feedback(K, x0s, t_final, …)`: `u = −K x` with zero-order hold on the book's cart
//!   pendulum from every initial state, by the lane kernel of `pendulab_sim::fast::lanes`
//!   (eight runs stepped together; the polynomial sine/cosine with the later RK4 stages' by the
//!   addition theorem, `AnchoredSinCos`), the workload of `pendulab bench sim-batch`;
//! - `batch_simulate_json(plant, controller, scenarios)`: the one simulate path
//!   (`pendulab_control::scenario::simulate`) for every scenario.

use numpy::{IntoPyArray, PyArray1, PyArrayMethods};
use pendulab_control::scenario::simulate;
use pendulab_plants::CartPendulum as CartPlant;
use pendulab_sim::fast::{AnchoredSinCos, LaneOptions, run_feedback_lanes};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rayon::prelude::*;

use crate::convert::{OneD, count, matrix, optional_count, vector};
use crate::errors::{Kind, from_error, new_err};
use crate::plants::{cart_params, plant_error, plant_spec, sim_error, spec};

/// Runs per lane group of the lane kernel.
const LANES: usize = 8;

/// Adds this facet's functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(batch_feedback, m)?)?;
    m.add_function(wrap_pyfunction!(batch_simulate_json, m)?)?;
    Ok(())
}

/// A rayon pool of `threads` threads (`None`: rayon's global pool, one thread per core).
pub fn pool(threads: Option<usize>) -> PyResult<Option<rayon::ThreadPool>> {
    match threads {
        None => Ok(None),
        Some(0) => Err(new_err(
            Kind::InvalidArgument,
            "threads must be at least 1".into(),
            None,
        )),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map(Some)
            .map_err(|e| new_err(Kind::Error, format!("cannot start {n} threads: {e}"), None)),
    }
}

/// Runs `f` over `items` in chunks of `chunk`, each chunk on `pool` (or rayon's global pool)
/// with the GIL released, checking Python's signal handlers between chunks; results in order.
///
/// # Errors
/// The first error of a chunk (later chunks are not run), or the exception a signal handler
/// raised (`KeyboardInterrupt` for Ctrl-C).
pub fn chunked<T, R, E, F>(
    py: Python<'_>,
    pool: Option<&rayon::ThreadPool>,
    items: &[T],
    chunk: usize,
    f: F,
    error: impl Fn(E) -> PyErr,
) -> PyResult<Vec<R>>
where
    T: Sync,
    R: Send,
    E: Send,
    F: Fn(&[T]) -> Result<Vec<R>, E> + Sync,
{
    let mut out = Vec::with_capacity(items.len());
    for part in items.chunks(chunk.max(1)) {
        let r = py.detach(|| match pool {
            Some(p) => p.install(|| f(part)),
            None => f(part),
        });
        out.extend(r.map_err(&error)?);
        py.check_signals()?;
    }
    Ok(out)
}

/// `batch_feedback(K, x0s, t_final, params=None, ts=1e-3, substeps=1, stay_within=None,
/// threads=None, chunk=1024)`: the nonlinear cart pendulum (book table 3.5, each parameter
/// overridable in `params`) under `u = −K x` (V) held over each sample `ts` (s), integrated by
/// RK4 with `substeps` steps per sample, from every row of `x0s` (`[z, θ, ż, θ̇]`) for `t_final`
/// seconds; with `stay_within=(i, bound)` a run stops at the first sample with `|x_i| > bound`.
/// Returns a dict: `held` (bool array), `steps` (RK4 steps integrated per run), `final_state`
/// (runs × 4: the last sample seen).
#[pyfunction]
#[pyo3(signature = (K, x0s, t_final, params = None, ts = 1e-3, substeps = 1, stay_within = None,
                    threads = None, chunk = 1024))]
#[allow(non_snake_case, clippy::too_many_arguments)]
fn batch_feedback<'py>(
    py: Python<'py>,
    K: &Bound<'py, PyAny>,
    x0s: &Bound<'py, PyAny>,
    t_final: f64,
    params: Option<std::collections::HashMap<String, f64>>,
    ts: f64,
    #[pyo3(from_py_with = count)] substeps: usize,
    stay_within: Option<(usize, f64)>,
    #[pyo3(from_py_with = optional_count)] threads: Option<usize>,
    #[pyo3(from_py_with = count)] chunk: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let plant = CartPlant::new(cart_params(params.as_ref())?).map_err(|e| plant_error(&e))?;
    let k = vector(K, "K")?;
    if k.len() != 4 {
        return Err(new_err(
            Kind::Shape,
            format!("K must have 4 entries (u = −K x), got {}", k.len()),
            None,
        ));
    }
    let gain = [k[0], k[1], k[2], k[3]];
    let x = matrix(x0s, "x0s", OneD::Row)?;
    if x.ncols() != 4 {
        return Err(new_err(
            Kind::Shape,
            format!("x0s must have 4 columns [z, θ, ż, θ̇], got {}", x.ncols()),
            None,
        ));
    }
    let starts: Vec<[f64; 4]> = x.row_iter().map(|r| [r[0], r[1], r[2], r[3]]).collect();
    let options = LaneOptions {
        ts,
        t_final,
        substeps,
        stay_within,
    };
    let pool = pool(threads)?;
    let runs = chunked(
        py,
        pool.as_ref(),
        &starts,
        chunk,
        |part| run_feedback_lanes::<_, AnchoredSinCos, 4, LANES>(&plant, &gain, &options, part),
        |e| sim_error(&e),
    )?;
    let held: Vec<bool> = runs.iter().map(|r| r.held).collect();
    let steps: Vec<u64> = runs.iter().map(|r| r.steps as u64).collect();
    let finals: Vec<f64> = runs.iter().flat_map(|r| r.final_state).collect();
    let d = PyDict::new(py);
    d.set_item("held", PyArray1::from_vec(py, held))?;
    d.set_item("steps", PyArray1::from_vec(py, steps))?;
    d.set_item(
        "final_state",
        finals.into_pyarray(py).reshape([runs.len(), 4])?,
    )?;
    Ok(d)
}

/// `batch_simulate_json(plant, controller, scenarios, threads=None, chunk=8)`: the one
/// simulate path for every `ScenarioSpec` (JSON text) of `scenarios`, on all cores; a list of
/// the dicts `simulate_json` returns, in order. A spec that does not parse raises
/// `InvalidArgumentError` naming its index before anything runs.
#[pyfunction]
#[pyo3(signature = (plant, controller, scenarios, threads = None, chunk = 8))]
fn batch_simulate_json<'py>(
    py: Python<'py>,
    plant: &str,
    controller: &str,
    scenarios: Vec<String>,
    #[pyo3(from_py_with = optional_count)] threads: Option<usize>,
    #[pyo3(from_py_with = count)] chunk: usize,
) -> PyResult<Bound<'py, PyList>> {
    let plant = plant_spec(plant)?;
    let controller: pendulab_control::spec::ControllerSpec = spec(controller, "controller")?;
    let specs: Vec<pendulab_sim::scenario::ScenarioSpec> = scenarios
        .iter()
        .enumerate()
        .map(|(i, s)| spec(s, &format!("scenario {i}")))
        .collect::<PyResult<_>>()?;
    let pool = pool(threads)?;
    let runs = chunked(
        py,
        pool.as_ref(),
        &specs,
        chunk,
        |part| {
            part.par_iter()
                .map(|s| simulate(&plant, &controller, s))
                .collect::<Result<Vec<_>, _>>()
        },
        |e| from_error(Kind::InvalidArgument, &e),
    )?;
    let items: Vec<_> = runs
        .iter()
        .map(|r| crate::plants::run_dict(py, r))
        .collect::<PyResult<_>>()?;
    PyList::new(py, items)
}
