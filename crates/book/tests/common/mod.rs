//! Helpers shared by the book's test files: running an example, reading its values, comparing
//! numbers and rendering figures into files of a scratch directory (as the command line does).

// Each test file uses its own subset of these helpers.
#![allow(dead_code)]

use pendulab_book::{BookError, ExampleOutput, RunContext, Value, find};
use pendulab_lti::Complex64;
use std::path::{Path, PathBuf};

/// Runs example `id` under `ctx`.
pub fn run_in(id: &str, ctx: &RunContext) -> Result<ExampleOutput, BookError> {
    (find(id).unwrap().run)(ctx)
}

/// Runs example `id` without figures on the optional CSV data `data`.
pub fn run_with(id: &str, data: Option<String>) -> Result<ExampleOutput, BookError> {
    run_in(
        id,
        &RunContext {
            figures: false,
            data_csv: data,
        },
    )
}

/// Runs example `id` without figures and data; it must succeed.
pub fn run(id: &str) -> ExampleOutput {
    run_in(id, &RunContext::default()).unwrap()
}

/// The number `name` of `out`.
pub fn num(out: &ExampleOutput, name: &str) -> f64 {
    match out.get(name) {
        Some(Value::Number(x)) => *x,
        other => panic!("{name}: {other:?}"),
    }
}

/// The vector `name` of `out`.
pub fn vector(out: &ExampleOutput, name: &str) -> Vec<f64> {
    match out.get(name) {
        Some(Value::Vector(v)) => v.clone(),
        other => panic!("{name}: {other:?}"),
    }
}

/// The complex numbers `name` of `out`.
pub fn cplx(out: &ExampleOutput, name: &str) -> Vec<Complex64> {
    match out.get(name) {
        Some(Value::Complex(c)) => c.clone(),
        other => panic!("{name}: {other:?}"),
    }
}

/// Every comparison of `out` with a printed reference is reproduced.
pub fn all_reproduced(out: &ExampleOutput) {
    for c in out.comparisons() {
        assert!(c.reproduced, "{c:?}");
    }
}

/// `out` has references and every one is reproduced.
pub fn references_reproduced(out: &ExampleOutput) {
    assert!(!out.references.is_empty());
    all_reproduced(out);
}

/// `|got_i − want_i| ≤ rel · max(|want_i|, 1)` for every `i` (relative, absolute near 0).
pub fn assert_rel(got: &[f64], want: &[f64], rel: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: {got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            (g - w).abs() <= rel * w.abs().max(1.0),
            "{what}: {got:?} vs {want:?}"
        );
    }
}

/// `|got_i − want_i| ≤ tol` for every `i`.
pub fn assert_abs(got: &[f64], want: &[f64], tol: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: {got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() <= tol, "{what}: {got:?} vs {want:?}");
    }
}

/// A scratch directory `<tmp>/pendulab-book-<tag>-<pid>`, removed when dropped.
pub struct TempDir(PathBuf);

impl TempDir {
    /// Creates the directory.
    pub fn new(tag: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("pendulab-book-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }

    /// Its path.
    pub fn path(&self) -> &Path {
        &self.0
    }

    /// A run context drawing figures, with optional CSV data.
    pub fn ctx(&self, data: Option<String>) -> RunContext {
        RunContext {
            figures: true,
            data_csv: data,
        }
    }

    /// Runs example `id` with figures on the optional CSV data `data` (it must succeed),
    /// renders every figure and writes its files here; the output and the files written.
    pub fn run(&self, id: &str, data: Option<String>) -> (ExampleOutput, Vec<PathBuf>) {
        let out = run_in(id, &self.ctx(data)).unwrap();
        let mut files = Vec::new();
        for g in &out.figures {
            for f in g.render().unwrap() {
                let path = self.0.join(&f.name);
                std::fs::write(&path, &f.bytes).unwrap();
                files.push(path);
            }
        }
        (out, files)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Every figure file in `files` exists and is larger than `min_bytes`.
pub fn assert_figures_larger(files: &[PathBuf], min_bytes: u64) {
    for f in files {
        let len = std::fs::metadata(f).map(|m| m.len()).unwrap_or(0);
        assert!(len > min_bytes, "{} has {len} bytes", f.display());
    }
}

/// Runs each example of `ids` with figures (no data), writing into `dir`, and checks that it
/// wrote at least two figure files, each larger than 2000 bytes; returns each example's files
/// in the order of `ids`.
pub fn assert_figures_written(dir: &TempDir, ids: &[&str]) -> Vec<Vec<PathBuf>> {
    ids.iter()
        .map(|id| {
            let (_, files) = dir.run(id, None);
            assert!(files.len() >= 2, "{id}");
            assert_figures_larger(&files, 2000);
            files
        })
        .collect()
}
