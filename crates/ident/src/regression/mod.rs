//! The book's least-squares identifications (book part 1 §3.2–3.3, eqs 3.43–3.47).
//!
//! Each model is written as `M(t) p = N(t)` with measured regressors `M` and target `N`:
//!
//! | function | `M` | `N` | `p` |
//! |---|---|---|---|
//! | [`cart_drive_ls`] | `[−ż, v]` | `z̈` | `[a_c, b_c]` |
//! | [`cart_pendulum_ls`] | `[φ̈, φ̇]` | `m_p l_p cos φ z̈ − m_p l_p² φ̈ − m_p g l_p sin φ` | `[J_p, μ_p]` |
//! | [`arm_drive_ls`] | `[−φ̇₁, v]` | `φ̈₁` | `[a₁, b₁]` |
//! | [`arm_pendulum_ls`] | `[φ̈₂, φ̇₂ − φ̇₁]` | `α₃ cos(φ₁−φ₂) φ̈₁ − α₃ φ̇₁² sin(φ₁−φ₂) − α₅ sin φ₂` | `[α₂, μ₂]`, `J₂ = α₂ − m₂ l₂²` |
//!
//! with `α₃ = m₂ L₁ l₂`, `α₅ = m₂ l₂ g`. Angles: the cart pendulum's `φ = θ − π` is measured
//! from the hanging rest (eq. 3.44); for the arm rig, as in the book's arm data and Simulink
//! model, `φ₁` is the arm angle θ₁ and `φ₂ = θ₂ − π` the pendulum's absolute angle from hanging.
//! Substituting θ₂ = φ₂ + π into the arm pendulum's equation (`docs/model.md` §2) gives exactly the
//! arm row of the table.
//!
//! The recipe: derivatives by a [`Differentiator`] (the book's three-point formulas applied
//! twice by default), the nonlinear target assembled sample by sample, then **every** column
//! of `M` and `N` passed through the same [`Prefilter`] (the book's causal
//! `1/(0.075 s + 1)³` by default), then [`least_squares`] by Householder QR.
//!
//! **Streaming.** With three-point derivatives and a causal (or no) filter — the book's recipe
//! — the `*_ls` functions never build the columns: each block of 256 rows is differentiated,
//! assembled, filtered (the filter states carried from block to block) and folded into the QR
//! factor while it is in cache. The arithmetic is the same, operation for operation, as that of
//! the explicit [`Regression`] (which the `*_regression` functions return for plotting), so
//! both routes give the same estimates up to the order of the least-squares sums.

mod constants;
mod drive;
mod options;
mod pendulum;
mod stream;

pub use constants::{
    ArmPendulumConstants, CartPendulumConstants, GRAVITY_RANGE, LENGTH_RANGE, MASS_RANGE,
};
pub use drive::{DriveLs, arm_drive_ls, cart_drive_ls, cart_drive_regression};
pub use options::{
    LsOptions, MAX_DERIVATIVE_ERROR, MAX_POLE_TIMES_TS, MAX_TF_FRACTION, MIN_STENCILS,
};
pub use pendulum::{
    ArmPendulumLs, CartPendulumLs, arm_pendulum_ls, arm_pendulum_regression, cart_pendulum_ls,
    cart_pendulum_regression,
};

use crate::error::{IdentError, Result};
use crate::filter::{LowPass3, Prefilter};
use crate::least_squares::{LeastSquares, least_squares};
use stream::describe_rank;

/// The (filtered) regression `M p = N` of one identification, ready to solve or to plot (the
/// book's `p1c322_cdip_plot_MN`).
#[derive(Debug, Clone, PartialEq)]
pub struct Regression {
    /// Parameter names, one per column of `M`.
    pub names: Vec<String>,
    /// What each column of `M` is, in terms of the measured signals (e.g. `−ż`, `v`).
    pub signals: Vec<String>,
    /// Columns of `M`, each as long as the data.
    pub columns: Vec<Vec<f64>>,
    /// Name of the target.
    pub target_name: String,
    /// The target `N`.
    pub target: Vec<f64>,
}

impl Regression {
    /// Solves it by Householder QR ([`least_squares`]).
    ///
    /// # Errors
    /// As [`least_squares`].
    pub fn solve(&self) -> Result<LeastSquares> {
        let cols: Vec<(&str, &[f64])> = self
            .names
            .iter()
            .zip(&self.columns)
            .map(|(n, c)| (n.as_str(), c.as_slice()))
            .collect();
        let names: Vec<&str> = self.names.iter().map(String::as_str).collect();
        let signals: Vec<&str> = self.signals.iter().map(String::as_str).collect();
        least_squares(&cols, (&self.target_name, &self.target))
            .map_err(|e| describe_rank(e, &names, &signals))
    }

    fn filtered(mut self, prefilter: &Prefilter, ts: f64) -> Result<Self> {
        match prefilter.design(ts)? {
            None => {}
            Some((f, zero_phase)) => {
                let mut all: Vec<Vec<f64>> = std::mem::take(&mut self.columns);
                all.push(std::mem::take(&mut self.target));
                let out = filter_all(&f, zero_phase, &all);
                let mut out = out;
                self.target = out.pop().expect("target column");
                self.columns = out;
            }
        }
        Ok(self)
    }
}

fn filter_all(f: &LowPass3, zero_phase: bool, cols: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let n = cols.first().map_or(0, Vec::len);
    let inputs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    let mut out: Vec<Vec<f64>> = vec![vec![0.0; n]; cols.len()];
    {
        let mut refs: Vec<&mut [f64]> = out.iter_mut().map(Vec::as_mut_slice).collect();
        f.filter_many(&inputs, &mut refs);
    }
    if zero_phase {
        for c in &mut out {
            c.reverse();
        }
        let rev: Vec<Vec<f64>> = out.clone();
        let inputs: Vec<&[f64]> = rev.iter().map(Vec::as_slice).collect();
        {
            let mut refs: Vec<&mut [f64]> = out.iter_mut().map(Vec::as_mut_slice).collect();
            f.filter_many(&inputs, &mut refs);
        }
        for c in &mut out {
            c.reverse();
        }
    }
    out
}

/// The first of the failed checks `failed`, or `Ok` if there is none: what each result's
/// `check` returns from its `failed_checks`.
fn first_failure(failed: Vec<IdentError>) -> Result<()> {
    failed.into_iter().next().map_or(Ok(()), Err)
}

/// The checks every least-squares result starts with: its own physical plausibility, then its
/// solution's ([`LeastSquares::check`]: finite, well conditioned); the failures, in that order.
fn plausible_and_solved(plausible: Result<()>, lsq: &LeastSquares) -> Vec<IdentError> {
    [plausible, lsq.check()]
        .into_iter()
        .filter_map(Result::err)
        .collect()
}

/// `Ok` if `v` is finite and positive, else [`IdentError::InvalidParameter`] naming it.
fn positive(name: &str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(IdentError::InvalidParameter {
            name: name.into(),
            value: v,
            reason: "must be finite and > 0".into(),
        })
    }
}

#[cfg(test)]
mod tests;
