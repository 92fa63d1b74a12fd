//! The sampled-data loop against independent references: a plain-Python loop (fixture), the
//! exact ZOH discretisation of pendulab-lti (with and without computation delay), closed forms
//! for pulses, disturbances and friction, and the defining properties of the rig's parts.

mod common;

use common::{CartPendulum, mul};
use pendulab_lti::matrix_functions::zoh_integrals;
use pendulab_lti::{Discretization, Mat, StateSpace};
use pendulab_sim::controllers::{OpenLoop, StaticStateFeedback};
use pendulab_sim::{
    Actuator, Delay, DisturbancePoint, Flow, FnDynamics, FnMonitor, Friction, Integrator,
    Quantizer, Record, RunStatus, SampledLoop, SampledOptions, SensorChain, Signal, SimError,
    StayWithin,
};
use serde_json::Value;

#[test]
fn cart_pendulum_loop_matches_independent_python_loop() {
    let f: Value =
        serde_json::from_str(include_str!("fixtures/rk4_reference.json")).expect("fixture");
    let c = f["cases"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "cart_pendulum_loop")
        .unwrap();
    let par = |k: &str| c["params"][k].as_f64().unwrap();
    let plant = CartPendulum {
        ac: par("a_c"),
        bc: par("b_c"),
        mp: par("m_p"),
        lp: par("l_p"),
        jp: par("J_p"),
        mup: par("mu_p"),
        g: par("g"),
    };
    let k: Vec<f64> = c["params"]["K"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let ts = par("ts");
    let substeps = par("substeps");
    let ctrl = StaticStateFeedback::new(Mat::from_row_slice(1, 4, &k)).unwrap();
    let opts = SampledOptions {
        ts,
        t_final: 2.0,
        integrator: Integrator::Rk4 { dt: ts / substeps },
        ..Default::default()
    };
    let mut lp = SampledLoop::new(plant, ctrl, opts)
        .unwrap()
        .with_actuator(Actuator::ideal().saturation(par("v_max")).unwrap())
        .unwrap();
    let run = lp.run(&[0.05, 0.3, 0.0, 0.0]).unwrap();
    let refs = c["samples"].as_array().unwrap();
    assert_eq!(run.trajectory.len(), refs.len());
    let mut clipped = 0;
    for (kk, r) in refs.iter().enumerate() {
        let r: Vec<f64> = r
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert!((run.trajectory.t()[kk] - r[0]).abs() < 1e-15);
        for i in 0..4 {
            let e = (run.trajectory.x()[(kk, i)] - r[1 + i]).abs();
            // Same formulas in IEEE double, different operation order: rounding only.
            assert!(e < 1e-12, "sample {kk}, x{i}: {e:e}");
        }
        assert!((run.trajectory.u()[(kk, 0)] - r[5]).abs() < 1e-12);
        if run.commands[(kk, 0)].abs() > 5.0 {
            clipped += 1;
        }
    }
    assert!(clipped > 0, "the reference case exercises the saturation");
    assert_eq!(run.diagnostics.saturated_samples, clipped);
    assert_eq!(run.diagnostics.integration.accepted_steps, 200 * 4);
}

/// ẋ₀ = u, ẋ₁ = t·u: the pulse's area and its first moment.
fn integrator_with_moment() -> impl pendulab_sim::Dynamics + Clone {
    FnDynamics::new(2, 1, |t, _x: &[f64], u: &[f64], dx: &mut [f64]| {
        dx[0] = u[0];
        dx[1] = t * u[0];
    })
}

#[test]
fn each_command_acts_exactly_over_its_sample_interval() {
    // A one-sample pulse of height 1 commanded at sample k = 37 (t = 0.37 s), ts = 0.01 s,
    // RK4 substeps of ts/5. The plant integrates u and t·u, so after the pulse
    // x₀ = ts (area: not skipped, not doubled) and x₁ = ts·(t_on + ts/2) (first moment: applied
    // over exactly [t_on, t_on + ts)), with t_on = t_37 + delay. RK4 integrates these
    // polynomials in t exactly, so only rounding remains (1e-15 on values ~1e-2).
    let ts = 0.01;
    let pulse = Signal::pulse(0.37, ts, 1.0).unwrap();
    for (delay, shift) in [
        (Delay::None, 0.0),
        (Delay::Time(0.004), 0.004),
        (Delay::Time(ts), ts),
        (Delay::Samples(2), 2.0 * ts),
    ] {
        for integrator in [
            Integrator::Rk4 { dt: ts / 5.0 },
            Integrator::dopri45(1e-10, 1e-12),
        ] {
            let opts = SampledOptions {
                ts,
                t_final: 1.0,
                integrator,
                delay,
                ..Default::default()
            };
            let mut lp = SampledLoop::new(
                integrator_with_moment(),
                OpenLoop::new(vec![pulse.clone()], 2),
                opts,
            )
            .unwrap();
            let run = lp.run(&[0.0, 0.0]).unwrap();
            let tr = &run.trajectory;
            assert_eq!(tr.len(), 101);
            let t_on = 0.37 + shift;
            for k in 0..tr.len() {
                let t = tr.t()[k];
                // The command is sampled: exactly one sample carries the pulse.
                let expect_u = if k == 37 { 1.0 } else { 0.0 };
                assert_eq!(tr.u()[(k, 0)], expect_u, "{delay:?}: sample {k}");
                let (x0, x1) = (tr.x()[(k, 0)], tr.x()[(k, 1)]);
                if t <= t_on + 1e-12 {
                    assert!(x0.abs() < 1e-15, "{delay:?}: x0 = {x0} at {t}");
                } else if t >= t_on + ts - 1e-12 {
                    assert!((x0 - ts).abs() < 1e-15, "{delay:?}: x0 = {x0} at {t}");
                    let moment = ts * (t_on + ts / 2.0);
                    // Dopri's error control at 1e-10/1e-12 on a piecewise-linear x₁.
                    let tol = if matches!(integrator, Integrator::Rk4 { .. }) {
                        1e-15
                    } else {
                        1e-12
                    };
                    assert!((x1 - moment).abs() < tol, "{delay:?}: x1 = {x1}, {moment}");
                } else {
                    // Inside the pulse (fractional delay): the ramp t − t_on.
                    assert!(
                        (x0 - (t - t_on)).abs() < 1e-15,
                        "{delay:?}: ramp {x0} at {t}"
                    );
                }
            }
        }
    }
}

/// The linearised cart pendulum with a discrete LQR gain at ts.
fn discrete_design(ts: f64) -> (StateSpace<pendulab_lti::Continuous>, Mat, Mat, Mat) {
    let sys = CartPendulum::default().linear();
    let dsys = sys.c2d(ts, Discretization::Zoh).unwrap();
    let q = Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&[10.0, 10.0, 0.0, 0.0]));
    let k = pendulab_lti::design::lqr(&dsys, &q, &Mat::identity(1, 1), None)
        .unwrap()
        .gain;
    let (phi, gamma) = (dsys.a().clone(), dsys.b().clone());
    (sys, k, phi, gamma)
}

