//! `find_operating_point` against closed forms: the cart pendulum's upright and hanging rests,
//! the cart rolling at constant speed (the drive law gives the voltage that holds it), the arm
//! at a given arm angle, a torque-driven pendulum held off the vertical (its gravity term gives
//! the torque) by a fixed angle or a fixed output, the same pendulum turning and accelerating
//! at given derivative targets, and the specifications that have no
//! solution or contradict themselves.

use pendulab_control::ControlError;
use pendulab_control::trim::{TrimOptions, TrimSpec, TrimStatus, find_operating_point};
use pendulab_plants::{ArmPendulum, CartPendulum};
use pendulab_sim::{Dynamics, FnDynamics};
use pendulab_testkit::arm::ArmParams;
use pendulab_testkit::cart::CartParams;
use std::f64::consts::PI;

fn opts() -> TrimOptions {
    TrimOptions::default()
}

#[test]
fn cart_upright_and_hanging_rests() {
    let plant = CartPendulum::book();
    // Upright: z fixed at 0.1, a guess off in every other entry → θ = 0, at rest, v = 0.
    let spec = TrimSpec::new(&[0.1, 0.3, 0.2, -0.4], &[0.7]).fix_states(&[0]);
    let op = find_operating_point(&plant, &spec, &opts()).unwrap();
    let expected = [0.1, 0.0, 0.0, 0.0];
    for (a, b) in op.x.iter().zip(expected) {
        assert!((a - b).abs() < 1e-10, "{:?}", op.x);
    }
    assert!(op.u[0].abs() < 1e-10);
    assert!(op.residual <= 1e-10);
    assert_eq!(op.status, TrimStatus::Isolated);
    // Hanging: θ near π → θ = π exactly (to the tolerance); z left free is a family of one.
    let spec = TrimSpec::new(&[0.0, 2.8, 0.1, 0.5], &[0.0]);
    let op = find_operating_point(&plant, &spec, &opts()).unwrap();
    assert!((op.x[1] - PI).abs() < 1e-10, "{:?}", op.x);
    assert!(op.x[2].abs() < 1e-10 && op.x[3].abs() < 1e-10 && op.u[0].abs() < 1e-10);
    assert_eq!(op.status, TrimStatus::Family { dimension: 1 });
    assert!(op.dx.iter().all(|d| d.abs() <= 1e-10));
}

#[test]
fn cart_rolling_at_constant_speed_needs_the_drive_voltage() {
    // ż = 0.3 m/s held, d z/dt freed: the drive law z̈ = −a_c ż + b_c v = 0 gives
    // v = a_c ż / b_c, and the pendulum hangs at rest (θ = π).
    let p = CartParams::book();
    let plant = CartPendulum::book();
    let spec = TrimSpec::new(&[0.0, 3.0, 0.3, 0.0], &[0.0])
        .fix_states(&[0, 2])
        .free_derivative(0);
    let op = find_operating_point(&plant, &spec, &opts()).unwrap();
    assert!((op.u[0] - p.a_c * 0.3 / p.b_c).abs() < 1e-11, "{:?}", op.u);
    assert!((op.x[1] - PI).abs() < 1e-10);
    assert!((op.dx[0] - 0.3).abs() < 1e-15);
    assert_eq!(op.status, TrimStatus::Isolated);
}

#[test]
fn arm_at_a_given_arm_angle() {
    // θ₁ = 0.7 rad held. The drive law θ̈₁ = −a₁ θ̇₁ + b₁ v has no gravity term (the motor's
    // identified law stands for the arm's equation, docs/model.md §2), so at rest v = 0; the
    // pendulum's equation at rest is α₅ sin θ₂ = 0: θ₂ = 0 upright or π hanging.
    let plant = ArmPendulum::book();
    let (_, _, alpha5) = ArmParams::book().alphas();
    assert!(alpha5 > 0.0);
    for (guess, theta2) in [(0.3, 0.0), (2.7, PI)] {
        let spec = TrimSpec::new(&[0.7, guess, 0.5, -0.2], &[1.0]).fix_states(&[0]);
        let op = find_operating_point(&plant, &spec, &opts()).unwrap();
        assert!((op.x[0] - 0.7).abs() == 0.0);
        assert!((op.x[1] - theta2).abs() < 1e-10, "{:?}", op.x);
        assert!(op.x[2].abs() < 1e-10 && op.x[3].abs() < 1e-10);
        assert!(op.u[0].abs() < 1e-10);
        assert_eq!(op.status, TrimStatus::Isolated);
    }
}

