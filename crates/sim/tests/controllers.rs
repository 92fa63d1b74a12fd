//! Controllers against independent references: PID recursions against `c2d` + `lsim` of the
//! continuous PID (pendulab-lti), the servo's integration rules and its loop against the exact
//! ZOH-augmented recursion, the prediction observer against `observer_controller` (MATLAB
//! `reg`), the current estimator's error recursion, scheduling and switching against their
//! definitions.

mod common;

use common::{CartPendulum, mul};
use pendulab_lti::response::{LsimOptions, lsim};
use pendulab_lti::{Discretization, Mat, StateSpace};
use pendulab_sim::controllers::{
    DiscreteLinearController, EstimatorForm, GainScheduled, IntegrationRule, LqIntegralServo, Mode,
    ObserverBased, OpenLoop, Pid, PidDiscretization, PidForm, Saturated, StaticStateFeedback,
    Switching,
};
use pendulab_sim::{
    Controller, FnDynamics, Integrator, SampledLoop, SampledOptions, SensorChain, Signal,
};

/// The continuous 2-DOF PID from (r, y) to u as a state space:
/// ξ̇₁ = r − y, ξ̇₂ = (c r − y − ξ₂)/T_f,
/// u = k_I ξ₁ + (k_D/T_f)(c r − y − ξ₂) + k_P (b r − y).
fn continuous_pid(
    kp: f64,
    ki: f64,
    kd: f64,
    tf: f64,
    b: f64,
    c: f64,
) -> StateSpace<pendulab_lti::Continuous> {
    StateSpace::continuous(
        Mat::from_row_slice(2, 2, &[0.0, 0.0, 0.0, -1.0 / tf]),
        Mat::from_row_slice(2, 2, &[1.0, -1.0, c / tf, -1.0 / tf]),
        Mat::from_row_slice(1, 2, &[ki, -kd / tf]),
        Mat::from_row_slice(1, 2, &[kp * b + kd * c / tf, -kp - kd / tf]),
    )
    .unwrap()
}

#[test]
fn pid_family_matches_c2d_of_the_continuous_pid() {
    let ts = 0.01;
    let n = 400;
    // r and y start at 0 (the LTI reference starts at rest; so does the PID).
    let r_sig = Signal::constant(1.0).unwrap()
        - Signal::sine(1.0, 3.0, std::f64::consts::FRAC_PI_2).unwrap();
    let y_of = |t: f64| 0.3 * (5.0 * t).sin() + 0.2 * (11.0 * t).sin();
    let (kp, ki, kd, tf) = (2.5, 4.0, 0.35, 0.03);
    let forms = [
        (PidForm::P { kp }, (kp, 0.0, 0.0, 1.0, 1.0, 0.0)),
        (PidForm::PD { kp, kd, tf }, (kp, 0.0, kd, tf, 1.0, 1.0)),
        (PidForm::PMinusD { kp, kd, tf }, (kp, 0.0, kd, tf, 1.0, 0.0)),
        (PidForm::PI { kp, ki }, (kp, ki, 0.0, 1.0, 1.0, 0.0)),
        (PidForm::PID { kp, ki, kd, tf }, (kp, ki, kd, tf, 1.0, 1.0)),
        (PidForm::IPD { kp, ki, kd, tf }, (kp, ki, kd, tf, 0.0, 0.0)),
    ];
    for (disc, method) in [
        (
            PidDiscretization::Tustin,
            Discretization::Tustin { prewarp: None },
        ),
        (
            PidDiscretization::BackwardEuler,
            Discretization::BackwardEuler,
        ),
    ] {
        for (form, (p, i, d, f, b, c)) in forms {
            let mut pid = Pid::new(form, ts, disc).unwrap().reference(r_sig.clone());
            let t: Vec<f64> = (0..n).map(|k| k as f64 * ts).collect();
            let u_in = Mat::from_fn(n, 2, |k, j| {
                if j == 0 {
                    r_sig.value(t[k])
                } else {
                    y_of(t[k])
                }
            });
            let dsys = continuous_pid(p, i, d, f, b, c).c2d(ts, method).unwrap();
            let reference = lsim(&dsys, &u_in, &t, None, &LsimOptions::default()).unwrap();
            let scale = reference
                .y_signal(0)
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs()));
            for k in 0..n {
                let u = pid.control(t[k], &[y_of(t[k])]).unwrap();
                // Two realisations of the same discrete transfer function (generalised
                // bilinear transform of a state space vs per-term recursions): rounding only.
                assert!(
                    (u - reference.y()[(k, 0)]).abs() < 1e-11 * scale,
                    "{form:?} {disc:?} k = {k}: {u} vs {}",
                    reference.y()[(k, 0)]
                );
            }
        }
    }
    assert!(
        Pid::new(
            PidForm::PD {
                kp: 1.0,
                kd: 1.0,
                tf: 0.0
            },
            ts,
            PidDiscretization::Tustin
        )
        .is_err()
    );
    assert!(Pid::new(PidForm::P { kp: f64::NAN }, ts, PidDiscretization::Tustin).is_err());
    assert!(Pid::new(PidForm::P { kp: 1.0 }, 0.0, PidDiscretization::Tustin).is_err());
    assert!(
        Pid::new(PidForm::P { kp: 1.0 }, ts, PidDiscretization::Tustin)
            .unwrap()
            .measurement(2, 2)
            .is_err()
    );
}

