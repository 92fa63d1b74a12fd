//! Linear dynamic controllers: any discrete state-space controller, and observer-based output
//! feedback.

use super::{mat_vec, row_major};
use crate::controller::Controller;
use crate::error::{Result, SimError, check_len};
use pendulab_lti::{Discrete, Mat, StateSpace};

/// A discrete linear controller from `y` to `u`: `ξ_{k+1} = A ξ_k + B y_k`,
/// `u_k = C ξ_k + D y_k`, given as a `StateSpace<Discrete>` whose inputs are the measurements
/// and whose outputs are the commands.
///
/// Typical sources: `pendulab_lti::design::observer_controller` (MATLAB `reg`) on a
/// discretised plant, a compensator discretised with `c2d`. The controller refuses to run at
/// another sample time than its own.
#[derive(Debug, Clone, PartialEq)]
pub struct DiscreteLinearController {
    a: Vec<f64>,
    b: Vec<f64>,
    c: Vec<f64>,
    d: Vec<f64>,
    ts: f64,
    xi0: Vec<f64>,
    xi: Vec<f64>,
    xi_next: Vec<f64>,
    tmp: Vec<f64>,
    nu: usize,
    ny: usize,
}

impl DiscreteLinearController {
    /// The controller `sys` (inputs = measurements, outputs = commands), starting at `ξ = 0`.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] for non-finite entries.
    pub fn new(sys: &StateSpace<Discrete>) -> Result<Self> {
        let n = sys.nx();
        Ok(Self {
            a: row_major("A", sys.a())?,
            b: row_major("B", sys.b())?,
            c: row_major("C", sys.c())?,
            d: row_major("D", sys.d())?,
            ts: sys.ts(),
            xi0: vec![0.0; n],
            xi: vec![0.0; n],
            xi_next: vec![0.0; n],
            tmp: vec![0.0; n.max(sys.ny())],
            nu: sys.ny(),
            ny: sys.nu(),
        })
    }

    /// Starts from `ξ₀` instead of zero.
    ///
    /// # Errors
    /// [`SimError::DimensionMismatch`], [`SimError::InvalidParameter`] for a non-finite entry.
    pub fn with_initial_state(mut self, xi0: &[f64]) -> Result<Self> {
        crate::error::check_finite_vector(
            "controller initial state",
            "controller initial state",
            xi0,
            self.xi.len(),
        )?;
        self.xi0.copy_from_slice(xi0);
        self.xi.copy_from_slice(xi0);
        Ok(self)
    }

    /// The controller state `ξ` (the value for the next update).
    pub fn state(&self) -> &[f64] {
        &self.xi
    }
}

impl Controller for DiscreteLinearController {
    sizes_from_fields!(sampled);
    fn reset(&mut self) {
        self.xi.copy_from_slice(&self.xi0);
    }
    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        let n = self.xi.len();
        // u = C ξ + D y.
        mat_vec(&self.c, &self.xi, u);
        let tmp = &mut self.tmp[..self.nu];
        mat_vec(&self.d, y, tmp);
        for (ui, t) in u.iter_mut().zip(tmp.iter()) {
            *ui += t;
        }
        // ξ⁺ = A ξ + B y.
        mat_vec(&self.a, &self.xi, &mut self.xi_next);
        let tmp = &mut self.tmp[..n];
        mat_vec(&self.b, y, tmp);
        for (x, t) in self.xi_next.iter_mut().zip(tmp.iter()) {
            *x += t;
        }
        std::mem::swap(&mut self.xi, &mut self.xi_next);
    }
}

/// Which estimate the observer-based controller feeds back.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EstimatorForm {
    /// Prediction estimator `x̂_{k+1} = A x̂_k + B u_k + L (y_k − C x̂_k − D u_k)`,
    /// `u_k = −K x̂_k` (uses `y` up to `k − 1`; error dynamics `A − LC`; MATLAB `reg`).
    #[default]
    Prediction,
    /// Current estimator (Franklin, Powell & Workman, *Digital Control of Dynamic Systems*,
    /// §8.6): `x̂_k = x̄_k + L (y_k − C x̄_k)`, `u_k = −K x̂_k`, `x̄_{k+1} = A x̂_k + B u_k`
    /// (uses `y_k` at once; error dynamics `A − LCA`; requires `D = 0`).
    Current,
}

/// Observer-based output feedback `u = −K x̂` with a discrete full-order observer of the
/// discretised plant `(A, B, C, D)` at its sample time (see [`EstimatorForm`]).
///
/// Gains in the library's convention (`u = −K x`, observer `A − LC`); the book's
/// `K_book = −K`, `L_book = −L`.
#[derive(Debug, Clone, PartialEq)]
pub struct ObserverBased {
    a: Vec<f64>,
    b: Vec<f64>,
    c: Vec<f64>,
    d: Vec<f64>,
    k: Vec<f64>,
    l: Vec<f64>,
    form: EstimatorForm,
    ts: f64,
    n: usize,
    nu: usize,
    ny: usize,
    xhat0: Vec<f64>,
    xhat: Vec<f64>,
    xbar: Vec<f64>,
    innov: Vec<f64>,
    tmp_n: Vec<f64>,
    tmp_y: Vec<f64>,
}