#[test]
fn linear_loop_matches_exact_zoh_closed_loop() {
    let ts = 0.01;
    let (sys, k, phi, gamma) = discrete_design(ts);
    let acl = &phi - &gamma * &k;
    let x0 = [0.1, 0.2, -0.3, 0.5];
    for integrator in [
        Integrator::Rk4 { dt: ts / 100.0 },
        Integrator::dopri45(1e-13, 1e-15),
    ] {
        let opts = SampledOptions {
            ts,
            t_final: 3.0,
            integrator,
            ..Default::default()
        };
        let mut lp = SampledLoop::new(
            sys.clone(),
            StaticStateFeedback::new(k.clone()).unwrap(),
            opts,
        )
        .unwrap();
        let run = lp.run(&x0).unwrap();
        let mut x = x0.to_vec();
        let mut worst = 0.0f64;
        for kk in 0..run.trajectory.len() {
            for i in 0..4 {
                worst = worst.max((run.trajectory.x()[(kk, i)] - x[i]).abs());
            }
            x = mul(&acl, &x);
        }
        // Reference: x_{k+1} = (Φ − ΓK) x_k with Φ, Γ from one block exponential. RK4 at
        // ts/100 has a local error ~(|λ| dt)⁵/120 ≈ 1e-19 per substep (|λ| ≤ 7), Dopri runs at
        // 1e-13: both leave only rounding accumulated over 300 samples.
        assert!(worst < 1e-12, "{integrator:?}: {worst:e}");
    }
}

