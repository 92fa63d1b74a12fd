//! `margins`: every gain and phase crossing against python-control's polynomial method
//! (fixture of `tools/reference/lti_toolbox_reference.py`), closed forms of first- and
//! third-order loops, a loop with an undamped pole, the delay margin's defining residual and
//! the gang of four's identities.

mod toolbox_support;

use pendulab_lti::linalg::Complex64;
use pendulab_lti::margins::{gang_of_four, stability_margins, stability_margins_tf};
use pendulab_lti::{LtiError, Mat, StateSpace, TimeDomain, TransferFunction};

/// 49 loops (35 continuous, 14 discrete): the same crossings, to 1e-6 relative in frequency
/// and gain margin and 1e-5° in phase margin (the fixture's crossings are checked there
/// against the state-space response to 1e-7).
#[test]
fn every_crossing_matches_python_control() {
    let cases = toolbox_support::cases("margins");
    assert!(cases.len() >= 45, "{} cases", cases.len());
    let mut crossings = 0;
    for (k, case) in cases.iter().enumerate() {
        let sys = toolbox_support::system(case);
        let m = on_sys!(&sys, |s| stability_margins(s).unwrap());
        let gain: Vec<(f64, f64)> = case["gain_crossings"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
            .collect();
        // python-control lists ω = 0 with a gain margin of (nearly) 0 for a loop with an integrator (the
        // response is infinite there); it is a pole, not a crossing.
        let phase: Vec<(f64, f64)> = case["phase_crossings"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
            .filter(|&(w, g)| !(w == 0.0 && g < 1e-9))
            .collect();
        assert_eq!(
            m.gain_crossings.len(),
            gain.len(),
            "case {k}: gain crossings {:?} vs {gain:?}",
            m.gain_crossings
        );
        assert_eq!(
            m.phase_crossings.len(),
            phase.len(),
            "case {k}: phase crossings {:?} vs {phase:?}",
            m.phase_crossings
        );
        for (c, &(w, pm)) in m.gain_crossings.iter().zip(&gain) {
            assert!(
                (c.frequency - w).abs() <= 1e-6 * w,
                "case {k}: {c:?} vs {w}"
            );
            assert!(
                (c.phase_margin_deg - pm).abs() <= 1e-5,
                "case {k}: {c:?} vs {pm}"
            );
        }
        for (c, &(w, gm)) in m.phase_crossings.iter().zip(&phase) {
            assert!(
                (c.frequency - w).abs() <= 1e-6 * w.max(1e-3),
                "case {k}: {c:?} vs {w}"
            );
            assert!(
                (c.gain_margin - gm).abs() <= 1e-6 * gm,
                "case {k}: {c:?} vs {gm}"
            );
        }
        crossings += gain.len() + phase.len();
    }
    assert!(crossings >= 90, "{crossings} crossings compared");
}

/// Delay margin: `L(jω) e^{−jωτ} = −1` at every gain crossing (its defining residual), and
/// the reported margins are the documented choices among all crossings.
#[test]
fn delay_margin_rotates_the_crossing_onto_minus_one_and_selection_rules() {
    for case in toolbox_support::cases("margins") {
        let sys = toolbox_support::system(&case);
        on_sys!(&sys, |s| {
            let m = stability_margins(s).unwrap();
            for c in &m.gain_crossings {
                let ts = s.domain().sample_time();
                let z = match ts {
                    None => Complex64::new(0.0, c.frequency),
                    Some(ts) => Complex64::from_polar(1.0, c.frequency * ts),
                };
                let l = s.evaluate(z).unwrap()[(0, 0)];
                let rotated = l * Complex64::from_polar(1.0, -c.frequency * c.delay_margin);
                assert!((rotated + 1.0).norm() < 1e-6, "{c:?}: {rotated}");
                assert!(c.delay_margin >= 0.0);
            }
            if let Some(pm) = m.phase_margin() {
                assert!(
                    m.gain_crossings
                        .iter()
                        .all(|c| c.phase_margin_deg.abs() >= pm.phase_margin_deg.abs())
                );
            }
            if let Some(gm) = m.gain_margin() {
                assert!(
                    m.phase_crossings
                        .iter()
                        .all(|c| c.gain_margin.ln().abs() >= gm.gain_margin.ln().abs())
                );
            }
        });
    }
}

/// `L = k/(s(s + 1))`: one gain crossing at `ω² = (√(1 + 4k²) − 1)/2` with
/// `PM = 90° − atan ω`, no phase crossing, the integrator reported at `ω = 0`.
#[test]
fn integrator_loop_closed_form() {
    for k in [0.3, 1.0, 10.0, 1e3] {
        let l = TransferFunction::continuous(&[k], &[1.0, 1.0, 0.0]).unwrap();
        let m = stability_margins_tf(&l).unwrap();
        let w = (((1.0 + 4.0 * k * k).sqrt() - 1.0) / 2.0).sqrt();
        assert_eq!(m.gain_crossings.len(), 1, "{m:?}");
        let c = m.gain_crossings[0];
        assert!((c.frequency - w).abs() <= 1e-12 * w, "{c:?} vs {w}");
        let pm = 90.0 - w.atan().to_degrees();
        assert!((c.phase_margin_deg - pm).abs() <= 1e-9, "{c:?} vs {pm}");
        assert!((c.delay_margin - pm.to_radians() / w).abs() <= 1e-9 * c.delay_margin);
        assert!(m.phase_crossings.is_empty(), "{m:?}");
        assert_eq!(m.boundary_pole_frequencies, vec![0.0]);
    }
}

/// `L = k/(s + 1)³`: the phase crossing at `ω = √3` with `GM = 8/k`, the gain crossing at
/// `ω = √(k^{2/3} − 1)` with `PM = 180° − 3 atan ω`; for `k < 1` no gain crossing.
#[test]
fn third_order_lag_closed_form() {
    for k in [2.0, 4.0, 8.0, 20.0, 0.5] {
        let l = TransferFunction::continuous(&[k], &[1.0, 3.0, 3.0, 1.0]).unwrap();
        let m = stability_margins_tf(&l).unwrap();
        assert_eq!(m.phase_crossings.len(), 1, "{m:?}");
        let p = m.phase_crossings[0];
        assert!((p.frequency - 3f64.sqrt()).abs() <= 1e-12, "{p:?}");
        assert!((p.gain_margin - 8.0 / k).abs() <= 1e-12 * 8.0 / k, "{p:?}");
        assert!((p.gain_margin_db() - 20.0 * (8.0 / k).log10()).abs() <= 1e-10);
        if k > 1.0 {
            let w = (k.powf(2.0 / 3.0) - 1.0).sqrt();
            let c = m.phase_margin().unwrap();
            assert!(
                (c.frequency - w).abs() <= 1e-12 * w.max(1.0),
                "{c:?} vs {w}"
            );
            let pm = 180.0 - 3.0 * w.atan().to_degrees();
            assert!((c.phase_margin_deg - pm).abs() <= 1e-9, "{c:?} vs {pm}");
        } else {
            assert!(m.gain_crossings.is_empty() && m.phase_margin().is_none());
        }
    }
}

/// `L = k/((s² + 1)(s + 1))`: the undamped pole at ω = 1 flips the phase by 180° without a
/// crossing of the negative real axis (`Im L = −kω/((1 − ω²)(1 + ω²))` vanishes only at
/// ω = 0); the gain crossings are the positive roots of `(1 − x)²(1 + x) = k²`, `x = ω²`.
#[test]
fn undamped_pole_is_not_a_phase_crossing() {
    for k in [0.5, 2.0] {
        let l = TransferFunction::continuous(&[k], &[1.0, 1.0, 1.0, 1.0]).unwrap();
        let m = stability_margins_tf(&l).unwrap();
        assert_eq!(m.boundary_pole_frequencies.len(), 1, "{m:?}");
        assert!((m.boundary_pole_frequencies[0] - 1.0).abs() < 1e-9);
        // L(0) = k > 0: no crossing at ω = 0 either.
        assert!(m.phase_crossings.is_empty(), "{m:?}");
        // (1 − x)²(1 + x) − k² = x³ − x² − x + 1 − k².
        let cubic = pendulab_lti::Polynomial::new(&[1.0, -1.0, -1.0, 1.0 - k * k]).unwrap();
        let mut want: Vec<f64> = cubic
            .roots()
            .unwrap()
            .into_iter()
            .filter(|r| r.im.abs() < 1e-9 && r.re > 0.0)
            .map(|r| r.re.sqrt())
            .collect();
        want.sort_by(f64::total_cmp);
        let got: Vec<f64> = m.gain_crossings.iter().map(|c| c.frequency).collect();
        assert_eq!(got.len(), want.len(), "{got:?} vs {want:?}");
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() <= 1e-9 * w, "{got:?} vs {want:?}");
        }
    }
}

