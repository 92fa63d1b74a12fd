//! Time responses: closed forms, superposition (book p1c41), error handling.

mod sys_support;

use pendulab_lti::response::{
    InputHold, LsimKernel, LsimOptions, default_final_time, impulse, initial, lsim, lsim_split,
    response_times, step, time_vector,
};
use pendulab_lti::{Continuous, Discretization, LtiError, Mat, StateSpace};
use sys_support::{assert_same_poles, c, mat};

fn first_order(a: f64, b: f64) -> StateSpace<Continuous> {
    StateSpace::continuous(
        mat(1, 1, &[-a]),
        mat(1, 1, &[b]),
        mat(1, 1, &[1.0]),
        mat(1, 1, &[0.0]),
    )
    .unwrap()
}

/// The grid from a final time and the default final time: 7 time constants of the slowest
/// decaying pole, 5 e-folding times of a growing one, ten periods of an undamped pair, 10 s
/// without a time scale; a discrete system's grid at its dt; the refusals.
#[test]
fn response_times_and_the_default_final_time() {
    let t = response_times(&first_order(2.0, 1.0), Some(3.0), None).unwrap();
    assert_eq!((t.len(), t[0]), (1001, 0.0));
    assert!((t[1000] - 3.0).abs() <= 1e-15);
    let t = response_times(&first_order(2.0, 1.0), Some(3.0), Some(0.5)).unwrap();
    assert_eq!(t, vec![0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0]);
    let slow_and_fast = StateSpace::continuous(
        mat(2, 2, &[-0.5, 0.0, 0.0, -4.0]),
        mat(2, 1, &[1.0, 1.0]),
        mat(1, 2, &[1.0, 1.0]),
        mat(1, 1, &[0.0]),
    )
    .unwrap();
    assert!((default_final_time(&slow_and_fast).unwrap() - 14.0).abs() <= 1e-12);
    let growing = StateSpace::continuous(
        mat(2, 2, &[-0.5, 0.0, 0.0, 2.0]),
        mat(2, 1, &[1.0, 1.0]),
        mat(1, 2, &[1.0, 1.0]),
        mat(1, 1, &[0.0]),
    )
    .unwrap();
    assert!((default_final_time(&growing).unwrap() - 2.5).abs() <= 1e-12);
    // ẍ = −4x: ω = 2, ten periods 10π.
    let undamped = StateSpace::continuous(
        mat(2, 2, &[0.0, 1.0, -4.0, 0.0]),
        mat(2, 1, &[0.0, 1.0]),
        mat(1, 2, &[1.0, 0.0]),
        mat(1, 1, &[0.0]),
    )
    .unwrap();
    assert!((default_final_time(&undamped).unwrap() - 10.0 * std::f64::consts::PI).abs() <= 1e-9);
    assert_eq!(default_final_time(&first_order(0.0, 1.0)).unwrap(), 10.0);
    // z = 0.5 at dt = 0.1: s = ln 0.5 / 0.1, 7/|s| = 1.0099 s → 11 steps.
    let d = StateSpace::discrete(
        mat(1, 1, &[0.5]),
        mat(1, 1, &[1.0]),
        mat(1, 1, &[1.0]),
        mat(1, 1, &[0.0]),
        0.1,
    )
    .unwrap();
    let t = response_times(&d, None, None).unwrap();
    assert_eq!(t.len(), 12);
    assert!((t[11] - 1.1).abs() <= 1e-12);
    let refused = |e: LtiError, what: &str| {
        assert!(
            matches!(&e, LtiError::InvalidArgument(m) if m.contains(what)),
            "{e}"
        );
    };
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        refused(
            response_times(&first_order(2.0, 1.0), Some(bad), None).unwrap_err(),
            "final time",
        );
        refused(
            response_times(&first_order(2.0, 1.0), Some(1.0), Some(bad)).unwrap_err(),
            "time step",
        );
    }
    refused(
        response_times(&d, Some(1.0), Some(0.1)).unwrap_err(),
        "discrete",
    );
    refused(
        response_times(&first_order(2.0, 1.0), Some(1e3), Some(1e-6)).unwrap_err(),
        "at most",
    );
}

