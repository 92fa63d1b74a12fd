//! The classic cart-pole (Gymnasium's `CartPole-v1` model) against independent references:
//! the Euler–Lagrange equations solved for the accelerations by Cramer's rule, the energy
//! balance `dE/dt = F ẋ` of the frictionless model, the step as `s + τ ṡ` (explicit) or
//! velocities-first (semi-implicit), the thresholds as Gymnasium states them (±2.4 m,
//! ±12°), and typed errors for bad parameters. The step-for-step equality with Gymnasium
//! itself is tested from Python (`crates/python/tests/test_gym_cartpole.py`).

use pendulab_plants::{
    CartPoleIntegrator, ClassicCartPole, ClassicCartPoleParams, PlantError, Requirement,
};

/// A deterministic sequence of states and forces (a 64-bit LCG, Knuth's MMIX constants).
fn samples(n: usize) -> Vec<([f64; 4], f64)> {
    let mut s = 7u64;
    let mut next = move |amp: f64| {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * amp
    };
    (0..n)
        .map(|_| ([next(2.4), next(3.0), next(3.2), next(8.0)], next(10.0)))
        .collect()
}

/// `(ẍ, θ̈)` from `M ẍ + m l cos θ θ̈ = F + m l sin θ θ̇²` and
/// `m l cos θ ẍ + (4/3) m l² θ̈ = m g l sin θ` by Cramer's rule.
fn lagrange_accelerations(p: &ClassicCartPoleParams, s: &[f64; 4], f: f64) -> (f64, f64) {
    let (m, l, g) = (p.masspole, p.length, p.gravity);
    let big_m = p.masscart + m;
    let (sn, cs) = s[2].sin_cos();
    let (a11, a12, a21, a22) = (big_m, m * l * cs, m * l * cs, 4.0 / 3.0 * m * l * l);
    let (b1, b2) = (f + m * l * sn * s[3] * s[3], m * g * l * sn);
    let det = a11 * a22 - a12 * a21;
    ((b1 * a22 - a12 * b2) / det, (a11 * b2 - a21 * b1) / det)
}

#[test]
fn accelerations_solve_the_euler_lagrange_equations() {
    let plant = ClassicCartPole::gymnasium();
    let p = *plant.params();
    for (s, f) in samples(10_000) {
        let d = plant.derivative(&s, f);
        let (xacc, thetaacc) = lagrange_accelerations(&p, &s, f);
        assert_eq!((d[0], d[2]), (s[1], s[3]));
        // Both are a few roundings of terms below ~200 (|θ̇|² ≤ 64 times m l / M etc.).
        assert!(
            (d[1] - xacc).abs() <= 1e-13 * (1.0 + xacc.abs()),
            "{s:?} {f}"
        );
        assert!(
            (d[3] - thetaacc).abs() <= 1e-13 * (1.0 + thetaacc.abs()),
            "{s:?} {f}"
        );
    }
}

/// `E = ½ M ẋ² + m l cos θ ẋ θ̇ + ½ (4/3) m l² θ̇² + m g l cos θ`; along the flow
/// `dE/dt = ∇E · ṡ` must equal the force's power `F ẋ` (no friction in the model).
#[test]
fn energy_changes_by_the_force_power_only() {
    let plant = ClassicCartPole::gymnasium();
    let p = *plant.params();
    let (m, l, g) = (p.masspole, p.length, p.gravity);
    let big_m = p.masscart + m;
    for (s, f) in samples(10_000) {
        let [_, xd, th, thd] = s;
        let (sn, cs) = th.sin_cos();
        let de_dx_dot = big_m * xd + m * l * cs * thd;
        let de_dtheta = -m * l * sn * xd * thd - m * g * l * sn;
        let de_dtheta_dot = m * l * cs * xd + 4.0 / 3.0 * m * l * l * thd;
        let d = plant.derivative(&s, f);
        let power = de_dx_dot * d[1] + de_dtheta * d[2] + de_dtheta_dot * d[3];
        let scale = 1.0 + (f * xd).abs() + (de_dtheta * d[2]).abs();
        assert!(
            (power - f * xd).abs() <= 1e-13 * scale,
            "{s:?} {f}: {power} vs {}",
            f * xd
        );
    }
}

#[test]
fn steps_are_euler_and_semi_implicit_euler() {
    let euler = ClassicCartPole::gymnasium();
    let semi = ClassicCartPole::new(ClassicCartPoleParams {
        integrator: CartPoleIntegrator::SemiImplicitEuler,
        ..ClassicCartPoleParams::gymnasium()
    })
    .unwrap();
    let tau = 0.02;
    for (s, f) in samples(1000) {
        let d = euler.derivative(&s, f);
        let e = euler.step_force(&s, f);
        for i in 0..4 {
            assert_eq!(e[i], s[i] + tau * d[i]);
        }
        let v = semi.step_force(&s, f);
        let (xd, thd) = (s[1] + tau * d[1], s[3] + tau * d[3]);
        assert_eq!(v, [s[0] + tau * xd, xd, s[2] + tau * thd, thd]);
    }
    // Discrete actions: 1 pushes with +10 N, 0 with −10 N.
    let s = [0.01, -0.02, 0.03, 0.04];
    assert_eq!(euler.step(&s, 1), euler.step_force(&s, 10.0));
    assert_eq!(euler.step(&s, 0), euler.step_force(&s, -10.0));
}

#[test]
fn terminal_beyond_2_4_m_or_12_degrees() {
    let plant = ClassicCartPole::gymnasium();
    let twelve = 12f64.to_radians();
    assert!((plant.params().theta_threshold - twelve).abs() <= 1e-16);
    assert!(!plant.is_terminal(&[2.4, 0.0, 0.0, 0.0]));
    assert!(plant.is_terminal(&[2.400001, 0.0, 0.0, 0.0]));
    assert!(plant.is_terminal(&[-2.400001, 0.0, 0.0, 0.0]));
    assert!(!plant.is_terminal(&[0.0, 9.0, 0.2094, 9.0]));
    assert!(plant.is_terminal(&[0.0, 0.0, 0.2095, 0.0]));
    assert!(plant.is_terminal(&[0.0, 0.0, -0.2095, 0.0]));
}

#[test]
fn bad_parameters_are_typed_errors_naming_the_field() {
    for (name, p) in [
        (
            "masspole",
            ClassicCartPoleParams {
                masspole: -0.1,
                ..Default::default()
            },
        ),
        (
            "tau",
            ClassicCartPoleParams {
                tau: f64::NAN,
                ..Default::default()
            },
        ),
        (
            "length",
            ClassicCartPoleParams {
                length: 0.0,
                ..Default::default()
            },
        ),
    ] {
        let e = ClassicCartPole::new(p).unwrap_err();
        assert!(
            matches!(
                e,
                PlantError::InvalidParameter {
                    name: n,
                    requirement: Requirement::Positive,
                    ..
                } if n == name
            ),
            "{e}"
        );
        assert!(e.to_string().contains(name));
    }
}