/// A discrete integrator loop `L(z) = k ts/(z − 1)`: the gain crossing solves
/// `|e^{jθ} − 1| = k ts`, i.e. `2 sin(θ/2) = k ts`, with `PM = 180° + ∠L = 90° + θ/2`.
#[test]
fn discrete_integrator_closed_form() {
    let ts = 0.01;
    for k in [1.0, 10.0, 100.0] {
        let l = TransferFunction::discrete(&[k * ts], &[1.0, -1.0], ts).unwrap();
        let m = stability_margins_tf(&l).unwrap();
        let theta = 2.0 * (k * ts / 2.0).asin();
        let c = m.phase_margin().unwrap();
        assert!(
            (c.frequency - theta / ts).abs() <= 1e-10 * theta / ts,
            "{c:?}"
        );
        let pm = 90.0 - (theta / 2.0).to_degrees();
        assert!((c.phase_margin_deg - pm).abs() <= 1e-9, "{c:?} vs {pm}");
        assert_eq!(m.sample_time, Some(ts));
        assert_eq!(m.boundary_pole_frequencies, vec![0.0]);
    }
}

/// A MIMO loop is refused with the typed error.
#[test]
fn mimo_loop_is_refused() {
    let s = StateSpace::continuous(
        Mat::identity(2, 2) * -1.0,
        Mat::identity(2, 2),
        Mat::identity(2, 2),
        Mat::zeros(2, 2),
    )
    .unwrap();
    assert!(matches!(
        stability_margins(&s),
        Err(LtiError::NotSiso { ny: 2, nu: 2, .. })
    ));
}

