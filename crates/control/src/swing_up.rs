//! Energy-based swing-up and the switch to a balancing controller (the book §3.2; K. J. Åström
//! and K. Furuta, "Swinging up a pendulum by energy control", *Automatica* 36(2), 287–295,
//! 2000).
//!
//! ## Energy and the drive as an acceleration source
//! Both rigs drive their first coordinate (cart position `z`, arm angle `θ₁`) through a
//! velocity-loop motor `q̈ = −a q̇ + b v`, so a commanded acceleration `q̈*` is realised by
//! `v = (a q̇ + q̈*)/b` (exactly, on the model). The pendulum's energy
//! - cart: `E = ½Jθ̇² + m_p g l_p (1 + cos θ)`, with `Ė = −m_p l_p θ̇ cos θ · z̈ − μ_p θ̇²`;
//! - arm: `E₂ = ½α₂θ̇₂² + α₅(1 + cos θ₂)`, with
//!   `Ė₂ = −α₃ θ̇₂ cos(θ₁ − θ₂) θ̈₁ + α₃ θ̇₁² θ̇₂ sin(θ₁ − θ₂) − μ₂ θ̇₂ (θ̇₂ − θ̇₁)`,
//!
//! is 0 hanging at rest and `E_up = 2mgl` (`2α₅`) upright at rest.
//!
//! ## Laws
//! - [`EnergyPumping`] (the book, `p2c323_ex1_cdip_swing_up`): `z̈* = −K₁ θ̇ cos θ`, which
//!   gives `Ė = m_p l_p K₁ (θ̇ cos θ)² − μ_p θ̇² ≥ 0` away from friction: energy grows
//!   monotonically until the switch.
//! - [`CartEnergyShaping`] and [`ArmEnergyShaping`] (Åström–Furuta): the commanded acceleration
//!   `sat_{a_max}(k_E (E − E_ref) sign(θ̇ cos θ))` (arm: `θ̇₂ cos(θ₁ − θ₂)`) drives `E` to the
//!   target `E_ref` and stops pumping there, plus a PD term `−k_p (q − q_ref) − k_d q̇` that
//!   keeps the cart (arm) near its reference; beyond the travel limit `|q − q_ref| ≥ q_lim` the
//!   energy term is switched off so only the centring acts.
//! - [`swing_up_then_balance`]: runs the swing-up law until every watched angle, wrapped to
//!   `(−π, π]`, is inside its window (the book: `|θ| ≤ π/4`), then hands over — for good — to
//!   the balancing controller with those angles wrapped ([`WrapAngles`]); the switch time is
//!   recorded.

use crate::error::{Result, check_param};
use pendulab_plants::{ArmPendulum, CartPendulum};
use pendulab_sim::Controller;
use pendulab_sim::controllers::Switching;
use std::f64::consts::PI;

/// `θ` wrapped to `(−π, π]`: the workspace's one wrapping, [`pendulab_plants::wrap_angle`]
/// (re-exported here for the swing-up laws' users).
pub use pendulab_plants::wrap_angle;

#[inline]
fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The book's energy pumping for the cart pendulum: `u = (a_c ż − K₁ θ̇ cos θ)/b_c`, i.e. the
/// commanded cart acceleration `z̈* = −K₁ θ̇ cos θ`. Measurement `[z, θ, ż, θ̇]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyPumping {
    k1: f64,
    a_c: f64,
    b_c: f64,
}

impl EnergyPumping {
    /// The law with gain `K₁ > 0` (m/rad·s… the book: 0.8) on the plant's drive.
    ///
    /// # Errors
    /// [`crate::ControlError::InvalidParameter`] for `K₁ ≤ 0`.
    pub fn new(plant: &CartPendulum, k1: f64) -> Result<Self> {
        check_param("pumping gain K1", k1, k1 > 0.0, "must be > 0")?;
        Ok(Self {
            k1,
            a_c: plant.params().a_c,
            b_c: plant.params().b_c,
        })
    }

    /// The voltage for a state `[z, θ, ż, θ̇]`.
    #[inline]
    pub fn control(&self, x: &[f64]) -> f64 {
        (self.a_c * x[2] - self.k1 * x[3] * x[1].cos()) / self.b_c
    }
}

impl Controller for EnergyPumping {
    fn ny(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    fn reset(&mut self) {}
    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        u[0] = self.control(y);
    }
}

