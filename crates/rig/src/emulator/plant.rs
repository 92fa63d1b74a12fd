//! The emulated rig's physics: the plant between the D/A converter and the encoders.
//!
//! One model of the rig's imperfections serves the simulator and the emulator: a
//! [`RigPlant`] is built from the rig's numbers (`pendulab_plants::RigSpec`, `docs/model.md`
//! §3) into sim's chains ([`pendulab_sim::rig::RigChains`]) and steps the nonlinear plant
//! with sim's integrator:
//!
//! ```text
//! command v ─ Actuator: saturation ±voltage_limit, D/A (RigSpec::dac, 16 bits over ±5 V)
//!   ─▶ the held input ─ CartPendulum / ArmPendulum (+ Karnopp friction, WithDriveFriction),
//!      one classical RK4 step of ts (pendulab_sim::rk4_step)
//!   ─▶ x ─ SensorChain: the two encoders (RigSpec::encoders), seeded Gaussian noise
//!      ─▶ counts (encoder 1 from the hanging rest, shifted by whole turns on request)
//! ```
//!
//! The velocity estimates of the rig's `RigChains::with_quantizer` are left out here: on a
//! real rig the encoders are read by the microcontroller and the pseudo-differentiator runs
//! on the controller's PC (`crate::runtime`), so the emulator puts only counts on the wire.

use crate::RigError;
use crate::emulator::{EmulatorConfig, PlantKind};
use pendulab_plants::rig::DriveFriction;
use pendulab_plants::spec::PlantParameters;
use pendulab_plants::{ArmPendulum, CartPendulum};
use pendulab_sim::rig::RigChains;
use pendulab_sim::{Actuator, Friction, Quantizer, SensorChain, WithDriveFriction, rk4_step};
use std::f64::consts::PI;

/// The velocity band `ε` of the emulator's Karnopp friction \[m/s or rad/s\]: inside it the
/// drive counts as stopped (`pendulab_sim::actuator` module documentation).
pub const FRICTION_VELOCITY_BAND: f64 = 1e-4;

/// The plant of either rig, with or without drive friction (friction is evaluated at every
/// RK4 stage); one variant per concrete type, so the step dispatches once, not per stage.
#[derive(Debug, Clone)]
enum Model {
    Cart(CartPendulum),
    Arm(ArmPendulum),
    CartFriction(WithDriveFriction<CartPendulum>),
    ArmFriction(WithDriveFriction<ArmPendulum>),
}

/// The emulated rig between the D/A converter and the encoders (module documentation):
/// sim's actuator chain, the nonlinear plant stepped by sim's RK4, sim's sensor chain.
///
/// ```
/// use pendulab_rig::emulator::{EmulatorConfig, PlantKind, RigPlant};
/// # fn main() -> Result<(), pendulab_rig::RigError> {
/// // The cart rig upright at rest: the pendulum encoder counts half a turn from hanging.
/// let mut rig = RigPlant::new(&EmulatorConfig::new(PlantKind::Cart, [0.0; 4]))?;
/// assert_eq!(rig.counts(0), [0, -7200]);
/// // 7 V saturates at 5 V, which the 16-bit D/A represents exactly.
/// assert_eq!(rig.amplify(7.0), (5.0, true));
/// # Ok(()) }
/// ```
#[derive(Debug, Clone)]
pub struct RigPlant {
    model: Model,
    chains: RigChains,
    /// The encoders' quantisers, the chain's own (`None` with noise: then the chain
    /// measures, noise and all; without noise the chain is exactly these quantisers, applied
    /// directly, which costs a sixth of a step less).
    exact: Option<[Quantizer; 2]>,
    /// `1/step` of each encoder: a reading `k·step` back to its count `k` (exact: the
    /// product is within an ulp of the integer `k`, far below the rounding's ½).
    inv_steps: [f64; 2],
    /// The encoders' zeros (`EncoderSpec::zero_offset`: the coordinate at count 0; the
    /// pendulum's is the hanging rest π on the book rigs).
    zeros: [f64; 2],
    ts: f64,
    x: [f64; 4],
    y: [f64; 2],
}

