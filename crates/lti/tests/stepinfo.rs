//! `stepinfo`: every characteristic against python-control's `step_info` (fixture of
//! `tools/reference/lti_toolbox_reference.py`) and the closed forms of first- and
//! second-order step responses.

mod toolbox_support;

use pendulab_lti::stepinfo::{StepInfoOptions, stepinfo, stepinfo_data};
use pendulab_lti::{LtiError, TransferFunction};

/// 30 stable SISO systems on python's own time grid: the sample-based times equal, the
/// values to 1e-8 relative. python-control includes the final value in SettlingMin/Max;
/// MATLAB (and we) take the response after the rise only, so the comparison is
/// `min(ours, y_final) = python's` (and `max` likewise).
#[test]
fn stepinfo_matches_python_control() {
    let cases = toolbox_support::cases("stepinfo");
    assert_eq!(cases.len(), 30);
    for (k, case) in cases.iter().enumerate() {
        let toolbox_support::Sys::C(sys) = toolbox_support::system(case) else {
            panic!("continuous cases only");
        };
        let tf = case["t_final"].as_f64().unwrap();
        let n = case["samples"].as_u64().unwrap() as usize;
        let step = tf / (n - 1) as f64;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * step).collect();
        let info = stepinfo(&sys, &t, &StepInfoOptions::default()).unwrap()[0][0];
        let r = &case["info"];
        let want = |key: &str| r[key].as_f64().unwrap();
        let yf = want("SteadyStateValue");
        let close = |a: f64, b: f64, what: &str| {
            assert!(
                (a - b).abs() <= 1e-8 * b.abs().max(yf.abs()),
                "case {k} {what}: {a} vs {b} ({info:?})"
            )
        };
        close(info.steady_state_value, yf, "final value");
        for (got, key) in [
            (info.rise_time, "RiseTime"),
            (info.settling_time, "SettlingTime"),
            (info.peak_time, "PeakTime"),
        ] {
            assert!(
                (got - want(key)).abs() <= 1e-9 * tf,
                "case {k} {key}: {got} vs {} ({info:?})",
                want(key)
            );
        }
        close(info.peak, want("Peak"), "peak");
        close(
            info.overshoot / 100.0,
            want("Overshoot") / 100.0,
            "overshoot",
        );
        close(
            info.undershoot / 100.0,
            want("Undershoot") / 100.0,
            "undershoot",
        );
        close(
            info.settling_min.min(yf),
            want("SettlingMin"),
            "settling min",
        );
        close(
            info.settling_max.max(yf),
            want("SettlingMax"),
            "settling max",
        );
    }
}

/// `1/(τ s + 1)`: rise time `τ ln 9`, settling time (2 %) `τ ln 50`, no overshoot, peak at
/// the end; ωn²/(s² + 2ζωn s + ωn²): overshoot `100 e^{−πζ/√(1−ζ²)}` % at
/// `t_p = π/(ωn√(1 − ζ²))`; times to one sample (1e-4 s here).
#[test]
fn closed_forms() {
    let dt = 1e-4;
    let t: Vec<f64> = (0..=100_000).map(|i| i as f64 * dt).collect();
    for tau in [0.5, 1.3] {
        let g = TransferFunction::continuous(&[1.0], &[tau, 1.0])
            .unwrap()
            .to_state_space()
            .unwrap();
        let i = stepinfo(&g, &t, &StepInfoOptions::default()).unwrap()[0][0];
        assert!((i.rise_time - tau * 9f64.ln()).abs() <= dt, "{i:?}");
        assert!((i.settling_time - tau * 50f64.ln()).abs() <= dt, "{i:?}");
        assert_eq!(i.overshoot, 0.0);
        assert_eq!(i.undershoot, 0.0);
    }
    for (zeta, wn) in [(0.2, 2.0), (0.5, 5.0), (0.7, 1.0)] {
        let g = TransferFunction::continuous(&[wn * wn], &[1.0, 2.0 * zeta * wn, wn * wn])
            .unwrap()
            .to_state_space()
            .unwrap();
        let i = stepinfo(&g, &t, &StepInfoOptions::default()).unwrap()[0][0];
        let wd = wn * (1.0 - zeta * zeta).sqrt();
        let os = 100.0 * (-std::f64::consts::PI * zeta / (1.0 - zeta * zeta).sqrt()).exp();
        assert!((i.overshoot - os).abs() <= 1e-5 * os, "{i:?} vs {os}");
        assert!(
            (i.peak_time - std::f64::consts::PI / wd).abs() <= dt,
            "{i:?}"
        );
        assert!((i.peak - (1.0 + os / 100.0)).abs() <= 1e-7);
        assert!((i.settling_max - i.peak).abs() <= 1e-15);
    }
}

