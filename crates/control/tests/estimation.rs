//! Linear controllers and the Kalman filter against independent computations: `lsim` of the
//! same discrete system, the defining Riccati identities, and a Monte-Carlo estimate of the
//! error covariance.

use pendulab_control::ControlError;
use pendulab_control::estimation::{kalman_controller, kalman_filter, output_feedback_controller};
use pendulab_lti::design::{StateFeedback, lqr, observer_controller, place, place_observer};
use pendulab_lti::response::{LsimOptions, lsim};
use pendulab_lti::{Complex64, Discretization, Mat, StateSpace};
use pendulab_sim::Controller;
use pendulab_testkit::cart;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// The book's cart pendulum at the upright rest with its encoder outputs `y = [z, θ]`
/// (`docs/model.md` §1, from pendulab-testkit).
fn cdip() -> StateSpace<pendulab_lti::Continuous> {
    let (a, b) = cart::upright();
    StateSpace::continuous(a, b, cart::measured_output(), Mat::zeros(2, 1)).unwrap()
}

#[test]
fn linear_controller_reproduces_lsim_of_its_system() {
    // The book's observer-based controller, discretised by ZOH and by Tustin at 10 ms: the
    // controller's sample-by-sample outputs equal lsim of the discrete system (an independent
    // implementation of the same recursion).
    let plant = cdip();
    let poles: Vec<Complex64> = [(-6.5, 1.5), (-6.5, -1.5), (-4.0, 0.0), (-2.5, 0.0)]
        .iter()
        .map(|&(r, i)| Complex64::new(r, i))
        .collect();
    let k = place(plant.a(), plant.b(), &poles).unwrap().gain;
    let obs: Vec<Complex64> = poles.iter().map(|p| p * 4.0).collect();
    let l = place_observer(plant.a(), plant.c(), &obs).unwrap().gain;
    let ctrl = observer_controller(&plant, &k, &l).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let steps = 300;
    let y: Mat = Mat::from_fn(steps, 2, |_, _| rng.random_range(-0.1..0.1));
    let t: Vec<f64> = (0..steps).map(|i| i as f64 * 0.01).collect();
    for method in [
        Discretization::Zoh,
        Discretization::Tustin { prewarp: None },
    ] {
        let feedback = StateFeedback::new(k.clone()).unwrap();
        let mut c = output_feedback_controller(&plant, &feedback, &l, 0.01, method).unwrap();
        assert_eq!((c.ny(), c.nu(), c.sample_time()), (2, 1, Some(0.01)));
        let reference = lsim(
            &ctrl.c2d(0.01, method).unwrap(),
            &y,
            &t,
            None,
            &LsimOptions::default(),
        )
        .unwrap();
        let mut u = [0.0];
        for i in 0..steps {
            c.update(t[i], &[y[(i, 0)], y[(i, 1)]], &mut u);
            let r = reference.y()[(i, 0)];
            // Same recursion, different summation order: rounding only.
            assert!(
                (u[0] - r).abs() <= 1e-12 * (1.0 + r.abs()),
                "{method:?} step {i}"
            );
        }
    }
}

#[test]
fn kalman_design_satisfies_its_defining_identities() {
    let plant = cdip().c2d(0.01, Discretization::Zoh).unwrap();
    let g = plant.b().clone();
    let qn = Mat::from_element(1, 1, 0.5);
    // Encoder noise variances (m², rad²): a few quantisation steps.
    let rn = Mat::from_row_slice(2, 2, &[(2e-4f64).powi(2), 0.0, 0.0, (2e-3f64).powi(2)]);
    let kf = kalman_filter(&plant, &g, &qn, &rn).unwrap();
    let (a, c) = (plant.a(), plant.c());
    let p = &kf.prior_covariance;
    // P = A P⁺ Aᵀ + G Q Gᵀ with P⁺ = (I − MC)P (the Riccati recursion at its fixed point).
    let lhs = a * &kf.posterior_covariance * a.transpose() + &g * &qn * g.transpose();
    assert!(
        (&lhs - p).norm() <= 1e-9 * p.norm(),
        "{:e}",
        (&lhs - p).norm() / p.norm()
    );
    // M = P Cᵀ (C P Cᵀ + R)⁻¹ and, without cross-covariance, L = A M.
    let s = c * p * c.transpose() + &rn;
    assert!(
        (&kf.filter_gain * &s - p * c.transpose()).norm() <= 1e-10 * (p * c.transpose()).norm()
    );
    assert!((a * &kf.filter_gain - &kf.predictor_gain).norm() <= 1e-9 * kf.predictor_gain.norm());
    assert!(kf.error_poles.iter().all(|z| z.norm() < 1.0));
}

