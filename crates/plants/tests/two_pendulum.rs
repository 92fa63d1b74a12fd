//! Tests of the cart with two pendulums (book example 5.4) and of the rig numbers.

mod common;

use common::*;
use pendulab_lti::analysis::{controllability_staircase, ctrb, rank};
use pendulab_plants::*;
use pendulab_sim::Dynamics;
use std::f64::consts::PI;

#[test]
fn controllable_with_different_pendulums_not_with_identical_ones() {
    // Book example 5.4 (p1c511_ex4_cdip): rank M_c = 6 with the 1.2-scaled second pendulum.
    // With identical pendulums δ = θ_a − θ_b evolves on its own (module docs), so the
    // reachable subspace is the single-pendulum cart's, of dimension 4. Two independent tests:
    // the SVD rank of M_c (MATLAB's tolerance) and the orthogonal staircase.
    for (params, expected) in [
        (TwoPendulumCartParams::book_example(), 6),
        (TwoPendulumCartParams::identical(), 4),
    ] {
        let plant = TwoPendulumCart::new(params).unwrap();
        let sys = plant
            .linearize(0.0, Posture::Upright, Posture::Upright)
            .unwrap();
        let mc = ctrb(sys.a(), sys.b()).unwrap();
        assert_eq!(rank(&mc).rank, expected);
        let stairs = controllability_staircase(sys.a(), sys.b(), None).unwrap();
        assert_eq!(stairs.controllable_dimension, expected);
        if expected == 4 {
            // The uncontrollable modes are those of J δ̈ = m g l δ − μ δ̇ (the fixed-cart upright
            // pendulum, eq. 4.45).
            let mut modes = stairs.uncontrollable_modes().unwrap();
            let fixed = CartPendulum::book().fixed_cart();
            let mut closed = fixed.eigenvalues(Posture::Upright).to_vec();
            modes.sort_by(|a, b| a.re.total_cmp(&b.re));
            closed.sort_by(|a, b| a.re.total_cmp(&b.re));
            for (m, c) in modes.iter().zip(&closed) {
                assert!((m - c).norm() <= 1e-9 * c.norm(), "{m} vs {c}");
            }
        }
    }
    // The pendulum parameters of the book's example.
    let p = TwoPendulumCartParams::book_example();
    let b = CartPendulumParams::book();
    assert_eq!(p.pendulum_b.m, 1.2 * b.m_p);
    assert_eq!(p.pendulum_b.l, 1.2 * b.l_p);
    assert_eq!(p.pendulum_b.L, 1.2 * b.L_p);
    assert!((p.pendulum_b.J - 1.728 * b.J_p).abs() <= 1e-15 * b.J_p);
    assert_eq!(p.pendulum_b.mu, b.mu_p);
}

#[test]
fn nonlinear_model_matches_sympy_euler_lagrange() {
    let fx = fixture();
    let cases = fx["two_pendulum_cart"].as_array().unwrap();
    assert_eq!(cases.len(), 2);
    for case in cases {
        let p = &case["params"];
        let pend = |q: &serde_json::Value, big_l: f64| PendulumParams {
            m: num(&q["m"]),
            l: num(&q["l"]),
            L: big_l,
            J: num(&q["J"]),
            mu: num(&q["mu"]),
        };
        let params = TwoPendulumCartParams {
            a_c: num(&p["a_c"]),
            b_c: num(&p["b_c"]),
            g: num(&p["g"]),
            pendulum_a: pend(&p["a"], 0.38),
            pendulum_b: pend(&p["b"], 0.456),
        };
        let plant = TwoPendulumCart::new(params).unwrap();
        let x: [f64; 6] = arr(&case["x"]);
        let f_ref: [f64; 6] = arr(&case["f"]);
        let u = num(&case["u"]);
        let f = plant.derivative_array(&x, u);
        // As for the single pendulum: 1e-12 relative to max(1, |f|).
        for i in 0..6 {
            assert!(
                (f[i] - f_ref[i]).abs() <= 1e-12 * f_ref[i].abs().max(1.0),
                "f[{i}] at {x:?}: {} vs SymPy {}",
                f[i],
                f_ref[i]
            );
        }
        let mut dx = [0.0; 6];
        plant.derivative(0.0, &x, &[u], &mut dx);
        assert_eq!(dx, f);
        assert_eq!((plant.nx(), plant.nu()), (6, 1));
    }
}