impl RigPlant {
    /// The rig of `cfg`: `cfg.plant` with the parameters `cfg.parameters` at
    /// `cfg.initial_state`, the encoders of `cfg.rig` (`RigSpec::encoders`, noise
    /// `cfg.encoder_noise_counts` counts, seeded by `cfg.seed`), saturation at
    /// `±cfg.voltage_limit` \[V\], the D/A of `cfg.rig.dac` if `cfg.dac`, and on the drive
    /// Karnopp friction of `cfg.friction_volts` \[V\] (Coulomb = stiction, band
    /// [`FRICTION_VELOCITY_BAND`]) if positive, else the friction of `cfg.rig.friction` if
    /// any; stepped by `cfg.ts` \[s\].
    ///
    /// # Errors
    /// [`RigError::Chain`] if sim refuses a number of the chains (a non-positive voltage
    /// limit, a negative noise or friction level: [`EmulatorConfig::validate`] catches them
    /// first, naming the setting) or the plant's parameters (invalid, or of the other plant).
    pub fn new(cfg: &EmulatorConfig) -> Result<Self, RigError> {
        let spec = cfg.rig;
        let steps = [spec.encoders[0].step, spec.encoders[1].step];
        let chain = |e| RigError::chain("the emulator's rig chains", e);
        let encoders = spec.encoders.map(|e| (e.state, e.step));
        let mut sensor = SensorChain::encoders(&encoders).map_err(chain)?;
        if cfg.encoder_noise_counts > 0.0 {
            let std = steps.map(|s| cfg.encoder_noise_counts * s);
            sensor = sensor.noise(&std, cfg.seed).map_err(chain)?;
        }
        let mut actuator = Actuator::ideal()
            .saturation(cfg.voltage_limit)
            .map_err(chain)?;
        if cfg.dac {
            let dac =
                Quantizer::from_bits(spec.dac.bits, spec.dac.max - spec.dac.min).map_err(chain)?;
            actuator = actuator.dac(dac).map_err(chain)?;
        }
        let exact = if cfg.encoder_noise_counts > 0.0 {
            None
        } else {
            Some([Quantizer::new(steps[0]), Quantizer::new(steps[1])])
                .map(|[a, b]| a.and_then(|a| b.map(|b| [a, b])))
                .transpose()
                .map_err(chain)?
        };
        let mut chains = RigChains { sensor, actuator };
        chains.sensor.prepare(4, cfg.ts).map_err(chain)?;
        let friction = if cfg.friction_volts > 0.0 {
            Some(Friction::Coulomb {
                input: 0,
                velocity_state: 2,
                coulomb: cfg.friction_volts,
                stiction: cfg.friction_volts,
                velocity_band: FRICTION_VELOCITY_BAND,
            })
        } else {
            spec.friction.map(|f| match f {
                DriveFriction::DeadZone { width } => Friction::DeadZone { input: 0, width },
                DriveFriction::Coulomb {
                    coulomb,
                    stiction,
                    velocity_band,
                } => Friction::Coulomb {
                    input: 0,
                    velocity_state: 2,
                    coulomb,
                    stiction,
                    velocity_band,
                },
            })
        };
        // A dead zone is a static map of the command (the actuator's); Karnopp friction acts
        // on the drive's velocity inside the plant.
        let friction = match friction {
            Some(f @ Friction::DeadZone { .. }) => {
                chains.actuator = chains.actuator.clone().friction(f);
                None
            }
            other => other,
        };
        let wrong = || {
            RigError::chain(
                "the emulator's plant",
                pendulab_sim::SimError::InvalidArgument(format!(
                    "parameters of the {} pendulum for the {} rig",
                    cfg.parameters.kind().name(),
                    cfg.plant.name()
                )),
            )
        };
        let invalid = |e: pendulab_plants::PlantError| {
            RigError::chain(
                "the emulator's plant",
                pendulab_sim::SimError::InvalidArgument(e.to_string()),
            )
        };
        let model = match (cfg.plant, cfg.parameters) {
            (PlantKind::Cart, PlantParameters::Cart(p)) => {
                let p = CartPendulum::new(p).map_err(invalid)?;
                match friction {
                    Some(f) => Model::CartFriction(WithDriveFriction::new(p, f).map_err(chain)?),
                    None => Model::Cart(p),
                }
            }
            (PlantKind::Arm, PlantParameters::Arm(p)) => {
                let p = ArmPendulum::new(p).map_err(invalid)?;
                match friction {
                    Some(f) => Model::ArmFriction(WithDriveFriction::new(p, f).map_err(chain)?),
                    None => Model::Arm(p),
                }
            }
            _ => return Err(wrong()),
        };
        Ok(Self {
            model,
            chains,
            exact,
            inv_steps: steps.map(|s| 1.0 / s),
            zeros: spec.encoders.map(|e| e.zero_offset),
            ts: cfg.ts,
            x: cfg.initial_state,
            y: [0.0; 2],
        })
    }