/// A torque-driven pendulum `m l² θ̈ = u − m g l sin θ − b θ̇` (θ from the hanging rest), its
/// output the horizontal position of the bob `y = l sin θ`.
struct TorquePendulum {
    m: f64,
    l: f64,
    g: f64,
    b: f64,
}

impl Dynamics for TorquePendulum {
    fn nx(&self) -> usize {
        2
    }
    fn nu(&self) -> usize {
        1
    }
    fn derivative(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        dx[0] = x[1];
        dx[1] = (u[0] - self.m * self.g * self.l * x[0].sin() - self.b * x[1])
            / (self.m * self.l * self.l);
    }
    fn ny(&self) -> usize {
        1
    }
    fn output(&self, _t: f64, x: &[f64], _u: &[f64], y: &mut [f64]) {
        y[0] = self.l * x[0].sin();
    }
}

#[test]
fn torque_pendulum_held_by_its_gravity_torque() {
    let p = TorquePendulum {
        m: 0.2,
        l: 0.3,
        g: 9.81,
        b: 0.01,
    };
    // θ fixed at 0.6 rad: u = m g l sin 0.6.
    let spec = TrimSpec::new(&[0.6, 0.0], &[0.0]).fix_states(&[0]);
    let op = find_operating_point(&p, &spec, &opts()).unwrap();
    assert!((op.u[0] - p.m * p.g * p.l * 0.6f64.sin()).abs() < 1e-11);
    // The bob's horizontal position fixed at 0.1 m instead: θ = asin(0.1/l), u = m g · 0.1.
    let spec = TrimSpec::new(&[0.1, 0.0], &[0.0]).fix_output(0, 0.1);
    let op = find_operating_point(&p, &spec, &opts()).unwrap();
    assert!((op.x[0] - (0.1 / p.l).asin()).abs() < 1e-10, "{:?}", op.x);
    assert!((op.u[0] - p.m * p.g * 0.1).abs() < 1e-10, "{:?}", op.u);
    assert!((op.y[0] - 0.1).abs() < 1e-10);
    assert_eq!(op.status, TrimStatus::Isolated);
}

/// Non-zero derivative targets (python-control's `dx0`): the torque pendulum at θ = 0.6 rad
/// turning at θ̇ = 0.4 rad/s and accelerating at θ̈ = 1.5 rad/s² needs, from
/// `m l² θ̈ = u − m g l sin θ − b θ̇`, `u = m l² · 1.5 + m g l sin 0.6 + b · 0.4`; the state
/// θ̇ is found from the held `θ̇`-equation `ẋ₀ = θ̇ = 0.4`.
#[test]
fn torque_pendulum_with_derivative_targets() {
    let p = TorquePendulum {
        m: 0.2,
        l: 0.3,
        g: 9.81,
        b: 0.01,
    };
    let spec = TrimSpec::new(&[0.6, 0.0], &[0.0])
        .fix_states(&[0])
        .derivatives(&[0.4, 1.5]);
    let op = find_operating_point(&p, &spec, &opts()).unwrap();
    let u = p.m * p.l * p.l * 1.5 + p.m * p.g * p.l * 0.6f64.sin() + p.b * 0.4;
    assert!((op.x[1] - 0.4).abs() < 1e-11, "{:?}", op.x);
    assert!((op.u[0] - u).abs() < 1e-10, "{} vs {u}", op.u[0]);
    assert!((op.dx[0] - 0.4).abs() < 1e-10 && (op.dx[1] - 1.5).abs() < 1e-10);
    // A freed derivative's target is ignored: θ̈ free, θ̇ = 0.4 held, u fixed at 0.
    let spec = TrimSpec::new(&[0.6, 0.0], &[0.0])
        .fix_states(&[0])
        .fix_inputs(&[0])
        .free_derivative(1)
        .derivatives(&[0.4, 123.0]);
    let op = find_operating_point(&p, &spec, &opts()).unwrap();
    assert!((op.x[1] - 0.4).abs() <= 1e-10);
    // Targets of the wrong length or not finite.
    for dx in [vec![0.4], vec![0.4, f64::NAN]] {
        let spec = TrimSpec::new(&[0.6, 0.0], &[0.0]).derivatives(&dx);
        assert!(matches!(
            find_operating_point(&p, &spec, &opts()),
            Err(ControlError::DimensionMismatch { .. } | ControlError::NonFinite { .. })
        ));
    }
}

