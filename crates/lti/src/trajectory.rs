//! [`Trajectory`]: the one time-series type of the workspace.
//!
//! Time responses (`initial`, `step`, `lsim`), simulations, rig logs and identification data
//! are all `Trajectory` values: sample times `t` and, per sample, the state `x`, the input `u`
//! and the output `y`. Like MATLAB's `lsim` output, each matrix has **one row per sample** and
//! one column per signal, so a column is one signal over time (contiguous in memory).

use crate::error::{LtiError, Result};
use crate::linalg::Mat;

/// Sampled signals of a system: `t[k]`, and rows `x[k,:]`, `u[k,:]`, `y[k,:]`.
///
/// Invariants: `t` is finite and non-decreasing; `x`, `u`, `y` each have `t.len()` rows (a
/// matrix with zero columns stands for "no such signal"). Signal names are optional labels
/// (empty, or one per column).
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    t: Vec<f64>,
    x: Mat,
    u: Mat,
    y: Mat,
    x_names: Vec<String>,
    u_names: Vec<String>,
    y_names: Vec<String>,
}

impl Trajectory {
    /// Builds a trajectory from sample times and per-sample signal matrices (rows = samples).
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] if a matrix has a row count other than `t.len()`, or `t`
    /// is not finite and non-decreasing (naming the first offending sample).
    pub fn new(t: Vec<f64>, x: Mat, u: Mat, y: Mat) -> Result<Self> {
        let n = t.len();
        for (name, m) in [("x", &x), ("u", &u), ("y", &y)] {
            if m.nrows() != n {
                return Err(LtiError::InvalidArgument(format!(
                    "trajectory: {name} has {} rows but there are {n} time samples",
                    m.nrows()
                )));
            }
        }
        if !times_are_valid(&t) {
            if let Some(k) = t.iter().position(|v| !v.is_finite()) {
                return Err(LtiError::InvalidArgument(format!(
                    "trajectory: time sample {k} is not finite ({})",
                    t[k]
                )));
            }
            if let Some(k) = t.windows(2).position(|w| w[1] < w[0]) {
                return Err(LtiError::InvalidArgument(format!(
                    "trajectory: time decreases between samples {k} and {} ({} -> {})",
                    k + 1,
                    t[k],
                    t[k + 1]
                )));
            }
        }
        Ok(Self {
            t,
            x,
            u,
            y,
            x_names: Vec::new(),
            u_names: Vec::new(),
            y_names: Vec::new(),
        })
    }

    /// Assembles a trajectory whose time vector the caller has already validated (finite,
    /// non-decreasing) and whose matrices have `t.len()` rows.
    pub(crate) fn from_validated(t: Vec<f64>, x: Mat, u: Mat, y: Mat) -> Self {
        debug_assert!(x.nrows() == t.len() && u.nrows() == t.len() && y.nrows() == t.len());
        Self {
            t,
            x,
            u,
            y,
            x_names: Vec::new(),
            u_names: Vec::new(),
            y_names: Vec::new(),
        }
    }

    /// Builds a trajectory from row-major sample buffers (`x_data[k * nx + i]` is state `i` at
    /// sample `k`), the layout simulation loops produce.
    ///
    /// # Errors
    /// As [`Trajectory::new`], and [`LtiError::InvalidArgument`] if a buffer length is not
    /// `t.len()` times its width.
    pub fn from_row_major(
        t: Vec<f64>,
        (nx, x_data): (usize, &[f64]),
        (nu, u_data): (usize, &[f64]),
        (ny, y_data): (usize, &[f64]),
    ) -> Result<Self> {
        let n = t.len();
        let build = |name: &str, w: usize, data: &[f64]| -> Result<Mat> {
            if data.len() != n * w {
                return Err(LtiError::InvalidArgument(format!(
                    "trajectory: {name} buffer has {} values, expected {n} samples x {w}",
                    data.len()
                )));
            }
            Ok(Mat::from_row_slice(n, w, data))
        };
        let x = build("x", nx, x_data)?;
        let u = build("u", nu, u_data)?;
        let y = build("y", ny, y_data)?;
        Self::new(t, x, u, y)
    }

    /// Attaches signal names (each list empty or one name per column).
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] if a list has the wrong length.
    pub fn with_names(
        mut self,
        x_names: Vec<String>,
        u_names: Vec<String>,
        y_names: Vec<String>,
    ) -> Result<Self> {
        for (name, list, width) in [
            ("x", &x_names, self.x.ncols()),
            ("u", &u_names, self.u.ncols()),
            ("y", &y_names, self.y.ncols()),
        ] {
            if !list.is_empty() && list.len() != width {
                return Err(LtiError::InvalidArgument(format!(
                    "trajectory: {} names given for {width} {name} signals",
                    list.len()
                )));
            }
        }
        self.x_names = x_names;
        self.u_names = u_names;
        self.y_names = y_names;
        Ok(self)
    }

    /// Sample times in seconds.
    pub fn t(&self) -> &[f64] {
        &self.t
    }
    /// States, one row per sample (`len × nx`).
    pub fn x(&self) -> &Mat {
        &self.x
    }
    /// Inputs, one row per sample (`len × nu`).
    pub fn u(&self) -> &Mat {
        &self.u
    }
    /// Outputs, one row per sample (`len × ny`).
    pub fn y(&self) -> &Mat {
        &self.y
    }
    /// State names (empty if none were given).
    pub fn x_names(&self) -> &[String] {
        &self.x_names
    }
    /// Input names (empty if none were given).
    pub fn u_names(&self) -> &[String] {
        &self.u_names
    }
    /// Output names (empty if none were given).
    pub fn y_names(&self) -> &[String] {
        &self.y_names
    }
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }
    /// `true` if there are no samples.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
    /// State `i` over time as a contiguous slice.
    ///
    /// # Panics
    /// If `i >= nx` (a programming error, not user input).
    pub fn x_signal(&self, i: usize) -> &[f64] {
        column(&self.x, i)
    }
    /// Input `i` over time as a contiguous slice.
    ///
    /// # Panics
    /// If `i >= nu`.
    pub fn u_signal(&self, i: usize) -> &[f64] {
        column(&self.u, i)
    }
    /// Output `i` over time as a contiguous slice.
    ///
    /// # Panics
    /// If `i >= ny`.
    pub fn y_signal(&self, i: usize) -> &[f64] {
        column(&self.y, i)
    }
    /// Consumes the trajectory, returning `(t, x, u, y)`.
    pub fn into_parts(self) -> (Vec<f64>, Mat, Mat, Mat) {
        (self.t, self.x, self.u, self.y)
    }
}

