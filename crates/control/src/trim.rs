//! Operating points (trim) of any [`Dynamics`]: MATLAB's `findop`, python-control's
//! `find_operating_point`.
//!
//! Given a system `ẋ = f(t, x, u)` with the optional output map `y = h(t, x, u)`, a
//! [`TrimSpec`] fixes some entries of `x` and `u` at given values, may fix outputs
//! `y_i = y_i*`, may release derivatives that need not vanish (a cart rolling at constant
//! speed: `ż` fixed, `d z/dt` free) and may give the held derivatives non-zero targets
//! `ẋ_i*` (python-control's `dx0`, MATLAB `operspec`'s `States.dx`: a steady acceleration, a
//! ramp). The remaining entries of `(x, u)`, the unknowns `p`, are found by solving the
//! equations
//!
//! ```text
//! r(p) = [ f_i(t, x, u) − ẋ_i*  for every state i whose derivative is held (ẋ_i* = 0 unless given) ;
//!          h_j(t, x, u) − y_j*  for every fixed output j ] = 0
//! ```
//!
//! in the least-squares sense by Levenberg–Marquardt with Marquardt's scaling (Moré, "The
//! Levenberg–Marquardt algorithm: implementation and theory", 1978): the step solves
//! `(JᵀJ + λ diag(JᵀJ)) δ = −Jᵀ r`, is accepted when it lowers `‖r‖₂` (then `λ ← λ/3`) and is
//! retried with `λ ← 4λ` otherwise; with `λ → 0` it is the Gauss–Newton step, so the iteration
//! converges quadratically near a regular solution. The Jacobian `J = ∂r/∂p` is the columns
//! and rows of `[A B; C D]` by `pendulab-sim`'s Richardson-extrapolated central differences
//! ([`jacobians`]; error ~1e-12).
//!
//! The point is accepted when `‖r‖_∞ ≤ tolerance` (absolute, in the units of `ẋ` and `y`).
//! A search that stalls above it — `Jᵀ r` vanishing (a local minimum of `‖r‖` that is not a
//! zero: no operating point, or none near the start), steps too small to change `p`, `λ`
//! overflowing or the iteration budget spent — is the error [`ControlError::NoConvergence`]
//! with the best residual. The returned [`TrimStatus`] says whether the point is isolated or one
//! of a family (the rank deficiency of `J` at the solution: the cart's position is free at
//! every equilibrium unless it is fixed).

use crate::error::{ControlError, Result, check_finite_slice, check_param};
use nalgebra::{DMatrix, DVector};
use pendulab_sim::{Dynamics, LinearizeOptions, jacobians};

/// What an operating point must satisfy: fixed states, inputs and outputs, and the initial
/// guess of everything else (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct TrimSpec {
    /// The state: the initial guess of each free entry and the value of each fixed one
    /// (length `nx`).
    pub x: Vec<f64>,
    /// The input, the same way (length `nu`).
    pub u: Vec<f64>,
    /// Indices of the states held at their value in `x`.
    pub fixed_states: Vec<usize>,
    /// Indices of the inputs held at their value in `u`.
    pub fixed_inputs: Vec<usize>,
    /// Fixed outputs `(j, y_j*)`: `h_j(t, x, u) = y_j*` (the system must have an output map).
    pub outputs: Vec<(usize, f64)>,
    /// Indices of the states whose derivative need not vanish (steady motion of a coordinate
    /// that does not feed back, e.g. a cart's position while it rolls at constant speed).
    pub free_derivatives: Vec<usize>,
    /// The values `ẋ_i*` the held derivatives must take (length `nx`; the entries of freed
    /// derivatives are ignored); empty: all zero, an equilibrium.
    pub derivative_targets: Vec<f64>,
    /// The time `t` at which `f` and `h` are evaluated (0 for time-invariant systems).
    pub t: f64,
}

