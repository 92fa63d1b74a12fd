//! The recursive filters against independent computations: the steady-state Kalman filter
//! (`kalman_filter`, a DARE) for the converged time-varying filter; batch weighted least
//! squares for a time-varying linear model; the Kalman filter of RK4's closed-form transition
//! matrix for the EKF and the UKF of a linear system; the true states of a simulation for the
//! velocity estimates of the nonlinear cart from quantised encoders (against the rig's
//! pseudo-differentiator); χ² bounds for NEES and NIS over a seeded Monte-Carlo run.

use nalgebra::{DMatrix, DVector};
use pendulab_control::estimation::kalman_filter;
use pendulab_control::kalman::{
    ExtendedKalmanFilter, KalmanFilter, Measurement, NonlinearFilter, SampledModel, SigmaPoints,
    UnscentedKalmanFilter, encoder_covariance, filter_log, nees, quantization_variance,
};
use pendulab_lti::design::lqe;
use pendulab_lti::{Discretization, Mat, StateSpace};
use pendulab_plants::CartPendulum;
use pendulab_sim::{Differentiation, PseudoDifferentiator, Rk4Work, rk4_step_slice};
use pendulab_testkit::cart;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::f64::consts::PI;

fn cdip() -> StateSpace<pendulab_lti::Continuous> {
    let (a, b) = cart::upright();
    StateSpace::continuous(a, b, cart::measured_output(), Mat::zeros(2, 1)).unwrap()
}

fn diag(v: &[f64]) -> Mat {
    Mat::from_diagonal(&DVector::from_row_slice(v))
}

fn max_abs_diff(a: &Mat, b: &Mat) -> f64 {
    (a - b).amax()
}

#[test]
fn quantisation_variance_is_a_twelfth_of_the_step_squared() {
    // The variance of a uniform error on [−q/2, q/2]: ∫ e² de / q = q²/12.
    let q = 2.0 * PI / 14400.0;
    assert_eq!(quantization_variance(q).unwrap(), q * q / 12.0);
    // And the empirical variance of rounding a finely spread signal matches it.
    let n = 200_000;
    let var: f64 = (0..n)
        .map(|i| {
            let s = 0.123 + i as f64 * 1.37e-3 * q;
            let e = q * (s / q).round() - s;
            e * e
        })
        .sum::<f64>()
        / n as f64;
    assert!((var / (q * q / 12.0) - 1.0).abs() < 0.01, "{var}");
    let r = encoder_covariance(&[4.8414e-5, q]).unwrap();
    assert_eq!(r[(0, 0)], 4.8414e-5 * 4.8414e-5 / 12.0);
    assert!(quantization_variance(0.0).is_err());
}

#[test]
fn time_varying_filter_converges_to_the_steady_state_filter() {
    // Constant matrices: the Riccati recursion of the time-varying filter converges to the DARE
    // solution kalman_filter computes (Schur-method DARE, an independent algorithm).
    let ts = 0.01;
    let sys = cdip().c2d(ts, Discretization::Zoh).unwrap();
    let g = Mat::identity(4, 4);
    let qn = diag(&[1e-8, 1e-8, 1e-3, 1e-2]);
    let rn = encoder_covariance(&[4.8414e-5, 2.0 * PI / 14400.0]).unwrap();
    let ss = kalman_filter(&sys, &g, &qn, &rn).unwrap();
    let mut kf = KalmanFilter::new(&[0.0; 4], &(Mat::identity(4, 4) * 0.1)).unwrap();
    let mut last = None;
    for _ in 0..4000 {
        kf.predict(sys.a(), sys.b(), &[0.0], &qn).unwrap();
        let prior = kf.covariance().clone();
        let inn = kf.update(sys.c(), None, &[0.0, 0.0], &rn).unwrap();
        last = Some((prior, inn.gain));
    }
    let (prior, gain) = last.unwrap();
    let rel = |a: &Mat, b: &Mat| max_abs_diff(a, b) / b.amax();
    assert!(
        rel(&prior, &ss.prior_covariance) < 1e-8,
        "{prior} {}",
        ss.prior_covariance
    );
    assert!(rel(&gain, &ss.filter_gain) < 1e-8);
    assert!(rel(kf.covariance(), &ss.posterior_covariance) < 1e-8);
    // The predictor gain of lqe is A M.
    let l = lqe(&sys, &g, &qn, &rn, None).unwrap().gain;
    assert!(rel(&(sys.a() * &gain), &l) < 1e-8);
}

