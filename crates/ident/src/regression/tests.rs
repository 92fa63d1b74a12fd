use super::*;
use crate::differentiate::Differentiator;
use crate::differentiate::savitzky_golay;
use crate::filter::FilterHold;

const TS: f64 = 1e-3;

fn causal(tf: f64) -> LsOptions {
    LsOptions {
        prefilter: Prefilter::Causal {
            tf,
            hold: FilterHold::Zoh,
        },
        ..LsOptions::default()
    }
}

#[test]
fn sample_count_for_the_differentiator() {
    // Three-point twice: a 5-sample stencil, four of them → 20 samples; unfiltered so the
    // filter bound does not interfere.
    let raw = LsOptions {
        prefilter: Prefilter::None,
        ..LsOptions::default()
    };
    assert!(raw.check_data(TS, 20).is_ok());
    let e = raw.check_data(TS, 19).unwrap_err();
    assert!(
        matches!(
            e,
            IdentError::TooFewSamples {
                needed: 20,
                found: 19,
                ..
            }
        ),
        "{e}"
    );
    // Savitzky–Golay: the window, four times.
    let sg = LsOptions {
        differentiator: Differentiator::SavitzkyGolay {
            window: 41,
            order: 3,
        },
        prefilter: Prefilter::None,
    };
    assert!(sg.check_data(TS, 164).is_ok());
    assert!(matches!(
        sg.check_data(TS, 163),
        Err(IdentError::TooFewSamples { needed: 164, .. })
    ));
}

#[test]
fn prefilter_time_constant_against_record_and_sample_time() {
    // Record of 4001 samples = 4 s: T_f up to 0.4 s.
    assert!(causal(0.4).check_data(TS, 4001).is_ok());
    let e = causal(0.41).check_data(TS, 4001).unwrap_err();
    assert!(
        matches!(&e, IdentError::UnsuitedOption { option, .. } if option.contains("T_f")),
        "{e}"
    );
    assert!(matches!(
        causal(1e9).check_data(TS, 4001),
        Err(IdentError::UnsuitedOption { .. })
    ));
    // Short T_f: the twice-applied three-point derivative errs by 1 − (sin x/x)², x = t_s/T_f.
    // Found independently by differentiating a sampled sinusoid at ω = 1/T_f.
    let err_at = |tf: f64| {
        let w = 1.0 / tf;
        let x: Vec<f64> = (0..200).map(|k| (w * k as f64 * TS).sin()).collect();
        let d2 = crate::differentiate::three_point_twice(&x, TS).unwrap();
        // Interior sample 100, away from the ends: exact second derivative −ω² sin.
        let exact = -w * w * (w * 100.0 * TS).sin();
        (d2[100] / exact - 1.0).abs()
    };
    let (short, long) = (4.0 * TS, 8.0 * TS);
    assert!(err_at(short) > MAX_DERIVATIVE_ERROR && err_at(long) < MAX_DERIVATIVE_ERROR);
    assert!(matches!(
        causal(short).check_data(TS, 4001),
        Err(IdentError::UnsuitedOption { .. })
    ));
    assert!(causal(long).check_data(TS, 4001).is_ok());
    // The book's recipe on the book's record passes.
    assert!(LsOptions::default().check_data(TS, 4001).is_ok());
}

#[test]
fn savitzky_golay_window_against_the_dynamics() {
    // The error at the band edge 1/T_f, measured independently by differentiating a
    // sampled sinusoid with the Savitzky–Golay routine (not the kernel's response).
    let measured = |window: usize, tf: f64| {
        let w = 1.0 / tf;
        let n = 3 * window;
        let x: Vec<f64> = (0..n).map(|k| (w * k as f64 * TS).sin()).collect();
        let d1 = savitzky_golay(&x, TS, window, 3, 1).unwrap();
        let d2 = savitzky_golay(&x, TS, window, 3, 2).unwrap();
        let k = n / 2;
        let t = k as f64 * TS;
        let e1 = (d1[k] - w * (w * t).cos()).abs() / w;
        let e2 = (d2[k] + w * w * (w * t).sin()).abs() / (w * w);
        e1.max(e2)
    };
    let sg = |window: usize, tf: f64| LsOptions {
        differentiator: Differentiator::SavitzkyGolay { window, order: 3 },
        ..causal(tf)
    };
    // 41 samples (40 ms) against T_f = 0.075 s: accurate, accepted.
    assert!(measured(41, 0.075) < MAX_DERIVATIVE_ERROR);
    assert!(sg(41, 0.075).check_data(TS, 4001).is_ok());
    // 301 samples (0.3 s) against T_f = 0.075 s: inaccurate, refused (the record is long
    // enough for the stencil count and the filter, so the window is what is named).
    assert!(measured(301, 0.075) > MAX_DERIVATIVE_ERROR);
    let e = sg(301, 0.075).check_data(TS, 20_001).unwrap_err();
    assert!(
        matches!(&e, IdentError::UnsuitedOption { option, .. } if option.contains("Savitzky")),
        "{e}"
    );
    // The 4001-sample window on the 4001-sample record: too few stencils.
    assert!(matches!(
        sg(4001, 0.075).check_data(TS, 4001),
        Err(IdentError::TooFewSamples { .. })
    ));
}

#[test]
fn constants_out_of_range_are_named() {
    assert!(CartPendulumConstants::default().check_range().is_ok());
    assert!(ArmPendulumConstants::default().check_range().is_ok());
    let e = CartPendulumConstants {
        mp: 1e-300,
        ..Default::default()
    }
    .check_range()
    .unwrap_err();
    assert!(
        matches!(&e, IdentError::ConstantOutOfRange { name, min, .. } if name == "m_p" && *min == MASS_RANGE.0),
        "{e}"
    );
    let e = ArmPendulumConstants {
        l2: 3.0,
        ..Default::default()
    }
    .check_range()
    .unwrap_err();
    assert!(e.to_string().contains("l2 = 3"), "{e}");
    assert!(matches!(
        CartPendulumConstants {
            g: 1.62,
            ..Default::default()
        }
        .check_range(),
        Err(IdentError::ConstantOutOfRange { .. })
    ));
}