#[test]
fn servo_integration_rules_follow_their_definitions() {
    // Constant error e = r = 2 (y = 0), K₁ = 0, K₂ = 1: u_k = −w_k with
    // forward Euler w_k = k ts e, backward Euler (k + 1) ts e, trapezoidal (k + ½) ts e.
    let ts = 0.1;
    for (rule, offset) in [
        (IntegrationRule::ForwardEuler, 0.0),
        (IntegrationRule::BackwardEuler, 1.0),
        (IntegrationRule::Trapezoidal, 0.5),
    ] {
        let mut s = LqIntegralServo::new(
            &Mat::zeros(1, 2),
            &Mat::identity(1, 1),
            &Mat::from_row_slice(1, 2, &[1.0, 0.0]),
            vec![Signal::constant(2.0).unwrap()],
            ts,
            rule,
        )
        .unwrap();
        for k in 0..5 {
            let mut u = [0.0];
            s.update(k as f64 * ts, &[0.0, 0.0], &mut u);
            assert!(
                (u[0] + (k as f64 + offset) * ts * 2.0).abs() < 1e-14,
                "{rule:?} k = {k}"
            );
        }
        s.reset();
        let mut u = [0.0];
        s.update(0.0, &[0.0, 0.0], &mut u);
        assert!((u[0] + offset * ts * 2.0).abs() < 1e-14);
    }
}

#[test]
fn servo_loop_matches_the_exact_augmented_recursion_and_tracks() {
    // Linear cart pendulum, LQ servo designed by pendulab-lti on the continuous model, run at
    // ts = 10 ms with forward-Euler integration. Reference: x_{k+1} = Φ x_k + Γ u_k,
    // w_{k+1} = w_k + ts (r − z_k), u_k = −K₁ x_k − K₂ w_k with Φ, Γ from c2d.
    let ts = 0.01;
    let plant = CartPendulum::default().linear();
    let (cz, design) = common::cart_lq_servo(&CartPendulum::default());
    let r = 0.1;
    let servo = LqIntegralServo::from_design(
        &design,
        cz.c(),
        vec![Signal::constant(r).unwrap()],
        ts,
        IntegrationRule::ForwardEuler,
    )
    .unwrap();
    let opts = SampledOptions {
        ts,
        t_final: 20.0,
        integrator: Integrator::Rk4 { dt: ts / 50.0 },
        ..Default::default()
    };
    let mut lp = SampledLoop::new(plant.clone(), servo, opts).unwrap();
    let run = lp.run(&[0.0; 4]).unwrap();
    let d = plant.c2d(ts, Discretization::Zoh).unwrap();
    let (k1, k2) = (&design.state_gain, design.integral_gain[(0, 0)]);
    let mut x = vec![0.0; 4];
    let mut w = 0.0;
    let mut worst = 0.0f64;
    for k in 0..run.trajectory.len() {
        for i in 0..4 {
            worst = worst.max((run.trajectory.x()[(k, i)] - x[i]).abs());
        }
        let u = -(0..4).map(|j| k1[(0, j)] * x[j]).sum::<f64>() - k2 * w;
        assert!((run.trajectory.u()[(k, 0)] - u).abs() < 1e-10);
        w += ts * (r - x[0]);
        let fx = mul(d.a(), &x);
        x = (0..4).map(|i| fx[i] + d.b()[(i, 0)] * u).collect();
    }
    // RK4 at ts/50 on |λ| ≤ 7: local error ~1e-16 per substep; rounding over 2000 samples.
    assert!(worst < 1e-11, "{worst:e}");
    // Internal model principle: zero steady-state error for a constant reference.
    let last = run.trajectory.len() - 1;
    assert!((run.trajectory.x()[(last, 0)] - r).abs() < 1e-6);
}