#[test]
fn time_varying_filter_equals_batch_least_squares() {
    // x_{k+1} = A_k x_k + B_k u_k + w_k, y_k = C_k x_k + v_k with A_k, C_k changing every
    // sample: the filtered x̂_N and P_N are the last block of the weighted least-squares
    // solution over x_0 … x_N and of the inverse of its normal matrix.
    let (n, steps) = (2usize, 12usize);
    let a_k = |k: usize| {
        let w = 1.0 + 0.3 * (k as f64).sin();
        Mat::from_row_slice(2, 2, &[1.0, 0.1, -0.1 * w * w, 0.98])
    };
    let b = Mat::from_row_slice(2, 1, &[0.0, 0.1]);
    let c_k = |k: usize| Mat::from_row_slice(1, 2, &[1.0, 0.5 * (0.7 * k as f64).cos()]);
    let q = Mat::from_row_slice(2, 2, &[1e-3, 2e-4, 2e-4, 4e-3]);
    let r = Mat::from_row_slice(1, 1, &[0.05]);
    let (m0, p0) = (
        [0.2, -0.1],
        Mat::from_row_slice(2, 2, &[0.5, 0.1, 0.1, 0.3]),
    );
    let u: Vec<f64> = (0..steps).map(|k| (0.4 * k as f64).cos()).collect();
    let y: Vec<f64> = (0..=steps)
        .map(|k| 0.3 * (0.9 * k as f64).sin() + 0.1)
        .collect();

    let mut kf = KalmanFilter::new(&m0, &p0).unwrap();
    kf.update(&c_k(0), None, &[y[0]], &r).unwrap();
    for k in 0..steps {
        kf.predict(&a_k(k), &b, &[u[k]], &q).unwrap();
        kf.update(&c_k(k + 1), None, &[y[k + 1]], &r).unwrap();
    }

    // Batch: whitened residual rows W (M X − c) for the prior, the measurements, the dynamics.
    let nvar = n * (steps + 1);
    let mut rows: Vec<(DMatrix<f64>, DVector<f64>)> = Vec::new();
    let whiten = |cov: &Mat| cov.clone().cholesky().unwrap().l().try_inverse().unwrap();
    let block = |m: &Mat, at: usize, rows_: usize| {
        let mut full = DMatrix::zeros(rows_, nvar);
        full.view_mut((0, at * n), (rows_, n)).copy_from(m);
        full
    };
    rows.push((
        &whiten(&p0) * block(&Mat::identity(2, 2), 0, 2),
        &whiten(&p0) * DVector::from_row_slice(&m0),
    ));
    for k in 0..=steps {
        let wr = whiten(&r);
        rows.push((
            &wr * block(&c_k(k), k, 1),
            &wr * DVector::from_row_slice(&[y[k]]),
        ));
    }
    for k in 0..steps {
        let wq = whiten(&q);
        let m = block(&Mat::identity(2, 2), k + 1, 2) - block(&a_k(k), k, 2);
        rows.push((&wq * m, &wq * (b.column(0) * u[k])));
    }
    let total: usize = rows.iter().map(|(m, _)| m.nrows()).sum();
    let mut jm = DMatrix::zeros(total, nvar);
    let mut e = DVector::zeros(total);
    let mut at = 0;
    for (m, v) in &rows {
        jm.view_mut((at, 0), (m.nrows(), nvar)).copy_from(m);
        e.rows_mut(at, m.nrows()).copy_from(v);
        at += m.nrows();
    }
    let normal = jm.transpose() * &jm;
    let inv = normal.clone().try_inverse().unwrap();
    let x = &inv * (jm.transpose() * e);
    let last = steps * n;
    for i in 0..n {
        assert!(
            (kf.state()[i] - x[last + i]).abs() < 1e-12,
            "{:?} {}",
            kf.state(),
            x
        );
        for j in 0..n {
            let pij = inv[(last + i, last + j)];
            assert!((kf.covariance()[(i, j)] - pij).abs() < 1e-12 * (1.0 + pij.abs()));
        }
    }
}

/// RK4's transition over `ts` in `substeps` steps of a linear system, in closed form:
/// `x⁺ = T(hA) x + h S(hA) B u` per step with `T(M) = I + M + M²/2 + M³/6 + M⁴/24` and
/// `S(M) = I + M/2 + M²/6 + M³/24`.
fn rk4_transition(a: &Mat, b: &Mat, ts: f64, substeps: usize) -> (Mat, Mat) {
    let h = ts / substeps as f64;
    let m = a * h;
    let i = Mat::identity(a.nrows(), a.nrows());
    let m2 = &m * &m;
    let m3 = &m2 * &m;
    let m4 = &m3 * &m;
    let t = &i + &m + &m2 / 2.0 + &m3 / 6.0 + &m4 / 24.0;
    let s = (&i + &m / 2.0 + &m2 / 6.0 + &m3 / 24.0) * b * h;
    let (mut ad, mut bd) = (i.clone(), Mat::zeros(b.nrows(), b.ncols()));
    for _ in 0..substeps {
        bd = &t * bd + &s;
        ad = &t * ad;
    }
    (ad, bd)
}