impl TrimSpec {
    /// A specification with everything free, starting from the guess `(x, u)`.
    pub fn new(x: &[f64], u: &[f64]) -> Self {
        Self {
            x: x.to_vec(),
            u: u.to_vec(),
            fixed_states: Vec::new(),
            fixed_inputs: Vec::new(),
            outputs: Vec::new(),
            free_derivatives: Vec::new(),
            derivative_targets: Vec::new(),
            t: 0.0,
        }
    }

    /// Holds the states `indices` at their values in `x`.
    pub fn fix_states(mut self, indices: &[usize]) -> Self {
        self.fixed_states.extend_from_slice(indices);
        self
    }

    /// Holds the inputs `indices` at their values in `u`.
    pub fn fix_inputs(mut self, indices: &[usize]) -> Self {
        self.fixed_inputs.extend_from_slice(indices);
        self
    }

    /// Requires the output `j` to equal `value`.
    pub fn fix_output(mut self, j: usize, value: f64) -> Self {
        self.outputs.push((j, value));
        self
    }

    /// Lets the derivative of state `i` be non-zero.
    pub fn free_derivative(mut self, i: usize) -> Self {
        self.free_derivatives.push(i);
        self
    }

    /// Requires the held derivatives to equal `dx` (one entry per state; those of freed
    /// derivatives are ignored) instead of zero.
    pub fn derivatives(mut self, dx: &[f64]) -> Self {
        self.derivative_targets = dx.to_vec();
        self
    }
}

/// Options of [`find_operating_point`].
#[derive(Debug, Clone, PartialEq)]
pub struct TrimOptions {
    /// Accept the point when `‖r‖_∞ ≤ tolerance` (default `1e-10`).
    pub tolerance: f64,
    /// Largest number of Levenberg–Marquardt iterations (Jacobian evaluations; default 100).
    pub max_iterations: usize,
    /// The finite differences of the Jacobian (default: `pendulab-sim`'s, Richardson with two
    /// extrapolations).
    pub differences: LinearizeOptions,
}

impl Default for TrimOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 100,
            differences: LinearizeOptions::default(),
        }
    }
}

/// Whether an operating point is isolated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrimStatus {
    /// `J` has full column rank at the point: no other operating point satisfies the
    /// specification nearby.
    Isolated,
    /// `J` has a null space of this dimension at the point: the point is one of a family
    /// (e.g. the cart's equilibria along the rail), the one nearest the start in the
    /// iteration's metric.
    Family {
        /// Number of free unknowns the equations do not determine (rank deficiency of `J`).
        dimension: usize,
    },
}

/// An operating point found by [`find_operating_point`].
#[derive(Debug, Clone, PartialEq)]
pub struct OperatingPoint {
    /// The state `x` (fixed entries as given).
    pub x: Vec<f64>,
    /// The input `u`.
    pub u: Vec<f64>,
    /// `ẋ = f(t, x, u)` at the point (its targets, zero unless given, but for the freed
    /// derivatives, to the tolerance).
    pub dx: Vec<f64>,
    /// `y = h(t, x, u)` at the point (empty without an output map).
    pub y: Vec<f64>,
    /// `‖r‖_∞` at the point (≤ the tolerance).
    pub residual: f64,
    /// Levenberg–Marquardt iterations taken.
    pub iterations: usize,
    /// Isolated or one of a family.
    pub status: TrimStatus,
}