    /// The true state (upright-zero angles, SI units).
    pub fn state(&self) -> [f64; 4] {
        self.x
    }

    /// Puts the plant at `x` (the encoders keep their noise sequence).
    pub fn set_state(&mut self, x: [f64; 4]) {
        self.x = x;
    }

    /// The amplifier: the voltage the plant receives for command `v` \[V\] (saturated, then
    /// quantised by the D/A) and whether the saturation clipped it.
    #[inline]
    pub fn amplify(&self, v: f64) -> (f64, bool) {
        let mut out = [0.0];
        let clipped = self.chains.actuator.apply(0.0, &[v], &mut out);
        (out[0], clipped)
    }

    /// One period `ts` of the plant with the amplified voltage `v` \[V\] held (one classical
    /// RK4 step, friction evaluated at every stage).
    #[inline]
    pub fn step(&mut self, v: f64) {
        let (x, u, h) = (&mut self.x, &[v], self.ts);
        match &self.model {
            Model::Cart(p) => rk4_step(p, 0.0, x, u, h),
            Model::Arm(p) => rk4_step(p, 0.0, x, u, h),
            Model::CartFriction(p) => rk4_step(p, 0.0, x, u, h),
            Model::ArmFriction(p) => rk4_step(p, 0.0, x, u, h),
        }
    }

