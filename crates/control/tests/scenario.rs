//! The one simulate path against independent results: the exact discretisation of the linear
//! closed loop, the linear limit of the nonlinear plant, closed forms of the summary's
//! settling time and overshoot, and two routes to the same servo reference.

use pendulab_control::scenario::{
    SETTLING_FRACTION, ScenarioError, overshoot, settling_time, simulate, simulate_on,
};
use pendulab_control::spec::{
    ControllerSpec, GainScheduledSpec, LqServoSpec, LqrSpec, StateFeedbackSpec, build, build_for,
};
use pendulab_lti::design::lqr;
use pendulab_lti::response::initial;
use pendulab_lti::{Discretization, Mat};
use pendulab_plants::rig::PlantKind;
use pendulab_plants::spec::{PlantParameters, PlantSpec, Provenance};
use pendulab_plants::{CartEquilibrium, CartPendulum, CartPendulumParams, RigSpec};
use pendulab_sim::scenario::{Imperfections, NoiseSpec, ScenarioSpec, SignalSpec};

/// The book's cart gain (`cdip_lqr_sim`, u = +K_book x).
const K_BOOK: [f64; 4] = [3.16228, 13.47175, 4.48137, 2.26289];

fn book_gain() -> ControllerSpec {
    ControllerSpec::StateFeedback(StateFeedbackSpec {
        k_book: Some(K_BOOK.to_vec()),
        ..Default::default()
    })
}

/// The zero-input response of the exactly discretised (ZOH) closed loop `Φ − Γ K` of the
/// linear plant `lin` at `ts`, by `pendulab_lti::initial`.
fn exact_closed_loop(
    lin: &pendulab_lti::StateSpace<pendulab_lti::Continuous>,
    k: &Mat,
    x0: &[f64],
    t: &[f64],
    ts: f64,
) -> Mat {
    let d = lin.c2d(ts, Discretization::Zoh).unwrap();
    let cl = pendulab_lti::StateSpace::discrete(
        d.a() - d.b() * k,
        d.b().clone(),
        Mat::identity(4, 4),
        Mat::zeros(4, 1),
        ts,
    )
    .unwrap();
    initial(&cl, x0, t).unwrap().x().clone()
}

/// [`exact_closed_loop`] of the cart's upright linearisation under the book gain.
fn discrete_closed_loop(x0: &[f64], t: &[f64], ts: f64) -> Mat {
    let lin = CartPendulum::book()
        .linearize(CartEquilibrium::upright())
        .unwrap();
    exact_closed_loop(&lin, &-Mat::from_row_slice(1, 4, &K_BOOK), x0, t, ts)
}

#[test]
fn linear_plant_run_equals_the_exact_discrete_closed_loop() {
    let ts = 1e-3;
    let x0 = [0.05, 0.1, 0.0, 0.0];
    let mut scenario = ScenarioSpec::new(x0.to_vec(), 3.0);
    scenario.substeps = 10;
    let lin = CartPendulum::book()
        .linearize(CartEquilibrium::upright())
        .unwrap();
    let spec = book_gain();
    let built = build(&spec, PlantKind::Cart, ts).unwrap();
    let run = simulate_on(lin, &RigSpec::cart(), &spec, built, &scenario).unwrap();
    let reference = discrete_closed_loop(&x0, &run.t, ts);
    let mut worst: f64 = 0.0;
    for (k, xk) in run.x.iter().enumerate() {
        for i in 0..4 {
            worst = worst.max((xk[i] - reference[(k, i)]).abs());
        }
    }
    // RK4 at 0.1 ms against the matrix exponential: local error ~(h·|λ|)⁵/120.
    assert!(worst < 1e-9, "max |x_run − x_exact| = {worst:e}");
    // The command is u = +K_book x at every sample.
    for k in [0, 100, 2000] {
        let u: f64 = (0..4).map(|i| K_BOOK[i] * run.x[k][i]).sum();
        assert!((run.command[k] - u).abs() < 1e-12);
    }
}