/// The non-minimum-phase response `y = 1 − e^{−t} − 2t e^{−t}` (the step response of
/// `(1 − s)/(s + 1)²`) dips to `1 − 2e^{−1/2}` at `t = 1/2`: the undershoot is
/// `100·(2e^{−1/2} − 1)/y_final` %; shifting the data and `y_init` together changes no time
/// and no percentage.
#[test]
fn undershoot_and_initial_value() {
    let dt = 1e-3;
    let t: Vec<f64> = (0..=20_000).map(|i| i as f64 * dt).collect();
    // Y(s) = (1 − s)/(s (s + 1)²) = 1/s − 1/(s + 1) − 2/(s + 1)².
    let y: Vec<f64> = t
        .iter()
        .map(|&t| 1.0 - (-t).exp() - 2.0 * t * (-t).exp())
        .collect();
    let i = stepinfo_data(&t, &y, &StepInfoOptions::default()).unwrap();
    // min of y: y' = e^{−t}(1 − 2 + 2t) = 0 at t = 1/2, y(1/2) = 1 − 2e^{−1/2}.
    let ymin = 1.0 - 2.0 * (-0.5f64).exp();
    let final_y = *y.last().unwrap();
    assert!(
        (i.undershoot - 100.0 * (-ymin) / final_y).abs() <= 1e-5,
        "{i:?}"
    );
    // Shifting the data and y_init by the same offset changes no time and no percentage.
    let shifted: Vec<f64> = y.iter().map(|v| v + 3.0).collect();
    let j = stepinfo_data(
        &t,
        &shifted,
        &StepInfoOptions {
            y_init: 3.0,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(i.rise_time, j.rise_time);
    assert_eq!(i.settling_time, j.settling_time);
    assert!((i.undershoot - j.undershoot).abs() <= 1e-9);
    assert!((i.overshoot - j.overshoot).abs() <= 1e-9);
}

/// Typed errors for bad data and options; an unstable system gives NaN characteristics.
#[test]
fn errors_and_unstable_systems() {
    let o = StepInfoOptions::default();
    assert!(matches!(
        stepinfo_data(&[0.0, 1.0], &[1.0], &o),
        Err(LtiError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        stepinfo_data(&[], &[], &o),
        Err(LtiError::InvalidArgument(_))
    ));
    assert!(matches!(
        stepinfo_data(&[0.0, 0.0], &[0.0, 1.0], &o),
        Err(LtiError::InvalidArgument(_))
    ));
    assert!(matches!(
        stepinfo_data(&[0.0, 1.0], &[0.0, f64::NAN], &o),
        Err(LtiError::NonFinite { .. })
    ));
    let bad = StepInfoOptions {
        rise_time_limits: (0.9, 0.1),
        ..o
    };
    assert!(matches!(
        stepinfo_data(&[0.0, 1.0], &[0.0, 1.0], &bad),
        Err(LtiError::InvalidArgument(_))
    ));
    let unstable = TransferFunction::continuous(&[1.0], &[1.0, -1.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let t: Vec<f64> = (0..100).map(|i| i as f64 * 0.01).collect();
    let i = stepinfo(&unstable, &t, &o).unwrap()[0][0];
    assert!(i.rise_time.is_nan() && i.overshoot.is_nan() && i.steady_state_value.is_nan());
}
