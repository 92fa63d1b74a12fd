//! One rigid pendulum on a pivot that is moved horizontally (by the cart): the parameters and
//! the equation of motion shared by the single- and the two-pendulum cart models.

use crate::error::{PlantError, Requirement, check, check_derived};

/// The physical parameters of one pendulum hung on the cart (the `_p` parameters of the
/// book's table 3.5).
///
/// Field names follow the book's symbols.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PendulumParams {
    /// Mass `m` \[kg\] (> 0).
    pub m: f64,
    /// Distance `l` from the pivot to the centre of mass \[m\] (> 0).
    pub l: f64,
    /// Drawing length `L` (pivot to tip) \[m\] (> 0); used only by the drawing geometry.
    pub L: f64,
    /// Moment of inertia `J` about the centre of mass \[kg m²\] (> 0).
    pub J: f64,
    /// Viscous friction coefficient `μ` of the pivot \[N m s/rad\] (≥ 0).
    pub mu: f64,
}

impl PendulumParams {
    /// Validates each field (requirements as documented on the fields); `model` and the names
    /// in `names` (`[m, l, L, J, mu]`) label the error.
    pub(crate) fn validate_named(
        &self,
        model: &'static str,
        names: [&'static str; 5],
    ) -> Result<(), PlantError> {
        check(model, names[0], self.m, Requirement::Positive)?;
        check(model, names[1], self.l, Requirement::Positive)?;
        check(model, names[2], self.L, Requirement::Positive)?;
        check(model, names[3], self.J, Requirement::Positive)?;
        check(model, names[4], self.mu, Requirement::NonNegative)
    }

    /// Moment of inertia about the pivot, `J + m l²` \[kg m²\].
    pub fn inertia_about_pivot(&self) -> f64 {
        self.J + self.m * self.l * self.l
    }
}

/// Precomputed constants of `(J + m l²) θ̈ + m l cos θ · z̈ = m g l sin θ − μ θ̇` (book eq. 3.7):
/// the Euler–Lagrange equation of the pendulum angle when the pivot has the prescribed
/// horizontal acceleration `z̈` (see the derivation on [`crate::cart`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PivotPendulum {
    /// `J = J_p + m_p l_p²` \[kg m²\].
    pub j: f64,
    pub inv_j: f64,
    /// `m_p l_p` \[kg m\].
    pub ml: f64,
    /// `m_p g l_p` \[N m\].
    pub mgl: f64,
    /// `μ_p` \[N m s/rad\].
    pub mu: f64,
}

impl PivotPendulum {
    pub fn new(p: &PendulumParams, g: f64, model: &'static str) -> Result<Self, PlantError> {
        let j = check_derived(model, "J + m l^2", p.inertia_about_pivot())?;
        let ml = check_derived(model, "m l", p.m * p.l)?;
        let mgl = check_derived(model, "m g l", p.m * g * p.l)?;
        let inv_j = check_derived(model, "1 / (J + m l^2)", 1.0 / j)?;
        Ok(Self {
            j,
            inv_j,
            ml,
            mgl,
            mu: p.mu,
        })
    }

    /// `θ̈` for `sin θ`, `cos θ`, `θ̇` and the pivot's acceleration `z̈`.
    #[inline(always)]
    pub fn acceleration(&self, sin: f64, cos: f64, dtheta: f64, ddz: f64) -> f64 {
        (self.mgl * sin - self.mu * dtheta - self.ml * cos * ddz) * self.inv_j
    }

    /// `(∂θ̈/∂θ, ∂θ̈/∂θ̇, ∂θ̈/∂z̈)` at `(θ, θ̇, z̈)`.
    #[inline]
    pub fn partials(&self, sin: f64, cos: f64, ddz: f64) -> (f64, f64, f64) {
        (
            (self.mgl * cos + self.ml * sin * ddz) / self.j,
            -self.mu / self.j,
            -self.ml * cos / self.j,
        )
    }

    /// `E = ½ J θ̇² + m g l (1 + cos θ)` \[J\].
    #[inline]
    pub fn energy(&self, theta: f64, dtheta: f64) -> f64 {
        0.5 * self.j * dtheta * dtheta + self.mgl * (1.0 + theta.cos())
    }
}