#[test]
fn jacobian_matches_central_differences() {
    let plant = TwoPendulumCart::new(TwoPendulumCartParams::book_example()).unwrap();
    for (x, u) in [
        ([0.0; 6], 0.0),
        ([0.1, 0.2, -0.3, 0.4, 0.5, -0.6], 0.8),
        ([-0.2, 3.0, 2.9, -0.1, -2.0, 1.0], -3.0),
    ] {
        let jac = plant.jacobian(&x, u);
        let (a_fd, b_fd) = fd_jacobian(|x, u| plant.derivative_array(x, u), &x, u);
        let scale = jac.a_matrix().amax().max(jac.b_matrix().amax());
        // Central differences: ~1e-9 of the scale; 1e-7 allowed (see the cart tests).
        for i in 0..6 {
            for j in 0..6 {
                assert!(
                    (jac.a[i][j] - a_fd[i][j]).abs() <= 1e-7 * scale,
                    "A[{i}][{j}]"
                );
            }
            assert!((jac.b[i] - b_fd[i]).abs() <= 1e-7 * scale, "B[{i}]");
        }
    }
    // The linearisation at (upright, hanging) is the Jacobian there.
    let sys = plant
        .linearize(0.3, Posture::Upright, Posture::Hanging)
        .unwrap();
    let jac = plant.jacobian(&[0.3, 0.0, PI, 0.0, 0.0, 0.0], 0.0);
    assert!((sys.a() - jac.a_matrix()).amax() <= 1e-15 * sys.a().amax());
    assert_eq!(sys.b(), &jac.b_matrix());
}

#[test]
fn energy_is_conserved_without_friction_with_the_cart_held() {
    let mut params = TwoPendulumCartParams::book_example();
    params.pendulum_a.mu = 0.0;
    params.pendulum_b.mu = 0.0;
    let plant = TwoPendulumCart::new(params).unwrap();
    let x0 = [0.0, 0.5, 2.5, 0.0, 1.0, -2.0];
    let path = rk4_path(|_, x| plant.derivative_array(x, 0.0), x0, 1e-4, 100_000);
    let e0 = plant.energy(&x0.into());
    let drift = path
        .iter()
        .map(|x| (plant.energy(&(*x).into()) - e0).abs())
        .fold(0.0, f64::max);
    // RK4 at 1e-4 s over 10 s: ~1e-11 relative expected, 1e-9 required.
    assert!(drift <= 1e-9 * e0, "drift {drift:e}");
    let s = TwoPendulumCartState::from(x0);
    assert_eq!(s.theta_b, 2.5);
    assert_eq!(<[f64; 6]>::from(s), x0);
}

#[test]
fn invalid_parameters_name_the_pendulum() {
    let mut p = TwoPendulumCartParams::book_example();
    p.pendulum_b.J = -1.0;
    match TwoPendulumCart::new(p) {
        Err(PlantError::InvalidParameter { name, value, .. }) => {
            assert_eq!(name, "J_b");
            assert_eq!(value, -1.0);
        }
        other => panic!("{other:?}"),
    }
    let p = TwoPendulumCartParams::scaled(&CartPendulumParams::book(), f64::NAN);
    assert!(TwoPendulumCart::new(p).is_err());
    let p = TwoPendulumCartParams::scaled(&CartPendulumParams::book(), -1.0);
    assert!(TwoPendulumCart::new(p).is_err());
    let plant = TwoPendulumCart::new(TwoPendulumCartParams::identical()).unwrap();
    assert!(
        plant
            .linearize(f64::NAN, Posture::Upright, Posture::Upright)
            .is_err()
    );
}

#[test]
fn rig_numbers_are_specs() {
    // docs/model.md §3.
    for rig in [RigSpec::cart(), RigSpec::arm()] {
        assert_eq!(rig.sample_time, 1e-3);
        assert_eq!(rig.input_limit, 5.0);
        assert_eq!((rig.dac.bits, rig.dac.min, rig.dac.max), (16, -5.0, 5.0));
        assert_eq!(rig.dac.step(), 10.0 / 65536.0);
        assert_eq!(rig.measured_states(), [0, 1]);
        assert_eq!(rig.nx, 4);
        for (k, est) in rig.velocity_estimators.iter().enumerate() {
            assert_eq!(est.position_state, k);
            assert_eq!(est.velocity_state, k + 2);
            assert_eq!(est.time_constant, 0.02);
        }
    }
    let cart = RigSpec::cart();
    assert_eq!(cart.encoders[0].step, 4.8414e-5);
    assert_eq!(cart.encoders[1].step, 2.0 * PI / 14400.0);
    let arm = RigSpec::arm();
    assert_eq!(arm.encoders[0].step, 2.0 * PI / 200000.0);
    assert_eq!(arm.encoders[1].step, 2.0 * PI / 14400.0);
    // The plants' measured states are the encoders' states.
    assert_eq!(cart.measured_states(), CartPendulum::MEASURED_STATES);
    assert_eq!(arm.measured_states(), ArmPendulum::MEASURED_STATES);
}