#[test]
fn nonlinear_run_approaches_the_linear_one_as_the_initial_angle_shrinks() {
    // The nonlinearity of the cart pendulum is odd in θ (sin θ, cos θ·z̈, θ̇²·sin θ), so the
    // relative deviation of the nonlinear from the linear run falls as θ₀²: a tenfold
    // smaller start gives a hundredfold smaller relative deviation.
    let ts = 1e-3;
    let plant = PlantSpec::book(PlantKind::Cart);
    let rel = |theta0: f64| {
        let x0 = [0.0, theta0, 0.0, 0.0];
        let mut scenario = ScenarioSpec::new(x0.to_vec(), 3.0);
        scenario.substeps = 10;
        let run = simulate(&plant, &book_gain(), &scenario).unwrap();
        let lin = discrete_closed_loop(&x0, &run.t, ts);
        let mut worst: f64 = 0.0;
        for (k, xk) in run.x.iter().enumerate() {
            for i in 0..2 {
                worst = worst.max((xk[i] - lin[(k, i)]).abs());
            }
        }
        worst / theta0
    };
    let (r1, r2, r3) = (rel(0.1), rel(0.01), rel(0.001));
    assert!(r3 < 1e-5, "relative deviation at 1 mrad: {r3:e}");
    for (a, b) in [(r1, r2), (r2, r3)] {
        let ratio = a / b;
        assert!(
            (80.0..125.0).contains(&ratio),
            "ratio {ratio} (expected ~100)"
        );
    }
}

#[test]
fn settling_time_of_a_first_order_response_is_tau_ln_50() {
    // q(t) = 1 − e^{−t/τ} from 0 to 1: the largest deviation is 1 (at t = 0), the 2 % band is
    // reached at t = τ ln 50 and never left; the first sample at or after it.
    let (tau, ts) = (0.3, 1e-3);
    let t: Vec<f64> = (0..3000).map(|k| k as f64 * ts).collect();
    let q: Vec<f64> = t.iter().map(|t| 1.0 - (-t / tau).exp()).collect();
    let exact = tau * (1.0 / SETTLING_FRACTION).ln();
    let expected = (exact / ts).ceil() * ts;
    let got = settling_time(&t, &q, 1.0, SETTLING_FRACTION).unwrap();
    assert!(
        (got - expected).abs() < 1e-12,
        "{got} vs {expected} (τ ln 50 = {exact})"
    );
    // A run that ends outside the band has none.
    assert_eq!(
        settling_time(&t[..1000], &q[..1000], 1.0, SETTLING_FRACTION),
        None
    );
}

#[test]
fn overshoot_of_a_second_order_step_is_the_closed_form() {
    // q(t) = 1 − e^{−ζωt}(cos ω_d t + ζ/√(1−ζ²) sin ω_d t): overshoot e^{−ζπ/√(1−ζ²)}.
    let (zeta, w) = (0.3_f64, 4.0_f64);
    let s = (1.0 - zeta * zeta).sqrt();
    let wd = w * s;
    let ts = 1e-5;
    let q: Vec<f64> = (0..300_000)
        .map(|k| {
            let t = k as f64 * ts;
            1.0 - (-zeta * w * t).exp() * ((wd * t).cos() + zeta / s * (wd * t).sin())
        })
        .collect();
    let expected = 100.0 * (-zeta * std::f64::consts::PI / s).exp();
    let got = overshoot(&q, 1.0).unwrap();
    // The peak is at t = π/ω_d; a sample within ts/2 of it misses it by O((ω_d ts)²).
    assert!((got - expected).abs() < 1e-6, "{got} vs {expected}");
    assert_eq!(overshoot(&[1.0, 1.0], 1.0), None);
}

#[test]
fn a_scenario_reference_is_the_servo_reference_of_the_spec() {
    // The same 0.1 m step at 0.5 s given in the controller spec and in the scenario: the two
    // runs are identical sample for sample.
    let plant = PlantSpec::book(PlantKind::Cart);
    let lqr = Some(LqrSpec {
        q: vec![1.0, 5.0, 0.0, 0.0, 100.0],
        r: 1.0,
    });
    let in_spec = ControllerSpec::LqServo(LqServoSpec {
        lqr: lqr.clone(),
        reference: Some(vec![0.1]),
        step_time: Some(0.5),
        ..Default::default()
    });
    let bare = ControllerSpec::LqServo(LqServoSpec {
        lqr,
        ..Default::default()
    });
    let mut scenario = ScenarioSpec::new(vec![0.0; 4], 6.0);
    scenario.imperfections = Imperfections::with_quantizer();
    let a = simulate(&plant, &in_spec, &scenario).unwrap();
    scenario.reference = SignalSpec::Step {
        time: 0.5,
        amplitude: 0.1,
    };
    let b = simulate(&plant, &bare, &scenario).unwrap();
    assert_eq!(a.x, b.x);
    assert_eq!(a.reference, b.reference);
    assert_eq!(a.reference[499], 0.0);
    assert_eq!(a.reference[500], 0.1);
    // Its summary: the servo settles at the reference within the run.
    let st = a.summary.settling_time.unwrap();
    assert!(st > 0.5 && st < 6.0, "settling {st}");
    assert_eq!(a.summary, b.summary);
    // Both references at once are refused.
    let e = simulate(&plant, &in_spec, &scenario)
        .unwrap_err()
        .to_string();
    assert!(e.contains("not both"), "{e}");
}

