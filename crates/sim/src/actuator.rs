//! The actuator chain: from the controller's command `u_k` to the plant input, and the
//! drive's friction.
//!
//! At every sample the command passes, in this order (each stage off by default and
//! switched on by one builder call):
//!
//! ```text
//! u_k ─(+ d(t_k) if DisturbancePoint::BeforeSaturation)─ saturation [lo, hi] ─ D/A quantiser
//!     ─(+ d(t_k) if DisturbancePoint::AfterSaturation)─ dead-zone friction ─▶ held plant input
//! ```
//!
//! - **Disturbances** are signals sampled at `t_k` and held like the command. Before
//!   saturation they model an offset of the controller's output (limited by the amplifier);
//!   after saturation a force on the mechanism expressed in volts (not limited, not
//!   quantised). The choice is explicit: [`DisturbancePoint`].
//! - **Saturation** clips each command to `[lo, hi]` (the rig: ±5 V); the number of samples
//!   with a clipped command is reported.
//! - **D/A quantisation** rounds to the nearest level `k·q` (the rig: 16 bits over 10 V,
//!   `q = 10/2¹⁶ V`).
//! - **Friction on the drive**, in voltage-equivalent units (the drive model
//!   `z̈ = −a ż + b v` takes friction as a voltage offset `v_f`, i.e. a force `v_f · m b`):
//!   - [`Friction::DeadZone`]: the static dead zone `v ↦ 0` for `|v| ≤ w`,
//!     `v − w·sign(v)` otherwise, applied to the held input (cheap; no velocity needed;
//!     behaves like stiction and Coulomb friction of level `w` at low speed).
//!   - [`Friction::Coulomb`]: velocity-dependent Coulomb friction with stiction, the Karnopp
//!     model (D. Karnopp, "Computer simulation of stick-slip friction in mechanical dynamic
//!     systems", J. Dyn. Syst. Meas. Control 107 (1985) 100–103) in voltage-equivalent form,
//!     evaluated inside the plant's dynamics ([`WithDriveFriction`]): with `s` the drive's
//!     velocity state and `ε` a small velocity band,
//!     `|s| > ε`: `v_eff = v − V_c·sign(s)` (sliding); `|s| ≤ ε` and `|v| ≤ V_s`:
//!     `v_eff = 0` (stuck: static friction balances the drive; the residual velocity decays
//!     through the drive's own damping); `|s| ≤ ε` and `|v| > V_s`:
//!     `v_eff = v − V_c·sign(v)` (break-away). Parameters `V_c ≤ V_s` in volts.

use crate::dynamics::Dynamics;
use crate::error::{Result, SimError, check_len, check_nonnegative, check_positive};
use crate::quantizer::Quantizer;
use crate::signal::Signal;

/// Where an input disturbance enters the actuator chain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DisturbancePoint {
    /// Added to the controller's command before saturation and D/A conversion.
    BeforeSaturation,
    /// Added to the converted, saturated command (not limited, not quantised).
    AfterSaturation,
}

/// Friction on the drive, in voltage-equivalent units (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Friction {
    /// Static dead zone of half-width `width` (V) on input `input`.
    DeadZone {
        /// Which plant input.
        input: usize,
        /// Half-width `w ≥ 0` (V).
        width: f64,
    },
    /// Karnopp Coulomb friction with stiction on input `input`, driven by the velocity state
    /// `velocity_state`.
    Coulomb {
        /// Which plant input.
        input: usize,
        /// Index of the drive's velocity in the plant state (e.g. `ż`, 2 for the cart).
        velocity_state: usize,
        /// Coulomb (sliding) level `V_c ≥ 0` (V).
        coulomb: f64,
        /// Static (break-away) level `V_s ≥ V_c` (V).
        stiction: f64,
        /// Velocity band `ε > 0` inside which the drive counts as stopped (state units,
        /// e.g. m/s).
        velocity_band: f64,
    },
}

