//! ARX identification (`pendulab_ident::arx`) on data simulated from a known ARX system:
//! the true coefficients are the independent reference (noise-free data satisfy the model's
//! defining equation exactly; with equation noise the estimate must lie within a few of its
//! own standard errors of them).

use pendulab_ident::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// The true system: `(1 − 1.5 q⁻¹ + 0.7 q⁻²) y = (1.0 q⁻¹ + 0.5 q⁻²) u + e`, orders [2 2 1].
const A: [f64; 3] = [1.0, -1.5, 0.7];
const B: [f64; 2] = [1.0, 0.5];
const TS: f64 = 0.01;

fn simulate(n: usize, noise: f64, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let g = Normal::new(0.0, 1.0).unwrap();
    let u: Vec<f64> = (0..n).map(|_| g.sample(&mut rng)).collect();
    let mut y = vec![0.0; n];
    for k in 0..n {
        let mut v = noise * g.sample(&mut rng);
        for i in 1..A.len() {
            if k >= i {
                v -= A[i] * y[k - i];
            }
        }
        for (j, b) in B.iter().enumerate() {
            if k > j {
                v += b * u[k - 1 - j];
            }
        }
        y[k] = v;
    }
    (u, y)
}

#[test]
fn noise_free_data_give_the_exact_parameters() {
    let (u, y) = simulate(500, 0.0, 1);
    let m = arx(&[Experiment::new(&u, &y)], TS, ArxOrders::new(2, 2, 1)).unwrap();
    for (e, t) in m.a.iter().zip(A) {
        assert!((e - t).abs() < 1e-10, "a = {:?}", m.a);
    }
    for (e, t) in m.b.iter().zip(B) {
        assert!((e - t).abs() < 1e-10, "b = {:?}", m.b);
    }
    assert!(m.noise_variance < 1e-20);
    // The transfer function's poles are the roots of z² − 1.5 z + 0.7 (closed form).
    let poles = m.transfer_function().unwrap().poles().unwrap();
    let (re, im) = (0.75, (0.7f64 - 0.75 * 0.75).sqrt());
    for p in poles {
        assert!(
            (p.re - re).abs() < 1e-9 && (p.im.abs() - im).abs() < 1e-9,
            "{p}"
        );
    }
    // The model simulated on its own input reproduces the output: 100 % fit.
    assert!((m.fit_percent(&u, &y).unwrap() - 100.0).abs() < 1e-6);
    // The state-space realisation has the same poles.
    let ss = m.state_space().unwrap();
    let ev = pendulab_lti::linalg::eigenvalues(ss.a()).unwrap();
    assert!(ev.iter().all(|p| (p.re - re).abs() < 1e-9));
}

#[test]
fn white_equation_noise_gives_estimates_within_their_standard_errors() {
    let sigma = 0.2;
    let (u, y) = simulate(4000, sigma, 2);
    let m = arx(&[Experiment::new(&u, &y)], TS, ArxOrders::new(2, 2, 1)).unwrap();
    let truth = [A[1], A[2], B[0], B[1]];
    let est = [m.a[1], m.a[2], m.b[0], m.b[1]];
    for i in 0..4 {
        let z = (est[i] - truth[i]) / m.std_error[i];
        assert!(
            z.abs() < 4.0,
            "parameter {i}: {} vs {} ({z} σ)",
            est[i],
            truth[i]
        );
        assert!(m.std_error[i] > 0.0 && m.std_error[i] < 0.05);
    }
    // The residual variance estimates σ² (relative standard deviation √(2/N) ≈ 2 %).
    assert!((m.noise_variance / (sigma * sigma) - 1.0).abs() < 0.1);
    // A second, independent record validates the model: its simulation explains most of
    // the output (the noise enters through 1/A, so the fit is below 100 %).
    let (uv, yv) = simulate(4000, sigma, 3);
    let fit = m.fit_percent(&uv, &yv).unwrap();
    assert!(fit > 70.0 && fit < 100.0, "fit {fit}");
}

#[test]
fn two_records_are_merged_without_crossing_their_boundary() {
    let (u1, y1) = simulate(300, 0.0, 4);
    let (u2, y2) = simulate(300, 0.0, 5);
    let m = arx(
        &[Experiment::new(&u1, &y1), Experiment::new(&u2, &y2)],
        TS,
        ArxOrders::new(2, 2, 1),
    )
    .unwrap();
    assert_eq!(m.lsq.samples, 2 * (300 - 2));
    assert!((m.a[1] - A[1]).abs() < 1e-10 && (m.b[1] - B[1]).abs() < 1e-10);
    // Concatenating the records instead would cross the boundary and leave a residual.
    let (u, y) = ([u1, u2].concat(), [y1, y2].concat());
    let c = arx(&[Experiment::new(&u, &y)], TS, ArxOrders::new(2, 2, 1)).unwrap();
    assert!(c.noise_variance > 1e-12);
}

#[test]
fn aic_selects_the_true_orders() {
    let (u, y) = simulate(3000, 0.2, 6);
    let sel = arx_order_selection(&[Experiment::new(&u, &y)], TS, 1..=4, 1..=4, 0..=2).unwrap();
    assert_eq!(sel.best.orders, ArxOrders::new(2, 2, 1), "{:?}", sel.best);
    assert_eq!(sel.candidates.len(), 4 * 4 * 3);
    // Every candidate was scored on the same rows, so larger models never lose on V.
    let v = |o: ArxOrders| sel.candidates.iter().find(|c| c.orders == o).unwrap().loss;
    assert!(v(ArxOrders::new(3, 3, 1)) <= v(ArxOrders::new(2, 2, 1)));
    assert!(v(ArxOrders::new(1, 1, 1)) > 2.0 * v(ArxOrders::new(2, 2, 1)));
}

#[test]
fn bad_input_gives_typed_errors() {
    let (u, mut y) = simulate(50, 0.0, 7);
    let o = ArxOrders::new(2, 2, 1);
    assert!(matches!(
        arx(&[Experiment::new(&u, &y)], TS, ArxOrders::new(0, 0, 1)),
        Err(IdentError::InvalidParameter { .. })
    ));
    assert!(matches!(
        arx(&[Experiment::new(&u[..5], &y[..5])], TS, o),
        Err(IdentError::TooFewSamples { .. })
    ));
    assert!(matches!(
        arx(&[Experiment::new(&u[..4], &y)], TS, o),
        Err(IdentError::LengthMismatch { .. })
    ));
    assert!(matches!(
        arx(&[Experiment::new(&u, &y)], 0.0, o),
        Err(IdentError::InvalidParameter { .. })
    ));
    // A constant input does not excite the B coefficients: rank deficient.
    let ones = vec![1.0; 50];
    let zeros = vec![0.0; 50];
    assert!(matches!(
        arx(&[Experiment::new(&ones, &zeros)], TS, o),
        Err(IdentError::RankDeficient { .. })
    ));
    y[17] = f64::NAN;
    match arx(&[Experiment::new(&u, &y)], TS, o) {
        Err(IdentError::NonFinite { column, at, .. }) => {
            assert_eq!((column.as_str(), at.index), ("y", 17));
        }
        other => panic!("{other:?}"),
    }
}