#[test]
fn state_feedback_tracks_a_scenario_reference_like_its_own() {
    // u = −K(y − [r, 0, 0, 0]): a constant scenario reference and the spec's reference vector
    // give the same run.
    let plant = PlantSpec::book(PlantKind::Cart);
    let own = ControllerSpec::StateFeedback(StateFeedbackSpec {
        k_book: Some(K_BOOK.to_vec()),
        reference: Some(vec![0.05, 0.0, 0.0, 0.0]),
        ..Default::default()
    });
    let scenario = ScenarioSpec::new(vec![0.0; 4], 4.0);
    let a = simulate(&plant, &own, &scenario).unwrap();
    let mut with_ref = scenario.clone();
    with_ref.reference = SignalSpec::Constant { value: 0.05 };
    let b = simulate(&plant, &book_gain(), &with_ref).unwrap();
    assert_eq!(a.x, b.x);
    assert_eq!(a.summary.overshoot_percent, b.summary.overshoot_percent);
}

#[test]
fn the_controller_is_designed_on_the_plant_spec_parameters() {
    // An LQR request on a heavier pendulum gives the gain of lqr() on that plant's
    // linearisation, not the book's.
    let p = CartPendulumParams {
        m_p: 0.15,
        ..CartPendulumParams::book()
    };
    let plant = PlantSpec::new(
        PlantParameters::Cart(p),
        Provenance::User { note: None },
        RigSpec::cart(),
    )
    .unwrap();
    let spec = ControllerSpec::StateFeedback(StateFeedbackSpec {
        lqr: Some(LqrSpec {
            q: vec![10.0, 10.0, 0.0, 0.0],
            r: 1.0,
        }),
        ..Default::default()
    });
    let lin = CartPendulum::new(p)
        .unwrap()
        .linearize(CartEquilibrium::upright())
        .unwrap();
    let q = Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&[10.0, 10.0, 0.0, 0.0]));
    let k = lqr(&lin, &q, &Mat::from_element(1, 1, 1.0), None)
        .unwrap()
        .gain;
    let mut own = build_for(&spec, &plant, 1e-3).unwrap().controller;
    let mut book = build(&spec, PlantKind::Cart, 1e-3).unwrap().controller;
    let (mut u, mut ub) = ([0.0], [0.0]);
    own.update(0.0, &[0.0, 1.0, 0.0, 0.0], &mut u);
    book.update(0.0, &[0.0, 1.0, 0.0, 0.0], &mut ub);
    assert!((u[0] + k[(0, 1)]).abs() < 1e-9 * k[(0, 1)].abs());
    assert!((u[0] - ub[0]).abs() > 1e-3, "{} vs book {}", u[0], ub[0]);
}