/// Gains and limits of an energy-shaping swing-up (Åström–Furuta with a centring term).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyShapingGains {
    /// Energy gain `k_E` (acceleration per joule: m/(s² J) for the cart, rad/(s² J) for the
    /// arm), > 0.
    pub k_energy: f64,
    /// Acceleration limit `a_max` of the energy term (m/s² or rad/s²), > 0.
    pub max_acceleration: f64,
    /// Target energy as a multiple of the upright energy (1 = exactly upright at rest; a
    /// little more makes the pendulum arrive with some speed), > 0.
    pub energy_ratio: f64,
    /// Centring stiffness `k_p` (1/s²), ≥ 0.
    pub k_position: f64,
    /// Centring damping `k_d` (1/s), ≥ 0.
    pub k_velocity: f64,
    /// Reference of the driven coordinate `q_ref` (m or rad).
    pub reference: f64,
    /// Travel limit `q_lim` (m or rad) around the reference beyond which only the centring
    /// acts, > 0.
    pub travel_limit: f64,
    /// Voltage limit applied to the command (V), > 0.
    pub max_voltage: f64,
}

impl EnergyShapingGains {
    /// Gains tuned for the book's cart rig (not from the book): `k_E = 20 m/(s² J)`,
    /// `a_max = 5 m/s²` (a quarter of what ±5 V give at rest, `b_c·5 ≈ 22 m/s²`), target
    /// `1.05 E_up` (the pendulum reaches the upright with some speed instead of creeping up
    /// the separatrix), centring `k_p = 4 1/s²`, `k_d = 4 1/s` about `z = 0`, pumping off
    /// beyond `|z| = 0.3 m`, commands clipped to ±5 V. With the switch to LQR at `|θ| ≤ 0.3`
    /// they swing the book's pendulum up from hanging in about 3–5 s with `|z| < 0.35 m`, on the
    /// plain model and on the quantised rig.
    pub fn cart_rig() -> Self {
        Self {
            k_energy: 20.0,
            max_acceleration: 5.0,
            energy_ratio: 1.05,
            k_position: 4.0,
            k_velocity: 4.0,
            reference: 0.0,
            travel_limit: 0.3,
            max_voltage: 5.0,
        }
    }

    /// Gains tuned for the book's arm rig (not from the book): `k_E = 100 rad/(s² J)`,
    /// `a_max = 30 rad/s²`, target `1.02 E_up`, centring `k_p = 10 1/s²`, `k_d = 5 1/s` about
    /// the upright arm `θ₁ = 0`, pumping off beyond `|θ₁| = 1.5 rad`, ±5 V. With the switch to
    /// LQR at `|θ₂| ≤ 0.3` they swing the pendulum up from hanging (arm up or down) in about
    /// 2–3 s, on the plain model and on the quantised rig; a larger target (1.05) makes the
    /// pendulum arrive too fast for that LQR on the quantised rig.
    pub fn arm_rig() -> Self {
        Self {
            k_energy: 100.0,
            max_acceleration: 30.0,
            energy_ratio: 1.02,
            k_position: 10.0,
            k_velocity: 5.0,
            reference: 0.0,
            travel_limit: 1.5,
            max_voltage: 5.0,
        }
    }

    fn validate(&self) -> Result<()> {
        check_param("k_E", self.k_energy, self.k_energy > 0.0, "must be > 0")?;
        check_param(
            "a_max",
            self.max_acceleration,
            self.max_acceleration > 0.0,
            "must be > 0",
        )?;
        check_param(
            "energy ratio",
            self.energy_ratio,
            self.energy_ratio > 0.0,
            "must be > 0",
        )?;
        check_param(
            "k_p",
            self.k_position,
            self.k_position >= 0.0,
            "must be ≥ 0",
        )?;
        check_param(
            "k_d",
            self.k_velocity,
            self.k_velocity >= 0.0,
            "must be ≥ 0",
        )?;
        check_param("q_ref", self.reference, true, "must be finite")?;
        check_param(
            "travel limit",
            self.travel_limit,
            self.travel_limit > 0.0,
            "must be > 0",
        )?;
        check_param(
            "voltage limit",
            self.max_voltage,
            self.max_voltage > 0.0,
            "must be > 0",
        )
    }