#[test]
fn monte_carlo_error_covariance_matches_the_posterior_covariance() {
    // Discrete plant with process noise on the input channel and encoder noise, balanced by
    // u = −K x̂ (the estimation error does not depend on the control, so any stabilising K
    // will do). Over N samples the sample covariance of x − x̂ must match P⁺.
    let plant = cdip().c2d(0.01, Discretization::Zoh).unwrap();
    let g = plant.b().clone();
    let qn = Mat::from_element(1, 1, 0.5);
    let sd = [2e-4, 2e-3];
    let rn = Mat::from_row_slice(2, 2, &[sd[0] * sd[0], 0.0, 0.0, sd[1] * sd[1]]);
    let kf = kalman_filter(&plant, &g, &qn, &rn).unwrap();
    let (q, r) = cart::lqr_weights();
    let k = lqr(&plant, &q, &r, None).unwrap().gain;
    let mut ctrl = kalman_controller(&plant, &StateFeedback::new(k).unwrap(), &kf).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let w = Normal::new(0.0, qn[(0, 0)].sqrt()).unwrap();
    let v: Vec<Normal<f64>> = sd.iter().map(|s| Normal::new(0.0, *s).unwrap()).collect();
    let (a, b, c) = (plant.a(), plant.b(), plant.c());
    let mut x = nalgebra::DVector::zeros(4);
    let n_samples = 200_000;
    let burn_in = 2_000;
    let mut sum = Mat::zeros(4, 4);
    let mut u = [0.0];
    for k in 0..n_samples + burn_in {
        let y = c * &x;
        let ym = [y[0] + v[0].sample(&mut rng), y[1] + v[1].sample(&mut rng)];
        ctrl.update(k as f64 * 0.01, &ym, &mut u);
        if k >= burn_in {
            let e = &x - nalgebra::DVector::from_column_slice(ctrl.estimate());
            sum += &e * e.transpose();
        }
        x = a * &x + b * u[0] + &g * w.sample(&mut rng);
    }
    let emp = sum / n_samples as f64;
    // Tolerance: the sample variance of a correlated sequence has relative standard error
    // ≈ √(2τ/N) with τ ≈ 1/(1 − ρ) samples the error's correlation time (ρ the spectral radius
    // of the error dynamics); allow four standard errors.
    let rho = kf.error_poles.iter().map(|z| z.norm()).fold(0.0, f64::max);
    let tau = 1.0 / (1.0 - rho);
    let tol = 4.0 * (2.0 * tau / n_samples as f64).sqrt();
    for i in 0..4 {
        let (e, p) = (emp[(i, i)], kf.posterior_covariance[(i, i)]);
        assert!(
            (e - p).abs() <= tol * p,
            "state {i}: empirical {e:e}, theory {p:e}, tolerance {tol}"
        );
    }
}

#[test]
fn bad_estimation_inputs_are_typed_errors() {
    let plant = cdip().c2d(0.01, Discretization::Zoh).unwrap();
    let with_d = StateSpace::discrete(
        plant.a().clone(),
        plant.b().clone(),
        plant.c().clone(),
        Mat::from_element(2, 1, 1.0),
        0.01,
    )
    .unwrap();
    assert!(matches!(
        kalman_filter(
            &with_d,
            plant.b(),
            &Mat::identity(1, 1),
            &Mat::identity(2, 2)
        ),
        Err(ControlError::NotApplicable { .. })
    ));
    let kf = kalman_filter(
        &plant,
        plant.b(),
        &Mat::identity(1, 1),
        &Mat::identity(2, 2),
    )
    .unwrap();
    assert!(matches!(
        kalman_controller(&plant, &StateFeedback::new(Mat::zeros(1, 3)).unwrap(), &kf),
        Err(ControlError::Sim(_))
    ));
    let cont = cdip();
    let zero = StateFeedback::new(Mat::zeros(1, 4)).unwrap();
    assert!(matches!(
        output_feedback_controller(&cont, &zero, &Mat::zeros(4, 3), 0.01, Discretization::Zoh),
        Err(ControlError::Lti(_))
    ));
    assert!(matches!(
        output_feedback_controller(&cont, &zero, &Mat::zeros(4, 2), -0.01, Discretization::Zoh),
        Err(ControlError::Lti(_))
    ));
}
