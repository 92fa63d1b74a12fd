//! Subspace identification (`pendulab_ident::moesp`, PO-MOESP) on noise-free data simulated
//! from random stable systems: the system's similarity invariants — eigenvalues, the Markov
//! parameters `D, C B, C A B, …` (which determine the transfer function) — are the independent
//! reference, and the order must stand out in the singular values.

use pendulab_ident::*;
use pendulab_lti::response::{LsimOptions, lsim};
use pendulab_lti::{Mat, StateSpace};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

const TS: f64 = 0.01;

/// A random system with the given real-block-diagonal `A₀` seen through a random similarity.
fn random_system(a0: &Mat, m: usize, l: usize, seed: u64) -> StateSpace<pendulab_lti::Discrete> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let g = Normal::new(0.0, 1.0).unwrap();
    let n = a0.nrows();
    let t = Mat::from_fn(n, n, |i, j| {
        g.sample(&mut rng) + if i == j { 2.0 } else { 0.0 }
    });
    let a = &t * a0 * t.clone().try_inverse().unwrap();
    let b = Mat::from_fn(n, m, |_, _| g.sample(&mut rng));
    let c = Mat::from_fn(l, n, |_, _| g.sample(&mut rng));
    let d = Mat::from_fn(l, m, |_, _| g.sample(&mut rng));
    StateSpace::discrete(a, b, c, d, TS).unwrap()
}

fn data(
    sys: &StateSpace<pendulab_lti::Discrete>,
    n: usize,
    seed: u64,
) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let g = Normal::new(0.0, 1.0).unwrap();
    let u = Mat::from_fn(n, sys.nu(), |_, _| g.sample(&mut rng));
    let t: Vec<f64> = (0..n).map(|k| k as f64 * TS).collect();
    let x0: Vec<f64> = (0..sys.nx()).map(|_| g.sample(&mut rng)).collect();
    let tr = lsim(sys, &u, &t, Some(&x0), &LsimOptions::default()).unwrap();
    let cols = |m: &Mat| {
        (0..m.ncols())
            .map(|j| m.column(j).iter().copied().collect())
            .collect()
    };
    (cols(&u), cols(tr.y()))
}

fn sorted_eigenvalues(a: &Mat) -> Vec<(f64, f64)> {
    let mut ev: Vec<(f64, f64)> = pendulab_lti::linalg::eigenvalues(a)
        .unwrap()
        .iter()
        .map(|z| (z.re, z.im))
        .collect();
    ev.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.total_cmp(&q.1)));
    ev
}

/// `D, C B, C A B, …, C A⁹ B`.
fn markov(sys: &StateSpace<pendulab_lti::Discrete>) -> Vec<Mat> {
    let mut out = vec![sys.d().clone()];
    let mut ak_b = sys.b().clone();
    for _ in 0..10 {
        out.push(sys.c() * &ak_b);
        ak_b = sys.a() * ak_b;
    }
    out
}

fn check_recovery(truth: &StateSpace<pendulab_lti::Discrete>, id: &Moesp) {
    let n = truth.nx();
    assert_eq!(id.order, n, "singular values {:?}", id.singular_values);
    // The order stands out: a gap of many decades after the n-th singular value.
    let sv = &id.singular_values;
    assert!(sv[n] < 1e-8 * sv[n - 1], "{sv:?}");
    for (p, q) in sorted_eigenvalues(truth.a())
        .iter()
        .zip(sorted_eigenvalues(id.model.a()))
    {
        assert!(
            (p.0 - q.0).abs() < 1e-8 && (p.1 - q.1).abs() < 1e-8,
            "{p:?} vs {q:?}"
        );
    }
    for (k, (p, q)) in markov(truth).iter().zip(markov(&id.model)).enumerate() {
        let err = (p - &q).norm() / p.norm();
        assert!(err < 1e-8, "Markov parameter {k}: relative error {err}");
    }
}

#[test]
fn siso_four_states_recovered_from_noise_free_data() {
    // Eigenvalues 0.9, 0.5, 0.6 ± 0.3i.
    let a0 = Mat::from_row_slice(
        4,
        4,
        &[
            0.9, 0.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.6, 0.3, 0.0, 0.0, -0.3, 0.6,
        ],
    );
    let sys = random_system(&a0, 1, 1, 11);
    let (u, y) = data(&sys, 600, 12);
    let rec = IoRecord::siso(&u[0], &y[0]);
    let id = moesp(&[rec], TS, MoespOptions::default()).unwrap();
    check_recovery(&sys, &id);
    // The identified model (with its estimated initial state) reproduces the record, and
    // from rest it reproduces a second record started at rest.
    assert!(id.lsq.residual_rms < 1e-8 * (y[0].iter().map(|v| v * v).sum::<f64>() / 600.0).sqrt());
    let (u2, mut y2) = data(&sys, 400, 13);
    let t: Vec<f64> = (0..400).map(|k| k as f64 * TS).collect();
    let u2m = Mat::from_fn(400, 1, |k, _| u2[0][k]);
    let y2m = lsim(&sys, &u2m, &t, None, &LsimOptions::default()).unwrap();
    y2[0] = y2m.y().column(0).iter().copied().collect();
    let fit = id.fit_percent(&IoRecord::siso(&u2[0], &y2[0])).unwrap();
    assert!((fit[0] - 100.0).abs() < 1e-6, "fit {fit:?}");
}

