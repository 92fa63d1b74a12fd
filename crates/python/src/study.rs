//! The native half of `pendulab.study` (region-of-attraction and Monte Carlo studies,
//! `docs/studies.md`): counter-based random draws, one Monte Carlo chunk through the one
//! simulate path, and the studies' figures through `pendulab-plot`.
//!
//! Every sample's random numbers depend only on `(seed, index, stream)`: the draw is the
//! SplitMix64 finaliser applied to a counter built from the three (a counter-based generator
//! in the manner of Philox, with no state carried from one sample to the next), so a sample
//! gives the same bits whichever chunk, thread or machine computes it.
//!
//! - `study_draws(seed, start, count, kinds, a, b)`: the parameter draws of samples
//!   `start .. start + count`;
//! - `study_monte_carlo_chunk(plant, controller, scenario, names, kinds, a, b, seed, start,
//!   count, threads=None)`: those samples simulated by `pendulab_control::scenario::simulate`
//!   on the plant with the drawn parameters, the noise generator (if the scenario has one)
//!   seeded per sample;
//! - `study_roa_figure` and `study_histogram_figure`: `pendulab-plot`'s region-of-attraction
//!   map and a histogram, saved as SVG or PNG.

use crate::convert::{count as count_arg, optional_count};
use numpy::{IntoPyArray, PyArray1, PyArrayMethods};
use pendulab_control::scenario::simulate;
use pendulab_lti::random::{GAMMA, SplitMix64};
use pendulab_plot::{Axes, Figure, region_of_attraction};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use serde_json::Value;

use crate::batch::{chunked, pool};
use crate::errors::{Kind, from_error, new_err};
use crate::plants::{plant_spec, spec};

/// Adds this facet's functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(study_draws, m)?)?;
    m.add_function(wrap_pyfunction!(study_monte_carlo_chunk, m)?)?;
    m.add_function(wrap_pyfunction!(study_roa_figure, m)?)?;
    m.add_function(wrap_pyfunction!(study_histogram_figure, m)?)?;
    Ok(())
}

/// The 64 random bits of `(seed, index, stream)`: the finaliser applied to the seed, then
/// to the index and then to the stream number, each step keyed by the previous result.
pub fn counter_bits(seed: u64, index: u64, stream: u64) -> u64 {
    let s = SplitMix64::mix(seed.wrapping_add(GAMMA));
    let i = SplitMix64::mix(s ^ index.wrapping_mul(GAMMA).wrapping_add(GAMMA));
    SplitMix64::mix(i ^ stream.wrapping_mul(GAMMA).wrapping_add(GAMMA))
}