#[test]
fn computation_delays_match_their_exact_discretisations() {
    // With a fractional delay δ the command u_k acts on [t_k + δ, t_{k+1}), u_{k−1} before:
    // x_{k+1} = Φ x_k + Γ₀ u_k + Γ₁ u_{k−1}, Γ₀ = ∫₀^{ts−δ} e^{As} ds B,
    // Γ₁ = e^{A(ts−δ)} ∫₀^δ e^{As} ds B (Franklin, Powell & Workman, §4.3.4).
    let ts = 0.01;
    let (sys, k, phi, _) = discrete_design(ts);
    let (a, b) = (sys.a().clone(), sys.b().clone());
    let x0 = [0.0, 0.1, 0.0, 0.0];
    for delay in [
        Delay::Time(0.0037),
        Delay::Time(ts),
        Delay::Samples(1),
        Delay::Samples(3),
    ] {
        let (g0, g1, d) = match delay {
            Delay::Time(dl) if dl < ts => {
                let (_, g0) = zoh_integrals(&a, &b, ts - dl).unwrap();
                let (e, _) = zoh_integrals(&a, &b, ts - dl).unwrap();
                let (_, gd) = zoh_integrals(&a, &b, dl).unwrap();
                (g0, &e * &gd, 1usize)
            }
            Delay::Time(_) => (Mat::zeros(4, 1), zoh_integrals(&a, &b, ts).unwrap().1, 1),
            Delay::Samples(n) => (Mat::zeros(4, 1), zoh_integrals(&a, &b, ts).unwrap().1, n),
            Delay::None => unreachable!(),
        };
        let opts = SampledOptions {
            ts,
            t_final: 2.0,
            integrator: Integrator::Rk4 { dt: ts / 100.0 },
            delay,
            ..Default::default()
        };
        let mut lp = SampledLoop::new(
            sys.clone(),
            StaticStateFeedback::new(k.clone()).unwrap(),
            opts,
        )
        .unwrap();
        let run = lp.run(&x0).unwrap();
        // Reference recursion with the command history.
        let mut x = x0.to_vec();
        let mut us: Vec<f64> = Vec::new();
        let mut worst = 0.0f64;
        for kk in 0..run.trajectory.len() {
            for i in 0..4 {
                worst = worst.max((run.trajectory.x()[(kk, i)] - x[i]).abs());
            }
            let u = -(0..4).map(|j| k[(0, j)] * x[j]).sum::<f64>();
            us.push(u);
            let old = if kk >= d { us[kk - d] } else { 0.0 };
            let fx = mul(&phi, &x);
            x = (0..4)
                .map(|i| fx[i] + g0[(i, 0)] * u + g1[(i, 0)] * old)
                .collect();
        }
        assert!(worst < 1e-12, "{delay:?}: {worst:e}");
    }
}