#[test]
fn no_solution_is_a_typed_error() {
    // The cart's voltage fixed at 1 V and every derivative required to vanish: ż = 0 and
    // −a_c ż + b_c v = 0 cannot both hold.
    let plant = CartPendulum::book();
    let spec = TrimSpec::new(&[0.0, 0.1, 0.0, 0.0], &[1.0]).fix_inputs(&[0]);
    match find_operating_point(&plant, &spec, &opts()) {
        Err(ControlError::NoConvergence { residual, .. }) => {
            // The least-squares minimum of ż² + (b_c − a_c ż)² is b_c/√(1 + a_c²) in the
            // 2-norm; its ∞-norm is at least that over √2.
            let p = CartParams::book();
            let floor = p.b_c / (1.0 + p.a_c * p.a_c).sqrt() / 2f64.sqrt();
            assert!(residual >= floor * (1.0 - 1e-9), "{residual}");
        }
        other => panic!("expected NoConvergence, got {other:?}"),
    }
    // A pendulum whose output can never reach 1 m (|l sin θ| ≤ 0.3).
    let p = TorquePendulum {
        m: 0.2,
        l: 0.3,
        g: 9.81,
        b: 0.01,
    };
    let spec = TrimSpec::new(&[0.1, 0.0], &[0.0]).fix_output(0, 1.0);
    assert!(matches!(
        find_operating_point(&p, &spec, &opts()),
        Err(ControlError::NoConvergence { .. })
    ));
}

#[test]
fn inconsistent_and_non_finite_specs_are_typed_errors() {
    let plant = CartPendulum::book();
    let x = [0.0, 0.1, 0.0, 0.0];
    let bad = |spec: TrimSpec| find_operating_point(&plant, &spec, &opts());
    assert!(matches!(
        bad(TrimSpec::new(&x, &[0.0]).fix_states(&[4])),
        Err(ControlError::InconsistentSpec { .. })
    ));
    assert!(matches!(
        bad(TrimSpec::new(&x, &[0.0]).fix_states(&[1, 1])),
        Err(ControlError::InconsistentSpec { .. })
    ));
    // The cart has no output map.
    assert!(matches!(
        bad(TrimSpec::new(&x, &[0.0]).fix_output(0, 0.0)),
        Err(ControlError::InconsistentSpec { .. })
    ));
    // Everything fixed at a point that is not a rest (θ = 0.1 falls).
    assert!(matches!(
        bad(TrimSpec::new(&x, &[0.0])
            .fix_states(&[0, 1, 2, 3])
            .fix_inputs(&[0])),
        Err(ControlError::InconsistentSpec { .. })
    ));
    assert!(matches!(
        bad(TrimSpec::new(&[0.0, f64::NAN, 0.0, 0.0], &[0.0])),
        Err(ControlError::NonFinite { .. })
    ));
    assert!(matches!(
        bad(TrimSpec::new(&x[..3], &[0.0])),
        Err(ControlError::DimensionMismatch { .. })
    ));
    // f not finite at the guess.
    let blow_up = FnDynamics::new(1, 0, |_t, x: &[f64], _u: &[f64], dx: &mut [f64]| {
        dx[0] = 1.0 / x[0]
    });
    assert!(matches!(
        find_operating_point(&blow_up, &TrimSpec::new(&[0.0], &[]), &opts()),
        Err(ControlError::NonFinite { .. })
    ));
}
