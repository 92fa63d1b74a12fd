//! The known constants of the pendulum identifications (book table 3.5 for the cart, the
//! arm's `L₁`, `m₂`, `l₂`, `g`), with their range and positivity checks.

use super::positive;
use crate::error::{IdentError, Result};

/// Plausible masses of the pendulum rigs' bodies, kg: from a 1 g bob to a 10 kg load (the
/// book's pendulums: 0.107 kg and 0.096 kg).
pub const MASS_RANGE: (f64, f64) = (1e-3, 10.0);

/// Plausible lengths of the pendulum rigs (pivot to centre of mass, arm length), m: 1 mm to
/// 2 m (the book's: 0.195–0.230 m).
pub const LENGTH_RANGE: (f64, f64) = (1e-3, 2.0);

/// Plausible gravitational acceleration, m/s²: Earth's surface gravity lies between 9.78
/// (equator) and 9.83 (poles), a little less at altitude.
pub const GRAVITY_RANGE: (f64, f64) = (9.7, 9.9);

/// `Ok` if `value` lies in `range` (inclusive), else [`IdentError::ConstantOutOfRange`] naming it
/// with its unit and the reason for the range.
fn in_range(name: &str, value: f64, unit: &str, range: (f64, f64), reason: &str) -> Result<()> {
    if value >= range.0 && value <= range.1 {
        Ok(())
    } else {
        Err(IdentError::ConstantOutOfRange {
            name: name.into(),
            value,
            unit: unit.into(),
            min: range.0,
            max: range.1,
            reason: reason.into(),
        })
    }
}

/// Known constants of the cart-type pendulum (book table 3.5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartPendulumConstants {
    /// Pendulum mass `m_p`, kg (book: 0.107).
    pub mp: f64,
    /// Pivot to centre of mass `l_p`, m (book: 0.230).
    pub lp: f64,
    /// Gravitational acceleration `g`, m/s² (book: 9.81).
    pub g: f64,
}

impl Default for CartPendulumConstants {
    fn default() -> Self {
        Self {
            mp: 0.107,
            lp: 0.230,
            g: 9.81,
        }
    }
}

/// Known constants of the arm-type pendulum (book table 3.7).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmPendulumConstants {
    /// Arm length `L₁` (pivot to pendulum joint), m (book: 0.227).
    pub l1: f64,
    /// Pendulum mass `m₂`, kg (book: 0.096).
    pub m2: f64,
    /// Joint to pendulum centre of mass `l₂`, m (book: 0.195).
    pub l2: f64,
    /// Gravitational acceleration `g`, m/s² (book: 9.81).
    pub g: f64,
}

impl Default for ArmPendulumConstants {
    fn default() -> Self {
        Self {
            l1: 0.227,
            m2: 0.096,
            l2: 0.195,
            g: 9.81,
        }
    }
}

impl ArmPendulumConstants {
    /// `α₃ = m₂ L₁ l₂`, kg m².
    pub fn alpha3(&self) -> f64 {
        self.m2 * self.l1 * self.l2
    }
    /// `α₅ = m₂ l₂ g`, N m.
    pub fn alpha5(&self) -> f64 {
        self.m2 * self.l2 * self.g
    }
}

impl CartPendulumConstants {
    /// Checks that every constant lies in its documented plausible range ([`MASS_RANGE`],
    /// [`LENGTH_RANGE`], [`GRAVITY_RANGE`]). The `*_ls` functions only require positive
    /// finite values; the command-line tool calls this too.
    ///
    /// # Errors
    /// [`IdentError::ConstantOutOfRange`] naming the constant, its value and the range.
    pub fn check_range(&self) -> Result<()> {
        self.validate()?;
        in_range(
            "m_p",
            self.mp,
            "kg",
            MASS_RANGE,
            "pendulum mass of a tabletop rig",
        )?;
        in_range("l_p", self.lp, "m", LENGTH_RANGE, "pivot to centre of mass")?;
        in_range(
            "g",
            self.g,
            "m/s²",
            GRAVITY_RANGE,
            "Earth's surface gravity",
        )
    }

    pub(super) fn validate(&self) -> Result<()> {
        positive("m_p", self.mp)?;
        positive("l_p", self.lp)?;
        positive("g", self.g)
    }
}

impl ArmPendulumConstants {
    /// Checks that every constant lies in its documented plausible range ([`MASS_RANGE`],
    /// [`LENGTH_RANGE`], [`GRAVITY_RANGE`]).
    ///
    /// # Errors
    /// [`IdentError::ConstantOutOfRange`] naming the constant, its value and the range.
    pub fn check_range(&self) -> Result<()> {
        self.validate()?;
        in_range(
            "L1",
            self.l1,
            "m",
            LENGTH_RANGE,
            "arm length of a tabletop rig",
        )?;
        in_range(
            "m2",
            self.m2,
            "kg",
            MASS_RANGE,
            "pendulum mass of a tabletop rig",
        )?;
        in_range("l2", self.l2, "m", LENGTH_RANGE, "joint to centre of mass")?;
        in_range(
            "g",
            self.g,
            "m/s²",
            GRAVITY_RANGE,
            "Earth's surface gravity",
        )
    }

    pub(super) fn validate(&self) -> Result<()> {
        positive("L1", self.l1)?;
        positive("m2", self.m2)?;
        positive("l2", self.l2)?;
        positive("g", self.g)
    }
}