#[test]
fn mimo_three_states_two_inputs_two_outputs() {
    // Eigenvalues 0.8, −0.4, 0.2.
    let a0 = Mat::from_diagonal(&pendulab_lti::Vector::from_vec(vec![0.8, -0.4, 0.2]));
    let sys = random_system(&a0, 2, 2, 21);
    let (u, y) = data(&sys, 500, 22);
    let rec = IoRecord {
        u: u.iter().map(Vec::as_slice).collect(),
        y: y.iter().map(Vec::as_slice).collect(),
    };
    let id = moesp(
        &[rec],
        TS,
        MoespOptions {
            horizon: 6,
            order: None,
            max_order: None,
        },
    )
    .unwrap();
    check_recovery(&sys, &id);
}

#[test]
fn two_records_are_combined() {
    let a0 = Mat::from_diagonal(&pendulab_lti::Vector::from_vec(vec![0.95, 0.7, -0.5]));
    let sys = random_system(&a0, 1, 1, 31);
    let (u1, y1) = data(&sys, 150, 32);
    let (u2, y2) = data(&sys, 150, 33);
    let id = moesp(
        &[
            IoRecord::siso(&u1[0], &y1[0]),
            IoRecord::siso(&u2[0], &y2[0]),
        ],
        TS,
        MoespOptions {
            horizon: 8,
            order: None,
            max_order: None,
        },
    )
    .unwrap();
    check_recovery(&sys, &id);
    assert_eq!(id.initial_states.len(), 2);
}

#[test]
fn bad_input_gives_typed_errors() {
    let u = vec![1.0; 30];
    let mut y = vec![0.5; 30];
    let short = MoespOptions::default();
    assert!(matches!(
        moesp(&[], TS, short),
        Err(IdentError::InvalidParameter { .. })
    ));
    assert!(matches!(
        moesp(&[IoRecord::siso(&u, &y)], TS, short),
        Err(IdentError::TooFewSamples { .. })
    ));
    assert!(matches!(
        moesp(
            &[IoRecord::siso(&u, &y)],
            TS,
            MoespOptions {
                horizon: 1,
                order: None,
                max_order: None,
            }
        ),
        Err(IdentError::InvalidParameter { .. })
    ));
    assert!(matches!(
        moesp(
            &[IoRecord::siso(&u, &y)],
            TS,
            MoespOptions {
                horizon: 3,
                order: Some(5),
                max_order: None,
            }
        ),
        Err(IdentError::InvalidParameter { .. })
    ));
    y[3] = f64::INFINITY;
    match moesp(
        &[IoRecord::siso(&u, &y)],
        TS,
        MoespOptions {
            horizon: 3,
            order: None,
            max_order: None,
        },
    ) {
        Err(IdentError::NonFinite { column, at, .. }) => {
            assert_eq!((column.as_str(), at.index), ("y0", 3))
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        moesp(&[IoRecord::siso(&u[..10], &y)], TS, short),
        Err(IdentError::LengthMismatch { .. })
    ));
}

#[test]
fn max_order_caps_the_selection() {
    // A third-order system: unbounded, the gap rule finds 3; with `max_order = 2` it may only
    // choose among 1 and 2, by the same rule (the largest σ_n/σ_{n+1}) applied here to the
    // returned singular values, and the model is the one `order = Some(n)` identifies.
    let a0 = Mat::from_diagonal(&pendulab_lti::Vector::from_vec(vec![0.9, 0.7, -0.6]));
    let sys = random_system(&a0, 1, 1, 41);
    let (u, y) = data(&sys, 400, 42);
    let rec = || [IoRecord::siso(&u[0], &y[0])];
    let opts = |order, max_order| MoespOptions {
        horizon: 8,
        order,
        max_order,
    };
    let full = moesp(&rec(), TS, opts(None, None)).unwrap();
    check_recovery(&sys, &full);
    let capped = moesp(&rec(), TS, opts(None, Some(2))).unwrap();
    let sv = &capped.singular_values;
    let want = if sv[0] / sv[1] >= sv[1] / sv[2] { 1 } else { 2 };
    assert_eq!(capped.order, want, "{sv:?}");
    assert_eq!(capped.order, 2, "{sv:?}");
    let fixed = moesp(&rec(), TS, opts(Some(2), None)).unwrap();
    assert_eq!(capped, fixed);
    // A cap above what the horizon allows is the horizon's limit: the unbounded result.
    assert_eq!(moesp(&rec(), TS, opts(None, Some(100))).unwrap(), full);
    for bad in [opts(None, Some(0)), opts(Some(2), Some(2))] {
        match moesp(&rec(), TS, bad) {
            Err(IdentError::InvalidParameter { name, .. }) => assert_eq!(name, "MOESP max_order"),
            other => panic!("{bad:?}: {other:?}"),
        }
    }
}
