//! Bode data and zeros against python-control (tools/reference/lti_reference.py), closed
//! forms, and ss↔tf conversions.

mod sys_support;

use pendulab_lti::frequency_response::{bode, bode_tf, freqresp, frequency_grid, logspace};
use pendulab_lti::{Complex64, Continuous, LtiError, Mat, StateSpace, TransferFunction};
use sys_support::{
    G, JP, LP, MP, MUP, assert_close, assert_same_poles, c, cdip, fixture, json_mat, json_vec, mat,
};

/// Phase difference reduced to (−180°, 180°].
fn phase_diff(a: f64, b: f64) -> f64 {
    let d = (a - b) % 360.0;
    if d > 180.0 {
        d - 360.0
    } else if d <= -180.0 {
        d + 360.0
    } else {
        d
    }
}

#[test]
fn python_control_bode_points() {
    let fx = fixture("lti_reference.json");
    let ad = json_mat(&fx["cdip"]["a"]);
    let bd = json_mat(&fx["cdip"]["b"]);
    for case in fx["bode"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let w = json_vec(&case["w"]);
        let b = match name {
            "cdip_cart_position" => {
                let sys = StateSpace::continuous(
                    ad.clone(),
                    bd.clone(),
                    mat(1, 4, &[1.0, 0.0, 0.0, 0.0]),
                    Mat::zeros(1, 1),
                )
                .unwrap();
                bode(&sys, &w).unwrap()
            }
            "g1" => {
                let g =
                    TransferFunction::continuous(&json_vec(&case["num"]), &json_vec(&case["den"]))
                        .unwrap();
                let b1 = bode(&g.to_state_space().unwrap(), &w).unwrap();
                let b2 = bode_tf(&g, &w).unwrap();
                // Two evaluation routes (Hessenberg solve vs Horner) agree to rounding.
                assert_close(&b1.magnitude_db, &b2.magnitude_db, 1e-12, "route");
                b1
            }
            "g1_zoh_0.1" => {
                let g = TransferFunction::continuous(&[1.0, 3.0], &[1.0, 2.0, 5.0]).unwrap();
                let gd = g
                    .c2d(
                        case["ts"].as_f64().unwrap(),
                        pendulab_lti::Discretization::Zoh,
                    )
                    .unwrap();
                bode(&gd.to_state_space().unwrap(), &w).unwrap()
            }
            other => panic!("unknown case {other}"),
        };
        let mag = json_vec(&case["mag_db"]);
        let ph = json_vec(&case["phase_deg"]);
        // Same complex values from two double-precision evaluations: 1e-9 dB (≈ 1e-10
        // relative magnitude) and 1e-8 degrees leave room for the conditioning of
        // (jωI − A) near the cart pendulum's poles.
        assert_close(&b.magnitude_db, &mag, 1e-9, name);
        for (k, (p, q)) in b.phase_deg.iter().zip(&ph).enumerate() {
            assert!(
                phase_diff(*p, *q).abs() < 1e-8,
                "{name} phase[{k}]: {p} vs {q}"
            );
        }
        // Unwrapping: no jump above 180° between neighbours.
        assert!(b.phase_deg.windows(2).all(|w| (w[1] - w[0]).abs() <= 180.0));
    }
}

#[test]
fn python_control_zeros_of_non_minimum_phase_systems() {
    let fx = fixture("lti_reference.json");
    for case in fx["zeros"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let sys = if name == "cdip_cart_position" {
            let (a, b) = cdip();
            StateSpace::continuous(a, b, json_mat(&case["c"]), json_mat(&case["d"])).unwrap()
        } else {
            StateSpace::continuous(
                json_mat(&case["a"]),
                json_mat(&case["b"]),
                json_mat(&case["c"]),
                json_mat(&case["d"]),
            )
            .unwrap()
        };
        let want: Vec<Complex64> = json_vec(&case["zeros_re"])
            .into_iter()
            .zip(json_vec(&case["zeros_im"]))
            .map(|(r, i)| c(r, i))
            .collect();
        // Simple, well-separated zeros: agreement to 1e-10 absolute on O(1–10) values.
        assert_same_poles(&sys.zeros().unwrap(), &want, 1e-10);
        assert!(
            want.iter().any(|z| z.re > 0.0),
            "{name} is non-minimum phase"
        );
    }
}