impl Friction {
    fn validate(&self, nx: usize, nu: usize) -> Result<()> {
        match *self {
            Friction::DeadZone { input, width } => {
                check_index("dead-zone input", input, nu)?;
                check_nonnegative("dead-zone width", width)
            }
            Friction::Coulomb {
                input,
                velocity_state,
                coulomb,
                stiction,
                velocity_band,
            } => {
                check_index("friction input", input, nu)?;
                check_index("friction velocity state", velocity_state, nx)?;
                check_nonnegative("Coulomb level V_c", coulomb)?;
                check_nonnegative("stiction level V_s", stiction)?;
                check_positive("friction velocity band", velocity_band)?;
                if stiction < coulomb {
                    return Err(SimError::InvalidParameter {
                        what: "stiction level V_s".into(),
                        value: stiction,
                        requirement: "must be at least the Coulomb level V_c",
                    });
                }
                Ok(())
            }
        }
    }
}

fn check_index(what: &str, index: usize, len: usize) -> Result<()> {
    if index >= len {
        return Err(SimError::InvalidArgument(format!(
            "{what} {index} is out of range (there are {len})"
        )));
    }
    Ok(())
}

/// The actuator chain (see the module documentation). [`Actuator::ideal`] passes the command
/// through unchanged.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Actuator {
    saturation: Option<(f64, f64)>,
    dac: Option<Quantizer>,
    disturbance: Option<(Vec<Signal>, DisturbancePoint)>,
    friction: Option<Friction>,
}

impl Actuator {
    /// The ideal actuator: plant input = command.
    pub fn ideal() -> Self {
        Self::default()
    }

    /// The book rig's amplifier and converter: saturation `±limit` (V) and a `bits`-bit D/A
    /// over the same range (`q = 2·limit/2^bits`). The cart rig: `rig(5.0, 16)`.
    ///
    /// # Errors
    /// As [`Actuator::saturation`] and [`Quantizer::from_bits`].
    pub fn rig(limit: f64, bits: u32) -> Result<Self> {
        Self::ideal()
            .saturation(limit)?
            .dac(Quantizer::from_bits(bits, 2.0 * limit)?)
    }

    /// Symmetric saturation `|v| ≤ limit` of every input.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] unless `limit > 0`.
    pub fn saturation(self, limit: f64) -> Result<Self> {
        check_positive("saturation limit", limit)?;
        self.saturation_range(-limit, limit)
    }

    /// Saturation of every input to `[lo, hi]`.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] unless `lo < hi`, both finite.
    pub fn saturation_range(mut self, lo: f64, hi: f64) -> Result<Self> {
        crate::error::check_finite("saturation lower limit", lo)?;
        crate::error::check_finite("saturation upper limit", hi)?;
        if lo >= hi {
            return Err(SimError::InvalidParameter {
                what: "saturation lower limit".into(),
                value: lo,
                requirement: "must be below the upper limit",
            });
        }
        self.saturation = Some((lo, hi));
        Ok(self)
    }

    /// D/A quantisation of every input with `q` (round to nearest).
    ///
    /// # Errors
    /// None beyond the quantiser's own validation; returns `Result` for uniform chaining.
    pub fn dac(mut self, q: Quantizer) -> Result<Self> {
        self.dac = Some(q);
        Ok(self)
    }

    /// Input disturbances `d(t)` (one signal per plant input), sampled at `t_k` and entering
    /// at `point`.
    pub fn disturbance(mut self, d: Vec<Signal>, point: DisturbancePoint) -> Self {
        self.disturbance = Some((d, point));
        self
    }

    /// Friction on the drive.
    pub fn friction(mut self, friction: Friction) -> Self {
        self.friction = Some(friction);
        self
    }

    /// The configured friction, if any.
    pub fn friction_model(&self) -> Option<Friction> {
        self.friction
    }

    /// Checks the chain against a plant with `nx` states and `nu` inputs.
    ///
    /// # Errors
    /// [`SimError::DimensionMismatch`] for a disturbance list of the wrong width; friction
    /// parameter and index errors.
    pub fn validate(&self, nx: usize, nu: usize) -> Result<()> {
        if let Some((d, _)) = &self.disturbance {
            check_len(
                "input disturbances (one signal per plant input)",
                d.len(),
                nu,
            )?;
        }
        if let Some(f) = &self.friction {
            f.validate(nx, nu)?;
        }
        Ok(())
    }