    /// The encoders' counts of the current state, each from its `EncoderSpec::zero_offset`:
    /// encoder 0 counts the drive from its zero, encoder 1 the pendulum from the hanging rest
    /// (`θ − π` on the book rigs), shifted by `turns` whole turns
    /// (`EmulatorHandle::shift_pendulum_encoder`); noise (if any) is added before the
    /// encoder's rounding. Counts beyond `i32` saturate.
    #[inline(always)]
    pub fn counts(&mut self, turns: i32) -> [i32; 2] {
        let zero = self.zeros[1] - 2.0 * PI * f64::from(turns);
        let x = [
            self.x[0] - self.zeros[0],
            self.x[1] - zero,
            self.x[2],
            self.x[3],
        ];
        match &self.exact {
            Some(q) => self.y = [q[0].apply(x[0]), q[1].apply(x[1])],
            None => self.chains.sensor.measure(&x, &mut self.y),
        }
        // A reading is `k·step`, so `y/step` is within a few ulps of the integer `k`: adding
        // ½ away from zero and truncating (`as`) gives `k` without a second rounding call.
        // `as` saturates at the ends of i32 (and maps NaN to 0).
        [0, 1].map(|j| {
            let k = self.y[j] * self.inv_steps[j];
            (k + 0.5f64.copysign(k)) as i32
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cart(x0: [f64; 4]) -> EmulatorConfig {
        EmulatorConfig::new(PlantKind::Cart, x0)
    }

    #[test]
    fn hanging_cart_pendulum_swings_at_its_closed_form_frequency() {
        // The cart held (v = 0, at rest) and a small swing about the hanging rest: the period
        // approaches 2π/ω with ω² = m_p g l_p / (J_p + m_p l_p²) (+ damping, negligible over
        // one period for the book's μ_p): check the RK4 loop against the linear closed form
        // to 1 %.
        let p = CartPendulum::book();
        let prm = p.params();
        let w2 = prm.m_p * prm.g * prm.l_p / p.inertia_about_pivot();
        let mut rig = RigPlant::new(&cart([0.0, PI + 0.01, 0.0, 0.0])).unwrap();
        let ts = 1e-3;
        // Find the first return to maximum via the sign changes of θ̇ (half periods).
        let mut crossings = Vec::new();
        let mut prev = rig.state()[3];
        for k in 0..5000 {
            rig.step(0.0);
            let x = rig.state();
            if prev < 0.0 && x[3] >= 0.0 {
                crossings.push(k as f64 * ts);
            }
            prev = x[3];
        }
        let period = crossings[1] - crossings[0];
        let expected = 2.0 * PI / w2.sqrt();
        assert!(
            (period - expected).abs() / expected < 0.01,
            "{period} vs {expected}"
        );
    }

    #[test]
    fn encoders_count_from_the_drive_zero_and_the_hanging_rest() {
        // Closed form: c = round((x − zero)/step), zero = (0, π − 2π·turns).
        let (sz, sth) = (4.8414e-5, 2.0 * PI / 14400.0);
        let x = [0.1234, 0.3, 0.0, 0.0];
        let mut rig = RigPlant::new(&cart(x)).unwrap();
        for turns in [0, 1, -2] {
            let zero = PI - 2.0 * PI * f64::from(turns);
            let want = [
                (x[0] / sz).round() as i32,
                ((x[1] - zero) / sth).round() as i32,
            ];
            assert_eq!(rig.counts(turns), want, "turns {turns}");
        }
        // A turn is 14400 counts of the pendulum encoder and none of the drive's.
        let (a, b) = (rig.counts(0), rig.counts(1));
        assert_eq!((b[0] - a[0], b[1] - a[1]), (0, 14_400));
        // The arm's drive encoder: 200 000 counts a turn.
        let mut arm =
            RigPlant::new(&EmulatorConfig::new(PlantKind::Arm, [PI, 0.0, 0.0, 0.0])).unwrap();
        assert_eq!(arm.counts(0), [100_000, -7200]);
    }

    #[test]
    fn encoder_noise_has_the_configured_deviation_in_counts() {
        // 20 000 readings of a still plant with σ = 2 counts: the sample deviation of the
        // counts is σ up to the sampling error (σ/√(2n) ≈ 0.01) and the rounding's variance
        // 1/12 (√(4 + 1/12) = 2.02); 0.1 holds both with room.
        let mut c = cart([0.0; 4]);
        c.encoder_noise_counts = 2.0;
        c.seed = 3;
        let mut rig = RigPlant::new(&c).unwrap();
        let n = 20_000;
        let v: Vec<f64> = (0..n).map(|_| f64::from(rig.counts(0)[1] + 7200)).collect();
        let mean = v.iter().sum::<f64>() / n as f64;
        let sd = (v.iter().map(|c| (c - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt();
        assert!(mean.abs() < 0.1, "{mean}");
        assert!((sd - 2.0).abs() < 0.1, "{sd}");
    }

    #[test]
    fn the_amplifier_saturates_then_quantises_over_the_dac_range() {
        // The D/A of RigSpec: 16 bits over ±5 V, q = 10/2¹⁶ V, independent of the clamp.
        let q = 10.0 / 65_536.0;
        let mut c = cart([0.0; 4]);
        c.voltage_limit = 2.0;
        let rig = RigPlant::new(&c).unwrap();
        // Clipped to ±2 V, then to the D/A's nearest level (2 V is 13107.2 steps).
        let level = |v: f64| q * (v / q).round();
        assert_eq!(rig.amplify(3.0), (level(2.0), true));
        assert_eq!(rig.amplify(-2.5), (level(-2.0), true));
        assert_eq!(level(2.0), 13_107.0 * q);
        let (v, clipped) = rig.amplify(1.0e-3);
        assert_eq!((v, clipped), (q * (1.0e-3f64 / q).round(), false));
        c.dac = false;
        assert_eq!(RigPlant::new(&c).unwrap().amplify(1.0e-3), (1.0e-3, false));
    }

    #[test]
    fn stiction_holds_the_cart_below_the_friction_level_and_not_above() {
        // Karnopp: at rest with |v| ≤ V_s the drive input is 0, so the cart (pendulum hanging
        // at rest) does not move; above it the cart accelerates with v − V_c.
        let mut c = cart([0.0, PI, 0.0, 0.0]);
        c.friction_volts = 0.5;
        let mut rig = RigPlant::new(&c).unwrap();
        for _ in 0..200 {
            rig.step(0.4);
        }
        assert_eq!(rig.state()[0], 0.0);
        for _ in 0..200 {
            rig.step(1.0);
        }
        // 0.2 s at (1 − 0.5) V against the frictionless cart at 0.5 V: the same motion (the
        // cart's own dynamics are linear in v).
        let mut free = RigPlant::new(&cart([0.0, PI, 0.0, 0.0])).unwrap();
        for _ in 0..200 {
            free.step(0.5);
        }
        assert!(rig.state()[0] > 0.0);
        assert!(
            (rig.state()[0] - free.state()[0]).abs() < 1e-3 * free.state()[0],
            "{:?} vs {:?}",
            rig.state(),
            free.state()
        );
    }
}
