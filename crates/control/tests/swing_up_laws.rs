//! The swing-up laws against the energy balance of the plant models: the energy rate computed
//! from the plants' own right-hand sides must have the sign (and, for the book's law, the
//! value) the derivation promises.

use pendulab_control::ControlError;
use pendulab_control::swing_up::{
    ArmEnergyShaping, CartEnergyShaping, EnergyPumping, EnergyShapingGains, swing_up_then_balance,
    wrap_angle,
};
use pendulab_plants::{
    ArmPendulum, ArmPendulumParams, ArmPendulumState, CartPendulum, CartPendulumState,
};
use pendulab_sim::Controller;
use pendulab_sim::controllers::Mode;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

fn cart_energy_rate(plant: &CartPendulum, x: &[f64; 4], v: f64) -> f64 {
    // Ė = J θ̇ θ̈ − m g l sin θ θ̇ with θ̈ from the plant's right-hand side.
    let p = plant.params();
    let f = plant.derivative_array(x, v);
    plant.inertia_about_pivot() * x[3] * f[3] - p.m_p * p.g * p.l_p * x[1].sin() * x[3]
}

#[test]
fn book_pumping_law_gives_the_promised_energy_rate() {
    let plant = CartPendulum::book();
    let p = *plant.params();
    let law = EnergyPumping::new(&plant, 0.8).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..200 {
        let x = [
            rng.random_range(-0.3..0.3),
            rng.random_range(-PI..PI),
            rng.random_range(-1.0..1.0),
            rng.random_range(-8.0..8.0),
        ];
        let v = law.control(&x);
        // The commanded acceleration is realised exactly by the drive model.
        let f = plant.derivative_array(&x, v);
        assert!((f[2] + 0.8 * x[3] * x[1].cos()).abs() < 1e-12);
        // Ė = m l K₁ (θ̇ cos θ)² − μ θ̇².
        let expect = p.m_p * p.l_p * 0.8 * (x[3] * x[1].cos()).powi(2) - p.mu_p * x[3] * x[3];
        let got = cart_energy_rate(&plant, &x, v);
        assert!(
            (got - expect).abs() < 1e-12 * (1.0 + expect.abs()),
            "{got} vs {expect}"
        );
        let s = CartPendulumState::from_array(x);
        assert!((plant.energy(&s) - law_energy(&plant, &x)).abs() < 1e-14);
    }
}

fn law_energy(plant: &CartPendulum, x: &[f64; 4]) -> f64 {
    let g = EnergyShapingGains {
        k_energy: 1.0,
        max_acceleration: 1.0,
        energy_ratio: 1.0,
        k_position: 0.0,
        k_velocity: 0.0,
        reference: 0.0,
        travel_limit: 1.0,
        max_voltage: 100.0,
    };
    CartEnergyShaping::new(plant, g).unwrap().energy(x[1], x[3])
}

fn gains(k: f64, amax: f64) -> EnergyShapingGains {
    EnergyShapingGains {
        k_energy: k,
        max_acceleration: amax,
        energy_ratio: 1.0,
        k_position: 0.0,
        k_velocity: 0.0,
        reference: 0.0,
        travel_limit: 10.0,
        max_voltage: 1e6,
    }
}

