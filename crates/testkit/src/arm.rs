//! The arm-type pendulum of `docs/model.md` §2 (book part 1 §3.3, drive eq. 3.29): state
//! `x = [θ₁, θ₂, θ̇₁, θ̇₂]` (rad, rad/s; both angles absolute, from the upward vertical), input
//! the motor voltage `v` (V).

use crate::{Mat, drive_and_pendulum};

/// The arm pendulum's parameters (SI units), the fields of `docs/model.md` §2 without the
/// drawing-only pendulum length `L₂`.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmParams {
    /// Velocity pole of the arm drive `a₁` (1/s).
    pub a1: f64,
    /// Gain of the arm drive `b₁` (rad/(s² V)).
    pub b1: f64,
    /// Arm pivot to pendulum pivot `L₁` (m).
    pub L1: f64,
    /// Pendulum mass `m₂` (kg).
    pub m2: f64,
    /// Pendulum pivot to centre of mass `l₂` (m).
    pub l2: f64,
    /// Pendulum inertia about its centre of mass `J₂` (kg m²).
    pub J2: f64,
    /// Viscous friction of the pendulum's joint `μ₂` (N m s/rad).
    pub mu2: f64,
    /// Gravity `g` (m/s²).
    pub g: f64,
}

impl ArmParams {
    /// Book table 3.7 (the IP Toolbox's `adip_para.m`): `a₁ = 6.20`, `b₁ = 15.8`,
    /// `L₁ = 0.227`, `m₂ = 0.096`, `l₂ = 0.195`, `J₂ = 9.06·10⁻⁴`, `μ₂ = 1.01·10⁻⁴`, `g = 9.81`.
    pub const fn book() -> Self {
        Self {
            a1: 6.20,
            b1: 15.8,
            L1: 0.227,
            m2: 0.096,
            l2: 0.195,
            J2: 9.06e-4,
            mu2: 1.01e-4,
            g: 9.81,
        }
    }

    /// `(α₂, α₃, α₅) = (J₂ + m₂ l₂², m₂ L₁ l₂, m₂ l₂ g)` (kg m², kg m², N m), `docs/model.md` §2.
    pub fn alphas(&self) -> (f64, f64, f64) {
        (
            self.J2 + self.m2 * self.l2 * self.l2,
            self.m2 * self.L1 * self.l2,
            self.m2 * self.l2 * self.g,
        )
    }

    /// The linearisation with the arm at `theta1e` (rad), the pendulum upright and everything at
    /// rest, written out from `docs/model.md` §2 with `c = cos θ₁ₑ`:
    ///
    /// ```text
    /// A = [[0, 0, 1, 0],
    ///      [0, 0, 0, 1],
    ///      [0, 0, −a₁, 0],
    ///      [0, α₅/α₂, (μ₂ + a₁ α₃ c)/α₂, −μ₂/α₂]],    B = [0, 0, b₁, −b₁ α₃ c/α₂]ᵀ
    /// ```
    pub fn linearization(&self, theta1e: f64) -> (Mat, Mat) {
        let (al2, al3, al5) = self.alphas();
        let c = theta1e.cos();
        drive_and_pendulum(
            self.a1,
            self.b1,
            [
                al5 / al2,
                (self.mu2 + self.a1 * al3 * c) / al2,
                self.mu2 / al2,
            ],
            self.b1 * al3 * c / al2,
        )
    }
}
