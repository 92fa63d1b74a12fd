//! Ready-made [`Dynamics`]: linear state-space systems, closures, and closed loops.
//!
//! - `StateSpace<Continuous>` implements [`Dynamics`] directly: `ẋ = A x + B u`, `y = C x + D u`.
//! - [`FnDynamics`]: any closure `f(t, x, u, ẋ)`.
//! - [`StateFeedbackLoop`]: a plant closed by continuous static state feedback
//!   `u = −K (x − x_ref) + v` (library sign; the book's `u = +K x` converts through
//!   [`pendulab_lti::design::StateFeedback::from_book`]); its input is `v`.
//! - [`Driven`]: a plant whose input is a given function of time ([`Input`]) — an autonomous
//!   system with no inputs.

use crate::dynamics::Dynamics;
use crate::error::{Result, check_len};
use crate::signal::Input;
use pendulab_lti::design::StateFeedback;
use pendulab_lti::{Continuous, StateSpace};

/// Largest number of plant inputs the feedback wrappers handle on the stack.
pub const MAX_INPUTS: usize = 16;

impl Dynamics for StateSpace<Continuous> {
    fn nx(&self) -> usize {
        StateSpace::nx(self)
    }
    fn nu(&self) -> usize {
        StateSpace::nu(self)
    }
    /// `ẋ = A x + B u` (column-major accumulation over the matrices, no allocation).
    #[inline]
    fn derivative(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        dx.fill(0.0);
        let a = self.a();
        for (j, &xj) in x.iter().enumerate() {
            for (d, &aij) in dx.iter_mut().zip(a.column(j).iter()) {
                *d += aij * xj;
            }
        }
        let b = self.b();
        for (j, &uj) in u.iter().enumerate() {
            for (d, &bij) in dx.iter_mut().zip(b.column(j).iter()) {
                *d += bij * uj;
            }
        }
    }
    fn ny(&self) -> usize {
        StateSpace::ny(self)
    }
    /// `y = C x + D u`.
    fn output(&self, _t: f64, x: &[f64], u: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        let c = self.c();
        for (j, &xj) in x.iter().enumerate() {
            for (yi, &cij) in y.iter_mut().zip(c.column(j).iter()) {
                *yi += cij * xj;
            }
        }
        let d = self.d();
        for (j, &uj) in u.iter().enumerate() {
            for (yi, &dij) in y.iter_mut().zip(d.column(j).iter()) {
                *yi += dij * uj;
            }
        }
    }
}

/// Dynamics given by a closure `f(t, x, u, ẋ)` with `nx` states and `nu` inputs.
#[derive(Clone, Copy)]
pub struct FnDynamics<F> {
    nx: usize,
    nu: usize,
    f: F,
}

impl<F: Fn(f64, &[f64], &[f64], &mut [f64])> FnDynamics<F> {
    /// Wraps `f`, which writes `ẋ = f(t, x, u)` into its last argument.
    pub fn new(nx: usize, nu: usize, f: F) -> Self {
        Self { nx, nu, f }
    }
}

impl<F> std::fmt::Debug for FnDynamics<F> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FnDynamics")
            .field("nx", &self.nx)
            .field("nu", &self.nu)
            .finish()
    }
}

impl<F: Fn(f64, &[f64], &[f64], &mut [f64])> Dynamics for FnDynamics<F> {
    fn nx(&self) -> usize {
        self.nx
    }
    fn nu(&self) -> usize {
        self.nu
    }
    #[inline]
    fn derivative(&self, t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        (self.f)(t, x, u, dx)
    }
}

/// A plant closed by continuous static state feedback: `ẋ = f(t, x, −K (x − x_ref) + v)`.
///
/// `K` is the library's gain (`u = −K x`); the external input `v` (length `nu`) is the input
/// of the closed loop, so `nu()` is the plant's. Outputs are the plant's. Internally `K` is
/// stored row-major; the feedback is computed on a stack buffer for up to
/// [`MAX_INPUTS`] inputs (no allocation).
#[derive(Debug, Clone)]
pub struct StateFeedbackLoop<P> {
    plant: P,
    gain: Vec<f64>,
    reference: Vec<f64>,
    nu: usize,
    nx: usize,
}

