//! H∞ and H2 synthesis by Riccati equations (`design::hinf_syn`, `h2_syn`, the state-feedback
//! forms, `augw`): closed forms (the full-information scalar problem, robust stabilisation
//! of `b/(s − p)`), the defining properties of every controller (stable closed loop,
//! `‖T_zw‖∞ ≤ γ` by `hinf_norm`, the H2 cost equal to the closed loop's `h2_norm`), and
//! Slycot's SB10AD/SB10HD through the fixture of `tools/reference/hinf_reference.py`
//! (python-control 0.10.2, Slycot 0.7.1).

use pendulab_lti::design::{
    GammaIteration, HinfCondition, PlantAssumption, StandardPlant, augw, h2_state_feedback, h2_syn,
    hinf_state_feedback, hinf_state_feedback_optimal, hinf_syn, hinf_syn_optimal,
};
use pendulab_lti::norms::{h2_norm, hinf_norm};
use pendulab_lti::{Complex64, Continuous, LtiError, Mat, StateSpace};

mod hinf_support;
use hinf_support::{fixture, plant_of, scalar_full_information};

fn m(rows: usize, cols: usize, v: &[f64]) -> Mat {
    Mat::from_row_slice(rows, cols, v)
}

fn tight() -> GammaIteration {
    GammaIteration {
        tolerance: 1e-10,
        ..GammaIteration::default()
    }
}

/// `‖T‖∞` of a closed loop that must be stable.
fn stable_norm(t: &StateSpace<Continuous>) -> f64 {
    assert!(
        t.is_stable().unwrap(),
        "closed loop unstable: {:?}",
        t.poles()
    );
    hinf_norm(t, 1e-10).unwrap().value
}

#[test]
fn full_information_scalar_closed_form() {
    let a = -1.0;
    let plant = scalar_full_information(a);
    let opt = hinf_state_feedback_optimal(&plant, &tight()).unwrap();
    let exact = 1.0 / (1.0 + a * a).sqrt();
    assert!(
        (opt.gamma - exact).abs() <= 1e-8 * exact,
        "{} vs {exact}",
        opt.gamma
    );
    assert!(opt.gamma_infeasible <= exact && exact <= opt.gamma);
    // The gain tends to k = −1/a as γ → γ_opt (error ~ √(γ − γ_opt)).
    assert!(
        (opt.design.gain[(0, 0)] + 1.0 / a).abs() < 1e-3,
        "{}",
        opt.design.gain
    );
    // At any feasible level the closed loop is stable with ‖T_zw‖∞ < γ.
    for g in [1.001 * exact, 1.1 * exact, 2.0, 10.0] {
        let sf = hinf_state_feedback(&plant, g).unwrap();
        assert!(stable_norm(&sf.closed_loop) < g);
    }
    // Below the optimum: a typed status, no panic.
    let err = hinf_state_feedback(&plant, 0.99 * exact).unwrap_err();
    assert!(matches!(err, LtiError::HinfInfeasible { .. }), "{err}");
    // Unstable plant: γ_opt = 1, approached as X∞ grows without bound.
    let unstable = scalar_full_information(2.0);
    let opt = hinf_state_feedback_optimal(&unstable, &tight()).unwrap();
    assert!((opt.gamma - 1.0).abs() < 1e-8, "{}", opt.gamma);
    let err = hinf_state_feedback(&unstable, 0.999).unwrap_err();
    match err {
        LtiError::HinfInfeasible { condition, .. } => assert!(matches!(
            condition,
            HinfCondition::NotPositiveSemidefinite { .. }
                | HinfCondition::NoStabilizingSolution { .. }
        )),
        e => panic!("{e}"),
    }
}

/// z = u, y = w + G u with G = b/(s − p), p > 0: the optimal `‖K(1 − GK)⁻¹‖∞` is `2p/|b|`
/// (robust stabilisation against additive uncertainty, Glover 1986: the inverse of the
/// Hankel singular value `|b|/(2p)` of the mirror image `b/(s + p)`).
#[test]
fn robust_stabilisation_closed_form() {
    for (p, b) in [(1.0, 1.0), (3.0, 2.0), (0.5, -4.0)] {
        let plant = StandardPlant::from_blocks(
            &m(1, 1, &[p]),
            &m(1, 1, &[0.0]),
            &m(1, 1, &[b]),
            &m(1, 1, &[0.0]),
            &m(1, 1, &[1.0]),
            &m(1, 1, &[0.0]),
            &m(1, 1, &[1.0]),
            &m(1, 1, &[1.0]),
            &m(1, 1, &[0.0]),
        )
        .unwrap();
        let exact = 2.0 * p / b.abs();
        let opt = hinf_syn_optimal(&plant, &tight()).unwrap();
        assert!(
            (opt.gamma - exact).abs() <= 1e-8 * exact,
            "{} vs {exact}",
            opt.gamma
        );
        let k = hinf_syn(&plant, 1.01 * exact).unwrap();
        assert!(stable_norm(&k.closed_loop) < 1.01 * exact);
        assert!(matches!(
            hinf_syn(&plant, 0.99 * exact),
            Err(LtiError::HinfInfeasible { .. })
        ));
    }
}