#[test]
fn lsim_first_order_closed_forms() {
    // ẋ = −a x + b u, x(0) = x0.
    let (a, b, x0) = (2.0f64, 3.0, 0.7);
    let sys = first_order(a, b);
    let t = time_vector(3.0, 0.01).unwrap();
    // Step input: x = x0 e^{−at} + (b/a)(1 − e^{−at}); exact for both holds.
    let u = Mat::from_element(t.len(), 1, 1.0);
    for hold in [InputHold::Zoh, InputHold::Foh] {
        let tr = lsim(&sys, &u, &t, Some(&[x0]), &LsimOptions { hold }).unwrap();
        for (k, &tk) in t.iter().enumerate() {
            let exact = x0 * (-a * tk).exp() + b / a * (1.0 - (-a * tk).exp());
            // Exact discretisation, so only rounding: the recursion converges to
            // Γ/(1 − Φ), whose relative sensitivity to the rounding of Φ = e^{−0.02} is
            // 1/(1 − Φ) ≈ 50, and the accumulated per-step rounding is Σ Φʲ u ≈ 50u; on the
            // O(1.5) solution that is ≈ 1.5·100u ≈ 1.7e-14, so 5e-14.
            let err = (tr.y()[(k, 0)] - exact).abs();
            assert!(err < 5e-14, "{hold:?} k={k}: {err:e}");
        }
    }
    // Ramp input u = t with FOH: x = x0 e^{−at} + (b/a)(t − (1 − e^{−at})/a), exact at samples.
    let u = Mat::from_fn(t.len(), 1, |k, _| t[k]);
    let tr = lsim(&sys, &u, &t, Some(&[x0]), &LsimOptions::default()).unwrap();
    for (k, &tk) in t.iter().enumerate() {
        let e = (-a * tk).exp();
        let exact = x0 * e + b / a * (tk - (1.0 - e) / a);
        assert!((tr.x()[(k, 0)] - exact).abs() < 1e-13, "ramp k={k}");
    }
    // The same ramp with ZOH is a staircase: x_{k+1} = Φx_k + Γ t_k, so at the end it lags
    // the FOH answer by the held half step: the difference must be visibly non-zero
    // (≈ b/a · dt/2 ≈ 0.0075), which shows the hold really changes the result.
    let trz = lsim(
        &sys,
        &u,
        &t,
        Some(&[x0]),
        &LsimOptions {
            hold: InputHold::Zoh,
        },
    )
    .unwrap();
    let last = t.len() - 1;
    let lag = tr.x()[(last, 0)] - trz.x()[(last, 0)];
    assert!((lag - b / a * 0.01 / 2.0).abs() < 1e-4, "lag {lag}");
}

#[test]
fn lsim_sine_response_matches_closed_form_to_foh_accuracy() {
    // ẋ = −x + sin t: x(t) = (sin t − cos t + e^{−t})/2 from 0. FOH interpolation error of a
    // sine is ≤ dt²/8 · max|ü| = 1.25e-5 per interval for dt = 0.01, filtered by the
    // (unit-gain) lag: error ≤ 1.25e-5 overall; with ZOH it is first order (≈ dt/2 = 5e-3).
    let sys = first_order(1.0, 1.0);
    let t = time_vector(10.0, 0.01).unwrap();
    let u = Mat::from_fn(t.len(), 1, |k, _| t[k].sin());
    let tr = lsim(&sys, &u, &t, None, &LsimOptions::default()).unwrap();
    let mut max_err: f64 = 0.0;
    for (k, &tk) in t.iter().enumerate() {
        let exact = 0.5 * (tk.sin() - tk.cos() + (-tk).exp());
        max_err = max_err.max((tr.y()[(k, 0)] - exact).abs());
    }
    assert!(max_err < 1.25e-5, "FOH error {max_err:e}");
    assert!(
        max_err > 1e-9,
        "the bound is not vacuous: error {max_err:e}"
    );
}

