//! Box bounds on inputs by dummy inputs (Ohtsuka 2004, §6; the book §3.3).

use super::OptimalControlProblem;
use crate::error::{ControlError, Result, check_param};

/// A bound `min ≤ u_j ≤ max` on one plant input, with the weight of its dummy input.
///
/// It is imposed as the equality `(u_j − c)² + v² − r² = 0` with `c = (max + min)/2`,
/// `r = (max − min)/2` and a dummy input `v`, whose stage cost `−w v` (small `w > 0`) selects
/// the branch `v > 0` and keeps the multiplier `ρ = w/(2v)` positive, so the problem stays
/// regular when the bound is active (`v → 0` only as `w → 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputBound {
    /// Index of the bounded input in the base problem's stage vector.
    pub index: usize,
    /// Lower bound (input units).
    pub min: f64,
    /// Upper bound (input units, > `min`).
    pub max: f64,
    /// Weight `w > 0` of the dummy input's linear cost `−w v`.
    pub dummy_weight: f64,
}

impl InputBound {
    /// A symmetric bound `|u_j| ≤ limit` with dummy weight `w`.
    pub fn symmetric(index: usize, limit: f64, dummy_weight: f64) -> Self {
        Self {
            index,
            min: -limit,
            max: limit,
            dummy_weight,
        }
    }

    fn center(&self) -> f64 {
        0.5 * (self.max + self.min)
    }

    fn radius(&self) -> f64 {
        0.5 * (self.max - self.min)
    }
}

/// A problem whose stage vector is all plant inputs, extended by box bounds.
///
/// Stage vector of the extended problem: `[u (m_b inputs); v (k dummies); ρ (k multipliers)]`
/// with `k` = number of bounds, in the order the bounds were given. The Hamiltonian gains
/// `Σ_j (−w_j v_j + ρ_j((u_{i_j} − c_j)² + v_j² − r_j²))`, so
/// `∂H/∂u_{i_j} += 2ρ_j (u_{i_j} − c_j)`, `∂H/∂v_j = −w_j + 2ρ_j v_j`,
/// `∂H/∂ρ_j = (u_{i_j} − c_j)² + v_j² − r_j²`; `f`, `Hₓ` and `φₓ` are the base problem's.
#[derive(Debug, Clone, PartialEq)]
pub struct InputBounds<P> {
    base: P,
    bounds: Vec<InputBound>,
}

impl<P: OptimalControlProblem> InputBounds<P> {
    /// Extends `base` by `bounds`.
    ///
    /// # Errors
    /// [`ControlError::NotApplicable`] if the base stage vector is not all inputs;
    /// [`ControlError::InvalidParameter`] for an index out of range, a repeated index,
    /// non-finite or empty bounds (`max ≤ min`), or a dummy weight that is not `> 0`.
    pub fn new(base: P, bounds: Vec<InputBound>) -> Result<Self> {
        if base.n_inputs() != base.nu() {
            return Err(ControlError::NotApplicable {
                reason: format!(
                    "input bounds need a base problem whose stage vector is all inputs ({} inputs, stage length {})",
                    base.n_inputs(),
                    base.nu()
                ),
            });
        }
        for (j, b) in bounds.iter().enumerate() {
            check_param(
                &format!("bound {j} input index"),
                b.index as f64,
                b.index < base.nu(),
                &format!("must be < {}", base.nu()),
            )?;
            if bounds[..j].iter().any(|o| o.index == b.index) {
                return Err(ControlError::InvalidParameter {
                    name: format!("bound {j} input index"),
                    value: b.index as f64,
                    requirement: "each input may be bounded once".into(),
                });
            }
            check_param(&format!("bound {j} min"), b.min, true, "must be finite")?;
            check_param(
                &format!("bound {j} max"),
                b.max,
                b.max > b.min,
                "must be finite and > min",
            )?;
            check_param(
                &format!("bound {j} dummy weight"),
                b.dummy_weight,
                b.dummy_weight > 0.0,
                "must be > 0",
            )?;
        }
        Ok(Self { base, bounds })
    }