/// Every fixture plant with `D₁₁ = 0`: the optimal level agrees with SB10AD's to 1e-6
/// (SB10AD's own tolerance is 1e-8) and never exceeds the norm its controller achieves; the
/// controllers at `1.01·γ_opt` and at the level the iteration returns close stable loops
/// below their levels; the H2 controller's cost equals SB10HD's closed-loop H2 norm, the
/// closed loop's `h2_norm`, and the dual formula.
#[test]
fn riccati_synthesis_matches_slycot() {
    let fix = fixture();
    let cases = fix["cases"].as_array().unwrap();
    let mut checked = 0;
    for case in cases {
        let name = case["name"].as_str().unwrap();
        let plant = plant_of(case);
        if plant.d11().iter().any(|v| *v != 0.0) {
            // The general formulas: `d11_nonzero_matches_slycot`; no finite H2 optimum.
            assert!(
                matches!(
                    h2_syn(&plant),
                    Err(LtiError::SynthesisAssumption {
                        assumption: PlantAssumption::D11Zero,
                        ..
                    })
                ),
                "{name}"
            );
            continue;
        }
        let reference = case["gamma_slycot"].as_f64().unwrap();
        let achieved = case["gamma_closed_loop"].as_f64().unwrap();
        let opt = hinf_syn_optimal(&plant, &tight()).unwrap();
        assert!(
            (opt.gamma - reference).abs() <= 1e-6 * reference,
            "{name}: γ_opt {} vs SB10AD {reference}",
            opt.gamma
        );
        assert!(opt.gamma <= achieved * (1.0 + 1e-9), "{name}");
        // The controller the default iteration returns (within 1e-6 of γ_opt): stable, below
        // its level to the accuracy of a controller this close to the optimum.
        let default = hinf_syn_optimal(&plant, &GammaIteration::default()).unwrap();
        let near = stable_norm(&default.design.closed_loop);
        assert!(
            near <= default.gamma * (1.0 + 1e-6),
            "{name}: {near} > {}",
            default.gamma
        );
        let g = 1.01 * opt.gamma;
        let k = hinf_syn(&plant, g).unwrap();
        assert!(stable_norm(&k.closed_loop) < g, "{name}");
        assert!(k.spectral_radius < g * g);
        let below = hinf_syn(&plant, 0.999 * opt.gamma).unwrap_err();
        assert!(
            matches!(below, LtiError::HinfInfeasible { .. }),
            "{name}: {below}"
        );

        let h2 = h2_syn(&plant).unwrap();
        let reference = case["h2_optimal"].as_f64().unwrap();
        let actual = h2_norm(&h2.closed_loop).unwrap();
        assert!(
            (h2.norm - reference).abs() <= 1e-8 * reference,
            "{name}: {} vs {reference}",
            h2.norm
        );
        assert!(
            (actual - h2.norm).abs() <= 1e-8 * h2.norm,
            "{name}: {actual} vs {}",
            h2.norm
        );
        let (c1, d21) = (plant.c1(), plant.d21());
        let dual = (&c1 * &h2.y * c1.transpose()).trace()
            + (&d21 * d21.transpose() * h2.estimator_gain.transpose() * &h2.x * &h2.estimator_gain)
                .trace();
        assert!((dual.sqrt() - h2.norm).abs() <= 1e-8 * h2.norm, "{name}");
        // H2 ≤ H∞-type bounds: the state-feedback optimum is a lower bound of the output
        // feedback one (more information).
        let sf = h2_state_feedback(&plant).unwrap();
        assert!(sf.norm <= h2.norm);
        assert!((h2_norm(&sf.closed_loop).unwrap() - sf.norm).abs() <= 1e-8 * sf.norm);
        let hsf = hinf_state_feedback_optimal(&plant, &tight()).unwrap();
        assert!(hsf.gamma <= opt.gamma * (1.0 + 1e-9), "{name}");
        checked += 1;
    }
    assert_eq!(checked, 5);
}