#[test]
fn cart_position_zeros_are_the_fixed_cart_pendulum_poles() {
    // With y = z, the zeros of the cart pendulum are the poles of the pendulum with the cart
    // held (book eq. 4.45): (−ζ ± √(ζ² + 1)) ω_np — an independent closed form.
    let (a, b) = cdip();
    let sys =
        StateSpace::continuous(a, b, mat(1, 4, &[1.0, 0.0, 0.0, 0.0]), Mat::zeros(1, 1)).unwrap();
    let j = JP + MP * LP * LP;
    let wn = (MP * G * LP / j).sqrt();
    let z = MUP / (2.0 * wn * j);
    let want = [
        c((-z + (z * z + 1.0).sqrt()) * wn, 0.0),
        c((-z - (z * z + 1.0).sqrt()) * wn, 0.0),
    ];
    assert_same_poles(&sys.zeros().unwrap(), &want, 1e-12);
    // Transfer function: den = charpoly(A); num = k (s − z₁)(s − z₂) with k = CAB = b_c.
    let g = TransferFunction::from_state_space(&sys).unwrap();
    assert_eq!(g.num().degree(), 2);
    assert!((g.num().leading() - sys_support::BC).abs() < 1e-12);
}

#[test]
fn zeros_with_relative_degree_and_feedthrough() {
    // (s + 2)/(s + 1)³: one zero at −2, relative degree 2 (the deflation runs twice).
    let g = TransferFunction::continuous(&[1.0, 2.0], &[1.0, 3.0, 3.0, 1.0]).unwrap();
    let sys = g.to_state_space().unwrap();
    assert_same_poles(&sys.zeros().unwrap(), &[c(-2.0, 0.0)], 1e-13);
    // D ≠ 0: (s² + 1)/(s² + 3s + 2) → zeros ±j, D = 1.
    let g = TransferFunction::continuous(&[1.0, 0.0, 1.0], &[1.0, 3.0, 2.0]).unwrap();
    let sys = g.to_state_space().unwrap();
    assert_eq!(sys.d()[(0, 0)], 1.0);
    assert_same_poles(&sys.zeros().unwrap(), &[c(0.0, 1.0), c(0.0, -1.0)], 1e-13);
    // No zeros: 1/(s + 1)² realised with a balanced non-companion basis.
    let sys = StateSpace::continuous(
        mat(2, 2, &[-1.0, 1.0, 0.0, -1.0]),
        mat(2, 1, &[0.0, 1.0]),
        mat(1, 2, &[1.0, 0.0]),
        Mat::zeros(1, 1),
    )
    .unwrap();
    assert!(sys.zeros().unwrap().is_empty());
    // An uncontrollable mode is an (input-decoupling) invariant zero, and ss→tf keeps it on
    // both sides, so num/den is exact but not minimal.
    let sys = StateSpace::continuous(
        mat(2, 2, &[-1.0, 0.0, 0.0, -3.0]),
        mat(2, 1, &[1.0, 0.0]),
        mat(1, 2, &[1.0, 1.0]),
        Mat::zeros(1, 1),
    )
    .unwrap();
    assert_same_poles(&sys.zeros().unwrap(), &[c(-3.0, 0.0)], 1e-13);
    let g = TransferFunction::from_state_space(&sys).unwrap();
    assert_close(g.num().coefficients(), &[1.0, 3.0], 1e-13, "num");
    assert_close(g.den().coefficients(), &[1.0, 4.0, 3.0], 1e-13, "den");
    // Identically zero transfer function: no zeros, zero numerator.
    let sys = StateSpace::continuous(
        mat(1, 1, &[-1.0]),
        mat(1, 1, &[0.0]),
        mat(1, 1, &[1.0]),
        Mat::zeros(1, 1),
    )
    .unwrap();
    assert!(sys.zeros().unwrap().is_empty());
    assert!(
        TransferFunction::from_state_space(&sys)
            .unwrap()
            .num()
            .is_zero()
    );
    // Measuring the whole state leaves no zeros: [[A − λI, B], [I, 0]] has full column
    // rank for every λ.
    let (a, b) = cdip();
    let mimo = StateSpace::continuous(a, b, Mat::identity(4, 4), Mat::zeros(4, 1)).unwrap();
    assert!(mimo.zeros().unwrap().is_empty());
}