#[test]
fn prediction_observer_equals_reg_and_current_estimator_error_recursion() {
    let ts = 0.005;
    let plant = CartPendulum::default().linear();
    let meas = StateSpace::continuous(
        plant.a().clone(),
        plant.b().clone(),
        Mat::from_row_slice(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]),
        Mat::zeros(2, 1),
    )
    .unwrap();
    let d = meas.c2d(ts, Discretization::Zoh).unwrap();
    let q = Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&[10.0, 10.0, 0.0, 0.0]));
    let k = pendulab_lti::design::lqr(&d, &q, &Mat::identity(1, 1), None)
        .unwrap()
        .gain;
    let obs_poles: Vec<pendulab_lti::Complex64> =
        [0.6, 0.62, 0.64, 0.66].iter().map(|&p| p.into()).collect();
    let l = pendulab_lti::design::place_observer(d.a(), d.c(), &obs_poles)
        .unwrap()
        .gain;
    let x0 = [0.05, 0.1, 0.0, 0.0];
    let opts = SampledOptions {
        ts,
        t_final: 3.0,
        integrator: Integrator::Rk4 { dt: ts / 20.0 },
        ..Default::default()
    };
    let sensor = SensorChain::states(&[0, 1]);
    // (a) Prediction form vs `reg` as a generic discrete controller.
    let pred = ObserverBased::new(&d, &k, &l, EstimatorForm::Prediction).unwrap();
    let reg = DiscreteLinearController::new(
        &pendulab_lti::design::observer_controller(&d, &k, &l).unwrap(),
    )
    .unwrap();
    let run_a = SampledLoop::new(plant.clone(), pred, opts.clone())
        .unwrap()
        .with_sensor(sensor.clone())
        .unwrap()
        .run(&x0)
        .unwrap();
    let run_b = SampledLoop::new(plant.clone(), reg, opts.clone())
        .unwrap()
        .with_sensor(sensor.clone())
        .unwrap()
        .run(&x0)
        .unwrap();
    let scale = run_a.commands.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for kk in 0..run_a.trajectory.len() {
        // Two implementations of one linear recursion: rounding only.
        assert!((run_a.commands[(kk, 0)] - run_b.commands[(kk, 0)]).abs() < 1e-11 * scale);
    }
    assert!(
        run_a.diagnostics.final_state[1].abs() < 1e-3,
        "the loop balances"
    );
    // (b) Current estimator: the prediction error ẽ_k = x_k − x̄_k obeys
    // ẽ_{k+1} = Φ (I − L_c C) ẽ_k, from ẽ₀ = x₀ (x̄₀ = 0).
    let lc = pendulab_lti::design::place_observer(d.a(), &(d.c() * d.a()), &obs_poles)
        .unwrap()
        .gain;
    let mut cur = ObserverBased::new(&d, &k, &lc, EstimatorForm::Current).unwrap();
    let mut lp = SampledLoop::new(plant.clone(), cur.clone(), opts)
        .unwrap()
        .with_sensor(sensor)
        .unwrap();
    let run = lp.run(&x0).unwrap();
    let m = d.a() * (Mat::identity(4, 4) - &lc * d.c());
    let mut e: Vec<f64> = x0.to_vec(); // x̄₀ = 0
    cur.reset();
    for kk in 0..60 {
        let x: Vec<f64> = (0..4).map(|i| run.trajectory.x()[(kk, i)]).collect();
        // Replay the controller on the recorded measurements: after the update at sample k
        // it holds the filtered estimate x̂_k = x̄_k + L_c (y_k − C x̄_k), whose error is
        // x_k − x̂_k = (I − L_c C) ẽ_k.
        let mut u = [0.0];
        let y = [run.trajectory.y()[(kk, 0)], run.trajectory.y()[(kk, 1)]];
        cur.update(kk as f64 * ts, &y, &mut u);
        let xbar_err: Vec<f64> = (0..4).map(|i| x[i] - cur.estimate()[i]).collect();
        let filtered = mul(&(Mat::identity(4, 4) - &lc * d.c()), &e);
        for i in 0..4 {
            // Exact sampling of a linear plant (RK4 at ts/20): ~1e-15 per sample.
            assert!(
                (xbar_err[i] - filtered[i]).abs() < 1e-11,
                "k = {kk}, i = {i}"
            );
        }
        assert!((u[0] - run.commands[(kk, 0)]).abs() < 1e-13);
        e = mul(&m, &e);
    }
    // D ≠ 0 is refused by the current form.
    let dd = StateSpace::discrete(
        d.a().clone(),
        d.b().clone(),
        d.c().clone(),
        Mat::from_element(2, 1, 1.0),
        ts,
    )
    .unwrap();
    assert!(ObserverBased::new(&dd, &k, &lc, EstimatorForm::Current).is_err());
    assert!(ObserverBased::new(&d, &Mat::zeros(1, 3), &lc, EstimatorForm::Current).is_err());
}