#[test]
fn p1c41_cdip_response_superposition() {
    // Book p1c41: A = [[0, 1], [−b_c k_P, −a_c]], B = [0; 1], C = [b_c k_P, 0], k_P = 1,
    // x0 = [1, 1], r = 2 sin t, t = 0:0.01:10; y3 = y1 + y2 to ≤ 1e-12 (book eq. 4.24).
    let (ac, bc, kp) = (6.25, 4.36, 1.0);
    let sys = StateSpace::continuous(
        mat(2, 2, &[0.0, 1.0, -bc * kp, -ac]),
        mat(2, 1, &[0.0, 1.0]),
        mat(1, 2, &[bc * kp, 0.0]),
        mat(1, 1, &[0.0]),
    )
    .unwrap();
    // eig: roots of s² + a_c s + b_c k_P (closed form, both real here).
    let disc = (ac * ac - 4.0 * bc * kp).sqrt();
    assert_same_poles(
        &sys.poles().unwrap(),
        &[c((-ac + disc) / 2.0, 0.0), c((-ac - disc) / 2.0, 0.0)],
        1e-13,
    );
    let t = time_vector(10.0, 0.01).unwrap();
    assert_eq!(t.len(), 1001);
    let u = Mat::from_fn(t.len(), 1, |k, _| 2.0 * t[k].sin());
    let split = lsim_split(&sys, &u, &t, &[1.0, 1.0], &LsimOptions::default()).unwrap();
    let y1 = split.zero_input.y_signal(0);
    let y2 = split.zero_state.y_signal(0);
    let y3 = split.total.y_signal(0);
    let err = (0..t.len())
        .map(|k| (y3[k] - y1[k] - y2[k]).abs())
        .fold(0.0, f64::max);
    assert!(err <= 1e-12, "superposition error {err:e}");
    // And y3 really is a response (not identically zero): y1(0) = C x0 = b_c.
    assert!((y3[0] - bc).abs() < 1e-15);
}

#[test]
fn step_and_impulse_of_second_order_system() {
    // G = ωn²/(s² + 2ζωn s + ωn²), ζ = 0.5, ωn = 2: step
    // y = 1 − e^{−ζωn t}(cos ωd t + ζ/√(1−ζ²) sin ωd t); impulse y = ωn/√(1−ζ²) e^{−ζωn t} sin ωd t.
    let (z, wn) = (0.5f64, 2.0f64);
    let wd = wn * (1.0 - z * z).sqrt();
    let sys = StateSpace::continuous(
        mat(2, 2, &[0.0, 1.0, -wn * wn, -2.0 * z * wn]),
        mat(2, 1, &[0.0, wn * wn]),
        mat(1, 2, &[1.0, 0.0]),
        mat(1, 1, &[0.0]),
    )
    .unwrap();
    let t = time_vector(6.0, 0.05).unwrap();
    let s = &step(&sys, &t).unwrap()[0];
    let im = &impulse(&sys, &t).unwrap()[0];
    for (k, &tk) in t.iter().enumerate() {
        let e = (-z * wn * tk).exp();
        let ys = 1.0 - e * ((wd * tk).cos() + z / (1.0 - z * z).sqrt() * (wd * tk).sin());
        let yi = wn / (1.0 - z * z).sqrt() * e * (wd * tk).sin();
        // Exact discretisation; rounding only (1e-13 on O(1) values).
        assert!((s.y()[(k, 0)] - ys).abs() < 1e-13, "step k={k}");
        assert!((im.y()[(k, 0)] - yi).abs() < 1e-13, "impulse k={k}");
    }
}