#[test]
fn ekf_and_ukf_of_a_linear_system_are_its_kalman_filter() {
    let sys = cdip();
    let (ts, substeps) = (0.01, 2);
    let (ad, bd) = rk4_transition(sys.a(), sys.b(), ts, substeps);
    let q = diag(&[1e-8, 1e-8, 1e-4, 1e-3]);
    let r = diag(&[1e-6, 2e-6]);
    let x0 = [0.01, -0.02, 0.0, 0.1];
    let p0 = diag(&[1e-3, 1e-3, 1e-2, 1e-2]);
    let model = |m: Measurement| SampledModel::new(sys.clone(), ts, substeps, m, &q, &r).unwrap();
    let mut ekf = ExtendedKalmanFilter::new(model(Measurement::Output), &x0, &p0).unwrap();
    let mut ukf = UnscentedKalmanFilter::new(
        model(Measurement::States(vec![0, 1])),
        &x0,
        &p0,
        SigmaPoints {
            alpha: 0.5,
            beta: 2.0,
            kappa: 1.0,
        },
    )
    .unwrap();
    let mut ukf_default =
        UnscentedKalmanFilter::new(model(Measurement::Output), &x0, &p0, SigmaPoints::default())
            .unwrap();
    let mut kf = KalmanFilter::new(&x0, &p0).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let noise = Normal::new(0.0, 0.01).unwrap();
    for k in 0..300 {
        let t = k as f64 * ts;
        let u = [(3.0 * t).sin()];
        let y = [noise.sample(&mut rng), noise.sample(&mut rng)];
        if k > 0 {
            let u_prev = [(3.0 * (t - ts)).sin()];
            kf.predict(&ad, &bd, &u_prev, &q).unwrap();
            for f in [
                &mut ekf as &mut dyn NonlinearFilter,
                &mut ukf,
                &mut ukf_default,
            ] {
                f.predict(t - ts, &u_prev).unwrap();
            }
        }
        let ik = kf.update(sys.c(), None, &y, &r).unwrap();
        for f in [
            &mut ekf as &mut dyn NonlinearFilter,
            &mut ukf,
            &mut ukf_default,
        ] {
            let inn = f.update(t, &u, &y).unwrap();
            assert!((inn.nis - ik.nis).abs() < 1e-7 * (1.0 + ik.nis), "k {k}");
            for (a, b) in f.state().iter().zip(kf.state()) {
                assert!((a - b).abs() < 1e-9 * (1.0 + b.abs()), "k {k}: {a} vs {b}");
            }
            let dp = max_abs_diff(f.covariance(), kf.covariance());
            assert!(dp < 1e-9 * kf.covariance().amax(), "k {k}: {dp}");
        }
    }
}

/// A run of the book's cart with a voltage that swings the pendulum, sampled at 1 ms: the true
/// states (RK4 with ten substeps per sample), the held inputs and the encoders' levels.
struct CartRun {
    t: Vec<f64>,
    u: Vec<Vec<f64>>,
    x: Vec<[f64; 4]>,
    y: Vec<Vec<f64>>,
}

const Q_Z: f64 = 4.8414e-5;
const Q_THETA: f64 = 2.0 * PI / 14400.0;

fn cart_run(seconds: f64) -> CartRun {
    let plant = CartPendulum::book();
    let ts = 1e-3;
    let steps = (seconds / ts).round() as usize;
    let voltage = |t: f64| 1.5 * (2.0 * PI * 0.8 * t).sin() + 0.8 * (2.0 * PI * 2.3 * t).sin();
    let mut x = vec![0.0, PI, 0.0, 0.0];
    let mut work = Rk4Work::new(4);
    let quant = |v: f64, q: f64| q * (v / q).round();
    let mut run = CartRun {
        t: vec![],
        u: vec![],
        x: vec![],
        y: vec![],
    };
    for k in 0..=steps {
        let t = k as f64 * ts;
        let u = voltage(t);
        run.t.push(t);
        run.u.push(vec![u]);
        run.x.push([x[0], x[1], x[2], x[3]]);
        run.y.push(vec![quant(x[0], Q_Z), quant(x[1], Q_THETA)]);
        for i in 0..10 {
            rk4_step_slice(&plant, t + i as f64 * 1e-4, &mut x, &[u], 1e-4, &mut work);
        }
    }
    run
}

