//! The cart rig's fast environment — `pendulab_sim::env::FixedEnv` over the cart pendulum
//! with `Trig::Anchored` (each RK4 step's later stages take their sines and cosines from the
//! step's first one by the addition theorem) — against the general `Env` over the default
//! plant (libm's sine and cosine at every stage, the generic RK4 on slices): the reference is
//! that independent implementation, and the tolerances come from the documented bound of the
//! anchored sines and cosines (within 2 ulp + 6·10⁻¹⁷ of libm's, 2 ulp + 1.1·10⁻¹⁶ for the
//! stage offsets beyond 1/32 rad).

use pendulab_lti::Mat;
use pendulab_plants::cart::fast::{FastCart, Trig};
use pendulab_plants::{CartEquilibrium, CartPendulum, Posture};
use pendulab_sim::env::FixedEnv;
use pendulab_sim::{Env, EnvConfig, SimError};

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

fn envs() -> (Env<CartPendulum, 4>, FixedEnv<FastCart, 4>) {
    let config = EnvConfig::cart_pole(0.4).unwrap();
    (
        Env::new(CartPendulum::book(), config.clone()).unwrap(),
        FixedEnv::new(FastCart::new(CartPendulum::book(), Trig::Anchored), config).unwrap(),
    )
}

fn max_abs_diff(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    (0..4).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max)
}

/// One step's deviation bound. Each stage's sine and cosine is within 2 ulp + 6·10⁻¹⁷ of
/// libm's (2 ulp + 1.1·10⁻¹⁶ for stage offsets beyond 1/32 rad; ulp ≤ 2.8·10⁻¹⁷ for the
/// sines of |θ| < 0.25 and 1.1·10⁻¹⁶ for the cosines) and the prescaled constants add a few
/// roundings, which moves θ̈ by at most
/// (m_p g l_p + m_p l_p |z̈|)/J · 5·10⁻¹⁶ (the sines and cosines' few ulp, times the
/// constants they multiply, plus a few roundings of those terms)
/// = (33.3 + 3.39 · 44) · 5·10⁻¹⁶ ≈ 1·10⁻¹³ 1/s² here (|z̈| ≤ a_c |ż| + b_c · 5 V ≤ 44 m/s²
/// for |ż| ≤ 3.5 m/s, the drive's terminal speed b_c · 5/a_c); RK4's weights sum to one, so
/// the step moves θ̇ by at most h · 1·10⁻¹³ = 2·10⁻¹⁵ (θ by h times less), and the
/// anchored step's reordered final sums add two roundings of values below 5 (≤ 2·10⁻¹⁵):
/// 1·10⁻¹⁴ leaves a factor ~2.5 of margin.
const STEP_TOL: f64 = 1e-14;

/// Over 2000 random-policy episodes (uniform actions in ±5 V, CartPole-v1 resets from the
/// same seeds), every step of the anchored environment from the general environment's state
/// stays within `STEP_TOL` of the general step, the seeded resets agree exactly, and the
/// anchored path does differ from libm somewhere (so the comparison is not vacuous).
#[test]
fn anchored_steps_are_within_the_documented_bound_of_libm_steps() {
    let (mut general, mut fast) = envs();
    let mut next = actions(1, 5.0);
    let (mut worst, mut steps) = (0.0f64, 0usize);
    for e in 0..2000u64 {
        assert_eq!(general.reset(Some(e)), fast.reset(Some(e)));
        loop {
            let x = general.observation();
            fast.reset_to(x).unwrap();
            let a = next();
            let (sa, sb) = (general.step(a).unwrap(), fast.step(a).unwrap());
            let d = max_abs_diff(&sa.obs, &sb.obs);
            assert!(
                d <= STEP_TOL,
                "step from {x:?}, action {a}: deviation {d:e}"
            );
            worst = worst.max(d);
            steps += 1;
            if sa.terminated || sa.truncated {
                break;
            }
        }
    }
    assert!(steps > 10_000, "{steps} steps");
    assert!(worst > 0.0, "the anchored path never differed from libm");
}

