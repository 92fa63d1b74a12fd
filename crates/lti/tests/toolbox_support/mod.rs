//! Shared by the toolbox tests (margins, norms, reduction, stepinfo): the fixture written by
//! `tools/reference/lti_toolbox_reference.py` (python-control 0.10.2, SciPy 1.16.3, Slycot
//! 0.7.1) and its systems as `StateSpace` values.
#![allow(dead_code)]

use pendulab_lti::{Continuous, Discrete, Mat, StateSpace};
use serde_json::Value;

/// The parsed fixture.
pub fn fixture() -> Value {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/lti_toolbox_reference.json");
    serde_json::from_str(&std::fs::read_to_string(path).expect("fixture")).expect("json")
}

/// A list of cases of the fixture.
pub fn cases(section: &str) -> Vec<Value> {
    fixture()[section].as_array().expect(section).clone()
}

fn matrix(v: &Value, rows: usize, cols: usize) -> Mat {
    let mut m = Mat::zeros(rows, cols);
    if rows == 0 || cols == 0 {
        return m;
    }
    for (i, row) in v.as_array().expect("rows").iter().enumerate() {
        for (j, x) in row.as_array().expect("row").iter().enumerate() {
            m[(i, j)] = x.as_f64().expect("number");
        }
    }
    m
}

/// A case's system, continuous or discrete.
pub enum Sys {
    /// Continuous time.
    C(StateSpace<Continuous>),
    /// Discrete time.
    D(StateSpace<Discrete>),
}

/// The system of a fixture case.
pub fn system(case: &Value) -> Sys {
    let n = case["nx"].as_u64().unwrap() as usize;
    let m = case["nu"].as_u64().unwrap() as usize;
    let p = case["ny"].as_u64().unwrap() as usize;
    let (a, b, c, d) = (
        matrix(&case["a"], n, n),
        matrix(&case["b"], n, m),
        matrix(&case["c"], p, n),
        matrix(&case["d"], p, m),
    );
    match case["dt"].as_f64() {
        None => Sys::C(StateSpace::continuous(a, b, c, d).unwrap()),
        Some(ts) => Sys::D(StateSpace::discrete(a, b, c, d, ts).unwrap()),
    }
}

/// Runs the same generic expression on a continuous or discrete system.
#[macro_export]
macro_rules! on_sys {
    ($sys:expr, |$s:ident| $body:expr) => {
        match $sys {
            toolbox_support::Sys::C($s) => $body,
            toolbox_support::Sys::D($s) => $body,
        }
    };
}

/// A number or `null` (= ∞) of the fixture.
pub fn num_or_inf(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::INFINITY)
}

/// The SplitMix64 stream of the toolbox tests (`Rng(seed)`; `matrix` draws uniform entries in
/// `[−1, 1)`).
pub use pendulab_lti::random::SplitMix64 as Rng;

/// A random stable continuous system: `A = M − (α + ρ(M)) I` style shift to put every
/// eigenvalue left of `−margin`.
pub fn random_stable(
    rng: &mut Rng,
    n: usize,
    p: usize,
    m: usize,
    margin: f64,
) -> StateSpace<Continuous> {
    let a0 = rng.matrix(n, n);
    let shift = pendulab_lti::linalg::eigenvalues(&a0)
        .unwrap()
        .iter()
        .map(|l| l.re)
        .fold(f64::NEG_INFINITY, f64::max);
    let a = a0 - Mat::identity(n, n) * (shift + margin);
    StateSpace::continuous(a, rng.matrix(n, m), rng.matrix(p, n), Mat::zeros(p, m)).unwrap()
}