#[test]
fn disturbances_enter_where_configured() {
    // Integrator plant ẋ = p; command 4.8 V held; saturation at 5 V; a 0.5 V step disturbance
    // at t = 0.3 s. Before saturation: p = min(4.8 + 0.5, 5) = 5 after 0.3 s; after
    // saturation: p = 5.3. x(1) is the closed-form integral of the held input.
    let plant = FnDynamics::new(1, 1, |_t, _x: &[f64], u: &[f64], dx: &mut [f64]| {
        dx[0] = u[0]
    });
    let d = Signal::step(0.3, 0.5).unwrap();
    for (point, after, clipped) in [
        (DisturbancePoint::BeforeSaturation, 5.0, 71),
        (DisturbancePoint::AfterSaturation, 5.3, 0),
    ] {
        let mut lp = SampledLoop::new(
            plant,
            OpenLoop::new(vec![Signal::constant(4.8).unwrap()], 1),
            SampledOptions {
                ts: 0.01,
                t_final: 1.0,
                integrator: Integrator::Rk4 { dt: 0.01 },
                ..Default::default()
            },
        )
        .unwrap()
        .with_actuator(
            Actuator::ideal()
                .saturation(5.0)
                .unwrap()
                .disturbance(vec![d.clone()], point),
        )
        .unwrap();
        let run = lp.run(&[0.0]).unwrap();
        let expect = 4.8 * 0.3 + after * 0.7;
        // Piecewise-constant input integrated exactly: rounding over 100 steps.
        assert!(
            (run.diagnostics.final_state[0] - expect).abs() < 1e-12,
            "{point:?}"
        );
        // Before saturation the 5.3 V sum is clipped at the 71 samples t = 0.30, …, 1.00.
        assert_eq!(run.diagnostics.saturated_samples, clipped);
    }
}

#[test]
fn dac_and_encoders_deliver_levels() {
    let ts = 0.001;
    let (sys, _, _, _) = discrete_design(ts);
    let k = pendulab_lti::design::lqr(
        &sys,
        &Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&[10.0, 10.0, 0.0, 0.0])),
        &Mat::identity(1, 1),
        None,
    )
    .unwrap()
    .gain;
    let (qz, qth) = (4.8414e-5, 2.0 * std::f64::consts::PI / 14400.0);
    let rig = pendulab_sim::rig::RigChains::with_quantizer(
        4,
        &[(0, qz), (1, qth)],
        &[(0, 2, 0.02), (1, 3, 0.02)],
        5.0,
        16,
    )
    .unwrap();
    // The same chain as the builder calls give.
    let chain = SensorChain::encoders(&[(0, qz), (1, qth)])
        .unwrap()
        .pseudo_differentiator(0.02)
        .unwrap();
    assert_eq!(rig.sensor, chain);
    let mut lp = SampledLoop::new(
        CartPendulum::default(),
        StaticStateFeedback::new(k).unwrap(),
        SampledOptions {
            t_final: 5.0,
            ..Default::default()
        },
    )
    .unwrap()
    .with_rig(rig)
    .unwrap();
    let run = lp.run(&[0.0, 15f64.to_radians(), 0.0, 0.0]).unwrap();
    let tr = &run.trajectory;
    let q = 10.0 / 65536.0;
    for kk in 0..tr.len() {
        let u = tr.u()[(kk, 0)];
        assert!(u.abs() <= 5.0);
        assert!(((u / q) - (u / q).round()).abs() < 1e-9, "u = {u}");
        for (i, step) in [(0, qz), (1, qth)] {
            let y = tr.y()[(kk, i)];
            assert!(((y / step) - (y / step).round()).abs() < 1e-6, "y{i} = {y}");
            // Round-to-nearest: within half a step of the true state.
            assert!((y - tr.x()[(kk, i)]).abs() <= 0.5 * step * (1.0 + 1e-9));
        }
    }
    // 15° with LQR Q = diag(10, 10, 0, 0): the quantised rig still balances.
    assert!(run.diagnostics.final_state[1].abs() < 0.01);
    let over = (0..tr.len())
        .filter(|&kk| run.commands[(kk, 0)].abs() > 5.0)
        .count();
    assert_eq!(run.diagnostics.saturated_samples, over);
}