    /// `true` if the chain changes nothing at the sample (no saturation, converter,
    /// disturbance or dead zone).
    pub(crate) fn is_transparent(&self) -> bool {
        self.saturation.is_none()
            && self.dac.is_none()
            && self.disturbance.is_none()
            && !matches!(self.friction, Some(Friction::DeadZone { .. }))
    }

    /// `Some(saturation)` if the chain is at most a saturation `[lo, hi]` (no D/A,
    /// disturbance or friction), `None` otherwise.
    pub(crate) fn saturation_only(&self) -> Option<Option<(f64, f64)>> {
        (self.dac.is_none() && self.disturbance.is_none() && self.friction.is_none())
            .then_some(self.saturation)
    }

    /// The plant input for command `u` at sample time `t`; returns whether any entry was
    /// clipped by the saturation.
    #[inline]
    pub fn apply(&self, t: f64, u: &[f64], out: &mut [f64]) -> bool {
        let mut clipped = false;
        for (i, (o, &ui)) in out.iter_mut().zip(u).enumerate() {
            let mut v = ui;
            let d = match &self.disturbance {
                Some((sigs, point)) => (sigs[i].value(t), *point),
                None => (0.0, DisturbancePoint::AfterSaturation),
            };
            if d.1 == DisturbancePoint::BeforeSaturation {
                v += d.0;
            }
            if let Some((lo, hi)) = self.saturation {
                if v > hi {
                    v = hi;
                    clipped = true;
                } else if v < lo {
                    v = lo;
                    clipped = true;
                }
            }
            if let Some(q) = &self.dac {
                v = q.apply(v);
            }
            if d.1 == DisturbancePoint::AfterSaturation {
                v += d.0;
            }
            if let Some(Friction::DeadZone { input, width }) = self.friction
                && input == i
            {
                v = dead_zone(v, width);
            }
            *o = v;
        }
        clipped
    }
}

/// The dead zone `v ↦ 0` for `|v| ≤ w`, `v − w·sign(v)` otherwise.
#[inline]
pub fn dead_zone(v: f64, w: f64) -> f64 {
    if v > w {
        v - w
    } else if v < -w {
        v + w
    } else {
        0.0
    }
}

/// The Karnopp friction law in voltage-equivalent form (see the module documentation):
/// the effective drive input for command `v` at drive velocity `s`.
#[inline]
pub fn karnopp(v: f64, s: f64, coulomb: f64, stiction: f64, band: f64) -> f64 {
    if s > band {
        v - coulomb
    } else if s < -band {
        v + coulomb
    } else if v.abs() <= stiction {
        0.0
    } else {
        v - coulomb * v.signum()
    }
}

/// A plant with Karnopp Coulomb friction and stiction on one drive input
/// ([`Friction::Coulomb`]), as [`Dynamics`].
#[derive(Debug, Clone)]
pub struct WithDriveFriction<P> {
    plant: P,
    input: usize,
    velocity_state: usize,
    coulomb: f64,
    stiction: f64,
    band: f64,
}

impl<P: Dynamics> WithDriveFriction<P> {
    /// Wraps `plant` with `friction` (must be [`Friction::Coulomb`]).
    ///
    /// # Errors
    /// [`SimError::InvalidArgument`] for a [`Friction::DeadZone`] (a static input map, applied
    /// by the [`Actuator`]); parameter and index errors as [`Actuator::validate`];
    /// [`SimError::DimensionMismatch`] for a plant with more than
    /// [`crate::systems::MAX_INPUTS`] inputs.
    pub fn new(plant: P, friction: Friction) -> Result<Self> {
        friction.validate(plant.nx(), plant.nu())?;
        if plant.nu() > crate::systems::MAX_INPUTS {
            return Err(SimError::DimensionMismatch {
                what: "plant inputs of a friction wrapper (at most MAX_INPUTS)".into(),
                expected: crate::systems::MAX_INPUTS,
                found: plant.nu(),
            });
        }
        match friction {
            Friction::Coulomb {
                input,
                velocity_state,
                coulomb,
                stiction,
                velocity_band,
            } => Ok(Self {
                plant,
                input,
                velocity_state,
                coulomb,
                stiction,
                band: velocity_band,
            }),
            Friction::DeadZone { .. } => Err(SimError::InvalidArgument(
                "a dead zone is a static input map: configure it on the Actuator".into(),
            )),
        }
    }