fn column(m: &Mat, j: usize) -> &[f64] {
    assert!(
        j < m.ncols(),
        "signal index {j} out of range ({} signals)",
        m.ncols()
    );
    let n = m.nrows();
    &m.as_slice()[j * n..(j + 1) * n]
}

/// `true` if every time sample is finite and none is smaller than its predecessor: one pass
/// without early exit, which the compiler vectorises (a long simulation result is checked at
/// about one instruction per sample); the caller looks for the offending sample only when it
/// is `false`.
fn times_are_valid(t: &[f64]) -> bool {
    let finite = t.iter().fold(true, |ok, v| ok & v.is_finite());
    let ordered = t
        .iter()
        .zip(t.iter().skip(1))
        .fold(true, |ok, (a, b)| ok & (b >= a));
    finite & ordered
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_are_signals() {
        let t = vec![0.0, 0.1, 0.2];
        let tr = Trajectory::from_row_major(
            t,
            (2, &[1.0, 10.0, 2.0, 20.0, 3.0, 30.0]),
            (0, &[]),
            (1, &[5.0, 6.0, 7.0]),
        )
        .unwrap();
        assert_eq!(tr.x_signal(0), &[1.0, 2.0, 3.0]);
        assert_eq!(tr.x_signal(1), &[10.0, 20.0, 30.0]);
        assert_eq!(tr.y_signal(0), &[5.0, 6.0, 7.0]);
        assert_eq!(tr.u().ncols(), 0);
    }

    #[test]
    fn rejects_bad_time_and_shapes() {
        let e = Trajectory::new(
            vec![0.0, -1.0],
            Mat::zeros(2, 1),
            Mat::zeros(2, 0),
            Mat::zeros(2, 0),
        );
        assert!(matches!(e, Err(LtiError::InvalidArgument(m)) if m.contains("decreases")));
        let e = Trajectory::new(
            vec![0.0, 1.0],
            Mat::zeros(3, 1),
            Mat::zeros(2, 0),
            Mat::zeros(2, 0),
        );
        assert!(matches!(e, Err(LtiError::InvalidArgument(m)) if m.contains("3 rows")));
        let e = Trajectory::new(
            vec![0.0, f64::NAN],
            Mat::zeros(2, 1),
            Mat::zeros(2, 0),
            Mat::zeros(2, 0),
        );
        assert!(
            matches!(e, Err(LtiError::InvalidArgument(m)) if m.contains("sample 1 is not finite"))
        );
    }

    #[test]
    fn time_checks_name_the_first_offending_sample() {
        let check = |t: Vec<f64>| {
            let n = t.len();
            Trajectory::new(t, Mat::zeros(n, 1), Mat::zeros(n, 0), Mat::zeros(n, 0))
        };
        // A long valid grid (with repeated instants, as at a switching event) passes.
        let mut t: Vec<f64> = (0..10_001).map(|k| k as f64 * 1e-3).collect();
        t[500] = t[499];
        assert!(check(t.clone()).is_ok());
        for (k, bad, what) in [
            (0, f64::NEG_INFINITY, "sample 0 is not finite"),
            (7_777, f64::INFINITY, "sample 7777 is not finite"),
            (10_000, f64::NAN, "sample 10000 is not finite"),
            (3_000, 0.5, "between samples 2999 and 3000"),
            (9_999, 20.0, "between samples 9999 and 10000"),
        ] {
            let mut tb = t.clone();
            tb[k] = bad;
            let e = check(tb);
            assert!(
                matches!(&e, Err(LtiError::InvalidArgument(m)) if m.contains(what)),
                "sample {k} = {bad}: {e:?}"
            );
        }
    }
}