impl ObserverBased {
    /// Observer-based controller for the discrete plant `plant`, state gain `K`
    /// (`nu × nx`), observer gain `L` (`nx × ny`), estimate starting at zero.
    ///
    /// # Errors
    /// [`SimError::DimensionMismatch`] for wrong gain shapes; [`SimError::InvalidParameter`]
    /// for non-finite entries; [`SimError::InvalidArgument`] for the current form with
    /// `D ≠ 0`.
    pub fn new(
        plant: &StateSpace<Discrete>,
        k: &Mat,
        l: &Mat,
        form: EstimatorForm,
    ) -> Result<Self> {
        let (n, nu, ny) = (plant.nx(), plant.nu(), plant.ny());
        check_len("K rows (commands)", k.nrows(), nu)?;
        check_len("K columns (states)", k.ncols(), n)?;
        check_len("L rows (states)", l.nrows(), n)?;
        check_len("L columns (measurements)", l.ncols(), ny)?;
        if form == EstimatorForm::Current && plant.d().iter().any(|&v| v != 0.0) {
            return Err(SimError::InvalidArgument(
                "the current-estimator form needs a plant without feedthrough (D = 0)".into(),
            ));
        }
        Ok(Self {
            a: row_major("A", plant.a())?,
            b: row_major("B", plant.b())?,
            c: row_major("C", plant.c())?,
            d: row_major("D", plant.d())?,
            k: row_major("K", k)?,
            l: row_major("L", l)?,
            form,
            ts: plant.ts(),
            n,
            nu,
            ny,
            xhat0: vec![0.0; n],
            xhat: vec![0.0; n],
            xbar: vec![0.0; n],
            innov: vec![0.0; ny],
            tmp_n: vec![0.0; n],
            tmp_y: vec![0.0; ny],
        })
    }

    /// Starts the estimate (`x̂` or `x̄`) at `x̂₀`.
    ///
    /// # Errors
    /// [`SimError::DimensionMismatch`], [`SimError::InvalidParameter`].
    pub fn with_initial_estimate(mut self, xhat0: &[f64]) -> Result<Self> {
        crate::error::check_finite_vector("initial estimate", "initial estimate", xhat0, self.n)?;
        self.xhat0.copy_from_slice(xhat0);
        self.reset();
        Ok(self)
    }

    /// The current state estimate (for the prediction form, the one-step prediction to be
    /// used at the next sample; for the current form, the filtered estimate of the last
    /// sample).
    pub fn estimate(&self) -> &[f64] {
        &self.xhat
    }
}

impl Controller for ObserverBased {
    sizes_from_fields!(sampled);
    fn reset(&mut self) {
        self.xhat.copy_from_slice(&self.xhat0);
        self.xbar.copy_from_slice(&self.xhat0);
    }
    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        match self.form {
            EstimatorForm::Prediction => {
                // u = −K x̂.
                mat_vec(&self.k, &self.xhat, u);
                u.iter_mut().for_each(|v| *v = -*v);
                // Innovation y − C x̂ − D u.
                mat_vec(&self.c, &self.xhat, &mut self.innov);
                mat_vec(&self.d, u, &mut self.tmp_y);
                for ((i, yi), t) in self.innov.iter_mut().zip(y).zip(&self.tmp_y) {
                    *i = yi - *i - t;
                }
                // x̂⁺ = A x̂ + B u + L·innovation.
                mat_vec(&self.a, &self.xhat, &mut self.xbar);
                mat_vec(&self.b, u, &mut self.tmp_n);
                for (x, t) in self.xbar.iter_mut().zip(&self.tmp_n) {
                    *x += t;
                }
                mat_vec(&self.l, &self.innov, &mut self.tmp_n);
                for (x, t) in self.xbar.iter_mut().zip(&self.tmp_n) {
                    *x += t;
                }
                std::mem::swap(&mut self.xhat, &mut self.xbar);
            }
            EstimatorForm::Current => {
                // x̂ = x̄ + L (y − C x̄).
                mat_vec(&self.c, &self.xbar, &mut self.innov);
                for (i, yi) in self.innov.iter_mut().zip(y) {
                    *i = yi - *i;
                }
                mat_vec(&self.l, &self.innov, &mut self.tmp_n);
                for ((xh, xb), t) in self.xhat.iter_mut().zip(&self.xbar).zip(&self.tmp_n) {
                    *xh = xb + t;
                }
                mat_vec(&self.k, &self.xhat, u);
                u.iter_mut().for_each(|v| *v = -*v);
                // x̄⁺ = A x̂ + B u.
                mat_vec(&self.a, &self.xhat, &mut self.xbar);
                mat_vec(&self.b, u, &mut self.tmp_n);
                for (x, t) in self.xbar.iter_mut().zip(&self.tmp_n) {
                    *x += t;
                }
            }
        }
    }
}