/// Finds `(x, u)` with `f(t, x, u) = 0` (or the derivative targets, and the fixed outputs)
/// for the specification `spec` by Levenberg–Marquardt (see the module documentation).
///
/// ```
/// use pendulab_control::trim::{find_operating_point, TrimOptions, TrimSpec};
/// use pendulab_sim::FnDynamics;
/// # fn main() -> Result<(), pendulab_control::ControlError> {
/// // A torque-driven pendulum θ̈ = u − 9.81 sin θ held at θ = 0.5 rad needs u = 9.81 sin 0.5.
/// let pend = FnDynamics::new(2, 1, |_t, x: &[f64], u: &[f64], dx: &mut [f64]| {
///     dx[0] = x[1];
///     dx[1] = u[0] - 9.81 * x[0].sin();
/// });
/// let spec = TrimSpec::new(&[0.5, 0.1], &[0.0]).fix_states(&[0]);
/// let op = find_operating_point(&pend, &spec, &TrimOptions::default())?;
/// assert!((op.u[0] - 9.81 * 0.5f64.sin()).abs() < 1e-9);
/// # Ok(()) }
/// ```
///
/// # Errors
/// [`ControlError::DimensionMismatch`] for `x`, `u` or derivative targets of the wrong
/// length; [`ControlError::NonFinite`] for a non-finite guess, fixed value or target;
/// [`ControlError::InvalidParameter`] for a tolerance that is not positive;
/// [`ControlError::InconsistentSpec`] for an index out of range or listed twice, an output on a
/// system without an output map, a derivative both freed and without a state, no equations, or
/// everything fixed at a point that is not an operating point;
/// [`ControlError::Sim`] if `f` or `h` is not finite at an evaluated point;
/// [`ControlError::NoConvergence`] when the search stalls above the tolerance.
#[doc(alias = "findop")]
#[doc(alias = "trim")]
pub fn find_operating_point<S: Dynamics + ?Sized>(
    sys: &S,
    spec: &TrimSpec,
    options: &TrimOptions,
) -> Result<OperatingPoint> {
    let problem = Problem::new(sys, spec, options)?;
    problem.solve()
}

/// The equations and unknowns of one specification.
struct Problem<'a, S: ?Sized> {
    sys: &'a S,
    spec: &'a TrimSpec,
    options: &'a TrimOptions,
    /// Free unknowns as indices into `[x; u]`.
    unknowns: Vec<usize>,
    /// States whose derivative must vanish.
    derivative_rows: Vec<usize>,
}

const WHAT: &str = "operating-point specification";

fn inconsistent(reason: String) -> ControlError {
    ControlError::InconsistentSpec {
        what: WHAT.into(),
        reason,
    }
}

/// Checks that every index is below `n` and none repeats.
fn check_indices(name: &str, indices: &[usize], n: usize) -> Result<Vec<bool>> {
    let mut seen = vec![false; n];
    for &i in indices {
        if i >= n {
            return Err(inconsistent(format!(
                "{name} index {i} is out of range (the system has {n})"
            )));
        }
        if seen[i] {
            return Err(inconsistent(format!("{name} index {i} is listed twice")));
        }
        seen[i] = true;
    }
    Ok(seen)
}

impl<'a, S: Dynamics + ?Sized> Problem<'a, S> {
    fn new(sys: &'a S, spec: &'a TrimSpec, options: &'a TrimOptions) -> Result<Self> {
        let (nx, nu, ny) = (sys.nx(), sys.nu(), sys.ny());
        crate::error::check_vector("state x of the operating-point guess", &spec.x, nx)?;
        crate::error::check_vector("input u of the operating-point guess", &spec.u, nu)?;
        if !spec.derivative_targets.is_empty() {
            crate::error::check_vector(
                "derivative targets dx of the operating point",
                &spec.derivative_targets,
                nx,
            )?;
        }
        check_param("time t", spec.t, true, "finite")?;
        check_param(
            "tolerance",
            options.tolerance,
            options.tolerance > 0.0,
            "positive",
        )?;
        let fixed_x = check_indices("fixed state", &spec.fixed_states, nx)?;
        let fixed_u = check_indices("fixed input", &spec.fixed_inputs, nu)?;
        let freed = check_indices("free derivative", &spec.free_derivatives, nx)?;
        let out_idx: Vec<usize> = spec.outputs.iter().map(|(j, _)| *j).collect();
        if !out_idx.is_empty() && ny == 0 {
            return Err(inconsistent(
                "outputs are fixed but the system has no output map".into(),
            ));
        }
        check_indices("fixed output", &out_idx, ny)?;
        let targets: Vec<f64> = spec.outputs.iter().map(|(_, v)| *v).collect();
        check_finite_slice("fixed output values", &targets)?;
        let unknowns: Vec<usize> = (0..nx)
            .filter(|&i| !fixed_x[i])
            .chain((0..nu).filter(|&i| !fixed_u[i]).map(|i| nx + i))
            .collect();
        let derivative_rows: Vec<usize> = (0..nx).filter(|&i| !freed[i]).collect();
        if derivative_rows.is_empty() && out_idx.is_empty() {
            return Err(inconsistent(
                "no equation is left: every derivative is freed and no output is fixed".into(),
            ));
        }
        Ok(Self {
            sys,
            spec,
            options,
            unknowns,
            derivative_rows,
        })
    }

