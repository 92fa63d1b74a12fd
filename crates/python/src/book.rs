//! The `book` facet of the extension module: the examples of 「倒立振子で学ぶ制御工学」
//! (`pendulab-book`'s registry) behind `pendulab.book`, as `pendulab book` and `pendulab
//! report` run them (`docs/report.md`).
//!
//! `book_list()` lists the registry; `book_run(id, out, data)` runs one example (the GIL
//! released) and returns its values, the book's printed values beside them, its notes and the
//! figure files it wrote into `out`; `book_report(out, only)` runs the examples in parallel and
//! writes the lab report's page (`index.html`), figures (`figures/<id>/`) and README table
//! (`status.md`) with `pendulab_book::report`.

use std::path::{Path, PathBuf};

use numpy::PyArray2;
use pendulab_book::report::{Entry, ReportOptions, Status, Summary, html, markdown_table};
use pendulab_book::{BookError, Example, ExampleOutput, RunContext, Value};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rayon::prelude::*;

use crate::convert::{complex_to_numpy, slice_to_numpy};
use crate::errors::{Kind, from_error, new_err};

/// Adds this facet's functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(book_list, m)?)?;
    m.add_function(wrap_pyfunction!(book_run, m)?)?;
    m.add_function(wrap_pyfunction!(book_report, m)?)?;
    Ok(())
}

/// A [`BookError`] as a `pendulab` exception: an unknown id or an example that needs data →
/// `InvalidArgumentError`, a failed computation or figure → `pendulab.Error`.
pub fn book_error(e: &BookError) -> PyErr {
    let kind = match e {
        BookError::UnknownId(_) | BookError::NeedsData { .. } => Kind::InvalidArgument,
        _ => Kind::Error,
    };
    from_error(kind, e)
}

/// `value` as Python: a bool, a float, a 1-d or 2-d float64 array, or a complex128 array.
fn value<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Bool(b) => pyo3::types::PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(x) => pyo3::types::PyFloat::new(py, *x).into_any(),
        Value::Vector(x) => slice_to_numpy(py, x).into_any(),
        Value::Matrix(rows) => PyArray2::from_vec2(py, rows)
            .map_err(|e| new_err(Kind::Error, format!("matrix value: {e}"), None))?
            .into_any(),
        Value::Complex(z) => complex_to_numpy(py, z).into_any(),
    })
}

/// One registry entry as a dict.
fn describe<'py>(py: Python<'py>, e: &Example) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("id", e.id)?;
    d.set_item("title", e.title)?;
    d.set_item("section", e.section)?;
    d.set_item("parameters", e.parameters)?;
    d.set_item("needs_data", e.needs_data)?;
    Ok(d)
}

/// `book_list()`: every example in book order, each a dict `id`, `title`, `section` (e.g.
/// `"Part 1 §4.1"`), `parameters`, `needs_data` (what a `data` CSV must hold, or `None`).
#[pyfunction]
fn book_list(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let items: Vec<_> = pendulab_book::registry()
        .iter()
        .map(|e| describe(py, e))
        .collect::<PyResult<_>>()?;
    PyList::new(py, items)
}

/// Renders the figures of `out` and writes their files into `dir` (created), in order.
fn write_figures(id: &str, out: &ExampleOutput, dir: &Path) -> Result<Vec<PathBuf>, BookError> {
    std::fs::create_dir_all(dir).map_err(|source| BookError::WriteFigure {
        id: id.to_string(),
        path: dir.to_path_buf(),
        source,
    })?;
    out.emit_figures(id, dir, |path, bytes| std::fs::write(path, bytes))
}

/// Runs `e` (figures drawn and written into `dir` when given).
fn run_one(
    e: &Example,
    dir: Option<&Path>,
    data: Option<String>,
) -> (Result<ExampleOutput, BookError>, Vec<PathBuf>) {
    let ctx = RunContext {
        figures: dir.is_some(),
        data_csv: data,
    };
    match ((e.run)(&ctx), dir) {
        (Ok(out), Some(dir)) => match write_figures(e.id, &out, dir) {
            Ok(files) => (Ok(out), files),
            Err(err) => (Err(err), Vec::new()),
        },
        (r, _) => (r, Vec::new()),
    }
}