#[test]
fn mimo_zeros_closed_forms() {
    // Block-diagonal system: the zeros are the union of the blocks' zeros, here
    // {1, −4} ∪ {−2} ∪ {} (a static gain adds none); this also runs the general algorithm on
    // SISO pieces.
    let g1 = TransferFunction::continuous(&[1.0, 3.0, -4.0], &[1.0, 8.0, 17.0, 10.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let g2 = TransferFunction::continuous(&[2.0, 4.0], &[1.0, 1.0, 1.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    let k = StateSpace::static_gain(mat(1, 1, &[3.0]), Continuous).unwrap();
    let sys = pendulab_lti::interconnect::append(&[&g1, &g2, &k]).unwrap();
    assert_same_poles(
        &sys.zeros().unwrap(),
        &[c(1.0, 0.0), c(-4.0, 0.0), c(-2.0, 0.0)],
        1e-12,
    );
    // Non-square (1 input, 2 outputs): y₁ = (s + 1)/((s + 2)(s + 3)) u,
    // y₂ = (s + 1)(s + 5)/((s + 2)(s + 3)) u; only the common zero −1 survives.
    let sys = StateSpace::continuous(
        mat(2, 2, &[0.0, 1.0, -6.0, -5.0]),
        mat(2, 1, &[0.0, 1.0]),
        mat(2, 2, &[1.0, 1.0, -1.0, 1.0]),
        mat(2, 1, &[0.0, 1.0]),
    )
    .unwrap();
    assert_same_poles(&sys.zeros().unwrap(), &[c(-1.0, 0.0)], 1e-12);
    // 2 inputs, 1 output with no common structure: a fat system generically has no zeros.
    let sys = StateSpace::continuous(
        mat(2, 2, &[0.0, 1.0, -6.0, -5.0]),
        mat(2, 2, &[1.0, 0.0, 0.0, 1.0]),
        mat(1, 2, &[1.0, 0.0]),
        Mat::zeros(1, 2),
    )
    .unwrap();
    assert!(sys.zeros().unwrap().is_empty());
    // An uncontrollable mode is an input-decoupling zero in the MIMO case too.
    let sys = StateSpace::continuous(
        Mat::from_diagonal(&pendulab_lti::Vector::from_row_slice(&[-1.0, -2.0, -7.0])),
        mat(3, 2, &[1.0, 0.0, 0.0, 1.0, 0.0, 0.0]),
        mat(2, 3, &[1.0, 0.0, 1.0, 0.0, 1.0, 1.0]),
        Mat::zeros(2, 2),
    )
    .unwrap();
    assert_same_poles(&sys.zeros().unwrap(), &[c(-7.0, 0.0)], 1e-12);
}

#[test]
fn ss_to_tf_matches_frequency_response_of_the_cart_pendulum() {
    // Both outputs of the cart pendulum, one at a time: G(jω) from the state space and from
    // the converted transfer function agree at every frequency (invariant comparison).
    let (a, b) = cdip();
    for row in [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.3, -1.0, 0.2, 0.05],
    ] {
        let sys = StateSpace::continuous(a.clone(), b.clone(), mat(1, 4, &row), Mat::zeros(1, 1))
            .unwrap();
        let g = TransferFunction::from_state_space(&sys).unwrap();
        for &w in &logspace(-1.0, 2.0, 7) {
            let s = c(0.0, w);
            let x = sys.evaluate(s).unwrap()[(0, 0)];
            // Polynomial evaluation of a degree-4 transfer function with O(100) coefficients:
            // 1e-11 relative.
            assert!((g.eval(s) - x).norm() < 1e-11 * x.norm(), "w={w}");
        }
    }
}

#[test]
fn freqresp_mimo_matches_direct_solves() {
    let (a, b) = cdip();
    let b2 = Mat::from_fn(
        4,
        2,
        |i, j| if j == 0 { b[(i, 0)] } else { (i as f64) - 1.5 },
    );
    let cm = mat(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let d = mat(2, 2, &[0.0, 0.1, 0.2, 0.0]);
    let sys = StateSpace::continuous(a, b2, cm, d).unwrap();
    let w = [0.1, 1.0, 5.7, 30.0];
    let f = freqresp(&sys, &w).unwrap();
    for (k, &wk) in w.iter().enumerate() {
        // Independent route: a dense complex LU solve of (jωI − A) X = B.
        let direct = sys.evaluate(c(0.0, wk)).unwrap();
        assert!((&f.response[k] - &direct).norm() < 1e-12 * direct.norm());
    }
    // A frequency exactly at a pole (discrete system with a pole on the unit circle at
    // z = 1, i.e. ω = 0) is reported, not returned as garbage.
    let dint = StateSpace::discrete(
        mat(1, 1, &[1.0]),
        mat(1, 1, &[1.0]),
        mat(1, 1, &[1.0]),
        Mat::zeros(1, 1),
        0.1,
    )
    .unwrap();
    assert!(matches!(
        freqresp(&dint, &[0.0]),
        Err(LtiError::PoleAtEvaluationPoint { .. })
    ));
    assert!(freqresp(&dint, &[f64::NAN]).is_err());
}

#[test]
fn frequency_grid_covers_the_dynamics() {
    // Poles at 0.5 and 200 rad/s: the grid spans a decade beyond each.
    let g = TransferFunction::<Continuous>::continuous(&[100.0], &[1.0, 200.5, 100.0]).unwrap();
    let w = frequency_grid(&g.to_state_space().unwrap(), 10).unwrap();
    assert!(w[0] <= 0.05 + 1e-12 && *w.last().unwrap() >= 2000.0 - 1e-9);
    assert!(w.windows(2).all(|p| p[1] > p[0]));
    // Discrete grids stop at Nyquist.
    let gd = g
        .c2d(0.01, pendulab_lti::Discretization::Zoh)
        .unwrap()
        .to_state_space()
        .unwrap();
    let w = frequency_grid(&gd, 10).unwrap();
    assert!(*w.last().unwrap() <= std::f64::consts::PI / 0.01 * (1.0 + 1e-12));
}

#[test]
fn dc_gain_of_state_space() {
    // G = 3/(s + 2) → 1.5; discrete 0.5/(z − 0.5) → 1; an integrator → error.
    let g = TransferFunction::continuous(&[3.0], &[1.0, 2.0])
        .unwrap()
        .to_state_space()
        .unwrap();
    assert!((g.dc_gain().unwrap()[(0, 0)] - 1.5).abs() < 1e-15);
    let gd = TransferFunction::discrete(&[0.5], &[1.0, -0.5], 0.1)
        .unwrap()
        .to_state_space()
        .unwrap();
    assert!((gd.dc_gain().unwrap()[(0, 0)] - 1.0).abs() < 1e-15);
    let (a, b) = cdip();
    let cart =
        StateSpace::continuous(a, b, mat(1, 4, &[1.0, 0.0, 0.0, 0.0]), Mat::zeros(1, 1)).unwrap();
    assert!(matches!(
        cart.dc_gain(),
        Err(LtiError::PoleAtEvaluationPoint { .. })
    ));
}
