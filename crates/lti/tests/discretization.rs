//! c2d / d2c: book examples (p1c83, p1c84), closed forms, round trips, python-control
//! reference values (tools/reference/lti_reference.py).

mod sys_support;

use pendulab_lti::frequency_response::freqresp;
use pendulab_lti::{
    Complex64, Continuous, Discretization, LtiError, Mat, StateSpace, TransferFunction,
};
use sys_support::{assert_close, assert_same_poles, cdip, fixture, json_mat, json_vec, mat};

fn all_methods() -> Vec<Discretization> {
    vec![
        Discretization::Zoh,
        Discretization::Foh,
        Discretization::Tustin { prewarp: None },
        Discretization::Tustin { prewarp: Some(3.0) },
        Discretization::ForwardEuler,
        Discretization::BackwardEuler,
    ]
}

#[test]
fn p1c83_ex1_zero_order_hold() {
    // Book: C(s) = 1/(s² + s + 1), ts = 1, ZOH → (0.3403 z + 0.2417)/(z² − 0.7859 z + 0.3679).
    let g = TransferFunction::continuous(&[1.0], &[1.0, 1.0, 1.0]).unwrap();
    let gd = g.c2d(1.0, Discretization::Zoh).unwrap();
    // Printed to 4 decimals: half a unit of the last digit.
    assert_close(gd.num().coefficients(), &[0.3403, 0.2417], 5e-5, "num");
    assert_close(
        gd.den().coefficients(),
        &[1.0, -0.7859, 0.3679],
        5e-5,
        "den",
    );
    // Closed form of the denominator: poles e^{λ ts}, λ = −½ ± j√3/2, so
    // den = z² − 2e^{−1/2}cos(√3/2) z + e^{−1}.
    let c1 = -2.0 * (-0.5f64).exp() * (3f64.sqrt() / 2.0).cos();
    assert_close(
        gd.den().coefficients(),
        &[1.0, c1, (-1f64).exp()],
        1e-14,
        "den closed form",
    );
    // DC gain is preserved by ZOH exactly: G(1) = C(0) = 1.
    assert!((gd.dc_gain().unwrap() - 1.0).abs() < 1e-14);
}

#[test]
fn p1c84_ex3_bilinear() {
    // Book: Tustin, ts = 1 → (0.14286 z² + 0.28571 z + 0.14286)/(z² − 0.85714 z + 0.42857).
    let g = TransferFunction::continuous(&[1.0], &[1.0, 1.0, 1.0]).unwrap();
    let gd = g
        .c2d(1.0, Discretization::Tustin { prewarp: None })
        .unwrap();
    assert_close(
        gd.num().coefficients(),
        &[0.14286, 0.28571, 0.14286],
        5e-6,
        "num",
    );
    assert_close(
        gd.den().coefficients(),
        &[1.0, -0.85714, 0.42857],
        5e-6,
        "den",
    );
    // Exact by substitution s = 2(z − 1)/(z + 1): (z + 1)²/(7z² − 6z + 3).
    assert_close(
        gd.num().coefficients(),
        &[1.0 / 7.0, 2.0 / 7.0, 1.0 / 7.0],
        1e-14,
        "num exact",
    );
    assert_close(
        gd.den().coefficients(),
        &[1.0, -6.0 / 7.0, 3.0 / 7.0],
        1e-14,
        "den exact",
    );
}

#[test]
fn zoh_of_first_order_lag_matches_closed_form() {
    // 1/(s + a) under ZOH: (1 − e^{−aT})/a / (z − e^{−aT}).
    for &(a, ts) in &[(2.0f64, 0.1), (0.5, 1.0), (30.0, 0.01), (-1.5, 0.2)] {
        let g = TransferFunction::continuous(&[1.0], &[1.0, a]).unwrap();
        let gd = g.c2d(ts, Discretization::Zoh).unwrap();
        let p = (-a * ts).exp();
        assert_close(gd.den().coefficients(), &[1.0, -p], 1e-15, "den");
        assert_close(
            gd.num().coefficients(),
            &[(1.0 - p) / a],
            1e-14 * ((1.0 - p) / a).abs(),
            "num",
        );
    }
}

