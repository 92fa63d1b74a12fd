//! `c2d` by pole-zero matching and by impulse invariance: closed forms, the defining
//! property (sampled impulse response), SciPy's `cont2discrete(…, 'impulse')` and
//! python-control's `sample_system(…, 'matched')` (fixture of `tools/reference/tf_python.py`,
//! python-control 0.10.2, SciPy 1.16.3).

use pendulab_lti::matrix_functions::expm;
use pendulab_lti::{
    Complex64, Discretization, LtiError, Mat, Polynomial, StateSpace, TransferFunction,
};
use pendulab_testkit::json::{matrix, vector};
use std::path::Path;

fn fixture() -> serde_json::Value {
    pendulab_testkit::json::read(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/tf_reference.json"),
    )
}

fn close(a: &Mat, b: &Mat, tol: f64) -> bool {
    a.shape() == b.shape() && (a - b).amax() <= tol * b.amax().max(1.0)
}

#[test]
fn matched_double_integrator_like_plant_is_matlabs_answer() {
    // MATLAB: c2d(tf(11, [1 1 0]), 0.1, 'matched') = 0.052339 (z + 1)/((z − 1)(z − 0.9048)):
    // one of the two zeros at infinity goes to z = −1, the gain matches lim s G(s) = 11 with
    // lim (z − 1)/ts G(z), i.e. K = 11 ts (1 − e^{−ts})/2.
    let ts = 0.1;
    let g = TransferFunction::continuous(&[11.0], &[1.0, 1.0, 0.0]).unwrap();
    let gd = g.c2d(ts, Discretization::Matched).unwrap();
    let p = (-ts).exp();
    let k = 11.0 * ts * (1.0 - p) / 2.0;
    let want_num = [k, k];
    let want_den = [1.0, -(1.0 + p), p];
    for (x, y) in gd.num().coefficients().iter().zip(want_num) {
        assert!((x - y).abs() < 1e-15, "{gd}");
    }
    for (x, y) in gd.den().coefficients().iter().zip(want_den) {
        assert!((x - y).abs() < 1e-15, "{gd}");
    }
    assert!((gd.num().leading() - 0.052339).abs() < 5e-7);
    assert!((gd.ts() - ts).abs() == 0.0);
}

#[test]
fn matched_agrees_with_python_control() {
    let f = fixture();
    for case in f["matched"].as_array().unwrap() {
        let (num, den, ts) = (
            vector(&case["num"]),
            vector(&case["den"]),
            case["ts"].as_f64().unwrap(),
        );
        let g = TransferFunction::continuous(&num, &den).unwrap();
        let ours = g.c2d(ts, Discretization::Matched).unwrap();
        let theirs =
            TransferFunction::discrete(&vector(&case["numd"]), &vector(&case["dend"]), ts).unwrap();
        // python-control leaves the zeros at infinity there; MATLAB's rule (ours) puts all but
        // one at z = −1: multiply theirs by ((z + 1)/2)^{r − 1}, which keeps G(1).
        let r = g.relative_degree().max(1) as usize - 1;
        let extra = (0..r).fold(Polynomial::one(), |acc, _| {
            &acc * &Polynomial::new(&[0.5, 0.5]).unwrap()
        });
        let theirs =
            TransferFunction::new(theirs.num() * &extra, theirs.den().clone(), theirs.domain())
                .unwrap();
        assert_eq!(ours.den().degree(), theirs.den().degree());
        for (x, y) in ours
            .den()
            .coefficients()
            .iter()
            .zip(theirs.den().coefficients())
        {
            assert!((x - y).abs() < 1e-12, "{g}: {ours} vs {theirs}");
        }
        for (x, y) in ours
            .num()
            .coefficients()
            .iter()
            .zip(theirs.num().coefficients())
        {
            assert!(
                (x - y).abs() < 1e-12 * y.abs().max(1.0),
                "{g}: {ours} vs {theirs}"
            );
        }
        assert!((ours.dc_gain().unwrap() - g.dc_gain().unwrap()).abs() < 1e-12);
    }
}

