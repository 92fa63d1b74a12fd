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
    /// `m_p g l_p / J`, `μ_p / J`, `m_p l_p / J` (for [`PivotPendulum::acceleration_prescaled`]).
    pub mgl_j: f64,
    pub mu_j: f64,
    pub ml_j: f64,
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
            mgl_j: mgl / j,
            mu_j: p.mu / j,
            ml_j: ml / j,
        })
    }

    /// `θ̈` for `sin θ`, `cos θ`, `θ̇` and the pivot's acceleration `z̈`.
    #[inline(always)]
    pub fn acceleration(&self, sin: f64, cos: f64, dtheta: f64, ddz: f64) -> f64 {
        (self.mgl * sin - self.mu * dtheta - self.ml * cos * ddz) * self.inv_j
    }

    /// `θ̈` as [`PivotPendulum::acceleration`], with the constants divided by `J` beforehand:
    /// `(m g l/J)·sin θ − (μ/J)·θ̇ − (m l/J)·cos θ·z̈` — one multiplication less after the
    /// sine on the dependency chain of an integration step; it differs from `acceleration`
    /// by a few roundings (relative ~1e-16).
    #[inline(always)]
    pub fn acceleration_prescaled(&self, sin: f64, cos: f64, dtheta: f64, ddz: f64) -> f64 {
        (self.mgl_j * sin - self.mu_j * dtheta) - self.ml_j * cos * ddz
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The prescaled form against the plain one over random arguments: both evaluate the
    /// same expression with at most five roundings each (and the constants' own divisions),
    /// so they agree to 8ε times the sum of the terms' magnitudes.
    #[test]
    fn prescaled_acceleration_agrees_with_the_plain_one_to_rounding() {
        let params = PendulumParams {
            m: 0.1,
            l: 0.2,
            L: 0.4,
            J: 1e-3,
            mu: 2e-4,
        };
        let p = PivotPendulum::new(&params, 9.81, "test").unwrap();
        let mut seed = 0x2545_F491_4F6C_DD1Du64;
        let mut uniform = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..10_000 {
            let th = 4.0 * uniform();
            let (s, c) = th.sin_cos();
            let (dth, ddz) = (20.0 * uniform(), 50.0 * uniform());
            let plain = p.acceleration(s, c, dth, ddz);
            let scaled = p.acceleration_prescaled(s, c, dth, ddz);
            let size = (p.mgl * s.abs() + p.mu * dth.abs() + p.ml * (c * ddz).abs()) / p.j;
            assert!(
                (plain - scaled).abs() <= 8.0 * f64::EPSILON * size,
                "{plain} vs {scaled} at θ = {th}, θ̇ = {dth}, z̈ = {ddz}"
            );
        }
    }
}