impl<P: Dynamics> StateFeedbackLoop<P> {
    /// Closes `plant` with `u = −K x + v` (`K` from a [`StateFeedback`], `nu × nx`).
    ///
    /// # Errors
    /// [`crate::SimError::DimensionMismatch`] if `K` is not `nu × nx` for the plant or the
    /// plant has more than [`MAX_INPUTS`] inputs.
    pub fn new(plant: P, feedback: &StateFeedback) -> Result<Self> {
        let (nx, nu) = (plant.nx(), plant.nu());
        let k = feedback.gain();
        check_len("feedback gain rows (plant inputs)", k.nrows(), nu)?;
        check_len("feedback gain columns (plant states)", k.ncols(), nx)?;
        if nu > MAX_INPUTS {
            return Err(crate::SimError::DimensionMismatch {
                what: "plant inputs of a StateFeedbackLoop (at most MAX_INPUTS)".into(),
                expected: MAX_INPUTS,
                found: nu,
            });
        }
        let gain = (0..nu)
            .flat_map(|i| (0..nx).map(move |j| (i, j)))
            .map(|(i, j)| k[(i, j)])
            .collect();
        Ok(Self {
            plant,
            gain,
            reference: vec![0.0; nx],
            nu,
            nx,
        })
    }

    /// Regulates to `x_ref` instead of the origin: `u = −K (x − x_ref) + v`.
    ///
    /// # Errors
    /// [`crate::SimError::DimensionMismatch`] for a wrong length,
    /// [`crate::SimError::InvalidParameter`] for a non-finite entry.
    pub fn with_reference(mut self, x_ref: &[f64]) -> Result<Self> {
        crate::error::check_finite_vector(
            "reference state",
            "reference state entry",
            x_ref,
            self.nx,
        )?;
        self.reference.copy_from_slice(x_ref);
        Ok(self)
    }

    /// The plant.
    pub fn plant(&self) -> &P {
        &self.plant
    }
}

impl<P: Dynamics> Dynamics for StateFeedbackLoop<P> {
    fn nx(&self) -> usize {
        self.nx
    }
    fn nu(&self) -> usize {
        self.nu
    }
    #[inline]
    fn derivative(&self, t: f64, x: &[f64], v: &[f64], dx: &mut [f64]) {
        let u = self.plant_input(x, v);
        self.plant.derivative(t, x, &u[..self.nu], dx)
    }
    fn ny(&self) -> usize {
        self.plant.ny()
    }
    fn output(&self, t: f64, x: &[f64], v: &[f64], y: &mut [f64]) {
        let u = self.plant_input(x, v);
        self.plant.output(t, x, &u[..self.nu], y)
    }
}

impl<P> StateFeedbackLoop<P> {
    /// The plant input `u = v − K (x − x_ref)` in the first `nu` entries (each row's products
    /// summed in order).
    #[inline]
    fn plant_input(&self, x: &[f64], v: &[f64]) -> [f64; MAX_INPUTS] {
        let mut u = [0.0; MAX_INPUTS];
        for (i, ui) in u[..self.nu].iter_mut().enumerate() {
            let row = &self.gain[i * self.nx..(i + 1) * self.nx];
            let fb: f64 = row
                .iter()
                .zip(x)
                .zip(&self.reference)
                .map(|((k, xi), ri)| k * (xi - ri))
                .sum();
            *ui = v[i] - fb;
        }
        u
    }
}

/// A plant driven by a given input `u(t)`: the autonomous system `ẋ = f(t, x, u(t))` with no
/// inputs of its own. Outputs are the plant's.
#[derive(Debug, Clone)]
pub struct Driven<P, I> {
    plant: P,
    input: I,
}

impl<P: Dynamics, I: Input> Driven<P, I> {
    /// Drives `plant` with `input`.
    ///
    /// # Errors
    /// [`crate::SimError::DimensionMismatch`] if the input width is not the plant's, or the
    /// plant has more than [`MAX_INPUTS`] inputs.
    pub fn new(plant: P, input: I) -> Result<Self> {
        check_len("driving input width", input.nu(), plant.nu())?;
        if plant.nu() > MAX_INPUTS {
            return Err(crate::SimError::DimensionMismatch {
                what: "plant inputs of a Driven system (at most 16)".into(),
                expected: MAX_INPUTS,
                found: plant.nu(),
            });
        }
        Ok(Self { plant, input })
    }
}

impl<P: Dynamics, I: Input> Dynamics for Driven<P, I> {
    fn nx(&self) -> usize {
        self.plant.nx()
    }
    fn nu(&self) -> usize {
        0
    }
    #[inline]
    fn derivative(&self, t: f64, x: &[f64], _u: &[f64], dx: &mut [f64]) {
        let mut u = [0.0; MAX_INPUTS];
        let u = &mut u[..self.plant.nu()];
        self.input.eval(t, u);
        self.plant.derivative(t, x, u, dx)
    }
    fn ny(&self) -> usize {
        self.plant.ny()
    }
    fn output(&self, t: f64, x: &[f64], _u: &[f64], y: &mut [f64]) {
        let mut u = [0.0; MAX_INPUTS];
        let u = &mut u[..self.plant.nu()];
        self.input.eval(t, u);
        self.plant.output(t, x, u, y)
    }
}