#[test]
fn matched_state_space_is_siso_only_and_improper_is_refused() {
    let g = TransferFunction::continuous(&[1.0, 2.0], &[1.0, 3.0, 5.0]).unwrap();
    let sys = g.to_state_space().unwrap();
    let sd = sys.c2d(0.05, Discretization::Matched).unwrap();
    let gd = g.c2d(0.05, Discretization::Matched).unwrap();
    let z = Complex64::from_polar(1.0, 0.9);
    assert!((sd.evaluate(z).unwrap()[(0, 0)] - gd.eval(z)).norm() < 1e-12);
    let mimo = StateSpace::continuous(
        Mat::from_row_slice(1, 1, &[-1.0]),
        Mat::from_row_slice(1, 2, &[1.0, 1.0]),
        Mat::from_row_slice(1, 1, &[1.0]),
        Mat::zeros(1, 2),
    )
    .unwrap();
    assert!(matches!(
        mimo.c2d(0.1, Discretization::Matched),
        Err(LtiError::NotSiso { .. })
    ));
    let pd = TransferFunction::continuous(&[1.0, 1.0], &[1.0]).unwrap();
    assert!(matches!(
        pd.c2d(0.1, Discretization::Matched),
        Err(LtiError::Improper { .. })
    ));
    // A differentiator-like zero at s = 0: s/(s + 1) → (z − 1)/(z − e^{−ts}) ts-scaled so that
    // lim s^{−1}G = 1 = lim (ts/(z − 1)) G(z): K = (1 − e^{−ts})/ts.
    let hp = TransferFunction::continuous(&[1.0, 0.0], &[1.0, 1.0]).unwrap();
    let ts = 0.2;
    let hd = hp.c2d(ts, Discretization::Matched).unwrap();
    let k = (1.0 - (-ts).exp()) / ts;
    assert!(
        (hd.num().coefficients()[0] - k).abs() < 1e-15
            && (hd.num().coefficients()[1] + k).abs() < 1e-15
    );
    // d2c by the new methods is refused with a typed error.
    let d = sys.c2d(0.1, Discretization::Zoh).unwrap();
    for m in [Discretization::Matched, Discretization::Impulse] {
        assert!(matches!(d.d2c(m), Err(LtiError::InvalidArgument(_))));
    }
}

#[test]
fn impulse_matches_scipy() {
    let f = fixture();
    for case in f["impulse"].as_array().unwrap() {
        let ts = case["ts"].as_f64().unwrap();
        let (a, b, c) = (matrix(&case["A"]), matrix(&case["B"]), matrix(&case["C"]));
        let d = Mat::zeros(c.nrows(), b.ncols());
        let sys = StateSpace::continuous(a, b, c, d).unwrap();
        let sd = sys.c2d(ts, Discretization::Impulse).unwrap();
        for (ours, key) in [
            (sd.a(), "Ad"),
            (sd.b(), "Bd"),
            (sd.c(), "Cd"),
            (sd.d(), "Dd"),
        ] {
            assert!(close(ours, &matrix(&case[key]), 1e-13), "{key}: {ours}");
        }
    }
}

#[test]
fn impulse_response_is_the_sampled_continuous_one_times_ts() {
    // h_d[0] = D_d, h_d[k] = C_d A_d^{k−1} B_d must equal ts · C e^{A k ts} B.
    let a = Mat::from_row_slice(3, 3, &[0.0, 1.0, 0.0, 0.0, 0.0, 1.0, -6.0, -11.0, -6.0]);
    let b = Mat::from_row_slice(3, 1, &[0.0, 0.0, 1.0]);
    let c = Mat::from_row_slice(1, 3, &[2.0, 1.0, 0.5]);
    let sys = StateSpace::continuous(a.clone(), b.clone(), c.clone(), Mat::zeros(1, 1)).unwrap();
    let ts = 0.13;
    let sd = sys.c2d(ts, Discretization::Impulse).unwrap();
    let mut power = Mat::identity(3, 3);
    for k in 0..12 {
        let hd = if k == 0 {
            sd.d()[(0, 0)]
        } else {
            let v = sd.c() * &power * sd.b();
            power = &power * sd.a();
            v[(0, 0)]
        };
        let h = (&c * expm(&(&a * (k as f64 * ts))).unwrap() * &b)[(0, 0)];
        assert!((hd - ts * h).abs() < 1e-14, "k = {k}: {hd} vs {}", ts * h);
    }
    // The transfer-function route gives the same G(z).
    let g = TransferFunction::from_state_space(&sys).unwrap();
    let gd = g.c2d(ts, Discretization::Impulse).unwrap();
    let z = Complex64::from_polar(1.1, 0.4);
    assert!((gd.eval(z) - sd.evaluate(z).unwrap()[(0, 0)]).norm() < 1e-12);
    // A feedthrough has no sampled impulse value.
    let biproper = TransferFunction::continuous(&[1.0, 2.0], &[1.0, 3.0]).unwrap();
    assert!(matches!(
        biproper.c2d(ts, Discretization::Impulse),
        Err(LtiError::InvalidArgument(_))
    ));
}