#[test]
fn discrete_responses() {
    // x[k+1] = 0.5 x[k] + u[k], y = x: step y[k] = 2(1 − 0.5ᵏ); MATLAB impulse (unit-area
    // pulse 1/ts at k = 0): y[k] = 0.5^{k−1}/ts for k ≥ 1.
    let ts = 0.1;
    let sys = StateSpace::discrete(
        mat(1, 1, &[0.5]),
        mat(1, 1, &[1.0]),
        mat(1, 1, &[1.0]),
        mat(1, 1, &[0.0]),
        ts,
    )
    .unwrap();
    let t: Vec<f64> = (0..10).map(|k| k as f64 * ts).collect();
    let s = &step(&sys, &t).unwrap()[0];
    let im = &impulse(&sys, &t).unwrap()[0];
    for k in 0..10 {
        assert!((s.y()[(k, 0)] - 2.0 * (1.0 - 0.5f64.powi(k as i32))).abs() < 1e-15);
        let want = if k == 0 {
            0.0
        } else {
            0.5f64.powi(k as i32 - 1) / ts
        };
        assert!((im.y()[(k, 0)] - want).abs() < 1e-13);
    }
    // The time step must equal the sample time.
    let bad: Vec<f64> = (0..10).map(|k| k as f64 * 0.2).collect();
    assert!(matches!(
        step(&sys, &bad),
        Err(LtiError::NonUniformTime { expected, .. }) if expected == ts
    ));
}

#[test]
fn continuous_lsim_agrees_with_lsim_of_the_zoh_discretisation() {
    // Two routes to the same samples: lsim with ZOH hold on the continuous system, and lsim
    // of c2d(sys, ZOH) (same exact map, different code path). Cart pendulum, 3 s.
    let (a, b) = sys_support::cdip();
    let sys = StateSpace::continuous(a, b, Mat::identity(4, 4), Mat::zeros(4, 1)).unwrap();
    let dt = 0.002;
    let t = time_vector(3.0, dt).unwrap();
    let u = Mat::from_fn(t.len(), 1, |k, _| (3.0 * t[k]).cos());
    let x0 = [0.01, 0.05, 0.0, -0.1];
    let tc = lsim(
        &sys,
        &u,
        &t,
        Some(&x0),
        &LsimOptions {
            hold: InputHold::Zoh,
        },
    )
    .unwrap();
    let sd = sys.c2d(dt, Discretization::Zoh).unwrap();
    let td = lsim(&sd, &u, &t, Some(&x0), &LsimOptions::default()).unwrap();
    // Unstable plant (pole +5.75): rounding grows like e^{5.75·3} ≈ 3e7 relative to 1e-16,
    // so compare relative to the size of the response, 1e-8.
    let scale = tc.x().norm();
    assert!((tc.x() - td.x()).norm() < 1e-8 * scale);
}

#[test]
fn kernel_handles_large_and_multi_input_systems() {
    // 10 states (dynamic path) and 2 inputs: compare lsim with the explicit recursion on the
    // c2d matrices.
    let n = 10;
    let a = Mat::from_fn(n, n, |i, j| {
        if i == j {
            -1.0 - i as f64 * 0.1
        } else {
            0.05 * ((i * 7 + j * 3) % 5) as f64 - 0.1
        }
    });
    let b = Mat::from_fn(n, 2, |i, j| ((i + 2 * j) % 3) as f64 - 1.0);
    let cm = Mat::from_fn(3, n, |i, j| ((i + j) % 4) as f64 * 0.25);
    let d = Mat::from_fn(3, 2, |i, j| (i + j) as f64 * 0.1);
    let sys = StateSpace::continuous(a, b, cm, d).unwrap();
    let t = time_vector(1.0, 0.01).unwrap();
    let u = Mat::from_fn(t.len(), 2, |k, j| ((k + j) as f64 * 0.1).sin());
    let tr = lsim(
        &sys,
        &u,
        &t,
        None,
        &LsimOptions {
            hold: InputHold::Zoh,
        },
    )
    .unwrap();
    let sd = sys.c2d(0.01, Discretization::Zoh).unwrap();
    let mut x = pendulab_lti::Vector::zeros(n);
    for k in 0..t.len() {
        let uk = u.row(k).transpose();
        let y = sd.c() * &x + sd.d() * &uk;
        for i in 0..3 {
            assert!((tr.y()[(k, i)] - y[i]).abs() < 1e-13);
        }
        x = sd.a() * &x + sd.b() * &uk;
    }
    // The low-level kernel validates buffer sizes.
    let kern = LsimKernel::new(&sys, 0.01, InputHold::Foh).unwrap();
    let mut xo = vec![0.0; 5 * n];
    let mut yo = vec![0.0; 4];
    assert!(
        kern.run(5, &[0.0; 10], &[0.0; 10], &mut xo, &mut yo)
            .is_err()
    );
}

