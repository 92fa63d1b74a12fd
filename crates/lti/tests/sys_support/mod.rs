//! Shared helpers of the pendulab-lti system tests: the book's cart pendulum (its parameters and
//! upright linearisation from pendulab-testkit), fixture loading and comparisons.
#![allow(dead_code)]

use pendulab_lti::{Complex64, Mat};
use pendulab_testkit::cart::CartParams;

/// Cart-type pendulum parameters (book table 3.5), from pendulab-testkit.
const CART: CartParams = CartParams::book();
pub const AC: f64 = CART.a_c;
pub const BC: f64 = CART.b_c;
pub const MP: f64 = CART.m_p;
pub const LP: f64 = CART.l_p;
pub const JP: f64 = CART.J_p;
pub const MUP: f64 = CART.mu_p;
pub const G: f64 = CART.g;

/// The linearised cart pendulum at the upright rest (`docs/model.md` §1), state `[z, θ, ż, θ̇]`.
pub fn cdip() -> (Mat, Mat) {
    pendulab_testkit::cart::upright()
}

pub fn mat(rows: usize, cols: usize, v: &[f64]) -> Mat {
    Mat::from_row_slice(rows, cols, v)
}

pub fn c(re: f64, im: f64) -> Complex64 {
    Complex64::new(re, im)
}

/// Reads a JSON fixture from `tests/fixtures/`.
pub fn fixture(name: &str) -> serde_json::Value {
    let path = format!("{}/tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    serde_json::from_str(&text).unwrap()
}

pub fn json_mat(v: &serde_json::Value) -> Mat {
    let rows: Vec<Vec<f64>> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            r.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        })
        .collect();
    let (n, m) = (rows.len(), rows.first().map_or(0, |r| r.len()));
    Mat::from_fn(n, m, |i, j| rows[i][j])
}

pub fn json_vec(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// Asserts that every expected eigenvalue has a distinct computed one within `tol` (absolute),
/// and the counts agree.
pub fn assert_same_poles(got: &[Complex64], want: &[Complex64], tol: f64) {
    assert_eq!(got.len(), want.len(), "got {got:?}, want {want:?}");
    let mut used = vec![false; got.len()];
    for w in want {
        let best = (0..got.len())
            .filter(|&i| !used[i])
            .min_by(|&a, &b| (got[a] - w).norm().total_cmp(&(got[b] - w).norm()))
            .unwrap();
        assert!(
            (got[best] - w).norm() <= tol,
            "pole {w} not matched within {tol}: nearest {} (all: {got:?})",
            got[best]
        );
        used[best] = true;
    }
}

/// Relative Frobenius distance `‖a − b‖ / max(‖b‖, tiny)`.
pub fn rel(a: &Mat, b: &Mat) -> f64 {
    (a - b).norm() / b.norm().max(f64::MIN_POSITIVE)
}

/// Asserts `|got − want| ≤ tol` elementwise for slices.
pub fn assert_close(got: &[f64], want: &[f64], tol: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: lengths {got:?} vs {want:?}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (g - w).abs() <= tol,
            "{what}[{i}]: got {g}, want {w} (tol {tol}); all {got:?}"
        );
    }
}