/// `book_run(id, out=None, data=None)`: runs the example `id` and returns a dict: `id`,
/// `values` (name → bool, float or array, in the example's order), `references` (the book's
/// printed values: `name`, `value`, `source`, `tolerance`, `reproduced`), `notes`, `figures`
/// (the paths, `pathlib.Path`, of the SVG/PNG/GIF files written into the directory `out`;
/// none without it) and `status`
/// (`"reproduced"`, `"agrees where compared"`, `"runs"`, `"differs from book"`: the report's
/// status labels). `data` is the text of a measured-data CSV for an
/// example that takes one. Raises `pendulab.InvalidArgumentError` for an unknown id or a
/// missing recording, `pendulab.Error` when the example fails.
#[pyfunction]
#[pyo3(signature = (id, out = None, data = None))]
fn book_run<'py>(
    py: Python<'py>,
    id: &str,
    out: Option<PathBuf>,
    data: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let example = pendulab_book::find(id).map_err(|e| book_error(&e))?;
    let (result, files) = py.detach(|| run_one(&example, out.as_deref(), data));
    let status = Status::of(&result);
    let output = result.map_err(|e| book_error(&e))?;
    let d = PyDict::new(py);
    d.set_item("id", example.id)?;
    let values = PyDict::new(py);
    for (name, v) in &output.values {
        values.set_item(name, value(py, v)?)?;
    }
    d.set_item("values", values)?;
    let refs = PyList::empty(py);
    for (r, c) in output.references.iter().zip(output.comparisons()) {
        let rd = PyDict::new(py);
        rd.set_item("name", &r.name)?;
        rd.set_item("value", value(py, &r.value)?)?;
        rd.set_item("source", &r.source)?;
        rd.set_item("tolerance", r.tolerance)?;
        rd.set_item("max_abs_error", c.max_abs_error)?;
        rd.set_item("reproduced", c.reproduced)?;
        refs.append(rd)?;
    }
    d.set_item("references", refs)?;
    d.set_item("notes", output.notes.clone())?;
    d.set_item("figures", files)?;
    d.set_item("status", status.label())?;
    Ok(d)
}

/// `book_report(out, only=None)`: runs the examples (`only`: these ids; default all) in
/// parallel, writes `out/index.html` (the lab notebook page), the figures under
/// `out/figures/<id>/` and `out/status.md` (the README table), and returns a dict: `index`
/// (the page's path), the counts per status (`total`, `reproduced`, `partly_compared` (agrees
/// where compared), `runs`, `differs`, `needs_data`, `failing`, `figures`) and `failing` (the ids that failed). Raises for an
/// unknown id or an output directory that cannot be written; a failing example is reported,
/// not raised.
#[pyfunction]
#[pyo3(signature = (out, only = None))]
fn book_report<'py>(
    py: Python<'py>,
    out: PathBuf,
    only: Option<Vec<String>>,
) -> PyResult<Bound<'py, PyDict>> {
    let examples: Vec<Example> = match only {
        None => pendulab_book::registry(),
        Some(ids) => ids
            .iter()
            .map(|id| pendulab_book::find(id).map_err(|e| book_error(&e)))
            .collect::<PyResult<_>>()?,
    };
    let io = |what: &Path, e: std::io::Error| {
        new_err(
            Kind::Error,
            format!("cannot write {}: {e}", what.display()),
            None,
        )
    };
    let figures = out.join("figures");
    std::fs::create_dir_all(&figures).map_err(|e| io(&figures, e))?;
    let entries: Vec<Entry> = py.detach(|| {
        examples
            .par_iter()
            .map(|e| {
                let start = std::time::Instant::now();
                let (result, files) = run_one(e, Some(&figures.join(e.id)), None);
                Entry {
                    example: *e,
                    result,
                    seconds: Some(start.elapsed().as_secs_f64()),
                    files,
                }
            })
            .collect()
    });
    let summary = Summary::of(&entries);
    let options = ReportOptions {
        base_dir: out.clone(),
        subtitle: Some(format!(
            "pendulab {} (Python) · {} examples",
            env!("CARGO_PKG_VERSION"),
            summary.total
        )),
        ..ReportOptions::default()
    };
    let index = out.join("index.html");
    std::fs::write(&index, html(&entries, &options)).map_err(|e| io(&index, e))?;
    let table = out.join("status.md");
    std::fs::write(&table, markdown_table(&entries)).map_err(|e| io(&table, e))?;
    let d = PyDict::new(py);
    d.set_item("index", index)?;
    d.set_item("total", summary.total)?;
    d.set_item("reproduced", summary.reproduced)?;
    d.set_item("partly_compared", summary.partly_compared)?;
    d.set_item("runs", summary.runs)?;
    d.set_item("differs", summary.differs)?;
    d.set_item("needs_data", summary.needs_data)?;
    d.set_item("failing", summary.failing)?;
    d.set_item("figures", summary.figures)?;
    let failing: Vec<&str> = entries
        .iter()
        .filter(|e| e.status() == Status::Failing)
        .map(|e| e.example.id)
        .collect();
    d.set_item("failing_ids", failing)?;
    Ok(d)
}