fn rms(e: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = e.fold((0.0, 0usize), |(s, n), v| (s + v * v, n + 1));
    (s / n as f64).sqrt()
}

#[test]
fn nonlinear_filters_estimate_velocities_better_than_the_pseudo_differentiator() {
    let run = cart_run(6.0);
    let ts: f64 = 1e-3;
    // Quantisation as measurement noise; process noise as unmodelled accelerations of 0.5 m/s²
    // and 5 rad/s² (standard deviations over a sample).
    let r = encoder_covariance(&[Q_Z, Q_THETA]).unwrap();
    let q = diag(&[1e-14, 1e-14, (0.5 * ts).powi(2), (5.0 * ts).powi(2)]);
    let model = SampledModel::new(
        CartPendulum::book(),
        ts,
        1,
        Measurement::States(vec![0, 1]),
        &q,
        &r,
    )
    .unwrap();
    let x0 = [run.y[0][0], run.y[0][1], 0.0, 0.0];
    let p0 = diag(&[1e-8, 1e-8, 1e-2, 1e-2]);
    let mut ekf = ExtendedKalmanFilter::new(model.clone(), &x0, &p0).unwrap();
    let mut ukf = UnscentedKalmanFilter::new(model, &x0, &p0, SigmaPoints::default()).unwrap();
    let est_ekf = filter_log(&mut ekf, &run.t, &run.u, &run.y).unwrap();
    let est_ukf = filter_log(&mut ukf, &run.t, &run.u, &run.y).unwrap();
    // The rig's velocities: s/(0.02 s + 1) on the quantised positions (Tustin, as sim's chain).
    let pd = PseudoDifferentiator::new(0.02, Differentiation::Tustin, ts).unwrap();
    let skip = 500; // the first 0.5 s: both estimators start from rest
    for (state, col) in [(2usize, 0usize), (3, 1)] {
        let p: Vec<f64> = run.y.iter().map(|y| y[col]).collect();
        let v_pd = pd.filter(&p);
        let truth = || run.x.iter().skip(skip).map(move |x| x[state]);
        let e_pd = rms(truth().zip(v_pd.iter().skip(skip)).map(|(a, b)| a - b));
        let e_ekf = rms(truth()
            .zip(est_ekf.states.iter().skip(skip))
            .map(|(a, b)| a - b[state]));
        let e_ukf = rms(truth()
            .zip(est_ukf.states.iter().skip(skip))
            .map(|(a, b)| a - b[state]));
        let scale = rms(truth());
        println!(
            "state {state}: rms truth {scale:.4}, pseudo-differentiator {e_pd:.2e}, EKF {e_ekf:.2e}, UKF {e_ukf:.2e}"
        );
        assert!(e_ekf < e_pd && e_ukf < e_pd, "{e_pd} {e_ekf} {e_ukf}");
    }
}

/// Wilson–Hilferty's approximation of the χ² quantile with `nu` degrees of freedom at the
/// standard normal quantile `z` (checked against SciPy below).
fn chi2_quantile(nu: f64, z: f64) -> f64 {
    let c = 2.0 / (9.0 * nu);
    nu * (1.0 - c + z * c.sqrt()).powi(3)
}

const Z975: f64 = 1.959963984540054;

#[test]
fn wilson_hilferty_matches_scipy() {
    // SciPy 1.16.3: chi2.ppf(0.025, ν), chi2.ppf(0.975, ν).
    for (nu, lo, hi) in [
        (160.0, 126.8700491819807, 196.91514232935145),
        (8000.0, 7753.98169654498, 8249.806847110303),
    ] {
        assert!((chi2_quantile(nu, -Z975) / lo - 1.0).abs() < 1e-3);
        assert!((chi2_quantile(nu, Z975) / hi - 1.0).abs() < 1e-3);
    }
}