#[test]
fn lsim_rejects_bad_input() {
    let sys = first_order(1.0, 1.0);
    let t = time_vector(1.0, 0.1).unwrap();
    let opts = LsimOptions::default();
    // Wrong input shape.
    assert!(matches!(
        lsim(&sys, &Mat::zeros(t.len() - 1, 1), &t, None, &opts),
        Err(LtiError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        lsim(&sys, &Mat::zeros(t.len(), 2), &t, None, &opts),
        Err(LtiError::DimensionMismatch { .. })
    ));
    // NaN in u, named with its sample.
    let mut u = Mat::zeros(t.len(), 1);
    u[(4, 0)] = f64::NAN;
    assert!(matches!(
        lsim(&sys, &u, &t, None, &opts),
        Err(LtiError::NonFinite { row: 4, col: 0, .. })
    ));
    // Uneven time vector, naming the step.
    let mut tt = t.clone();
    tt[5] += 0.03;
    assert!(matches!(
        lsim(&sys, &Mat::zeros(t.len(), 1), &tt, None, &opts),
        Err(LtiError::NonUniformTime { index: 4, .. })
    ));
    // NaN time, decreasing time, empty time.
    let mut tn = t.clone();
    tn[2] = f64::NAN;
    assert!(lsim(&sys, &Mat::zeros(t.len(), 1), &tn, None, &opts).is_err());
    let rev: Vec<f64> = t.iter().rev().copied().collect();
    assert!(lsim(&sys, &Mat::zeros(t.len(), 1), &rev, None, &opts).is_err());
    assert!(lsim(&sys, &Mat::zeros(0, 1), &[], None, &opts).is_err());
    // Wrong x0 length, NaN x0.
    assert!(matches!(
        initial(&sys, &[1.0, 2.0], &t),
        Err(LtiError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        initial(&sys, &[f64::INFINITY], &t),
        Err(LtiError::NonFinite { .. })
    ));
    // A single sample is a valid (trivial) simulation: y = C x0.
    let one = initial(&sys, &[2.5], &[0.0]).unwrap();
    assert_eq!(one.y()[(0, 0)], 2.5);
}

#[test]
fn static_gain_and_feedthrough_responses() {
    // A system without states is y = D u at every sample.
    let k = StateSpace::static_gain(mat(2, 1, &[2.0, -0.5]), Continuous).unwrap();
    let t = time_vector(0.3, 0.1).unwrap();
    let u = Mat::from_fn(t.len(), 1, |i, _| i as f64);
    let tr = lsim(&k, &u, &t, None, &LsimOptions::default()).unwrap();
    for i in 0..t.len() {
        assert_eq!(tr.y()[(i, 0)], 2.0 * i as f64);
        assert_eq!(tr.y()[(i, 1)], -0.5 * i as f64);
    }
    assert_eq!(tr.x().ncols(), 0);
}