/// The fixture plants with `D₁₁ ≠ 0` (a random 6-state plant with a random `D₁₁`, and the
/// mixed-sensitivity plant of Skogestad & Postlethwaite's example 2.11 with `D₁₁ = 1/M`):
/// the general (Glover–Doyle) formulas give the optimal level of SB10AD to 1e-6, never above
/// the norm SB10AD's controller achieves; the controller at `1.01·γ_opt` closes a stable
/// loop with `‖T_zw‖∞ < γ` (`hinf_norm`), and `0.999·γ_opt` is infeasible.
#[test]
fn d11_nonzero_matches_slycot() {
    let fix = fixture();
    let cases = fix["cases"].as_array().unwrap();
    let mut checked = 0;
    for case in cases {
        let name = case["name"].as_str().unwrap();
        let plant = plant_of(case);
        if plant.d11().iter().all(|v| *v == 0.0) {
            continue;
        }
        let reference = case["gamma_slycot"].as_f64().unwrap();
        let achieved = case["gamma_closed_loop"].as_f64().unwrap();
        let opt = hinf_syn_optimal(&plant, &tight()).unwrap();
        assert!(
            (opt.gamma - reference).abs() <= 1e-6 * reference,
            "{name}: γ_opt {} vs SB10AD {reference}",
            opt.gamma
        );
        assert!(opt.gamma <= achieved * (1.0 + 1e-9), "{name}");
        let g = 1.01 * opt.gamma;
        let k = hinf_syn(&plant, g).unwrap();
        let norm = stable_norm(&k.closed_loop);
        assert!(norm < g, "{name}: {norm} ≥ {g}");
        let below = hinf_syn(&plant, 0.999 * opt.gamma).unwrap_err();
        assert!(
            matches!(below, LtiError::HinfInfeasible { .. }),
            "{name}: {below}"
        );
        checked += 1;
    }
    assert_eq!(checked, 2);
}

/// `D₁₁` sets a floor on γ that no controller moves: with `z₁` not reachable by `u`
/// (`D₁₂ = [0; 1]`) and `w₁` not seen by `y` (`D₂₁ = [0 1]`), `D₁₁ = [3 0; 0 0]` gives
/// `D₁₁₁₁ = 3` and the bound `max(‖[3 0]‖, ‖[3; 0]‖) = 3`: a level below it is refused with
/// the bound named, the optimum lies above it, and a controller at `1.05·γ_opt` meets its
/// level. With `D₁₁ = [0 0; 0 2]` instead (`D₁₁₂₂ = 2`, reachable by `u` and seen by `y`)
/// the bound is 0: a low level fails a Riccati or coupling condition, not the bound.
#[test]
fn d11_bound_and_reachable_feedthrough() {
    let plant = |d11: [f64; 4]| {
        StandardPlant::from_blocks(
            &m(1, 1, &[1.0]),
            &m(1, 2, &[1.0, 0.0]),
            &m(1, 1, &[1.0]),
            &m(2, 1, &[1.0, 0.0]),
            &m(1, 1, &[1.0]),
            &m(2, 2, &d11),
            &m(2, 1, &[0.0, 1.0]),
            &m(1, 2, &[0.0, 1.0]),
            &m(1, 1, &[0.0]),
        )
        .unwrap()
    };
    let p = plant([3.0, 0.0, 0.0, 0.0]);
    match hinf_syn(&p, 2.9) {
        Err(LtiError::HinfInfeasible {
            condition: HinfCondition::D11Bound { bound },
            ..
        }) => assert!((bound - 3.0).abs() < 1e-12, "{bound}"),
        other => panic!("{other:?}"),
    }
    let opt = hinf_syn_optimal(&p, &tight()).unwrap();
    assert!(opt.gamma > 3.0);
    let g = 1.05 * opt.gamma;
    assert!(stable_norm(&hinf_syn(&p, g).unwrap().closed_loop) < g);

    let q = plant([0.0, 0.0, 0.0, 2.0]);
    let opt = hinf_syn_optimal(&q, &tight()).unwrap();
    match hinf_syn(&q, 0.5 * opt.gamma) {
        Err(LtiError::HinfInfeasible { condition, .. }) => {
            assert!(
                !matches!(condition, HinfCondition::D11Bound { .. }),
                "{condition}"
            )
        }
        other => panic!("{other:?}"),
    }
    let g = 1.05 * opt.gamma;
    assert!(stable_norm(&hinf_syn(&q, g).unwrap().closed_loop) < g);
}