#[test]
fn state_feedback_sign_conventions() {
    // u = −K y (library) and u = +K_book y (book) with K_book = −K are the same law.
    let k = Mat::from_row_slice(1, 3, &[1.0, -2.0, 0.5]);
    let mut lib = StaticStateFeedback::new(k.clone()).unwrap();
    let mut book = StaticStateFeedback::from_book(&(-&k)).unwrap();
    let fb = pendulab_lti::design::StateFeedback::new(k.clone()).unwrap();
    let mut from_fb = StaticStateFeedback::from_state_feedback(&fb).unwrap();
    let y = [0.3, 0.7, -1.1];
    let want = fb.control(&y).unwrap()[0];
    assert_eq!(want, -(0.3 - 1.4 - 0.55));
    for c in [&mut lib, &mut book, &mut from_fb] {
        let mut u = [0.0];
        c.update(0.0, &y, &mut u);
        assert!((u[0] - want).abs() < 1e-15);
    }
    let mut with_ref = StaticStateFeedback::new(k)
        .unwrap()
        .with_reference(&[1.0, 0.0, 0.0])
        .unwrap();
    let mut u = [0.0];
    with_ref.update(0.0, &[1.0, 0.0, 0.0], &mut u);
    assert_eq!(u[0], 0.0);
    assert!(StaticStateFeedback::new(Mat::from_element(1, 1, f64::NAN)).is_err());
}