/// A uniform draw in `[0, 1)` with 53 random bits from [`counter_bits`].
pub fn counter_uniform(seed: u64, index: u64, stream: u64) -> f64 {
    (counter_bits(seed, index, stream) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// How one parameter is drawn.
#[derive(Debug, Clone, Copy)]
enum Draw {
    /// Uniform on `[a, b)`: `a + (b − a)·U`.
    Uniform(f64, f64),
    /// Normal with mean `a` and standard deviation `b` by the Box–Muller transform
    /// `a + b·√(−2 ln(1 − U₁))·cos(2π U₂)`.
    Normal(f64, f64),
}

impl Draw {
    /// Parameter `j` of sample `index`: streams `2j` and `2j + 1`.
    fn sample(self, seed: u64, index: u64, j: usize) -> f64 {
        let s = 2 * j as u64;
        match self {
            Draw::Uniform(a, b) => a + (b - a) * counter_uniform(seed, index, s),
            Draw::Normal(m, sd) => {
                let u1 = counter_uniform(seed, index, s);
                let u2 = counter_uniform(seed, index, s + 1);
                m + sd * (-2.0 * (1.0 - u1).ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
            }
        }
    }
}

/// The stream of the per-sample noise seed (after every parameter's two streams).
const NOISE_STREAM: u64 = u64::MAX;

/// The draws from `kinds` (`"uniform"` / `"normal"`) with bounds or moments `a`, `b`.
fn draws(kinds: &[String], a: &[f64], b: &[f64]) -> PyResult<Vec<Draw>> {
    if kinds.len() != a.len() || kinds.len() != b.len() {
        return Err(new_err(
            Kind::Shape,
            format!(
                "study: kinds, a and b must have one entry per parameter, got {}, {} and {}",
                kinds.len(),
                a.len(),
                b.len()
            ),
            None,
        ));
    }
    kinds
        .iter()
        .zip(a.iter().zip(b))
        .enumerate()
        .map(|(j, (k, (&a, &b)))| {
            if !a.is_finite() || !b.is_finite() {
                return Err(new_err(
                    Kind::NotFinite,
                    format!("study: parameter {j} has the bounds ({a}, {b}); both must be finite"),
                    None,
                ));
            }
            match k.as_str() {
                "uniform" if a <= b => Ok(Draw::Uniform(a, b)),
                "normal" if b >= 0.0 => Ok(Draw::Normal(a, b)),
                "uniform" => Err(new_err(
                    Kind::InvalidArgument,
                    format!("study: parameter {j} is uniform on ({a}, {b}); needs low ≤ high"),
                    None,
                )),
                "normal" => Err(new_err(
                    Kind::InvalidArgument,
                    format!("study: parameter {j} is normal with std {b}; needs std ≥ 0"),
                    None,
                )),
                other => Err(new_err(
                    Kind::InvalidArgument,
                    format!("study: parameter {j} has the distribution {other:?}; expected \"uniform\" or \"normal\""),
                    None,
                )),
            }
        })
        .collect()
}

/// The `count × p` draws of samples `start ..` (row-major).
fn draw_rows(d: &[Draw], seed: u64, start: u64, count: usize) -> Vec<f64> {
    (0..count as u64)
        .flat_map(|i| {
            d.iter()
                .enumerate()
                .map(move |(j, d)| d.sample(seed, start + i, j))
        })
        .collect()
}

/// `study_draws(seed, start, count, kinds, a, b)`: the parameter draws of samples `start ..
/// start + count` as a `count × len(kinds)` float64 array; parameter `j` of sample `i` is
/// uniform on `[a_j, b_j)` (`kinds[j] = "uniform"`) or normal with mean `a_j` and standard
/// deviation `b_j` (`"normal"`, Box–Muller), from the counter-based streams `(seed, i, 2j)`
/// and `(seed, i, 2j + 1)`. Bounds that are not finite raise `NotFiniteError`, an unknown
/// kind, `low > high` or a negative standard deviation `InvalidArgumentError`.
#[pyfunction]
fn study_draws<'py>(
    py: Python<'py>,
    seed: u64,
    start: u64,
    #[pyo3(from_py_with = count_arg)] count: usize,
    kinds: Vec<String>,
    a: Vec<f64>,
    b: Vec<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let d = draws(&kinds, &a, &b)?;
    let rows = draw_rows(&d, seed, start, count);
    Ok(rows.into_pyarray(py).reshape([count, d.len()])?.into_any())
}

/// One sample's outcome.
struct Outcome {
    caught: bool,
    settling_time: f64,
    peak_input: f64,
    max_angle_deviation: f64,
}

/// `study_monte_carlo_chunk(plant, controller, scenario, names, kinds, a, b, seed, start,
/// count, threads=None)`: samples `start .. start + count` of a Monte Carlo study. Sample `i`
/// sets plant parameter `names[j]` (a key of the `PlantSpec`'s `parameters`, e.g. `m_p`) to
/// its draw (as `study_draws`; a `source = "book"` provenance becomes `"user"`), seeds the scenario's measurement noise (if any) with
/// `counter_bits(seed, i, 2⁶⁴ − 1)`, and runs `pendulab_control::scenario::simulate`
/// (`docs/model.md` §6) on all cores (or `threads`), the GIL released. Returns a dict of
/// arrays of length `count`: `caught` (bool: the pendulum stayed in the rig's angle window —
/// or, for a swing-up, ended within it — and the cart within its travel), `settling_time`
/// (s, NaN where it did not settle), `peak_input` (V), `max_angle_deviation` (rad), and
/// `params` (`count × len(names)`).
///
/// A spec that does not parse, an unknown parameter name or a draw the plant refuses (a
/// negative mass) raise `InvalidArgumentError` naming it.
#[pyfunction]
#[pyo3(signature = (plant, controller, scenario, names, kinds, a, b, seed, start, count, threads = None))]
#[allow(clippy::too_many_arguments)]
fn study_monte_carlo_chunk<'py>(
    py: Python<'py>,
    plant: &str,
    controller: &str,
    scenario: &str,
    names: Vec<String>,
    kinds: Vec<String>,
    a: Vec<f64>,
    b: Vec<f64>,
    seed: u64,
    start: u64,
    #[pyo3(from_py_with = count_arg)] count: usize,
    #[pyo3(from_py_with = optional_count)] threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let base = serde_json::to_value(plant_spec(plant)?)
        .map_err(|e| from_error(Kind::InvalidArgument, &e))?;
    let known: Vec<String> = base["parameters"]
        .as_object()
        .map(|m| m.keys().cloned().collect())
        .unwrap_or_default();
    if let Some(bad) = names.iter().find(|n| !known.contains(n)) {
        return Err(new_err(
            Kind::InvalidArgument,
            format!(
                "study: {bad:?} is not a parameter of the plant (its parameters: {})",
                known.join(", ")
            ),
            None,
        ));
    }
    let d = draws(&kinds, &a, &b)?;
    if names.len() != d.len() {
        return Err(new_err(
            Kind::Shape,
            format!("study: {} names for {} distributions", names.len(), d.len()),
            None,
        ));
    }
    let controller: pendulab_control::spec::ControllerSpec = spec(controller, "controller")?;
    let scenario_value: Value = spec(scenario, "scenario")?;
    // Validate the scenario once, before any sample runs.
    let _: pendulab_sim::scenario::ScenarioSpec = spec(scenario, "scenario")?;
    let has_noise = scenario_value
        .pointer("/imperfections/noise")
        .is_some_and(|n| !n.is_null());
    let params = draw_rows(&d, seed, start, count);
    let indices: Vec<u64> = (start..start + count as u64).collect();
    let p = d.len();
    let pool = pool(threads)?;
    let one = |i: u64| -> Result<Outcome, String> {
        let row = &params[(i - start) as usize * p..][..p];
        let mut plant = base.clone();
        for (name, v) in names.iter().zip(row) {
            plant["parameters"][name] = Value::from(*v);
        }
        // Drawn values are no longer the book's table: a book plant becomes a user one.
        if !names.is_empty() && plant["provenance"]["source"] == "book" {
            plant["provenance"] = serde_json::json!({
                "source": "user",
                "note": format!("Monte Carlo sample {i} of seed {seed}")
            });
        }
        let plant: pendulab_plants::spec::PlantSpec = serde_json::from_value(plant)
            .map_err(|e| format!("sample {i} ({}): {e}", describe(&names, row)))?;
        let mut sc = scenario_value.clone();
        if has_noise {
            sc["imperfections"]["noise"]["seed"] = Value::from(counter_bits(seed, i, NOISE_STREAM));
        }
        let sc: pendulab_sim::scenario::ScenarioSpec =
            serde_json::from_value(sc).map_err(|e| format!("sample {i}: scenario: {e}"))?;
        let run = simulate(&plant, &controller, &sc)
            .map_err(|e| format!("sample {i} ({}): {e}", describe(&names, row)))?;
        let s = &run.summary;
        let fell = match s.left_angle_window {
            Some(left) => left,
            None => s.final_state.get(1).is_none_or(|th| wrap(*th).abs() > 0.5),
        };
        Ok(Outcome {
            caught: !fell && !s.left_travel,
            settling_time: s.settling_time.unwrap_or(f64::NAN),
            peak_input: s.peak_input,
            max_angle_deviation: s.max_angle_deviation,
        })
    };
    let outs = chunked(
        py,
        pool.as_ref(),
        &indices,
        64,
        |part| {
            part.par_iter()
                .map(|&i| one(i))
                .collect::<Result<Vec<_>, _>>()
        },
        |e: String| new_err(Kind::InvalidArgument, format!("study: {e}"), None),
    )?;
    let dict = PyDict::new(py);
    dict.set_item(
        "caught",
        PyArray1::from_vec(py, outs.iter().map(|o| o.caught).collect()),
    )?;
    dict.set_item(
        "settling_time",
        PyArray1::from_vec(py, outs.iter().map(|o| o.settling_time).collect()),
    )?;
    dict.set_item(
        "peak_input",
        PyArray1::from_vec(py, outs.iter().map(|o| o.peak_input).collect()),
    )?;
    dict.set_item(
        "max_angle_deviation",
        PyArray1::from_vec(py, outs.iter().map(|o| o.max_angle_deviation).collect()),
    )?;
    dict.set_item("params", params.into_pyarray(py).reshape([count, p])?)?;
    Ok(dict)
}

/// An angle wrapped to `(−π, π]`.
fn wrap(th: f64) -> f64 {
    let t = th.rem_euclid(std::f64::consts::TAU);
    if t > std::f64::consts::PI {
        t - std::f64::consts::TAU
    } else {
        t
    }
}

/// `m_p = 0.1, …` for an error message.
fn describe(names: &[String], row: &[f64]) -> String {
    names
        .iter()
        .zip(row)
        .map(|(n, v)| format!("{n} = {v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Saves `fig` as SVG or PNG by the extension of `path`.
fn save(fig: &Figure, path: &str) -> PyResult<()> {
    let err = |e: &dyn std::fmt::Display| new_err(Kind::Error, format!("{path}: {e}"), None);
    if path.to_ascii_lowercase().ends_with(".png") {
        fig.save_png(path).map_err(|e| err(&e))
    } else if path.to_ascii_lowercase().ends_with(".svg") {
        fig.save_svg(path).map_err(|e| err(&e))
    } else {
        Err(new_err(
            Kind::InvalidArgument,
            format!("{path}: the figure is saved as .svg or .png"),
            None,
        ))
    }
}

/// `study_roa_figure(path, x_range, y_range, nx, ny, cells, xlabel, ylabel, title)`:
/// `pendulab-plot`'s region-of-attraction map (`cells[j·nx + i]` for column `i` from
/// `x_range[0]`, row `j` from `y_range[0]`) saved to `path` (`.svg` or `.png`).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn study_roa_figure(
    path: &str,
    x_range: (f64, f64),
    y_range: (f64, f64),
    #[pyo3(from_py_with = count_arg)] nx: usize,
    #[pyo3(from_py_with = count_arg)] ny: usize,
    cells: Vec<bool>,
    xlabel: &str,
    ylabel: &str,
    title: &str,
) -> PyResult<()> {
    if nx == 0 || ny == 0 || cells.len() != nx * ny {
        return Err(new_err(
            Kind::Shape,
            format!("study: {} cells for a {nx} × {ny} map", cells.len()),
            None,
        ));
    }
    let mut ax = region_of_attraction(x_range, y_range, nx, ny, &cells, xlabel, ylabel);
    ax.title(title);
    save(&Figure::new(ax), path)
}

/// `study_histogram_figure(path, edges, counts, xlabel, title)`: a histogram (one bar per
/// bin, `len(edges) = len(counts) + 1`) saved to `path` (`.svg` or `.png`).
#[pyfunction]
fn study_histogram_figure(
    path: &str,
    edges: Vec<f64>,
    counts: Vec<f64>,
    xlabel: &str,
    title: &str,
) -> PyResult<()> {
    if counts.is_empty() || edges.len() != counts.len() + 1 {
        return Err(new_err(
            Kind::Shape,
            format!(
                "study: {} edges for {} bins (needs one more edge than bins)",
                edges.len(),
                counts.len()
            ),
            None,
        ));
    }
    let centres: Vec<f64> = edges.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
    let mut ax = Axes::new();
    ax.xlabel(xlabel).ylabel("samples").title(title);
    ax.bar(&centres, &counts);
    save(&Figure::new(ax), path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix_finaliser_matches_the_reference_sequence() {
        // SplitMix64 seeded with 0 (Vigna's splitmix64.c): next() = mix(k·γ) for k = 1, 2, …;
        // its first output is 0xe220a8397b1dcdaf.
        assert_eq!(SplitMix64::mix(GAMMA), 0xe220_a839_7b1d_cdaf);
    }

    #[test]
    fn draws_depend_only_on_seed_index_and_stream() {
        let d = [Draw::Uniform(-1.0, 1.0), Draw::Normal(0.0, 1.0)];
        let all = draw_rows(&d, 7, 0, 10);
        let tail = draw_rows(&d, 7, 4, 6);
        assert_eq!(&all[8..], &tail[..]);
        assert_ne!(draw_rows(&d, 8, 0, 10), all);
    }
}