#[test]
fn monitors_stop_runs_and_see_every_sample() {
    // Unstable open loop: the pendulum falls; StayWithin stops it past 0.5 rad.
    let mut seen = 0usize;
    let mut lp = SampledLoop::new(
        CartPendulum::default(),
        OpenLoop::new(vec![Signal::zero()], 4),
        SampledOptions {
            t_final: 5.0,
            record: Record::Off,
            ..Default::default()
        },
    )
    .unwrap();
    let mut m = (
        StayWithin::new(1, 0.5),
        FnMonitor(|_t: f64, _x: &[f64], _y: &[f64], _u: &[f64]| {
            seen += 1;
            Flow::Continue
        }),
    );
    let run = lp.run_with(&[0.0, 0.05, 0.0, 0.0], &mut m).unwrap();
    let RunStatus::Stopped { t } = run.status else {
        panic!("{:?}", run.status)
    };
    assert_eq!(m.0.violated_at, Some(t));
    assert!(run.trajectory.is_empty());
    assert_eq!(run.diagnostics.samples, (t / 1e-3).round() as usize + 1);
    assert!(run.diagnostics.final_state[1] > 0.5);
    let _ = m;
    assert_eq!(seen, run.diagnostics.samples);
}

#[test]
fn drive_friction_closed_forms() {
    // Cart drive alone, ż̈ = −a ż + b v_eff. Below break-away (|v| ≤ V_s) the stuck cart does
    // not move. Above, from rest: z̈ = −a ż + b (v − V_c), so
    // z(t) = (b (v − V_c)/a) (t − (1 − e^{−a t})/a).
    let (a, b) = (6.25, 4.36);
    let drive = FnDynamics::new(2, 1, move |_t, x: &[f64], u: &[f64], dx: &mut [f64]| {
        dx[0] = x[1];
        dx[1] = -a * x[1] + b * u[0];
    });
    let (vc, vs) = (0.4, 0.6);
    let friction = Friction::Coulomb {
        input: 0,
        velocity_state: 1,
        coulomb: vc,
        stiction: vs,
        velocity_band: 1e-9,
    };
    for (v, moves) in [(0.55, false), (-0.55, false), (2.0, true), (-2.0, true)] {
        let mut lp = SampledLoop::new(
            drive,
            OpenLoop::new(vec![Signal::constant(v).unwrap()], 2),
            SampledOptions {
                ts: 1e-3,
                t_final: 1.0,
                integrator: Integrator::Rk4 { dt: 1e-4 },
                ..Default::default()
            },
        )
        .unwrap()
        .with_actuator(Actuator::ideal().friction(friction))
        .unwrap();
        let run = lp.run(&[0.0, 0.0]).unwrap();
        let z = run.diagnostics.final_state[0];
        if moves {
            let ve = v - vc * v.signum();
            let zt = b * ve / a * (1.0 - (1.0 - (-a * 1.0f64).exp()) / a);
            // Sliding never reverses, so the law is smooth after the first substep; the
            // first substep starts inside the band (break-away branch, same v_eff) — RK4 at
            // 1e-4 s leaves ~1e-12, the tolerance allows the band's 1e-9 m/s.
            assert!((z - zt).abs() < 1e-8, "v = {v}: {z} vs {zt}");
        } else {
            assert_eq!(z, 0.0, "v = {v}");
        }
    }
    // The static dead zone: v_eff = v − w sign(v) outside, 0 inside.
    let mut lp = SampledLoop::new(
        drive,
        OpenLoop::new(vec![Signal::constant(1.0).unwrap()], 2),
        SampledOptions {
            ts: 1e-3,
            t_final: 1.0,
            integrator: Integrator::Rk4 { dt: 1e-4 },
            ..Default::default()
        },
    )
    .unwrap()
    .with_actuator(Actuator::ideal().friction(Friction::DeadZone {
        input: 0,
        width: 0.3,
    }))
    .unwrap();
    let run = lp.run(&[0.0, 0.0]).unwrap();
    assert!((run.trajectory.u()[(0, 0)] - 0.7).abs() < 1e-15);
    let zt = b * 0.7 / a * (1.0 - (1.0 - (-a * 1.0f64).exp()) / a);
    assert!((run.diagnostics.final_state[0] - zt).abs() < 1e-10);
}