#[test]
fn gain_scheduling_follows_its_polynomial() {
    // K(ρ) = K₀ + ρ K₁ + ρ² K₂, ρ = 1 − cos y₀ (the arm's LPV parameter).
    let k0 = Mat::from_row_slice(1, 2, &[1.0, 2.0]);
    let k1 = Mat::from_row_slice(1, 2, &[-0.5, 3.0]);
    let k2 = Mat::from_row_slice(1, 2, &[0.25, 0.0]);
    let mut g = GainScheduled::polynomial(&[k0.clone(), k1.clone(), k2.clone()], |y: &[f64]| {
        1.0 - y[0].cos()
    })
    .unwrap();
    for y in [[0.0f64, 1.0], [0.8, -0.3], [2.5, 0.1]] {
        let rho = 1.0 - y[0].cos();
        let k = &k0 + &k1 * rho + &k2 * (rho * rho);
        let want = -(k[(0, 0)] * y[0] + k[(0, 1)] * y[1]);
        let mut u = [0.0];
        g.update(0.0, &y, &mut u);
        assert!((u[0] - want).abs() < 1e-14);
        assert_eq!(g.rho(), rho);
        assert!((g.gain_at(rho) - &k).norm() < 1e-15);
    }
    assert!(GainScheduled::polynomial(&[], |_y: &[f64]| 0.0).is_err());
    assert!(GainScheduled::polynomial(&[k0, Mat::zeros(2, 2)], |_y: &[f64]| 0.0).is_err());
    // A constant schedule runs exactly like static feedback (same arithmetic).
    let k = Mat::from_row_slice(1, 4, &[-2.0, -30.0, -3.0, -4.0]);
    let kk = k.clone();
    let sched = GainScheduled::from_fn(
        1,
        4,
        move |_rho, out: &mut [f64]| out.copy_from_slice(kk.as_slice()),
        |_y: &[f64]| 0.0,
    );
    let opts = SampledOptions {
        t_final: 2.0,
        ..Default::default()
    };
    let a = SampledLoop::new(CartPendulum::default(), sched, opts.clone())
        .unwrap()
        .run(&[0.0, 0.1, 0.0, 0.0])
        .unwrap();
    let b = SampledLoop::new(
        CartPendulum::default(),
        StaticStateFeedback::new(k).unwrap(),
        opts,
    )
    .unwrap()
    .run(&[0.0, 0.1, 0.0, 0.0])
    .unwrap();
    assert_eq!(a.trajectory.x(), b.trajectory.x());
}

#[test]
fn switching_records_the_first_sample_where_the_condition_holds() {
    // Double integrator pushed by u = 1 until x₀ ≥ 0.45 (x₀ = t²/2: t* = √0.9 ≈ 0.9487 s),
    // then braked by state feedback; the switch happens at the first sample at or after t*.
    let ts = 0.01;
    let plant = FnDynamics::new(2, 1, |_t, x: &[f64], u: &[f64], dx: &mut [f64]| {
        dx[0] = x[1];
        dx[1] = u[0];
    });
    let push = OpenLoop::new(vec![Signal::constant(1.0).unwrap()], 2);
    let brake = StaticStateFeedback::new(Mat::from_row_slice(1, 2, &[4.0, 4.0])).unwrap();
    let sw = Switching::new(push, brake, |_t, y: &[f64]| y[0] >= 0.45).unwrap();
    let mut lp = SampledLoop::new(
        plant,
        sw,
        SampledOptions {
            ts,
            t_final: 3.0,
            integrator: Integrator::Rk4 { dt: ts },
            ..Default::default()
        },
    )
    .unwrap();
    let run = lp.run(&[0.0, 0.0]).unwrap();
    let t_star = 0.9f64.sqrt();
    let k_star = (t_star / ts).ceil() as usize;
    assert_eq!(run.diagnostics.switch_times.len(), 1);
    assert!((run.diagnostics.switch_times[0] - k_star as f64 * ts).abs() < 1e-12);
    // The same instant found by scanning the recorded measurement.
    let scan = run
        .trajectory
        .y_signal(0)
        .iter()
        .position(|&v| v >= 0.45)
        .unwrap();
    assert_eq!(scan, k_star);
    assert_eq!(lp.controller().mode(), Mode::B);
    // Before the switch the command is 1, from the switch on it is the brake's.
    assert_eq!(run.commands[(k_star - 1, 0)], 1.0);
    assert!(run.commands[(k_star, 0)] < 0.0);
    // Reset returns to mode A with no switch recorded.
    lp.controller_mut().reset();
    assert_eq!(lp.controller().mode(), Mode::A);
    assert!(lp.controller().switch_times().is_empty());
    // Shape mismatch between modes.
    assert!(
        Switching::new(
            OpenLoop::new(vec![Signal::zero()], 2),
            OpenLoop::new(vec![Signal::zero()], 3),
            |_t, _y: &[f64]| true
        )
        .is_err()
    );
}

#[test]
fn saturated_controller_clips_and_counts() {
    let mut s = Saturated::new(
        StaticStateFeedback::new(Mat::from_row_slice(1, 1, &[-10.0])).unwrap(),
        -1.0,
        2.0,
    )
    .unwrap();
    let mut u = [0.0];
    for (y, want) in [(0.05, 0.5), (0.5, 2.0), (-0.3, -1.0)] {
        s.update(0.0, &[y], &mut u);
        assert_eq!(u[0], want);
    }
    assert_eq!(s.clipped(), 2);
    assert!(Saturated::new(OpenLoop::new(vec![], 0), 1.0, 1.0).is_err());
}

