//! The Gymnasium-style environment: reproducible resets, steps equal to the RK4 kernel,
//! termination, truncation, clipping and errors; `FixedEnv` against `Env`.

mod common;

use common::CartPendulum;
use pendulab_sim::env::FixedEnv;
use pendulab_sim::fixed::FixedDynamics;
use pendulab_sim::{Dynamics, Env, EnvConfig, SimError, Step, rk4_step};

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
    let obs = env.reset(Some(3));
    let (n, _) = balance_to_the_end(&plant, obs, |u| env.step(u).unwrap());
    assert_eq!(n, 500);
}

/// Runs `u = −K x` (the LQR gain of the linear model, `common::cart_lqr_gain`) through `step`
/// from `obs` until the episode ends, asserting that it ends by truncation, not by a fall.
/// Returns the number of steps and the last observation.
fn balance_to_the_end(
    plant: &CartPendulum,
    mut obs: [f64; 4],
    mut step: impl FnMut(f64) -> Step<4>,
) -> (usize, [f64; 4]) {
    let k = common::cart_lqr_gain(plant);
    let mut n = 0;
    loop {
        let u = -(0..4).map(|j| k[(0, j)] * obs[j]).sum::<f64>();
        let s = step(u);
        n += 1;
        obs = s.obs;
        if s.terminated || s.truncated {
            assert!(s.truncated && !s.terminated, "fell at step {n}");
            return (n, obs);
        }
    }
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

/// The test plant on arrays for `FixedEnv`: its own `Dynamics::derivative` (the contract of
/// `FixedDynamics`), with the provided RK4 step.
impl FixedDynamics<4> for CartPendulum {
    fn derivative_fixed(&self, x: &[f64; 4], u: f64) -> [f64; 4] {
        let mut dx = [0.0; 4];
        self.derivative(0.0, x, &[u], &mut dx);
        dx
    }
}

/// A deterministic action sequence in ±`amp` (a 64-bit LCG, Knuth's MMIX constants): the
/// actions only need to be the same for both environments.
fn actions(seed: u64, amp: f64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * amp
    }
}

/// `FixedEnv` with the provided RK4 step (`rk4_fixed`, the operations of `rk4_step`) against
/// `Env` (the generic RK4 on slices): the same seeds draw the same initial states and every
/// step of thousands of random-action episodes (actions up to ±6 V, beyond the ±5 V limit,
/// so the clipping is exercised) agrees bit for bit, observation, reward and flags, with one
/// and with three substeps; `Env::fixed` continues from the same generator state.
#[test]
fn fixed_env_repeats_the_general_env_bit_for_bit() {
    for substeps in [1, 3] {
        let config = EnvConfig {
            substeps,
            ..EnvConfig::cart_pole(0.4).unwrap()
        };
        let mut general = Env::<_, 4>::new(CartPendulum::default(), config.clone()).unwrap();
        let mut fast = FixedEnv::<_, 4>::new(CartPendulum::default(), config).unwrap();
        assert_eq!(general.reset(Some(11)), fast.reset(Some(11)));
        let mut next = actions(5, 6.0);
        let (mut episodes, mut truncated) = (0, 0);
        for _ in 0..20_000 {
            let a = next();
            let (sa, sb) = (general.step(a).unwrap(), fast.step(a).unwrap());
            assert_eq!(sa, sb);
            assert_eq!(general.steps(), fast.steps());
            if sa.terminated || sa.truncated {
                episodes += 1;
                truncated += usize::from(sa.truncated);
                // Reward 0 and no change after the end, in both.
                assert_eq!(general.step(0.3).unwrap(), fast.step(0.3).unwrap());
                assert_eq!(general.reset(None), fast.reset(None));
            }
        }
        assert!(episodes > 100, "{episodes} episodes");
        assert_eq!(truncated, 0, "random actions never balance for 500 steps");
        // The conversion carries the generator state along.
        let mut copy = general.fixed();
        assert_eq!(copy.observation(), general.observation());
        assert_eq!(copy.reset(None), general.reset(None));
        assert_eq!(copy.config(), general.config());
    }
}

/// `FixedEnv` keeps the semantics: seeded resets, truncation at 500 steps under a
/// stabilising policy, and the configuration and action errors of `Env`.
#[test]
fn fixed_env_seeds_truncates_and_refuses_bad_input() {
    let plant = CartPendulum::default();
    let mut env = FixedEnv::<_, 4>::new(plant, EnvConfig::cart_pole(0.4).unwrap()).unwrap();
    let a = env.reset(Some(7));
    assert_eq!(a, env.reset(Some(7)));
    assert_ne!(a, env.reset(None));
    let obs = env.reset(Some(3));
    let (n, obs) = balance_to_the_end(&plant, obs, |u| env.step(u).unwrap());
    assert_eq!((n, env.steps()), (500, 500));
    let after = env.step(1.0).unwrap();
    assert_eq!((after.reward, after.truncated, after.obs), (0.0, true, obs));
    let bad = |f: fn(&mut EnvConfig)| {
        let mut c = EnvConfig::cart_pole(0.4).unwrap();
        f(&mut c);
        FixedEnv::<_, 4>::new(plant, c).is_err()
    };
    assert!(bad(|c| c.dt = 0.0));
    assert!(bad(|c| c.substeps = 0));
    assert!(bad(|c| c.max_steps = 0));
    assert!(bad(|c| c.action_limit = -1.0));
    assert!(bad(|c| c.reset_half_width = vec![0.1; 3]));
    assert!(bad(|c| c.nominal = vec![0.0; 5]));
    assert!(bad(|c| c.reset_half_width[2] = -0.1));
    assert!(bad(|c| c.limits.push((4, 1.0))));
    assert!(bad(|c| c.nominal[0] = f64::NAN));
    env.reset(Some(1));
    env.step(0.5).unwrap();
    match env.step(f64::NAN) {
        Err(SimError::NonFiniteCommand { t, index: 0, value }) => {
            assert!(value.is_nan());
            assert_eq!(t, 0.02, "the time of the refused step");
        }
        other => panic!("expected NonFiniteCommand, got {other:?}"),
    }
    // The refused action changed nothing.
    assert_eq!(env.steps(), 1);
    assert!(matches!(
        env.reset_to([0.0, f64::NAN, 0.0, 0.0]),
        Err(SimError::NonFiniteInitialState { .. })
    ));
    // A state that blows up is an error, not a panic: an unbounded action limit and a
    // huge action overflow the cart's velocity within a step.
    let mut wild = FixedEnv::<_, 4>::new(
        plant,
        EnvConfig {
            action_limit: f64::MAX,
            limits: vec![],
            ..EnvConfig::cart_pole(0.4).unwrap()
        },
    )
    .unwrap();
    wild.reset(Some(1));
    assert!(matches!(
        wild.step(f64::MAX),
        Err(SimError::NonFiniteState { .. })
    ));
}