#[test]
fn imperfections_show_in_the_summary() {
    // From 22° the book gain asks for K_book[1]·θ₀ = 13.47 · 0.384 = 5.17 V at once: with
    // saturation the command is clipped for a while, without it never.
    let plant = PlantSpec::book(PlantKind::Cart);
    let x0 = vec![0.0, 22f64.to_radians(), 0.0, 0.0];
    let mut s = ScenarioSpec::new(x0, 3.0);
    let ideal = simulate(&plant, &book_gain(), &s).unwrap();
    assert_eq!(ideal.summary.time_in_saturation, 0.0);
    assert!(ideal.summary.peak_input > 5.0);
    s.imperfections = Imperfections::with_quantizer();
    let rig = simulate(&plant, &book_gain(), &s).unwrap();
    assert!(rig.summary.time_in_saturation > 0.0);
    assert!(rig.summary.peak_input <= 5.0);
    assert_eq!(rig.summary.left_angle_window, Some(false));
    // Quantised measurements: every measured angle is a whole number of counts.
    let step = 2.0 * std::f64::consts::PI / 14400.0;
    for y in rig.y.iter().take(50) {
        let c = y[1] / step;
        assert!((c - c.round()).abs() < 1e-6);
    }
    // Seeded noise: the same seed gives the same run, another seed another.
    let noisy = |seed| {
        let mut s = s.clone();
        s.imperfections.noise = Some(NoiseSpec {
            std: vec![1e-4, 1e-3, 0.0, 0.0],
            seed,
        });
        simulate(&plant, &book_gain(), &s).unwrap().x
    };
    assert_eq!(noisy(3), noisy(3));
    assert_ne!(noisy(3), noisy(4));
    // A delay of 10 samples at 22° makes the loop worse: a larger angle excursion.
    s.imperfections.delay_samples = 10;
    let late = simulate(&plant, &book_gain(), &s).unwrap();
    assert!(late.summary.max_angle_deviation >= rig.summary.max_angle_deviation);
}

#[test]
fn errors_name_the_key() {
    let plant = PlantSpec::book(PlantKind::Arm);
    let ctrl = ControllerSpec::StateFeedback(StateFeedbackSpec {
        k: Some(vec![0.0; 4]),
        ..Default::default()
    });
    let msg = |s: &ScenarioSpec, c: &ControllerSpec| -> String {
        let e: ScenarioError = simulate(&plant, c, s).unwrap_err();
        e.to_string()
    };
    let short = ScenarioSpec::new(vec![0.0; 3], 1.0);
    assert!(
        msg(&short, &ctrl).contains("scenario.initial_state has 3 entries; the arm plant has 4")
    );
    let long = ScenarioSpec::new(vec![0.0; 4], 1e5);
    assert!(msg(&long, &ctrl).contains("scenario.duration"));
    let mut fr = ScenarioSpec::new(vec![0.0; 4], 1.0);
    fr.imperfections.drive_friction = true;
    assert!(msg(&fr, &ctrl).contains("scenario.imperfections"));
    let mut noise = ScenarioSpec::new(vec![0.0; 4], 1.0);
    noise.imperfections.noise = Some(NoiseSpec {
        std: vec![0.0; 2],
        seed: 1,
    });
    assert!(msg(&noise, &ctrl).contains("scenario.imperfections"));
    let mut gs = ScenarioSpec::new(vec![0.0; 4], 1.0);
    gs.reference = SignalSpec::Constant { value: 0.1 };
    let sched = ControllerSpec::GainScheduled(GainScheduledSpec {
        coefficients: Some(vec![vec![0.0; 4]]),
        ..Default::default()
    });
    assert!(msg(&gs, &sched).contains("gain-scheduled"));
    let mut bad_sig = ScenarioSpec::new(vec![0.0; 4], 1.0);
    bad_sig.reference = SignalSpec::Steps {
        times: vec![1.0, 0.5],
        values: vec![0.1, 0.2],
    };
    assert!(msg(&bad_sig, &ctrl).contains("scenario.reference"));
    let bad_ts = ScenarioSpec {
        sample_time: Some(-1.0),
        ..ScenarioSpec::new(vec![0.0; 4], 1.0)
    };
    assert!(msg(&bad_ts, &ctrl).contains("scenario.sample_time"));
}