fn max_response_error<D: pendulab_lti::TimeDomain>(
    s1: &StateSpace<D>,
    s2: &StateSpace<D>,
    w: &[f64],
) -> f64 {
    let f1 = freqresp(s1, w).unwrap();
    let f2 = freqresp(s2, w).unwrap();
    f1.response
        .iter()
        .zip(&f2.response)
        .map(|(a, b)| (a - b).norm() / b.norm().max(1e-300))
        .fold(0.0, f64::max)
}

#[test]
fn d2c_inverts_c2d_for_every_method() {
    // The cart pendulum with both outputs (z, θ) and a D term: poles and frequency response
    // of d2c(c2d(G)) must return to G's (issue acceptance: ≤ 1e-9 relative).
    let (a, b) = cdip();
    let c = mat(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let d = mat(2, 1, &[0.0, 0.1]);
    let sys = StateSpace::continuous(a, b, c, d).unwrap();
    let w = [0.05, 0.5, 2.0, 5.0, 20.0];
    for ts in [0.001, 0.01, 0.1] {
        for m in all_methods() {
            if let Discretization::Tustin { prewarp: Some(w0) } = m
                && w0 * ts >= std::f64::consts::PI
            {
                continue;
            }
            let back = sys.c2d(ts, m).unwrap().d2c(m).unwrap();
            let p0 = sys.poles().unwrap();
            let p1 = back.poles().unwrap();
            // Poles to 1e-9 relative to the largest (|λ| ≈ 6.25).
            assert_same_poles(&p1, &p0, 1e-9 * 6.25);
            let e = max_response_error(&back, &sys, &w);
            assert!(e < 1e-9, "ts {ts} {m:?}: response error {e:e}");
        }
    }
}

#[test]
fn d2c_rejects_negative_real_discrete_pole() {
    let sys = StateSpace::discrete(
        mat(2, 2, &[-0.5, 0.0, 0.0, 0.9]),
        mat(2, 1, &[1.0, 1.0]),
        mat(1, 2, &[1.0, 1.0]),
        Mat::zeros(1, 1),
        0.1,
    )
    .unwrap();
    let e = sys.d2c(Discretization::Zoh).unwrap_err();
    assert!(
        matches!(e, LtiError::NoRealLogarithm { eigenvalue, .. } if (eigenvalue - Complex64::new(-0.5, 0.0)).norm() < 1e-15),
        "{e}"
    );
    assert!(sys.d2c(Discretization::Foh).is_err());
    // A pole at z = 0 (a pure delay) has no continuous counterpart either.
    let delay = StateSpace::discrete(
        Mat::zeros(1, 1),
        mat(1, 1, &[1.0]),
        mat(1, 1, &[1.0]),
        Mat::zeros(1, 1),
        0.1,
    )
    .unwrap();
    assert!(matches!(
        delay.d2c(Discretization::Zoh),
        Err(LtiError::NoRealLogarithm { .. })
    ));
    // Tustin is singular at z = −1.
    let alt = StateSpace::discrete(
        mat(1, 1, &[-1.0]),
        mat(1, 1, &[1.0]),
        mat(1, 1, &[1.0]),
        Mat::zeros(1, 1),
        0.1,
    )
    .unwrap();
    assert!(matches!(
        alt.d2c(Discretization::Tustin { prewarp: None }),
        Err(LtiError::Singular { .. })
    ));
}

#[test]
fn c2d_rejects_bad_parameters() {
    let g = TransferFunction::continuous(&[1.0], &[1.0, 1.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    assert!(matches!(
        g.c2d(0.0, Discretization::Zoh),
        Err(LtiError::InvalidSampleTime(_))
    ));
    assert!(matches!(
        g.c2d(f64::NAN, Discretization::Zoh),
        Err(LtiError::InvalidSampleTime(_))
    ));
    // Prewarp at or above Nyquist (π/ts = 31.4 rad/s for ts = 0.1).
    assert!(matches!(
        g.c2d(
            0.1,
            Discretization::Tustin {
                prewarp: Some(40.0)
            }
        ),
        Err(LtiError::InvalidArgument(_))
    ));
    // Backward Euler of a pole at s = 1/ts is singular.
    let unstable = TransferFunction::continuous(&[1.0], &[1.0, -10.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    assert!(matches!(
        unstable.c2d(0.1, Discretization::BackwardEuler),
        Err(LtiError::Singular { .. })
    ));
}

#[test]
fn tustin_prewarp_matches_frequency_exactly() {
    // With prewarp ω₀ the discrete response at e^{jω₀ts} equals G(jω₀) (definition).
    let g = TransferFunction::continuous(&[1.0, 3.0], &[1.0, 2.0, 5.0]).unwrap();
    let w0 = 7.0;
    let gd = g
        .c2d(0.2, Discretization::Tustin { prewarp: Some(w0) })
        .unwrap();
    let zc = gd.eval(Complex64::from_polar(1.0, w0 * 0.2));
    let sc = g.eval(Complex64::new(0.0, w0));
    assert!((zc - sc).norm() < 1e-13 * sc.norm());
}

#[test]
fn python_control_c2d_foh_and_tustin_prewarp() {
    let fx = fixture("lti_reference.json");
    for case in fx["c2d_tf"].as_array().unwrap() {
        let g =
            TransferFunction::continuous(&json_vec(&case["num"]), &json_vec(&case["den"])).unwrap();
        let ts = case["ts"].as_f64().unwrap();
        let method = match case["method"].as_str().unwrap() {
            "foh" => Discretization::Foh,
            "tustin" => Discretization::Tustin {
                prewarp: Some(case["prewarp"].as_f64().unwrap()),
            },
            other => panic!("unknown method {other}"),
        };
        let gd = g.c2d(ts, method).unwrap();
        // Same exact formulas (scipy's cont2discrete) evaluated in double precision: the
        // coefficients agree to the rounding of a small-norm block exponential and a
        // polynomial conversion, 1e-12 absolute on O(1) coefficients.
        assert_close(
            gd.num().coefficients(),
            &json_vec(&case["num_d"]),
            1e-12,
            "num",
        );
        assert_close(
            gd.den().coefficients(),
            &json_vec(&case["den_d"]),
            1e-12,
            "den",
        );
    }
}

#[test]
fn python_control_mimo_foh_frequency_response() {
    let fx = fixture("lti_reference.json");
    let case = &fx["c2d_mimo_foh"];
    let sys = StateSpace::continuous(
        json_mat(&case["a"]),
        json_mat(&case["b"]),
        json_mat(&case["c"]),
        json_mat(&case["d"]),
    )
    .unwrap();
    let ts = case["ts"].as_f64().unwrap();
    let sd = sys.c2d(ts, Discretization::Foh).unwrap();
    let w = json_vec(&case["w"]);
    let f = freqresp(&sd, &w).unwrap();
    for i in 0..2 {
        for j in 0..2 {
            for (k, g) in f.response.iter().enumerate() {
                let want = Complex64::new(
                    case["re"][i][j][k].as_f64().unwrap(),
                    case["im"][i][j][k].as_f64().unwrap(),
                );
                // Two double-precision evaluations of the same exact map: 1e-12 relative.
                assert!(
                    (g[(i, j)] - want).norm() < 1e-12 * want.norm().max(1.0),
                    "({i},{j}) at w={}: {} vs {want}",
                    w[k],
                    g[(i, j)]
                );
            }
        }
    }
}

#[test]
fn foh_discretisation_is_exact_for_ramps() {
    // ẋ = −x + u with u = t (a ramp): x(t) = t − 1 + e^{−t} from x(0) = 0. The FOH model
    // reproduces it exactly at the samples (the ramp is piecewise linear).
    let sys = StateSpace::<Continuous>::continuous(
        mat(1, 1, &[-1.0]),
        mat(1, 1, &[1.0]),
        mat(1, 1, &[1.0]),
        mat(1, 1, &[0.0]),
    )
    .unwrap();
    let ts = 0.25;
    let sd = sys.c2d(ts, Discretization::Foh).unwrap();
    // FOH realisation: ξ_{k+1} = Φξ_k + B_d u_k, y_k = Cξ_k + D_d u_k (y = x at samples).
    let (ad, bd, cd, dd) = (
        sd.a()[(0, 0)],
        sd.b()[(0, 0)],
        sd.c()[(0, 0)],
        sd.d()[(0, 0)],
    );
    // ξ₀ = x₀ − Γ₁u₀ = 0 since u₀ = 0.
    let mut xi = 0.0;
    for k in 0..20 {
        let t = k as f64 * ts;
        let y = cd * xi + dd * t;
        let exact = t - 1.0 + (-t).exp();
        assert!((y - exact).abs() < 1e-14, "k={k}: {y} vs {exact}");
        xi = ad * xi + bd * t;
    }
}

#[test]
fn round_trips_with_repeated_and_defective_poles() {
    // Double integrator (A nilpotent: a Jordan block at 0, so A_d is a Jordan block at 1)
    // and a triple pole at −2 (Jordan block): c2d by ZOH is [[1, ts], [0, 1]]-like in closed
    // form, and d2c must undo it to 1e-9 (issue acceptance) for every method.
    let dint = StateSpace::continuous(
        mat(2, 2, &[0.0, 1.0, 0.0, 0.0]),
        mat(2, 1, &[0.0, 1.0]),
        mat(1, 2, &[1.0, 0.0]),
        Mat::zeros(1, 1),
    )
    .unwrap();
    let ts = 0.05;
    let d = dint.c2d(ts, Discretization::Zoh).unwrap();
    // Closed form: A_d = [[1, ts], [0, 1]], B_d = [ts²/2; ts].
    assert!((d.a() - mat(2, 2, &[1.0, ts, 0.0, 1.0])).norm() < 1e-16);
    assert!((d.b() - mat(2, 1, &[ts * ts / 2.0, ts])).norm() < 1e-17);
    let triple = TransferFunction::continuous(&[1.0, 1.0], &[1.0, 6.0, 12.0, 8.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let w = [0.1, 1.0, 4.0];
    for sys in [&dint, &triple] {
        for m in all_methods() {
            let back = sys.c2d(ts, m).unwrap().d2c(m).unwrap();
            let e = max_response_error(&back, sys, &w);
            assert!(e < 1e-9, "{m:?}: {e:e}");
        }
    }
}

#[test]
fn discrete_transfer_function_conversions() {
    // A pure two-step delay z⁻² = 1/z²: poles at 0, no zeros, unit gain.
    let g = TransferFunction::discrete(&[1.0], &[1.0, 0.0, 0.0], 0.1).unwrap();
    let s = g.to_state_space().unwrap();
    let back = TransferFunction::from_state_space(&s).unwrap();
    assert_close(back.den().coefficients(), &[1.0, 0.0, 0.0], 1e-15, "den");
    assert_close(back.num().coefficients(), &[1.0], 1e-14, "num");
    // d2c of a ZOH-discretised transfer function returns the original coefficients.
    let gc = TransferFunction::continuous(&[2.0, 1.0], &[1.0, 3.0, 2.0]).unwrap();
    let gb = gc
        .c2d(0.1, Discretization::Zoh)
        .unwrap()
        .d2c(Discretization::Zoh)
        .unwrap();
    assert_close(
        gb.num().coefficients(),
        gc.num().coefficients(),
        1e-9,
        "num",
    );
    assert_close(
        gb.den().coefficients(),
        gc.den().coefficients(),
        1e-9,
        "den",
    );
}