    /// The commanded acceleration for energy error `e = E − E_ref`, pumping direction
    /// `s` (`θ̇ cos θ` or `θ̇₂ cos(θ₁ − θ₂)`), offset `q − q_ref` and rate `q̇`.
    #[inline]
    fn acceleration(&self, e: f64, s: f64, offset: f64, rate: f64) -> f64 {
        let pump = if offset.abs() < self.travel_limit {
            (self.k_energy * e * sign(s)).clamp(-self.max_acceleration, self.max_acceleration)
        } else {
            0.0
        };
        pump - self.k_position * offset - self.k_velocity * rate
    }
}

/// Energy-shaping swing-up of the cart pendulum: `z̈* = sat(k_E (E − E_ref) sign(θ̇ cos θ)) −
/// k_p (z − z_ref) − k_d ż`, `u = clip((a_c ż + z̈*)/b_c, ±u_max)`. Measurement `[z, θ, ż, θ̇]`.
#[derive(Debug, Clone, PartialEq)]
pub struct CartEnergyShaping {
    gains: EnergyShapingGains,
    a_c: f64,
    b_c: f64,
    inertia: f64,
    mgl: f64,
    target: f64,
}

impl CartEnergyShaping {
    /// The law on `plant` with `gains`.
    ///
    /// # Errors
    /// [`crate::ControlError::InvalidParameter`] naming the offending gain.
    pub fn new(plant: &CartPendulum, gains: EnergyShapingGains) -> Result<Self> {
        gains.validate()?;
        let p = plant.params();
        let mgl = p.m_p * p.g * p.l_p;
        Ok(Self {
            gains,
            a_c: p.a_c,
            b_c: p.b_c,
            inertia: plant.inertia_about_pivot(),
            mgl,
            target: gains.energy_ratio * plant.upright_energy(),
        })
    }

    /// The energy `E(θ, θ̇)` this law regulates (J).
    #[inline]
    pub fn energy(&self, theta: f64, dtheta: f64) -> f64 {
        0.5 * self.inertia * dtheta * dtheta + self.mgl * (1.0 + theta.cos())
    }

    /// The energy target `E_ref` (J).
    pub fn target_energy(&self) -> f64 {
        self.target
    }

    /// The voltage for a state `[z, θ, ż, θ̇]`.
    #[inline]
    pub fn control(&self, x: &[f64]) -> f64 {
        let e = self.energy(x[1], x[3]) - self.target;
        let a = self
            .gains
            .acceleration(e, x[3] * x[1].cos(), x[0] - self.gains.reference, x[2]);
        ((self.a_c * x[2] + a) / self.b_c).clamp(-self.gains.max_voltage, self.gains.max_voltage)
    }
}

impl Controller for CartEnergyShaping {
    fn ny(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    fn reset(&mut self) {}
    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        u[0] = self.control(y);
    }
}

/// Energy-shaping swing-up of the arm pendulum: `θ̈₁* = sat(k_E (E₂ − E_ref)
/// sign(θ̇₂ cos(θ₁ − θ₂))) − k_p wrap(θ₁ − θ₁_ref) − k_d θ̇₁`,
/// `u = clip((a₁ θ̇₁ + θ̈₁*)/b₁, ±u_max)`. Measurement `[θ₁, θ₂, θ̇₁, θ̇₂]`.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmEnergyShaping {
    gains: EnergyShapingGains,
    a1: f64,
    b1: f64,
    alpha2: f64,
    alpha5: f64,
    target: f64,
}

impl ArmEnergyShaping {
    /// The law on `plant` with `gains` (reference and travel limit in radians).
    ///
    /// # Errors
    /// [`crate::ControlError::InvalidParameter`] naming the offending gain.
    pub fn new(plant: &ArmPendulum, gains: EnergyShapingGains) -> Result<Self> {
        gains.validate()?;
        let p = plant.params();
        Ok(Self {
            gains,
            a1: p.a1,
            b1: p.b1,
            alpha2: plant.alpha2(),
            alpha5: plant.alpha5(),
            target: gains.energy_ratio * plant.upright_energy(),
        })
    }

    /// The pendulum energy `E₂(θ₂, θ̇₂)` this law regulates (J).
    #[inline]
    pub fn energy(&self, theta2: f64, dtheta2: f64) -> f64 {
        0.5 * self.alpha2 * dtheta2 * dtheta2 + self.alpha5 * (1.0 + theta2.cos())
    }

    /// The energy target `E_ref` (J).
    pub fn target_energy(&self) -> f64 {
        self.target
    }