#[test]
fn scenario_files_round_trip_and_refuse_unknown_keys() {
    let mut s = ScenarioSpec::new(vec![0.0, 0.1, 0.0, 0.0], 5.0);
    s.reference = SignalSpec::Sine {
        amplitude: 0.1,
        omega: 2.0,
        phase: 0.0,
        offset: 0.05,
    };
    s.disturbance = SignalSpec::Steps {
        times: vec![1.0, 2.0],
        values: vec![0.5, 0.0],
    };
    s.imperfections = Imperfections::with_quantizer();
    s.imperfections.delay_samples = 2;
    let text = s.to_toml().unwrap();
    assert_eq!(ScenarioSpec::from_toml(&text).unwrap(), s);
    let e = ScenarioSpec::from_toml(&text.replace("delay_samples", "delay_sample"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("delay_sample"), "{e}");
    let e = ScenarioSpec::from_toml(&text.replace("omega", "frequency"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("frequency"), "{e}");
}

#[test]
fn arm_linear_plant_run_equals_the_exact_discrete_closed_loop() {
    // The arm's LQR gain from the factory, read back from the controller (u = −K e_i), and
    // the exact ZOH closed loop Φ − Γ K of the arm's upright linearisation.
    let ts = 1e-3;
    let spec = ControllerSpec::StateFeedback(StateFeedbackSpec {
        lqr: Some(LqrSpec {
            q: vec![1.0, 10.0, 0.0, 0.0],
            r: 1.0,
        }),
        ..Default::default()
    });
    let mut probe = build(&spec, PlantKind::Arm, ts).unwrap().controller;
    let mut k = Mat::zeros(1, 4);
    for i in 0..4 {
        let mut y = [0.0; 4];
        y[i] = 1.0;
        let mut u = [0.0];
        probe.update(0.0, &y, &mut u);
        k[(0, i)] = -u[0];
    }
    let lin = PlantSpec::book(PlantKind::Arm)
        .parameters()
        .linearize_upright(0.0)
        .unwrap();
    let x0 = [0.1, 0.05, 0.0, 0.0];
    let mut scenario = ScenarioSpec::new(x0.to_vec(), 3.0);
    scenario.substeps = 10;
    let built = build(&spec, PlantKind::Arm, ts).unwrap();
    let run = simulate_on(lin.clone(), &RigSpec::arm(), &spec, built, &scenario).unwrap();
    let exact = exact_closed_loop(&lin, &k, &x0, &run.t, ts);
    let mut worst: f64 = 0.0;
    for (j, xk) in run.x.iter().enumerate() {
        for i in 0..4 {
            worst = worst.max((xk[i] - exact[(j, i)]).abs());
        }
    }
    assert!(worst < 1e-9, "max |x_run − x_exact| = {worst:e}");
}

#[test]
fn a_swing_up_run_switches_once_and_ends_upright() {
    // Energy shaping from the hanging rest, then the book's balance gain inside 17°: the run
    // records the switch, has no angle window (it starts outside it) and ends upright.
    let plant = PlantSpec::book(PlantKind::Cart);
    let spec = ControllerSpec::SwingUpBalance(pendulab_control::spec::SwingUpBalanceSpec {
        balance: Some(pendulab_control::spec::GainSpec {
            k_book: Some(K_BOOK.to_vec()),
            ..Default::default()
        }),
        switch_deg: None,
        ..Default::default()
    });
    // (The hanging rest itself is an equilibrium of the energy shaping: start 1 mrad off.)
    let mut s = ScenarioSpec::new(vec![0.0, std::f64::consts::PI + 0.001, 0.0, 0.0], 20.0);
    s.imperfections = Imperfections::with_quantizer();
    let run = simulate(&plant, &spec, &s).unwrap();
    assert_eq!(run.switch_times.len(), 1, "{:?}", run.switch_times);
    assert_eq!(run.summary.left_angle_window, None);
    let theta = pendulab_plants::wrap_angle(run.summary.final_state[1]);
    assert!(theta.abs() < 1e-2, "final θ = {theta}");
}

#[test]
fn specs_round_trip_through_json_for_the_other_front_ends() {
    let mut s = ScenarioSpec::new(vec![0.0, 0.1, 0.0, 0.0], 2.0);
    s.reference = SignalSpec::Step {
        time: 0.5,
        amplitude: 0.1,
    };
    s.imperfections.noise = Some(NoiseSpec {
        std: vec![0.0; 4],
        seed: 9,
    });
    let js = serde_json::to_string(&s).unwrap();
    assert_eq!(serde_json::from_str::<ScenarioSpec>(&js).unwrap(), s);
    let c = book_gain();
    let jc = serde_json::to_string(&c).unwrap();
    assert_eq!(serde_json::from_str::<ControllerSpec>(&jc).unwrap(), c);
    let p = PlantSpec::book(PlantKind::Cart);
    let jp = serde_json::to_string(&p).unwrap();
    // The three read from JSON give the same run as the values they came from.
    let a = simulate(&p, &c, &s).unwrap();
    let b = simulate(
        &serde_json::from_str(&jp).unwrap(),
        &serde_json::from_str(&jc).unwrap(),
        &serde_json::from_str(&js).unwrap(),
    )
    .unwrap();
    assert_eq!(a, b);
}