/// The loop shift for `D₂₂ ≠ 0` leaves the optimal level unchanged (the same plant with and
/// without `D₂₂` in the fixture) and the controller still closes a stable loop below γ.
#[test]
fn d22_loop_shift() {
    let fix = fixture();
    let cases = fix["cases"].as_array().unwrap();
    let find = |n: &str| plant_of(cases.iter().find(|c| c["name"] == n).unwrap());
    let (p0, p1) = (find("random6"), find("random6_d22"));
    assert!(p1.d22().norm() > 0.1);
    let g = 1.05
        * hinf_syn_optimal(&p0, &GammaIteration::default())
            .unwrap()
            .gamma;
    let k = hinf_syn(&p1, g).unwrap();
    assert!(stable_norm(&k.closed_loop) < g);
    let k0 = hinf_syn(&p0, g).unwrap();
    // Same closed loop either way (the shift only undoes D₂₂).
    for w in [0.1, 1.0, 10.0] {
        let s = Complex64::new(0.0, w);
        let d = k.closed_loop.evaluate(s).unwrap() - k0.closed_loop.evaluate(s).unwrap();
        assert!(d.norm() < 1e-8, "{w}: {d}");
    }
    let h = h2_syn(&p1).unwrap();
    assert!((h2_norm(&h.closed_loop).unwrap() - h2_syn(&p0).unwrap().norm).abs() < 1e-7);
}

fn siso(num: &[f64], den: &[f64]) -> StateSpace<Continuous> {
    pendulab_lti::TransferFunction::continuous(num, den)
        .unwrap()
        .to_state_space()
        .unwrap()
}

fn eval(sys: &StateSpace<Continuous>, w: f64) -> Complex64 {
    sys.evaluate(Complex64::new(0.0, w)).unwrap()[(0, 0)]
}

/// `augw` against its closed form `[W₁, −W₁G; 0, W₂; 0, W₃G; I, −G]` at several
/// frequencies, and the lower LFT with a controller against `[W₁S; W₂KS; W₃T]`.
#[test]
fn augw_closed_form() {
    let g = siso(&[2.0, 1.0], &[1.0, 3.0, 2.0, 0.5]);
    let w1 = siso(&[0.5, 2.0], &[1.0, 0.02]);
    let w2 = siso(&[0.1, 0.2], &[0.01, 1.0]);
    let w3 = siso(&[1.0, 0.0], &[0.1, 1.0]);
    let k = siso(&[3.0, 1.0], &[1.0, 4.0]);
    let p = augw(&g, Some(&w1), Some(&w2), Some(&w3)).unwrap();
    assert_eq!((p.nmeas(), p.ncon(), p.nz(), p.nw()), (1, 1, 3, 1));
    let cl = p.close_loop(&k).unwrap();
    for w in [0.0, 0.05, 0.7, 3.0, 40.0] {
        let s = Complex64::new(0.0, w);
        let pv = p.system().evaluate(s).unwrap();
        let (gv, w1v, w2v, w3v, kv) = (
            eval(&g, w),
            eval(&w1, w),
            eval(&w2, w),
            eval(&w3, w),
            eval(&k, w),
        );
        let one = Complex64::new(1.0, 0.0);
        let zero = Complex64::new(0.0, 0.0);
        let expected = [[w1v, -w1v * gv], [zero, w2v], [zero, w3v * gv], [one, -gv]];
        for (i, row) in expected.iter().enumerate() {
            for (j, e) in row.iter().enumerate() {
                assert!(
                    (pv[(i, j)] - e).norm() <= 1e-10 * (1.0 + e.norm()),
                    "ω={w} ({i},{j})"
                );
            }
        }
        let sens = one / (one + gv * kv);
        let t = gv * kv * sens;
        let clv = cl.evaluate(s).unwrap();
        for (i, e) in [w1v * sens, w2v * kv * sens, w3v * t].iter().enumerate() {
            assert!(
                (clv[(i, 0)] - e).norm() <= 1e-10 * (1.0 + e.norm()),
                "ω={w} row {i}"
            );
        }
    }
    // Absent weights drop their rows; a weight of the wrong size is refused.
    let p1 = augw(&g, Some(&w1), None, None).unwrap();
    assert_eq!((p1.nz(), p1.nx()), (1, g.nx() + w1.nx()));
    let wide = StateSpace::continuous(
        Mat::zeros(0, 0),
        Mat::zeros(0, 2),
        Mat::zeros(1, 0),
        m(1, 2, &[1.0, 1.0]),
    )
    .unwrap();
    assert!(matches!(
        augw(&g, Some(&wide), None, None),
        Err(LtiError::DimensionMismatch { .. })
    ));
}

