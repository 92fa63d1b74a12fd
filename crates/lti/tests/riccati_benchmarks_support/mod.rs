//! The Riccati benchmark collections CAREX and DAREX (Benner, Laub & Mehrmann, TU Chemnitz
//! SPC 95_22 and 95_23, 1995; version 2.0 by Abels & Benner, SLICOT Working Notes 1999-14 and
//! 1999-16), written from the published definitions (the SLICOT generators `BB01AD`/`BB02AD`
//! document them): the data of each example and, where the collection gives one, the closed-form
//! stabilising solution.
//!
//! Conventions of the collections, mapped to pendulab's:
//! - CAREX: `0 = Q + AᵀX + XA − XGX` with `G = BR⁻¹Bᵀ` and `Q = CᵀWC`. An example with
//!   "`B = I`" and a weight `R` has `G = R⁻¹`; we pass `B = I`, `R` as is.
//! - DAREX: `0 = AᵀXA − X − (AᵀXB + S)(R + BᵀXB)⁻¹(BᵀXA + Sᵀ) + Q` with `Q = CᵀQ₀C`; `S` is
//!   pendulab's cross term `N`.
//! - Symmetric weights are listed by the generators in packed lower-triangular order
//!   (column by column); [`packed_lower`] unpacks them.
//!
//! Nothing here computes a solution: the closed forms are the formulas printed in the
//! collections.
//!
//! The generators are [`carex`] (`carex.rs`) and [`darex`] (`darex.rs`); this file holds the
//! [`Example`] type, the [`sweep`] tables and the helpers both share.
#![allow(dead_code)]

mod carex;
mod darex;

// Each test binary uses the generators it needs (as with `dead_code` above).
#[allow(unused_imports)]
pub use self::{carex::carex, darex::darex};

use pendulab_lti::Mat;

/// One benchmark problem.
#[derive(Debug, Clone)]
pub struct Example {
    /// "CAREX 2.1 (eps = 1e-6)", ...
    pub id: String,
    /// State matrix.
    pub a: Mat,
    /// Input matrix.
    pub b: Mat,
    /// State weight `Q = CᵀWC` (continuous) or `CᵀQ₀C` (discrete).
    pub q: Mat,
    /// Input weight.
    pub r: Mat,
    /// Cross weight (`S` of DAREX), if any.
    pub n: Option<Mat>,
    /// The stabilising solution in closed form, if the collection gives one.
    pub x: Option<Mat>,
}

/// Unpacks a symmetric `k × k` matrix from its packed lower triangle (column by column).
pub fn packed_lower(k: usize, p: &[f64]) -> Mat {
    assert_eq!(p.len(), k * (k + 1) / 2);
    let mut m = Mat::zeros(k, k);
    let mut pos = 0;
    for j in 0..k {
        for i in j..k {
            m[(i, j)] = p[pos];
            m[(j, i)] = p[pos];
            pos += 1;
        }
    }
    m
}

fn rows(r: usize, c: usize, v: &[f64]) -> Mat {
    Mat::from_row_slice(r, c, v)
}

fn eye(n: usize) -> Mat {
    Mat::identity(n, n)
}

fn diag(v: &[f64]) -> Mat {
    Mat::from_diagonal(&pendulab_lti::Vector::from_column_slice(v))
}

/// `CᵀWC`, symmetrised.
fn weight(c: &Mat, w: &Mat) -> Mat {
    let q = c.transpose() * w * c;
    (&q + q.transpose()) * 0.5
}

/// A list of benchmark examples: `(group, numbers, parameter values, size)` stands for the
/// examples `group.number` for each of `numbers`, each at every parameter value (`eps` of the
/// collection; `0.0` for the examples without one), in that order.
pub type Sweep<'a> = &'a [(u32, &'a [u32], &'a [f64], Option<usize>)];

/// The examples of `table` from `collection` ([`carex`] or [`darex`]), in the table's order.
pub fn sweep(
    collection: fn(u32, u32, f64, Option<usize>) -> Example,
    table: Sweep<'_>,
) -> Vec<Example> {
    let mut examples = Vec::new();
    for &(group, numbers, values, size) in table {
        for &number in numbers {
            for &eps in values {
                examples.push(collection(group, number, eps, size));
            }
        }
    }
    examples
}

fn example(id: String, a: Mat, b: Mat, q: Mat, r: Mat, x: Option<Mat>) -> Example {
    Example {
        id,
        a,
        b,
        q,
        r,
        n: None,
        x,
    }
}

/// Reads Fortran list-directed data the way the generators do: each `read(count)` starts on a
/// new line and consumes lines until `count` numbers are read (the rest of its last line is
/// discarded). `D` exponents are accepted.
pub struct FortranData {
    lines: Vec<Vec<f64>>,
    next: usize,
}

impl FortranData {
    /// Loads `tests/fixtures/riccati_benchmarks/<name>`.
    pub fn load(name: &str) -> Self {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/fixtures/riccati_benchmarks")
            .join(name);
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
        let lines = text
            .lines()
            .map(|l| {
                l.split_whitespace()
                    .map(|t| {
                        t.replace(['D', 'd'], "E")
                            .parse::<f64>()
                            .unwrap_or_else(|_| panic!("{name}: bad number {t}"))
                    })
                    .collect::<Vec<_>>()
            })
            .filter(|v| !v.is_empty())
            .collect();
        Self { lines, next: 0 }
    }

    /// One list-directed read of `count` numbers.
    pub fn read(&mut self, count: usize) -> Vec<f64> {
        let mut out = Vec::with_capacity(count);
        while out.len() < count {
            let line = &self.lines[self.next];
            self.next += 1;
            let take = (count - out.len()).min(line.len());
            out.extend_from_slice(&line[..take]);
        }
        out
    }

    /// `r` reads of `c` numbers: a matrix given row by row.
    pub fn matrix(&mut self, r: usize, c: usize) -> Mat {
        let mut m = Mat::zeros(r, c);
        for i in 0..r {
            let row = self.read(c);
            for j in 0..c {
                m[(i, j)] = row[j];
            }
        }
        m
    }
}

/// `V = I − (2/3) 1 1ᵀ` (3×3, symmetric orthogonal), used by CAREX 2.6 and DAREX 2.4.
fn v3() -> Mat {
    Mat::from_fn(3, 3, |i, j| if i == j { 1.0 / 3.0 } else { -2.0 / 3.0 })
}