    fn effective(&self, x: &[f64], u: &[f64], buf: &mut [f64; crate::systems::MAX_INPUTS]) {
        buf[..u.len()].copy_from_slice(u);
        buf[self.input] = karnopp(
            u[self.input],
            x[self.velocity_state],
            self.coulomb,
            self.stiction,
            self.band,
        );
    }
}

impl<P: Dynamics> Dynamics for WithDriveFriction<P> {
    fn nx(&self) -> usize {
        self.plant.nx()
    }
    fn nu(&self) -> usize {
        self.plant.nu()
    }
    #[inline]
    fn derivative(&self, t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        let mut buf = [0.0; crate::systems::MAX_INPUTS];
        self.effective(x, u, &mut buf);
        self.plant.derivative(t, x, &buf[..u.len()], dx)
    }
    fn ny(&self) -> usize {
        self.plant.ny()
    }
    fn output(&self, t: f64, x: &[f64], u: &[f64], y: &mut [f64]) {
        let mut buf = [0.0; crate::systems::MAX_INPUTS];
        self.effective(x, u, &mut buf);
        self.plant.output(t, x, &buf[..u.len()], y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pipeline_order_and_counts() {
        let act = Actuator::rig(5.0, 16).unwrap();
        let mut out = [0.0];
        assert!(act.apply(0.0, &[7.0], &mut out));
        assert_eq!(out[0], 5.0);
        assert!(!act.apply(0.0, &[1.0e-4], &mut out));
        let q = 10.0 / 65536.0;
        assert_eq!(out[0], q * (1.0e-4f64 / q).round());
        // Disturbance after saturation is neither clipped nor quantised.
        let d = Signal::step(1.0, 0.3).unwrap();
        let a2 = Actuator::rig(5.0, 16)
            .unwrap()
            .disturbance(vec![d.clone()], DisturbancePoint::AfterSaturation);
        a2.apply(1.0, &[9.0], &mut out);
        assert_eq!(out[0], 5.3);
        let a3 = Actuator::ideal()
            .saturation(5.0)
            .unwrap()
            .disturbance(vec![d], DisturbancePoint::BeforeSaturation);
        a3.apply(1.0, &[4.9], &mut out);
        assert_eq!(out[0], 5.0);
        a3.apply(0.5, &[4.9], &mut out);
        assert_eq!(out[0], 4.9);
        assert!(Actuator::ideal().saturation(0.0).is_err());
        assert!(Actuator::ideal().saturation_range(1.0, -1.0).is_err());
        let dz = Actuator::ideal().friction(Friction::DeadZone {
            input: 0,
            width: 0.5,
        });
        dz.apply(0.0, &[0.4], &mut out);
        assert_eq!(out[0], 0.0);
        dz.apply(0.0, &[-2.0], &mut out);
        assert_eq!(out[0], -1.5);
        assert!(dz.validate(2, 1).is_ok());
        assert!(dz.validate(2, 0).is_err());
    }

    #[test]
    fn karnopp_regimes() {
        // Sliding: V_c opposes the motion.
        assert_eq!(karnopp(1.0, 0.1, 0.2, 0.3, 1e-4), 0.8);
        assert_eq!(karnopp(1.0, -0.1, 0.2, 0.3, 1e-4), 1.2);
        // Stuck below break-away.
        assert_eq!(karnopp(0.25, 0.0, 0.2, 0.3, 1e-4), 0.0);
        // Break-away above V_s.
        assert_eq!(karnopp(-0.5, 0.0, 0.2, 0.3, 1e-4), -0.3);
        let bad = Friction::Coulomb {
            input: 0,
            velocity_state: 1,
            coulomb: 0.3,
            stiction: 0.2,
            velocity_band: 1e-4,
        };
        assert!(bad.validate(2, 1).is_err());
    }
}