    /// The voltage for a state `[θ₁, θ₂, θ̇₁, θ̇₂]`.
    #[inline]
    pub fn control(&self, x: &[f64]) -> f64 {
        let e = self.energy(x[1], x[3]) - self.target;
        let offset = wrap_angle(x[0] - self.gains.reference);
        let a = self
            .gains
            .acceleration(e, x[3] * (x[0] - x[1]).cos(), offset, x[2]);
        ((self.a1 * x[2] + a) / self.b1).clamp(-self.gains.max_voltage, self.gains.max_voltage)
    }
}

impl Controller for ArmEnergyShaping {
    fn ny(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    fn reset(&mut self) {}
    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        u[0] = self.control(y);
    }
}

/// A controller fed its measurement with some entries wrapped to `(−π, π]` (angles that a
/// linear balancing law expects near the upright, after a swing-up has wound them up).
#[derive(Debug, Clone)]
pub struct WrapAngles<C> {
    inner: C,
    indices: Vec<usize>,
    buffer: Vec<f64>,
}

impl<C: Controller> WrapAngles<C> {
    /// Wraps entries `indices` of the measurement before `inner` sees it.
    ///
    /// # Errors
    /// [`crate::ControlError::InvalidParameter`] for an index `≥ inner.ny()`.
    pub fn new(inner: C, indices: Vec<usize>) -> Result<Self> {
        for &i in &indices {
            check_param(
                &format!("wrapped measurement index {i}"),
                i as f64,
                i < inner.ny(),
                &format!("must be < {}", inner.ny()),
            )?;
        }
        let ny = inner.ny();
        Ok(Self {
            inner,
            indices,
            buffer: vec![0.0; ny],
        })
    }

    /// The wrapped controller.
    pub fn inner(&self) -> &C {
        &self.inner
    }
}

impl<C: Controller> Controller for WrapAngles<C> {
    fn ny(&self) -> usize {
        self.inner.ny()
    }

    fn nu(&self) -> usize {
        self.inner.nu()
    }

    fn reset(&mut self) {
        self.inner.reset();
    }

    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        self.buffer.copy_from_slice(y);
        for &i in &self.indices {
            self.buffer[i] = wrap_angle(y[i]);
        }
        self.inner.update(t, &self.buffer, u);
    }

    fn sample_time(&self) -> Option<f64> {
        self.inner.sample_time()
    }

    fn switch_times(&self) -> &[f64] {
        self.inner.switch_times()
    }

    fn retune(&mut self, gain: &[f64]) -> pendulab_sim::Result<bool> {
        self.inner.retune(gain)
    }
}

/// The swing-up → balance switch of the book: `swing_up` runs until every watched angle
/// `y_i`, wrapped to `(−π, π]`, satisfies `|wrap(y_i)| ≤ w_i` (the book: `[(1, π/4)]` on
/// `[z, θ, ż, θ̇]`); then `balance`, fed the measurement with the watched angles wrapped, runs
/// for the rest of the run (latched; it is reset at the switch). Built on `pendulab-sim`'s
/// [`Switching`], which records the switch time ([`Controller::switch_times`], copied into the
/// sampled loop's diagnostics).
///
/// # Errors
/// [`crate::ControlError::InvalidParameter`] for no window, an index out of range or a half-width
/// not in `(0, π]`; [`Switching::new`]'s errors (different measurement or command sizes).
pub fn swing_up_then_balance<S, B>(
    swing_up: S,
    balance: B,
    windows: Vec<(usize, f64)>,
) -> Result<Switching<S, WrapAngles<B>>>
where
    S: Controller,
    B: Controller,
{
    check_param(
        "number of switching windows",
        windows.len() as f64,
        !windows.is_empty(),
        "must be ≥ 1",
    )?;
    for &(i, w) in &windows {
        check_param(
            &format!("switching window index {i}"),
            i as f64,
            i < swing_up.ny(),
            &format!("must be < {}", swing_up.ny()),
        )?;
        check_param(
            &format!("switching window half-width for index {i}"),
            w,
            w > 0.0 && w <= PI,
            "must be in (0, π]",
        )?;
    }
    let indices: Vec<usize> = windows.iter().map(|&(i, _)| i).collect();
    let balance = WrapAngles::new(balance, indices)?;
    Ok(Switching::new(swing_up, balance, move |_t, y: &[f64]| {
        windows.iter().all(|&(i, w)| wrap_angle(y[i]).abs() <= w)
    })?)
}