/// Each violated assumption is named: `D₁₂ = 0`, `D₂₁ = 0`, an unstabilisable mode, and the
/// mixed-sensitivity plant of the cart pendulum, whose integrator (the cart position) is an
/// imaginary-axis zero of `P₂₁` (`w` enters at the output and cannot move `G`'s states).
#[test]
fn assumption_errors_are_named() {
    let base = |d12: f64, d21: f64, b2: f64| {
        StandardPlant::from_blocks(
            &m(1, 1, &[1.0]),
            &m(1, 2, &[1.0, 0.0]),
            &m(1, 1, &[b2]),
            &m(2, 1, &[1.0, 0.0]),
            &m(1, 1, &[1.0]),
            &Mat::zeros(2, 2),
            &m(2, 1, &[0.0, d12]),
            &m(1, 2, &[0.0, d21]),
            &m(1, 1, &[0.0]),
        )
        .unwrap()
    };
    let named = |p: &StandardPlant| match hinf_syn(p, 5.0) {
        Err(LtiError::SynthesisAssumption { assumption, .. }) => assumption,
        other => panic!("{other:?}"),
    };
    assert!(hinf_syn(&base(1.0, 1.0, 1.0), 5.0).is_ok());
    assert_eq!(
        named(&base(0.0, 1.0, 1.0)),
        PlantAssumption::D12FullColumnRank
    );
    assert_eq!(named(&base(1.0, 0.0, 1.0)), PlantAssumption::D21FullRowRank);
    assert_eq!(named(&base(1.0, 1.0, 0.0)), PlantAssumption::Stabilizable);
    assert!(matches!(
        h2_syn(&base(0.0, 1.0, 1.0)),
        Err(LtiError::SynthesisAssumption { .. })
    ));

    let (a, b) = pendulab_testkit::cart::upright();
    let g = StateSpace::continuous(
        a,
        b,
        pendulab_testkit::cart::measured_output(),
        Mat::zeros(2, 1),
    )
    .unwrap();
    let w1 = StateSpace::continuous(
        Mat::identity(2, 2) * -0.1,
        Mat::identity(2, 2),
        Mat::identity(2, 2),
        Mat::zeros(2, 2),
    )
    .unwrap();
    let w2 = StateSpace::static_gain(m(1, 1, &[0.1]), Continuous).unwrap();
    let p = augw(&g, Some(&w1), Some(&w2), None).unwrap();
    match hinf_syn(&p, 10.0) {
        Err(LtiError::SynthesisAssumption {
            assumption: PlantAssumption::P21NoImaginaryZeros,
            detail,
        }) => assert!(detail.contains("zero at 0"), "{detail}"),
        other => panic!("{other:?}"),
    }
}

/// The cart pendulum with the book's LQ weights (fixture case `cart_lq`): the H∞ controller
/// at 1.2·γ_opt stabilises the upright pendulum, and the H∞ and H2 state-feedback optima
/// bracket the LQ problem (`h2_state_feedback` is the LQR of `Q = C₁ᵀC₁`, `R = 1`).
#[test]
fn cart_pendulum_with_weights() {
    let fix = fixture();
    let case = fix["cases"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "cart_lq")
        .unwrap();
    let plant = plant_of(case);
    let (a, b) = pendulab_testkit::cart::upright();
    assert!((plant.a() - &a).norm() < 1e-12 && (plant.b2() - &b).norm() < 1e-12);
    let opt = hinf_syn_optimal(&plant, &GammaIteration::default()).unwrap();
    let k = hinf_syn(&plant, 1.2 * opt.gamma).unwrap();
    assert!(stable_norm(&k.closed_loop) < 1.2 * opt.gamma);
    let (q, r) = pendulab_testkit::cart::lqr_weights();
    let lqr = pendulab_lti::design::lqr(
        &StateSpace::continuous(a.clone(), b.clone(), Mat::identity(4, 4), Mat::zeros(4, 1))
            .unwrap(),
        &q,
        &r,
        None,
    )
    .unwrap();
    let sf = h2_state_feedback(&plant).unwrap();
    assert!(
        (&sf.gain - &lqr.gain).norm() <= 1e-9 * lqr.gain.norm(),
        "{} vs {}",
        sf.gain,
        lqr.gain
    );
}
