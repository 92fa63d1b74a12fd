//! pendulab-ident against independent references: NumPy's `lstsq`, SciPy's Savitzky–Golay
//! and `cont2discrete` + `lfilter` (fixture written by `tools/reference/ident_reference.py`),
//! and closed forms of the filter `1/(T s + 1)³`.

use pendulab_ident::{
    FilterHold, LowPass3, least_squares, savgol_coefficients, savitzky_golay, three_point,
    three_point_twice,
};
use serde_json::Value;

fn fixture() -> Value {
    serde_json::from_str(include_str!("fixtures/ident_reference.json")).unwrap()
}

fn vecf(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

#[test]
fn least_squares_matches_numpy_lstsq() {
    let f = fixture();
    for (i, case) in f["lstsq"].as_array().unwrap().iter().enumerate() {
        let cols: Vec<Vec<f64>> = case["a_columns"]
            .as_array()
            .unwrap()
            .iter()
            .map(vecf)
            .collect();
        let names: Vec<String> = (0..cols.len()).map(|j| format!("p{j}")).collect();
        let pairs: Vec<(&str, &[f64])> = names
            .iter()
            .zip(&cols)
            .map(|(n, c)| (n.as_str(), c.as_slice()))
            .collect();
        let b = vecf(&case["b"]);
        let ls = least_squares(&pairs, ("b", &b)).unwrap();
        let est = vecf(&case["estimate"]);
        let se = vecf(&case["std_error"]);
        let n = b.len() as f64;
        // Householder QR vs LAPACK's SVD-based gelsd: both backward stable, so they agree to
        // about cond(A)·ε relative (case 1: cond 2 → 1e-13; case 2: cond 5e4 → 1e-11).
        let tol = 1e3 * f64::EPSILON * case["condition"].as_f64().unwrap();
        for j in 0..est.len() {
            assert!(
                rel(ls.estimate[j], est[j]) < tol,
                "case {i} p{j}: {} vs {}",
                ls.estimate[j],
                est[j]
            );
            assert!(
                rel(ls.std_error[j], se[j]) < tol,
                "case {i} se{j}: {} vs {}",
                ls.std_error[j],
                se[j]
            );
        }
        // Residual: RSS from NumPy; RMS = √(RSS/n). Condition: numpy.linalg.cond (SVD of A)
        // vs ours (SVD of R): same singular values up to rounding.
        let rms = (case["rss"].as_f64().unwrap() / n).sqrt();
        assert!(rel(ls.residual_rms, rms) < 1e-10, "case {i} rms");
        assert!(
            rel(ls.condition, case["condition"].as_f64().unwrap()) < 1e-10,
            "case {i} cond"
        );
        assert_eq!(case["rank"].as_u64().unwrap() as usize, est.len());
    }
}

#[test]
fn savgol_coefficients_match_scipy() {
    let f = fixture();
    for c in f["savgol_coeffs"].as_array().unwrap() {
        let (w, o, d, delta, pos) = (
            c["window"].as_u64().unwrap() as usize,
            c["order"].as_u64().unwrap() as usize,
            c["deriv"].as_u64().unwrap() as usize,
            c["delta"].as_f64().unwrap(),
            c["pos"].as_u64().unwrap() as usize,
        );
        let ours = savgol_coefficients(w, o, d, delta, pos).unwrap();
        let theirs = vecf(&c["coefficients"]);
        let scale = theirs.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (a, b) in ours.iter().zip(&theirs) {
            // Both are pseudo-inverse rows of a small Vandermonde matrix (SciPy: lstsq on
            // unscaled powers, ours: QR on scaled powers); agreement to ~1e-10 of the largest
            // coefficient leaves room for SciPy's conditioning at order 4.
            assert!(
                (a - b).abs() < 1e-10 * scale,
                "w={w} o={o} d={d} pos={pos}: {a} vs {b}"
            );
        }
    }
    let s = &f["savgol_filter"];
    let x = vecf(&s["x"]);
    let ours = savitzky_golay(
        &x,
        s["ts"].as_f64().unwrap(),
        s["window"].as_u64().unwrap() as usize,
        s["order"].as_u64().unwrap() as usize,
        s["deriv"].as_u64().unwrap() as usize,
    )
    .unwrap();
    let theirs = vecf(&s["result"]);
    let scale = theirs.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (k, (a, b)) in ours.iter().zip(&theirs).enumerate() {
        // Whole signal including the polynomial-fit ends (mode="interp").
        assert!((a - b).abs() < 1e-9 * scale, "sample {k}: {a} vs {b}");
    }
}

#[test]
fn lowpass_matches_scipy_cont2discrete() {
    let f = fixture();
    let l = &f["lowpass3"];
    let (tf, ts) = (l["tf"].as_f64().unwrap(), l["ts"].as_f64().unwrap());
    let u = vecf(&l["u"]);
    for (hold, key) in [(FilterHold::Zoh, "zoh"), (FilterHold::Foh, "foh")] {
        let y = LowPass3::new(tf, ts, hold).unwrap().filter(&u);
        let r = vecf(&l[key]);
        for (k, (a, b)) in y.iter().zip(&r).enumerate() {
            // SciPy: transfer-function coefficients run by lfilter (direct form II transposed);
            // ours: the state-space recursion. Same exact discretisation; the polynomial form
            // of a triple pole at 0.987 loses ~6 digits to coefficient rounding.
            assert!((a - b).abs() < 1e-8, "{key} sample {k}: {a} vs {b}");
        }
    }
}

#[test]
fn lowpass_step_response_is_the_closed_form_at_the_samples() {
    // ZOH-exact: a unit step (constant between samples) gives the continuous step response of
    // 1/(T s + 1)³, 1 − e^{−t/T}(1 + t/T + t²/(2T²)), exactly at t = k·ts.
    for (tf, ts) in [(0.075, 0.001), (0.02, 0.005), (1.0, 0.1)] {
        let f = LowPass3::new(tf, ts, FilterHold::Zoh).unwrap();
        let y = f.filter(&vec![1.0; 2000]);
        for (k, yk) in y.iter().enumerate() {
            let r = k as f64 * ts / tf;
            let exact = 1.0 - (-r).exp() * (1.0 + r + r * r / 2.0);
            // Rounding of a 2000-step recursion with a contraction: ~1e-14.
            assert!(
                (yk - exact).abs() < 1e-12,
                "tf={tf} ts={ts} k={k}: {yk} vs {exact}"
            );
        }
        // DC gain 1 (closed form of the discrete filter; rounding only).
        assert!((f.dc_gain() - 1.0).abs() < 1e-12);
        let g = LowPass3::new(tf, ts, FilterHold::Foh).unwrap();
        assert!((g.dc_gain() - 1.0).abs() < 1e-12);
    }
}

#[test]
fn zero_phase_filter_has_no_delay_and_the_squared_gain() {
    // A sinusoid through the forward–backward filter: amplitude |F(jω)|² = 1/(1 + (ωT)²)³
    // and zero phase in the middle of the record (transients of both passes decay as
    // e^{−t/T}·poly, negligible 2 s from the ends). The discretisation changes |F| by
    // O((ω ts)²) ≈ 1e-5 at ω = 5 rad/s, ts = 1 ms.
    let (tf, ts, w) = (0.075, 0.001, 5.0);
    let n = 12_000;
    let u: Vec<f64> = (0..n).map(|k| (w * k as f64 * ts).sin()).collect();
    for hold in [FilterHold::Zoh, FilterHold::Foh] {
        let y = LowPass3::new(tf, ts, hold).unwrap().filter_zero_phase(&u);
        // Project y on sin and cos over whole periods in the middle.
        let period = (2.0 * std::f64::consts::PI / w / ts).round() as usize;
        let periods = 5;
        let (a, b) = (3000, 3000 + periods * period);
        let (mut s, mut c) = (0.0, 0.0);
        for k in a..b {
            let ph = w * k as f64 * ts;
            s += y[k] * ph.sin();
            c += y[k] * ph.cos();
        }
        let m = (b - a) as f64 / 2.0;
        let (in_phase, quad) = (s / m, c / m);
        let expected = 1.0 / (1.0 + (w * tf).powi(2)).powi(3);
        // Whole periods on a 1 ms grid are 1257 samples for 2π/5 = 1256.6 ms: the projection
        // leaks ~3e-4 of the amplitude; the discretisation ~1e-5.
        assert!(
            (in_phase - expected).abs() < 1e-3,
            "{hold:?}: {in_phase} vs {expected}"
        );
        assert!(quad.abs() < 1e-3, "{hold:?}: quadrature {quad}");
    }
}

#[test]
fn three_point_on_a_cubic_is_second_order_accurate() {
    // x = t³: interior error of the central difference is ts² x'''/6 = ts²; at the ends the
    // one-sided formula errs by ts² x'''/3 = 2 ts² (Taylor remainder), both exact in closed form.
    let ts = 0.01;
    let x: Vec<f64> = (0..30).map(|k| (k as f64 * ts).powi(3)).collect();
    let d = three_point(&x, ts).unwrap();
    for k in 1..29 {
        let t = k as f64 * ts;
        assert!((d[k] - (3.0 * t * t + ts * ts)).abs() < 1e-12, "k={k}");
    }
    assert!((d[0] - (0.0 - 2.0 * ts * ts)).abs() < 1e-12);
    let t = 29.0 * ts;
    assert!((d[29] - (3.0 * t * t - 2.0 * ts * ts)).abs() < 1e-12);
    // Twice: interior second difference over 2ts of a cubic = 6t exactly.
    let dd = three_point_twice(&x, ts).unwrap();
    for k in 2..28 {
        assert!((dd[k] - 6.0 * k as f64 * ts).abs() < 1e-9, "k={k}");
    }
}