#[test]
fn sensor_noise_is_seeded_and_has_its_statistics() {
    // A plant at rest measured with σ = 0.01 noise on an unquantised channel: the samples are
    // N(0, σ²). With n = 10001 samples the sample mean lies within 5σ/√n and the sample
    // standard deviation within 5 % of σ (≈ 7 standard errors of 0.7 %), for any seed.
    let rest = FnDynamics::new(1, 1, |_t, _x: &[f64], _u: &[f64], dx: &mut [f64]| {
        dx[0] = 0.0
    });
    let sigma = 0.01;
    let run_with_seed = |seed| {
        let mut lp = SampledLoop::new(
            rest,
            OpenLoop::new(vec![Signal::zero()], 1),
            SampledOptions::default(),
        )
        .unwrap()
        .with_sensor(SensorChain::states(&[0]).noise(&[sigma], seed).unwrap())
        .unwrap();
        lp.run(&[0.0]).unwrap().trajectory.y_signal(0).to_vec()
    };
    let a = run_with_seed(1);
    let b = run_with_seed(1);
    let c = run_with_seed(2);
    assert_eq!(a, b, "same seed, same noise");
    assert_ne!(a, c);
    let n = a.len() as f64;
    let mean = a.iter().sum::<f64>() / n;
    let sd = (a.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    assert!(mean.abs() < 5.0 * sigma / n.sqrt(), "{mean}");
    assert!((sd / sigma - 1.0).abs() < 0.05, "{sd}");
}

#[test]
fn bad_configurations_are_typed_errors() {
    let plant = CartPendulum::default();
    let k = StaticStateFeedback::new(Mat::zeros(1, 4)).unwrap();
    let mk = |o: SampledOptions| SampledLoop::new(plant, k.clone(), o).map(|_| ());
    assert!(matches!(
        mk(SampledOptions {
            ts: 0.0,
            ..Default::default()
        }),
        Err(SimError::InvalidSampleTime(_))
    ));
    assert!(matches!(
        mk(SampledOptions {
            ts: -1e-3,
            ..Default::default()
        }),
        Err(SimError::InvalidSampleTime(_))
    ));
    assert!(matches!(
        mk(SampledOptions {
            integrator: Integrator::Rk4 { dt: 3e-4 },
            ..Default::default()
        }),
        Err(SimError::StepDoesNotDivide { .. })
    ));
    assert!(matches!(
        mk(SampledOptions {
            integrator: Integrator::Rk4 { dt: 2e-3 },
            ..Default::default()
        }),
        Err(SimError::StepDoesNotDivide { .. })
    ));
    assert!(matches!(
        mk(SampledOptions {
            delay: Delay::Time(2e-3),
            ..Default::default()
        }),
        Err(SimError::InvalidParameter { .. })
    ));
    assert!(matches!(
        mk(SampledOptions {
            t_final: 1e-4,
            ..Default::default()
        }),
        Err(SimError::InvalidTimeSpan { .. })
    ));
    assert!(matches!(
        mk(SampledOptions {
            t_final: f64::NAN,
            ..Default::default()
        }),
        Err(SimError::InvalidTimeSpan { .. })
    ));
    assert!(matches!(
        mk(SampledOptions {
            initial_input: Some(vec![0.0, 0.0]),
            ..Default::default()
        }),
        Err(SimError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        mk(SampledOptions {
            record: Record::Every(0),
            ..Default::default()
        }),
        Err(SimError::InvalidParameter { .. })
    ));
    // Controller of the wrong shape: too many commands (at construction), a measurement the
    // sensor chain does not deliver (when run).
    let wrong = StaticStateFeedback::new(Mat::zeros(2, 4)).unwrap();
    assert!(matches!(
        SampledLoop::new(plant, wrong, SampledOptions::default()),
        Err(SimError::DimensionMismatch { .. })
    ));
    let wrong = StaticStateFeedback::new(Mat::zeros(1, 3)).unwrap();
    let mut lw = SampledLoop::new(plant, wrong, SampledOptions::default()).unwrap();
    assert!(matches!(
        lw.run(&[0.0; 4]),
        Err(SimError::DimensionMismatch { .. })
    ));
    // Sensor reading a state that does not exist; sensor of the wrong width.
    let lp = SampledLoop::new(plant, k.clone(), SampledOptions::default()).unwrap();
    assert!(
        lp.clone()
            .with_sensor(SensorChain::states(&[0, 1, 2, 7]))
            .is_err()
    );
    assert!(matches!(
        lp.clone().with_sensor(SensorChain::states(&[0, 1])),
        Err(SimError::DimensionMismatch { .. })
    ));
    // A controller designed for another sample time.
    let (dsys, kd) = {
        let d = plant.linear().c2d(0.01, Discretization::Zoh).unwrap();
        (d, Mat::zeros(1, 4))
    };
    let obs = pendulab_sim::controllers::ObserverBased::new(
        &dsys,
        &kd,
        &Mat::zeros(4, 4),
        Default::default(),
    )
    .unwrap();
    assert!(matches!(
        SampledLoop::new(plant, obs, SampledOptions::default()),
        Err(SimError::SampleTimeMismatch { .. })
    ));
    // NaN initial state; wrong length.
    let mut lp2 = lp.clone();
    assert!(matches!(
        lp2.run(&[0.0, f64::NAN, 0.0, 0.0]),
        Err(SimError::NonFiniteInitialState { index: 1, .. })
    ));
    assert!(matches!(
        lp2.run(&[0.0, 0.0]),
        Err(SimError::DimensionMismatch { .. })
    ));
    // A controller returning NaN.
    let mut nan = SampledLoop::new(
        plant,
        OpenLoop::new(
            vec![Signal::step(0.5, 1.0).unwrap().scaled(1.0).unwrap()],
            4,
        ),
        SampledOptions::default(),
    )
    .unwrap();
    assert!(nan.run(&[0.0; 4]).is_ok());
    let mut nan = SampledLoop::new(
        plant,
        pendulab_sim::controllers::GainScheduled::from_fn(
            1,
            4,
            |_rho, k: &mut [f64]| k.fill(f64::NAN),
            |_y: &[f64]| 0.0,
        ),
        SampledOptions::default(),
    )
    .unwrap();
    assert!(matches!(
        nan.run(&[0.0; 4]),
        Err(SimError::NonFiniteCommand { t, .. }) if t == 0.0
    ));
    // A blow-up names its time: ẋ = x² from x = 1 under zero input diverges at t = 1.
    let blow = FnDynamics::new(1, 1, |_t, x: &[f64], _u: &[f64], dx: &mut [f64]| {
        dx[0] = x[0] * x[0]
    });
    let mut b = SampledLoop::new(
        blow,
        OpenLoop::new(vec![Signal::zero()], 1),
        SampledOptions {
            ts: 0.01,
            t_final: 3.0,
            integrator: Integrator::Rk4 { dt: 0.01 },
            ..Default::default()
        },
    )
    .unwrap();
    match b.run(&[1.0]) {
        Err(SimError::NonFiniteState { t, .. }) => assert!(t > 0.99 && t <= 3.0, "{t}"),
        other => panic!("{other:?}"),
    }
    assert!(Quantizer::new(-1.0).is_err());
}