/// NEES and NIS of a filter over `runs` seeded Monte-Carlo runs of the nonlinear cart whose
/// truth has exactly the filter's Gaussian process and measurement noise: per sample the
/// run-averaged NEES must lie within the 95 % χ² bounds of `runs · 4` degrees of freedom for at
/// least 90 % of the samples, and the NIS averaged over every sample and run within the 95 %
/// bounds of χ²(runs · samples · 2).
fn check_consistency(ukf: bool) {
    let (ts, runs, samples) = (1e-3 * 10.0, 40usize, 200usize);
    let q = diag(&[1e-8, 1e-8, 1e-4, 1e-3]);
    let r = diag(&[1e-6, 1e-6]);
    let model = SampledModel::new(
        CartPendulum::book(),
        ts,
        2,
        Measurement::States(vec![0, 1]),
        &q,
        &r,
    )
    .unwrap();
    let p0 = diag(&[1e-4, 1e-4, 1e-3, 1e-3]);
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    let n01 = Normal::new(0.0, 1.0).unwrap();
    let sq = |m: &Mat| m.clone().cholesky().unwrap().l();
    let (lq, lr, lp) = (sq(&q), sq(&r), sq(&p0));
    let mut nees_sum = vec![0.0; samples];
    let mut nis_total = 0.0;
    for _ in 0..runs {
        let mean0 = DVector::from_row_slice(&[0.0, 2.8, 0.0, 0.0]);
        let draw =
            |l: &Mat, rng: &mut ChaCha8Rng| l * DVector::from_fn(l.nrows(), |_, _| n01.sample(rng));
        let mut x = &mean0 + draw(&lp, &mut rng);
        let mut f: Box<dyn NonlinearFilter> = if ukf {
            Box::new(
                UnscentedKalmanFilter::new(
                    model.clone(),
                    mean0.as_slice(),
                    &p0,
                    SigmaPoints::default(),
                )
                .unwrap(),
            )
        } else {
            Box::new(ExtendedKalmanFilter::new(model.clone(), mean0.as_slice(), &p0).unwrap())
        };
        for (k, nees_k) in nees_sum.iter_mut().enumerate() {
            let t = k as f64 * ts;
            let u = [2.0 * (4.0 * t).sin()];
            if k > 0 {
                let u_prev = [2.0 * (4.0 * (t - ts)).sin()];
                x = DVector::from_vec(model.propagate(t - ts, x.as_slice(), &u_prev))
                    + draw(&lq, &mut rng);
                f.predict(t - ts, &u_prev).unwrap();
            }
            let y = DVector::from_vec(model.measure(t, x.as_slice(), &u)) + draw(&lr, &mut rng);
            let inn = f.update(t, &u, y.as_slice()).unwrap();
            nis_total += inn.nis;
            *nees_k += nees(x.as_slice(), f.state(), f.covariance()).unwrap();
        }
    }
    let dof = runs as f64 * 4.0;
    let (lo, hi) = (chi2_quantile(dof, -Z975), chi2_quantile(dof, Z975));
    let inside = nees_sum.iter().filter(|&&s| s >= lo && s <= hi).count() as f64 / samples as f64;
    let dof_nis = (runs * samples * 2) as f64;
    let (nlo, nhi) = (chi2_quantile(dof_nis, -Z975), chi2_quantile(dof_nis, Z975));
    println!(
        "{}: NEES inside its 95 % band at {:.1} % of the samples; NIS sum {nis_total:.0} in [{nlo:.0}, {nhi:.0}]",
        if ukf { "UKF" } else { "EKF" },
        100.0 * inside
    );
    assert!(inside >= 0.9, "{inside}");
    assert!(nis_total >= nlo && nis_total <= nhi, "{nis_total}");
}

#[test]
fn ekf_is_consistent_by_nees_and_nis() {
    check_consistency(false);
}

#[test]
fn ukf_is_consistent_by_nees_and_nis() {
    check_consistency(true);
}

#[test]
fn filters_reject_bad_input() {
    let q = diag(&[1e-8, 1e-8, 1e-4, 1e-3]);
    let r = diag(&[1e-6, 1e-6]);
    let plant = CartPendulum::book();
    assert!(SampledModel::new(plant, 0.0, 1, Measurement::States(vec![0, 1]), &q, &r).is_err());
    assert!(SampledModel::new(plant, 1e-3, 1, Measurement::States(vec![0, 4]), &q, &r).is_err());
    // The cart has no output map.
    assert!(SampledModel::new(plant, 1e-3, 1, Measurement::Output, &q, &r).is_err());
    let model = SampledModel::new(plant, 1e-3, 1, Measurement::States(vec![0, 1]), &q, &r).unwrap();
    assert!(ExtendedKalmanFilter::new(model.clone(), &[0.0; 4], &Mat::zeros(4, 4)).is_err());
    let mut ekf = ExtendedKalmanFilter::new(model, &[0.0; 4], &Mat::identity(4, 4)).unwrap();
    assert!(ekf.update(0.0, &[0.0], &[0.0]).is_err());
    assert!(ekf.update(0.0, &[0.0], &[f64::NAN, 0.0]).is_err());
    assert!(ekf.predict(0.0, &[]).is_err());
    assert!(nees(&[0.0; 2], &[0.0; 2], &Mat::zeros(2, 2)).is_err());
}
