//! Identification of data simulated from known parameters with pendulab-lti's exact `lsim`,
//! quantised like the rigs' encoders (`docs/model.md` §3): the estimates must come back within
//! tolerances derived from the quantisation.

use pendulab_ident::validation::drive_model;
use pendulab_ident::*;
use pendulab_lti::Mat;
use pendulab_lti::response::{InputHold, LsimOptions, lsim};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

const TS: f64 = 1e-3;
/// Cart encoder step, m.
const Q_CART: f64 = 4.8414e-5;
/// Arm encoder step, rad.
const Q_ARM: f64 = 2.0 * std::f64::consts::PI / 200_000.0;

fn quantise(x: &[f64], q: f64) -> Vec<f64> {
    x.iter().map(|v| (v / q).round() * q).collect()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Position of the drive `ÿ = −a ẏ + b v` from rest under the held input `v`.
fn simulate_drive(a: f64, b: f64, v: &[f64]) -> Vec<f64> {
    let t: Vec<f64> = (0..v.len()).map(|k| k as f64 * TS).collect();
    let tr = lsim(
        &drive_model(a, b).unwrap(),
        &Mat::from_column_slice(v.len(), 1, v),
        &t,
        None,
        &LsimOptions {
            hold: InputHold::Zoh,
        },
    )
    .unwrap();
    tr.y_signal(0).to_vec()
}

#[test]
fn p1c221_open_loop_velocity_steps() {
    // Book part 1 §2.2.1 (p1c221_id_cart.m): open-loop steps of 0.8, 0.9, 1.0, 1.1 V on the linear
    // drive with the book's a_c = 6.25, b_c = 4.36 (K = b/a = 0.6976 m/(s V), T = 1/a = 0.16 s),
    // the position quantised to the encoder step; K from the mean velocity over 1.4–1.5 s, T from
    // the first 63.2 % crossing; a = 1/T̄, b = K̄/T̄ (book: ≈ 6.250, 4.362).
    let (a, b) = (6.25, 4.36);
    let n = 1501; // 0 … 1.5 s
    let t: Vec<f64> = (0..n).map(|k| k as f64 * TS).collect();
    let mut steps = Vec::new();
    for u in [0.8, 0.9, 1.0, 1.1] {
        let z = quantise(&simulate_drive(a, b, &vec![u; n]), Q_CART);
        let s = velocity_step(
            &t,
            &z,
            &VelocityStepOptions {
                step_time: 0.0,
                input: u,
                gain_window: (1.4, 1.5),
            },
        )
        .unwrap();
        // K: the window mean of three-point differences telescopes to (end − start
        // differences)/(2 ts · 101), at most 2q/(0.202 s) = 4.8e-4 m/s of quantisation error,
        // plus the unfinished exponential e^{−1.4/0.16} = 1.6e-4 of K u: 0.2 % covers both.
        assert!(rel(s.gain, b / a) < 2e-3, "u = {u}: K = {}", s.gain);
        steps.push(s);
    }
    let e = drive_from_velocity_steps(&steps).unwrap();
    // T: a velocity error δ shifts the crossing by δ/slope, slope = K u/(e T) ≈ 1.6 u m/s²;
    // quantisation gives three-point velocity errors of standard deviation q/(√6 · ts)·½ ≈
    // 0.01 m/s, so ≈ 6 ms per step and ≈ 3 ms (2 %) for the mean of four; the first-crossing
    // rule biases T early. Allow 3 % on a and b.
    assert!(rel(e.a, a) < 0.03, "a = {}", e.a);
    assert!(rel(e.b, b) < 0.03, "b = {}", e.b);
    // Without quantisation the recipe itself is exact to the 1 ms grid of the crossing time
    // (≤ 1 ms of 160 ms, 0.6 %).
    let mut exact = Vec::new();
    for u in [0.8, 0.9, 1.0, 1.1] {
        let z = simulate_drive(a, b, &vec![u; n]);
        exact.push(
            velocity_step(
                &t,
                &z,
                &VelocityStepOptions {
                    step_time: 0.0,
                    input: u,
                    gain_window: (1.4, 1.5),
                },
            )
            .unwrap(),
        );
    }
    let e = drive_from_velocity_steps(&exact).unwrap();
    assert!(
        rel(e.a, a) < 0.007 && rel(e.b, b) < 0.007,
        "{} {}",
        e.a,
        e.b
    );
}

/// A square wave of ±amp with the given period (held), zero mean.
fn square(n: usize, amp: f64, period: f64) -> Vec<f64> {
    (0..n)
        .map(|k| {
            if ((k as f64 * TS) / period).fract() < 0.5 {
                amp
            } else {
                -amp
            }
        })
        .collect()
}

#[test]
fn drive_least_squares_round_trip_cart_and_arm() {
    // Open-loop square-wave voltage (±1 V, 2 s period, plus a 0.3 V 0.37 s square so v and ż
    // are not proportional), 20 s at 1 ms; position quantised, plus Gaussian sensor noise of
    // half an encoder step. The book's recipe must return the simulating parameters.
    let n = 20_001;
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for (name, a, b, q) in [("cart", 6.25, 4.36, Q_CART), ("arm", 6.20, 15.8, Q_ARM)] {
        let v: Vec<f64> = square(n, 1.0, 2.0)
            .iter()
            .zip(square(n, 0.3, 0.37))
            .map(|(x, y)| x + y)
            .collect();
        let noise = Normal::new(0.0, 0.5 * q).unwrap();
        let y: Vec<f64> = quantise(&simulate_drive(a, b, &v), q)
            .iter()
            .map(|x| x + noise.sample(&mut rng))
            .collect();
        let est = if name == "cart" {
            cart_drive_ls(TS, &y, &v, &LsOptions::default()).unwrap()
        } else {
            arm_drive_ls(TS, &y, &v, &LsOptions::default()).unwrap()
        };
        // Three-point differences centre the derivative on the sample while the held voltage
        // changes right after it: at each of the ~160 voltage jumps the relation is off for a
        // few samples (a half-sample misalignment), a bias of order ts·(jump rate)·a ≈ 0.5 %.
        // Allow 1 %.
        assert!(rel(est.a, a) < 0.01, "{name}: a = {}", est.a);
        assert!(rel(est.b, b) < 0.01, "{name}: b = {}", est.b);
        // The standard errors are small but, with correlated residuals, not a bound on the
        // error: only check they are finite and positive.
        assert!(est.lsq.std_error.iter().all(|s| s.is_finite() && *s > 0.0));
        // Validation by lsim: the identified model reproduces the noiseless position closely.
        let val = validate_drive(TS, &y, &v, est.a, est.b, "y").unwrap();
        assert!(val.fit_percent > 95.0, "{name}: fit {}", val.fit_percent);
    }
}

#[test]
fn rank_deficient_and_bad_inputs_are_typed_errors() {
    let n = 2000;
    let v = vec![0.0; n];
    let z = vec![0.0; n];
    // No input at all: the regressor [−ż, v] is zero.
    let e = cart_drive_ls(TS, &z, &v, &LsOptions::default()).unwrap_err();
    assert!(matches!(e, IdentError::RankDeficient { .. }), "{e}");
    // Constant input, steady velocity: ż ∝ v, the columns are dependent.
    let v = vec![1.0; n];
    let z: Vec<f64> = (0..n).map(|k| 0.7 * k as f64 * TS).collect();
    let e = cart_drive_ls(TS, &z, &v, &LsOptions::default()).unwrap_err();
    assert!(
        matches!(&e, IdentError::RankDeficient { detail, .. } if detail.contains("bc multiplies v")),
        "{e}"
    );
    // NaN, lengths, too few samples, bad constants.
    let mut zn = z.clone();
    zn[10] = f64::NAN;
    let e = cart_drive_ls(TS, &zn, &v, &LsOptions::default()).unwrap_err();
    assert!(
        matches!(&e, IdentError::NonFinite { column, at, .. } if column == "z" && at.index == 10)
    );
    let mut vi = v.clone();
    vi[1500] = f64::INFINITY;
    let e = cart_drive_ls(TS, &z, &vi, &LsOptions::default()).unwrap_err();
    assert!(
        matches!(&e, IdentError::NonFinite { column, at, .. } if column == "v" && at.index == 1500),
        "{e}"
    );
    let e = cart_drive_ls(TS, &z[..5], &v, &LsOptions::default()).unwrap_err();
    assert!(matches!(e, IdentError::LengthMismatch { .. }));
    let e = cart_drive_ls(TS, &z[..2], &v[..2], &LsOptions::default()).unwrap_err();
    assert!(matches!(e, IdentError::TooFewSamples { .. }));
    let e = cart_pendulum_ls(
        TS,
        &z,
        &z,
        &CartPendulumConstants {
            mp: -1.0,
            ..Default::default()
        },
        &LsOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(e, IdentError::InvalidParameter { .. }));
    let e = cart_drive_ls(
        TS,
        &z,
        &v,
        &LsOptions {
            prefilter: Prefilter::Causal {
                tf: 0.0,
                hold: FilterHold::Zoh,
            },
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(matches!(e, IdentError::InvalidParameter { .. }));
    // Free oscillation with no oscillation: a feature error.
    let t: Vec<f64> = (0..n).map(|k| k as f64 * TS).collect();
    let e = free_oscillation(&t, &vec![0.0; n], &OscillationOptions::default()).unwrap_err();
    assert!(matches!(e, IdentError::FeatureNotFound { .. }));
}

#[test]
fn free_oscillation_survives_quantisation_flicker() {
    // A damped oscillation about 0 quantised to the pendulum encoder (2π/14400 rad) and held
    // long enough for the swing to die into ±1-step flicker: the hysteresis keeps the flicker
    // from making cycles, and the period and decay of the big cycles are those of the model
    // (ω_d, e^{−ζω_n T_d}) to the quantisation of the peak times and amplitudes.
    let (wn, zeta): (f64, f64) = (5.77, 0.01);
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let q = 2.0 * std::f64::consts::PI / 14_400.0;
    let n = 120_000;
    let t: Vec<f64> = (0..n).map(|k| k as f64 * TS).collect();
    let y: Vec<f64> = t
        .iter()
        .map(|&t| {
            let x = 0.3 * (-zeta * wn * t).exp() * (wd * t).cos();
            // A 1-step flicker riding on everything.
            let flick = if (t * 1000.0) as i64 % 2 == 0 {
                0.6 * q
            } else {
                -0.6 * q
            };
            ((x + flick) / q).round() * q
        })
        .collect();
    let osc = free_oscillation(&t, &y, &OscillationOptions::default()).unwrap();
    let td = 2.0 * std::f64::consts::PI / wd;
    let lambda = (-zeta * wn * td).exp();
    // Peaks until the amplitude falls below the hysteresis 0.02·0.3 rad: ln(0.3/0.006)/(ζω_n)
    // ≈ 68 s ≈ 62 cycles; with flicker alone later, no extra cycles appear.
    assert!(
        (55..=66).contains(&osc.peaks.len()),
        "{} peaks",
        osc.peaks.len()
    );
    // Peak times: plateaus of ≥ tens of samples at the top of a slow cosine, midpoint within
    // ~1 ms; mean over 60 periods → ≪ 0.1 %.
    assert!(rel(osc.period, td) < 1e-3, "{} vs {td}", osc.period);
    // Amplitudes quantised to q ≈ 4.4e-4 rad on peaks ≥ 6e-3: each ratio within ~10 %, the
    // mean within ~1 %.
    assert!(
        rel(osc.decay_ratio, lambda) < 0.01,
        "{} vs {lambda}",
        osc.decay_ratio
    );
}

#[test]
fn streamed_route_handles_every_block_boundary() {
    // Lengths around the 256-row block size and the smallest ones: the streamed *_ls route
    // must reproduce the explicit regression (same formulas; rounding only).
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let noise = Normal::new(0.0, 1.0).unwrap();
    for n in [3, 4, 5, 6, 255, 256, 257, 258, 511, 512, 513, 1000] {
        let z: Vec<f64> = (0..n).map(|_| noise.sample(&mut rng)).collect();
        let v: Vec<f64> = (0..n).map(|_| noise.sample(&mut rng)).collect();
        for opts in [
            LsOptions::default(),
            LsOptions {
                prefilter: Prefilter::None,
                ..LsOptions::default()
            },
        ] {
            let a = cart_drive_ls(TS, &z, &v, &opts).unwrap().lsq;
            let b = regression::cart_drive_regression(TS, &z, &v, &opts)
                .unwrap()
                .solve()
                .unwrap();
            for j in 0..2 {
                assert!(
                    (a.estimate[j] - b.estimate[j]).abs() <= 1e-12 * b.estimate[j].abs(),
                    "n = {n}: {} vs {}",
                    a.estimate[j],
                    b.estimate[j]
                );
            }
        }
    }
}