    /// The base problem.
    pub fn base(&self) -> &P {
        &self.base
    }

    /// The bounds.
    pub fn bounds(&self) -> &[InputBound] {
        &self.bounds
    }

    /// A consistent stage vector for the given plant inputs (strictly inside their bounds):
    /// `v_j = √(r_j² − (u_{i_j} − c_j)²)` and `ρ_j = w_j/(2 v_j)`, which zero the dummy and
    /// multiplier rows of `H_u`. Useful as the initial guess of [`super::Cgmres::initialize`].
    ///
    /// # Errors
    /// [`ControlError::DimensionMismatch`] for the wrong number of inputs;
    /// [`ControlError::InvalidParameter`] for an input not strictly inside its bound.
    pub fn stage_guess(&self, inputs: &[f64]) -> Result<Vec<f64>> {
        let mb = self.base.nu();
        if inputs.len() != mb {
            return Err(ControlError::DimensionMismatch {
                what: "inputs for the stage guess".into(),
                expected: mb,
                found: inputs.len(),
            });
        }
        let k = self.bounds.len();
        let mut s = vec![0.0; mb + 2 * k];
        s[..mb].copy_from_slice(inputs);
        for (j, b) in self.bounds.iter().enumerate() {
            let d = inputs[b.index] - b.center();
            let v2 = b.radius() * b.radius() - d * d;
            check_param(
                &format!("input {} of the stage guess", b.index),
                inputs[b.index],
                v2 > 0.0,
                "must lie strictly inside its bound",
            )?;
            let v = v2.sqrt();
            s[mb + j] = v;
            s[mb + k + j] = b.dummy_weight / (2.0 * v);
        }
        Ok(s)
    }
}

impl<P: OptimalControlProblem> OptimalControlProblem for InputBounds<P> {
    fn nx(&self) -> usize {
        self.base.nx()
    }

    fn nu(&self) -> usize {
        self.base.nu() + 2 * self.bounds.len()
    }

    fn n_inputs(&self) -> usize {
        self.base.nu()
    }

    #[inline]
    fn state_equation(&self, t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        self.base.state_equation(t, x, &u[..self.base.nu()], dx);
    }

    #[inline]
    fn hamiltonian_x(&self, t: f64, x: &[f64], u: &[f64], lambda: &[f64], hx: &mut [f64]) {
        self.base
            .hamiltonian_x(t, x, &u[..self.base.nu()], lambda, hx);
    }

    #[inline]
    fn hamiltonian_u(&self, t: f64, x: &[f64], u: &[f64], lambda: &[f64], hu: &mut [f64]) {
        let mb = self.base.nu();
        self.base
            .hamiltonian_u(t, x, &u[..mb], lambda, &mut hu[..mb]);
        self.add_constraint_terms(u, hu);
    }

    #[inline]
    fn hamiltonian_xu(
        &self,
        t: f64,
        x: &[f64],
        u: &[f64],
        lambda: &[f64],
        hx: &mut [f64],
        hu: &mut [f64],
    ) {
        let mb = self.base.nu();
        self.base
            .hamiltonian_xu(t, x, &u[..mb], lambda, hx, &mut hu[..mb]);
        self.add_constraint_terms(u, hu);
    }

    #[inline]
    fn terminal_gradient(&self, t: f64, x: &[f64], phix: &mut [f64]) {
        self.base.terminal_gradient(t, x, phix);
    }
}

impl<P: OptimalControlProblem> InputBounds<P> {
    /// Adds the bounds' terms to `H_u` (base part already written).
    #[inline]
    fn add_constraint_terms(&self, u: &[f64], hu: &mut [f64]) {
        let mb = self.base.nu();
        let k = self.bounds.len();
        for (j, b) in self.bounds.iter().enumerate() {
            let d = u[b.index] - b.center();
            let v = u[mb + j];
            let rho = u[mb + k + j];
            hu[b.index] += 2.0 * rho * d;
            hu[mb + j] = -b.dummy_weight + 2.0 * rho * v;
            hu[mb + k + j] = d * d + v * v - b.radius() * b.radius();
        }
    }
}
