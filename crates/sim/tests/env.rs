//! The Gymnasium-style environment: reproducible resets, steps equal to the RK4 kernel,
//! termination, truncation, clipping and errors.

mod common;

use common::CartPendulum;
use pendulab_lti::Mat;
use pendulab_sim::{Env, EnvConfig, SimError, rk4_step};

#[test]
fn resets_are_seeded_and_steps_are_rk4_periods() {
    let plant = CartPendulum::default();
    let mut env = Env::<_, 4>::new(plant, EnvConfig::cart_pole(0.4).unwrap()).unwrap();
    let a = env.reset(Some(7));
    let b = env.reset(Some(7));
    let c = env.reset(None);
    assert_eq!(a, b);
    assert_ne!(b, c);
    assert!(a.iter().all(|v| v.abs() <= 0.05));
    // One step = one RK4 step of 0.02 s with the action held (and clipped to ±5 V).
    let x0 = env.reset_to([0.01, 0.02, -0.03, 0.04]).unwrap();
    let s = env.step(100.0).unwrap();
    let mut x = x0;
    rk4_step(&plant, 0.0, &mut x, &[5.0], 0.02);
    assert_eq!(s.obs, x);
    assert_eq!(s.reward, 1.0);
    assert!(!s.terminated && !s.truncated);
    let s2 = env.step(-0.7).unwrap();
    rk4_step(&plant, 0.02, &mut x, &[-0.7], 0.02);
    assert_eq!(s2.obs, x);
}

#[test]
fn episodes_terminate_when_the_pendulum_falls_and_truncate_at_500_steps() {
    let plant = CartPendulum::default();
    let mut env = Env::<_, 4>::new(plant, EnvConfig::cart_pole(0.4).unwrap()).unwrap();
    // No action: the pendulum falls past 12° in well under 500 steps.
    env.reset_to([0.0, 0.05, 0.0, 0.0]).unwrap();
    let mut total = 0.0;
    let last = loop {
        let s = env.step(0.0).unwrap();
        total += s.reward;
        if s.terminated || s.truncated {
            break s;
        }
    };
    assert!(last.terminated && !last.truncated);
    assert!(last.obs[1].abs() > 12f64.to_radians());
    assert_eq!(total, env.steps() as f64);
    // Past the end: nothing changes, no reward.
    let after = env.step(1.0).unwrap();
    assert_eq!(
        (after.obs, after.reward, after.terminated),
        (last.obs, 0.0, true)
    );
    // A stabilising policy u = −K x (LQR on the linear model) survives the 500 steps.
    let q = Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&[10.0, 10.0, 0.0, 0.0]));
    let k = pendulab_lti::design::lqr(&plant.linear(), &q, &Mat::identity(1, 1), None)
        .unwrap()
        .gain;
    let mut obs = env.reset(Some(3));
    let mut n = 0;
    loop {
        let u = -(0..4).map(|j| k[(0, j)] * obs[j]).sum::<f64>();
        let s = env.step(u).unwrap();
        n += 1;
        obs = s.obs;
        if s.terminated || s.truncated {
            assert!(s.truncated && !s.terminated, "fell at step {n}");
            break;
        }
    }
    assert_eq!(n, 500);
}

#[test]
fn bad_configuration_and_actions_are_errors() {
    let plant = CartPendulum::default();
    assert!(matches!(
        Env::<_, 3>::new(plant, EnvConfig::cart_pole(0.4).unwrap()),
        Err(SimError::DimensionMismatch { .. })
    ));
    assert!(EnvConfig::cart_pole(0.0).is_err());
    let bad = |f: fn(&mut EnvConfig)| {
        let mut c = EnvConfig::cart_pole(0.4).unwrap();
        f(&mut c);
        Env::<_, 4>::new(plant, c).is_err()
    };
    assert!(bad(|c| c.dt = 0.0));
    assert!(bad(|c| c.substeps = 0));
    assert!(bad(|c| c.max_steps = 0));
    assert!(bad(|c| c.action_limit = -1.0));
    assert!(bad(|c| c.reset_half_width = vec![0.1; 3]));
    assert!(bad(|c| c.reset_half_width[2] = -0.1));
    assert!(bad(|c| c.limits.push((9, 1.0))));
    assert!(bad(|c| c.nominal[0] = f64::NAN));
    let mut env = Env::<_, 4>::new(plant, EnvConfig::cart_pole(0.4).unwrap()).unwrap();
    env.reset(Some(1));
    assert!(matches!(
        env.step(f64::NAN),
        Err(SimError::NonFiniteCommand { .. })
    ));
    assert!(env.reset_to([0.0, f64::INFINITY, 0.0, 0.0]).is_err());
}