    /// `(x, u)` with the unknowns set to `p`.
    fn point(&self, p: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let nx = self.sys.nx();
        let (mut x, mut u) = (self.spec.x.clone(), self.spec.u.clone());
        for (&k, &v) in self.unknowns.iter().zip(p) {
            if k < nx {
                x[k] = v;
            } else {
                u[k - nx] = v;
            }
        }
        (x, u)
    }

    /// `(ẋ, y)` at `(x, u)`.
    fn evaluate(&self, x: &[f64], u: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut dx = vec![0.0; self.sys.nx()];
        self.sys.derivative(self.spec.t, x, u, &mut dx);
        let mut y = vec![0.0; self.sys.ny()];
        if !y.is_empty() {
            self.sys.output(self.spec.t, x, u, &mut y);
        }
        (dx, y)
    }

    /// The residual vector `r(p)`; `None` if it is not finite.
    fn residual(&self, p: &[f64]) -> Option<DVector<f64>> {
        let (x, u) = self.point(p);
        let (dx, y) = self.evaluate(&x, &u);
        let r: Vec<f64> = self
            .derivative_rows
            .iter()
            .map(|&i| dx[i] - self.spec.derivative_targets.get(i).copied().unwrap_or(0.0))
            .chain(self.spec.outputs.iter().map(|&(j, v)| y[j] - v))
            .collect();
        r.iter()
            .all(|v| v.is_finite())
            .then(|| DVector::from_vec(r))
    }

    /// `J = ∂r/∂p`.
    fn jacobian(&self, p: &[f64]) -> Result<DMatrix<f64>> {
        let (x, u) = self.point(p);
        let j = jacobians(self.sys, self.spec.t, &x, &u, &self.options.differences)?;
        let nx = self.sys.nx();
        let rows = self.derivative_rows.len() + self.spec.outputs.len();
        let mut out = DMatrix::zeros(rows, self.unknowns.len());
        for (c, &k) in self.unknowns.iter().enumerate() {
            for (r, &i) in self.derivative_rows.iter().enumerate() {
                out[(r, c)] = if k < nx {
                    j.a[(i, k)]
                } else {
                    j.b[(i, k - nx)]
                };
            }
            let base = self.derivative_rows.len();
            for (r, &(o, _)) in self.spec.outputs.iter().enumerate() {
                out[(base + r, c)] = if k < nx {
                    j.c[(o, k)]
                } else {
                    j.d[(o, k - nx)]
                };
            }
        }
        Ok(out)
    }

    fn finish(&self, p: &[f64], residual: f64, iterations: usize) -> Result<OperatingPoint> {
        let (x, u) = self.point(p);
        let (dx, y) = self.evaluate(&x, &u);
        let status = if self.unknowns.is_empty() {
            TrimStatus::Isolated
        } else {
            let j = self.jacobian(p)?;
            let sv = j.clone().svd(false, false).singular_values;
            let smax = sv.iter().fold(0.0f64, |m, v| m.max(*v));
            let tol = 1e-8 * smax.max(f64::MIN_POSITIVE);
            let rank = sv.iter().filter(|&&s| s > tol).count();
            match self.unknowns.len() - rank {
                0 => TrimStatus::Isolated,
                dimension => TrimStatus::Family { dimension },
            }
        };
        Ok(OperatingPoint {
            x,
            u,
            dx,
            y,
            residual,
            iterations,
            status,
        })
    }