/// Whole episodes: the same seeds and actions give episodes of the same length ending the
/// same way, and the states stay within the per-step bound accumulated and amplified by the
/// unstable pendulum: deviations grow at most like e^{λ t} with λ ≤ √(max ∂θ̈/∂θ) =
/// √((m_p g l_p + m_p l_p sin 12° · 44)/J) = √(33.3 + 31) ≈ 8 1/s, so after `n` steps
/// the deviation is below n · STEP_TOL · e^{8 n h} (and the episode ends alike unless a state
/// lies within that of a termination bound, which random states do not).
#[test]
fn anchored_episodes_end_alike_and_stay_close() {
    let (mut general, mut fast) = envs();
    let mut next = actions(2, 5.0);
    let h = general.config().dt;
    let mut lengths = 0usize;
    for e in 0..2000u64 {
        general.reset(Some(e));
        fast.reset(Some(e));
        let mut n = 0usize;
        loop {
            let a = next();
            let (sa, sb) = (general.step(a).unwrap(), fast.step(a).unwrap());
            n += 1;
            let bound = n as f64 * STEP_TOL * (8.0 * n as f64 * h).exp();
            let d = max_abs_diff(&sa.obs, &sb.obs);
            assert!(d <= bound, "episode {e} step {n}: {d:e} > {bound:e}");
            assert_eq!(
                (sa.terminated, sa.truncated, sa.reward),
                (sb.terminated, sb.truncated, sb.reward),
                "episode {e} step {n}"
            );
            if sa.terminated || sa.truncated {
                break;
            }
        }
        lengths += n;
    }
    // Random voltages topple the pendulum within a second or so (CartPole-like).
    assert!(
        lengths > 2000 * 5,
        "mean length {}",
        lengths as f64 / 2000.0
    );
}

/// A balancing policy (LQR on the upright model, Q = diag(10, 10, 0, 0), R = 1) through the
/// whole 500-step episode, each environment in its own closed loop: both truncate at 500
/// without terminating, and the stable closed loop (its slowest mode decaying) keeps the
/// accumulated deviation near the sum of the per-step ones, 500 · STEP_TOL = 5·10⁻¹², below
/// 1·10⁻¹¹.
#[test]
fn anchored_env_balances_like_the_general_env() {
    let (mut general, mut fast) = envs();
    let sys = CartPendulum::book()
        .linearize(CartEquilibrium::upright())
        .unwrap();
    let q = Mat::from_row_slice(
        4,
        4,
        &[
            10.0, 0.0, 0.0, 0.0, 0.0, 10.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        ],
    );
    let k = pendulab_lti::design::lqr(&sys, &q, &Mat::identity(1, 1), None)
        .unwrap()
        .gain;
    let x0 = general.reset(Some(4));
    assert_eq!(fast.reset(Some(4)), x0);
    let mut worst = 0.0f64;
    let mut n = 0;
    loop {
        // Each environment in its own closed loop (the open-loop plant is unstable: driven by
        // the other's commands, any difference would grow like e^{5.75 t}).
        let policy = |obs: [f64; 4]| -(0..4).map(|j| k[(0, j)] * obs[j]).sum::<f64>();
        let (ua, ub) = (policy(general.observation()), policy(fast.observation()));
        let (sa, sb) = (general.step(ua).unwrap(), fast.step(ub).unwrap());
        worst = worst.max(max_abs_diff(&sa.obs, &sb.obs));
        n += 1;
        if sa.terminated || sa.truncated {
            assert!(sa.truncated && !sa.terminated, "fell at {n}");
            assert_eq!((sb.truncated, sb.terminated), (true, false));
            break;
        }
    }
    assert_eq!(n, 500);
    assert!(worst < 1e-11, "{worst:e}");
    // The eigenvalue the amplification bound above uses: the fixed-cart pendulum's unstable
    // one (the cart rows of A are decoupled from θ, so these are A's unstable eigenvalues).
    let [up, _] = CartPendulum::book()
        .fixed_cart()
        .eigenvalues(Posture::Upright);
    assert!(up.re > 5.0 && up.re < 8.0, "{up}");
}

/// The anchored environment refuses what the general one refuses.
#[test]
fn anchored_env_errors() {
    let (mut general, mut fast) = envs();
    general.reset(Some(1));
    fast.reset(Some(1));
    assert!(matches!(
        fast.step(f64::NAN),
        Err(SimError::NonFiniteCommand { index: 0, .. })
    ));
    assert!(matches!(
        general.step(f64::NAN),
        Err(SimError::NonFiniteCommand { index: 0, .. })
    ));
    assert!(fast.reset_to([f64::INFINITY, 0.0, 0.0, 0.0]).is_err());
    assert!(
        FixedEnv::<_, 4>::new(
            FastCart::new(CartPendulum::book(), Trig::Anchored),
            EnvConfig::cart_pole(0.4)
                .map(|c| EnvConfig { max_steps: 0, ..c })
                .unwrap()
        )
        .is_err()
    );
}
