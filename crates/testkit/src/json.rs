//! Reference fixtures written by the scripts of `tools/reference/` as JSON: reading one and its
//! matrices (nested row arrays, as NumPy's `tolist()` writes them).

use crate::Mat;
use serde_json::Value;
use std::path::Path;

/// The JSON document at `path`.
///
/// # Panics
/// When the file cannot be read or is not JSON: a broken fixture fails the test that reads it.
pub fn read(path: &Path) -> Value {
    let text =
        std::fs::read_to_string(path).unwrap_or_else(|e| panic!("fixture {}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("fixture {}: {e}", path.display()))
}

/// The matrix of a list of rows (`[[a11, a12], [a21, a22]]`); `[]` is the empty 0 × 0 matrix.
///
/// # Panics
/// When `v` is not a list of equally long lists of numbers.
pub fn matrix(v: &Value) -> Mat {
    let rows = v.as_array().expect("a matrix is a list of rows");
    let cols = rows
        .first()
        .map_or(0, |r| r.as_array().expect("a row is a list").len());
    let mut m = Mat::zeros(rows.len(), cols);
    for (i, row) in rows.iter().enumerate() {
        let row = row.as_array().expect("a row is a list");
        assert_eq!(
            row.len(),
            cols,
            "row {i} has {} entries, not {cols}",
            row.len()
        );
        for (j, x) in row.iter().enumerate() {
            m[(i, j)] = x.as_f64().expect("a number");
        }
    }
    m
}

/// The numbers of a flat list (`[a, b, c]`).
///
/// # Panics
/// When `v` is not a list of numbers.
pub fn vector(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("a vector is a list")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}