/// Gang of four of `P = 1/(s(s + 1))`, `C = 2 (s + 3)/(s + 10)`: `S = 1/(1 + PC)`,
/// `T = PC/(1 + PC)`, `PS = P/(1 + PC)`, `CS = C/(1 + PC)` evaluated from the factors, and
/// `S + T = 1`.
#[test]
fn gang_of_four_identities() {
    let p = TransferFunction::continuous(&[1.0], &[1.0, 1.0, 0.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let c = TransferFunction::continuous(&[2.0, 6.0], &[1.0, 10.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let g = gang_of_four(&p, &c).unwrap();
    for w in [0.01, 0.3, 1.0, 4.0, 50.0] {
        let s = Complex64::new(0.0, w);
        let pv = 1.0 / (s * (s + 1.0));
        let cv = 2.0 * (s + 3.0) / (s + 10.0);
        let den = 1.0 + pv * cv;
        let at = |sys: &StateSpace<pendulab_lti::Continuous>| sys.evaluate(s).unwrap()[(0, 0)];
        for (got, want) in [
            (at(&g.s), 1.0 / den),
            (at(&g.t), pv * cv / den),
            (at(&g.ps), pv / den),
            (at(&g.cs), cv / den),
        ] {
            assert!(
                (got - want).norm() <= 1e-12 * want.norm().max(1.0),
                "{got} vs {want}"
            );
        }
        assert!((at(&g.s) + at(&g.t) - 1.0).norm() <= 1e-12);
    }
    assert!(g.s.is_stable().unwrap());
}