/// `Controller::retune`: a retuned state feedback computes what a controller built with the
/// new gain (and the same reference) computes, bit for bit; a retuned LQ servo keeps its
/// integrator, so after the retune it computes what a servo built with the new gains computes
/// after the same measurements (its integrator, which does not depend on the gains, is then
/// in the same state); both through `Box<dyn Controller>`. Wrong lengths and non-finite
/// entries are refused with the controller unchanged; controllers without a gain say so.
#[test]
fn retune_replaces_the_gain_and_keeps_the_state() {
    let (k_a, k_b) = ([1.0, -2.0, 0.5, 0.25], [3.0, 1.5, -0.75, 2.0]);
    let r = [0.1, 0.0, 0.0, 0.0];
    let mut sf: Box<dyn Controller> = Box::new(
        StaticStateFeedback::new(Mat::from_row_slice(1, 4, &k_a))
            .unwrap()
            .with_reference(&r)
            .unwrap(),
    );
    let mut fresh = StaticStateFeedback::new(Mat::from_row_slice(1, 4, &k_b))
        .unwrap()
        .with_reference(&r)
        .unwrap();
    assert!(sf.retune(&k_b).unwrap());
    let y = [0.3, -0.2, 1.1, 0.7];
    let (mut u1, mut u2) = ([0.0], [0.0]);
    sf.update(0.0, &y, &mut u1);
    fresh.update(0.0, &y, &mut u2);
    assert_eq!(u1[0].to_bits(), u2[0].to_bits());
    // Refusals leave the gain as it was.
    assert!(matches!(
        sf.retune(&k_a[..3]),
        Err(pendulab_sim::SimError::DimensionMismatch {
            expected: 4,
            found: 3,
            ..
        })
    ));
    assert!(matches!(
        sf.retune(&[1.0, f64::NAN, 0.0, 0.0]),
        Err(pendulab_sim::SimError::InvalidParameter { .. })
    ));
    sf.update(0.0, &y, &mut u1);
    assert_eq!(u1[0].to_bits(), u2[0].to_bits());

    // The servo: K₁ (1 × 4) and K₂ (1 × 1) as [K₁ K₂].
    let servo = |k: &[f64]| {
        LqIntegralServo::new(
            &Mat::from_row_slice(1, 4, &k[..4]),
            &Mat::from_row_slice(1, 1, &k[4..]),
            &Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]),
            vec![Signal::step(0.0, 0.2).unwrap()],
            1e-3,
            IntegrationRule::ForwardEuler,
        )
        .unwrap()
    };
    let (g_a, g_b) = ([1.0, -2.0, 0.5, 0.25, -3.0], [2.0, -4.0, 0.1, 0.3, -7.0]);
    let mut running: Box<dyn Controller> = Box::new(servo(&g_a));
    let mut other = servo(&g_b);
    let ys: Vec<[f64; 4]> = (0..50)
        .map(|k| {
            let t = k as f64;
            [0.01 * t, (0.3 * t).sin(), 0.1, -0.05 * t]
        })
        .collect();
    let (mut u1, mut u2) = ([0.0], [0.0]);
    for (k, y) in ys.iter().enumerate().take(30) {
        running.update(k as f64 * 1e-3, y, &mut u1);
        other.update(k as f64 * 1e-3, y, &mut u2);
    }
    assert_ne!(u1[0], u2[0]);
    assert!(running.retune(&g_b).unwrap());
    for (k, y) in ys.iter().enumerate().skip(30) {
        running.update(k as f64 * 1e-3, y, &mut u1);
        other.update(k as f64 * 1e-3, y, &mut u2);
        assert_eq!(u1[0].to_bits(), u2[0].to_bits(), "sample {k}");
    }
    assert!(running.retune(&g_b[..4]).is_err());
    // A controller without a gain to replace.
    let mut open = OpenLoop::new(vec![Signal::constant(1.0).unwrap()], 4);
    assert!(!open.retune(&[1.0]).unwrap());
}