#[test]
fn energy_shaping_drives_the_energy_towards_its_target() {
    // Cart without pivot friction: Ė = −m l θ̇ cos θ z̈*, and z̈* = k_E (E − E_ref) sign(θ̇ cos θ)
    // (no saturation) gives Ė = −m l k_E (E − E_ref)|θ̇ cos θ|: opposite sign to E − E_ref.
    let mut params = *CartPendulum::book().params();
    params.mu_p = 0.0;
    let plant = CartPendulum::new(params).unwrap();
    let law = CartEnergyShaping::new(&plant, gains(20.0, 1e6)).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for _ in 0..200 {
        let x = [
            rng.random_range(-0.3..0.3),
            rng.random_range(-PI..PI),
            rng.random_range(-1.0..1.0),
            rng.random_range(-8.0..8.0),
        ];
        let e = law.energy(x[1], x[3]) - law.target_energy();
        let rate = cart_energy_rate(&plant, &x, law.control(&x));
        let expect = -params.m_p * params.l_p * 20.0 * e * (x[3] * x[1].cos()).abs();
        assert!(
            (rate - expect).abs() < 1e-10 * (1.0 + expect.abs()),
            "{rate} vs {expect}"
        );
    }
    // Arm without pendulum friction, arm at rest (θ̇₁ = 0, so the centripetal coupling
    // vanishes): Ė₂ = −α₃ θ̇₂ cos(θ₁ − θ₂) θ̈₁* = −α₃ k_E (E₂ − E_ref)|θ̇₂ cos(θ₁ − θ₂)|.
    let arm = ArmPendulum::new(ArmPendulumParams {
        mu2: 0.0,
        ..*ArmPendulum::book().params()
    })
    .unwrap();
    let law = ArmEnergyShaping::new(&arm, gains(100.0, 1e6)).unwrap();
    for _ in 0..200 {
        let x = [
            rng.random_range(-1.0..1.0),
            rng.random_range(-PI..PI),
            0.0,
            rng.random_range(-10.0..10.0),
        ];
        let v = law.control(&x);
        let f = arm.derivative_array(&x, v);
        let rate = arm.alpha2() * x[3] * f[3] - arm.alpha5() * x[1].sin() * x[3];
        let e = law.energy(x[1], x[3]) - law.target_energy();
        let expect = -arm.alpha3() * 100.0 * e * (x[3] * (x[0] - x[1]).cos()).abs();
        assert!(
            (rate - expect).abs() < 1e-10 * (1.0 + expect.abs()),
            "{rate} vs {expect}"
        );
        let s = ArmPendulumState::from_array(x);
        assert!((arm.pendulum_energy(&s) - law.energy(x[1], x[3])).abs() < 1e-14);
    }
}

#[test]
fn wrapping_lands_in_the_half_open_interval() {
    for (a, w) in [
        (0.0, 0.0),
        (PI, PI),
        (-PI, PI),
        (3.0 * PI, PI),
        (2.0 * PI + 0.1, 0.1),
        (-2.0 * PI - 0.1, -0.1),
        (PI + 0.001, -PI + 0.001),
    ] {
        let got = wrap_angle(a);
        assert!((got - w).abs() < 1e-12, "wrap({a}) = {got}, expected {w}");
        assert!(got > -PI && got <= PI);
    }
}

/// A controller that outputs a constant and records the last measurement.
struct Probe(f64, Vec<f64>, usize);

impl Controller for Probe {
    fn ny(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    fn reset(&mut self) {
        self.2 += 1;
    }
    fn update(&mut self, _t: f64, y: &[f64], u: &mut [f64]) {
        self.1 = y.to_vec();
        u[0] = self.0;
    }
}

#[test]
fn switching_is_latched_at_the_first_time_inside_the_window() {
    let mut c = swing_up_then_balance(
        Probe(1.0, vec![], 0),
        Probe(2.0, vec![], 0),
        vec![(1, PI / 4.0)],
    )
    .unwrap();
    let mut u = [0.0];
    c.update(0.0, &[0.0, PI, 0.0, 0.0], &mut u);
    assert_eq!((u[0], c.mode()), (1.0, Mode::A));
    // θ = 2π − 0.5 wraps to −0.5: inside π/4.
    c.update(0.5, &[0.0, 2.0 * PI - 0.5, 0.0, 0.0], &mut u);
    assert_eq!(
        (u[0], c.mode(), c.switch_times()),
        (2.0, Mode::B, &[0.5][..])
    );
    let balance = c.second().inner();
    assert!(
        (balance.1[1] + 0.5).abs() < 1e-12,
        "balance sees the wrapped angle"
    );
    assert_eq!(balance.2, 1, "balance controller reset at the switch");
    // Leaving the window does not switch back.
    c.update(0.6, &[0.0, PI, 0.0, 0.0], &mut u);
    assert_eq!(u[0], 2.0);
    c.reset();
    assert_eq!((c.mode(), c.switch_times().len()), (Mode::A, 0));
}

#[test]
fn bad_swing_up_settings_are_typed_errors() {
    let plant = CartPendulum::book();
    assert!(matches!(
        EnergyPumping::new(&plant, 0.0),
        Err(ControlError::InvalidParameter { .. })
    ));
    let mut g = gains(1.0, 1.0);
    g.travel_limit = -1.0;
    assert!(matches!(
        CartEnergyShaping::new(&plant, g),
        Err(ControlError::InvalidParameter { .. })
    ));
    assert!(matches!(
        swing_up_then_balance(Probe(0.0, vec![], 0), Probe(0.0, vec![], 0), vec![(4, 0.5)]),
        Err(ControlError::InvalidParameter { .. })
    ));
    assert!(matches!(
        swing_up_then_balance(Probe(0.0, vec![], 0), Probe(0.0, vec![], 0), vec![]),
        Err(ControlError::InvalidParameter { .. })
    ));
}