    fn no_convergence(&self, residual: f64, iterations: usize, reason: &str) -> ControlError {
        ControlError::NoConvergence {
            what: "operating-point search".into(),
            residual,
            iterations,
            tolerance: self.options.tolerance,
            reason: reason.into(),
        }
    }

    fn solve(&self) -> Result<OperatingPoint> {
        let tol = self.options.tolerance;
        let mut p: Vec<f64> = self
            .unknowns
            .iter()
            .map(|&k| {
                let nx = self.sys.nx();
                if k < nx {
                    self.spec.x[k]
                } else {
                    self.spec.u[k - nx]
                }
            })
            .collect();
        let mut r = match self.residual(&p) {
            Some(r) => r,
            None => {
                let (x, u) = self.point(&p);
                let (dx, y) = self.evaluate(&x, &u);
                let all: Vec<f64> = dx.into_iter().chain(y).collect();
                check_finite_slice("[f; h] at the initial guess", &all)?;
                return Err(inconsistent(
                    "f or h is not finite at the initial guess".into(),
                ));
            }
        };
        let norm_inf = |r: &DVector<f64>| r.amax();
        if self.unknowns.is_empty() {
            let res = norm_inf(&r);
            if res <= tol {
                return self.finish(&p, res, 0);
            }
            return Err(inconsistent(format!(
                "every state and input is fixed and the point is not an operating point \
                 (residual {res:e})"
            )));
        }
        let mut lambda = 1e-3;
        for it in 0..self.options.max_iterations {
            let res = norm_inf(&r);
            if res <= tol {
                return self.finish(&p, res, it);
            }
            let j = self.jacobian(&p)?;
            let jtj = j.transpose() * &j;
            let g = j.transpose() * &r;
            let scale = (0..jtj.nrows())
                .map(|i| jtj[(i, i)])
                .fold(0.0f64, f64::max)
                .max(f64::MIN_POSITIVE);
            if g.amax() <= 1e-14 * scale.sqrt() * r.norm().max(f64::MIN_POSITIVE).max(tol) {
                return Err(self.no_convergence(
                    res,
                    it,
                    "the residual has a non-zero local minimum here (∂‖r‖²/∂p = 0): \
                     no operating point, or none near the start",
                ));
            }
            let cost = r.norm();
            let mut accepted = false;
            while lambda < 1e16 {
                let mut m = jtj.clone();
                for i in 0..m.nrows() {
                    m[(i, i)] += lambda * jtj[(i, i)].max(1e-12 * scale);
                }
                let Some(step) = m.cholesky().map(|c| c.solve(&(-&g))) else {
                    lambda *= 4.0;
                    continue;
                };
                let trial: Vec<f64> = p.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
                let moved = trial.iter().zip(&p).any(|(a, b)| a != b);
                if !moved {
                    return Err(self.no_convergence(
                        res,
                        it,
                        "the steps no longer change the point",
                    ));
                }
                if let Some(rt) = self.residual(&trial)
                    && rt.norm() < cost
                {
                    p = trial;
                    r = rt;
                    lambda = (lambda / 3.0).max(1e-15);
                    accepted = true;
                    break;
                }
                lambda *= 4.0;
            }
            if !accepted {
                return Err(self.no_convergence(
                    res,
                    it,
                    "no step lowers the residual (damping overflowed)",
                ));
            }
        }
        let res = norm_inf(&r);
        if res <= tol {
            return self.finish(&p, res, self.options.max_iterations);
        }
        Err(self.no_convergence(
            res,
            self.options.max_iterations,
            "the iteration budget is spent",
        ))
    }
}
