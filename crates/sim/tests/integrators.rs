//! Integrators against independent references: a plain-Python RK4 (fixture), the matrix
//! exponential, closed-form event times, and the order of the dense output.

use pendulab_lti::Mat;
use pendulab_lti::matrix_functions::expm;
use pendulab_sim::{
    Direction, Event, FnDynamics, Integrator, OdeOptions, Output, Rk4Work, Signal, SimError,
    Status, rk4_step, rk4_step_slice, simulate, simulate_free,
};
use serde_json::Value;

fn fixture() -> Value {
    serde_json::from_str(include_str!("fixtures/rk4_reference.json")).expect("fixture JSON")
}

fn case<'a>(f: &'a Value, name: &str) -> &'a Value {
    f["cases"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == name)
        .unwrap_or_else(|| panic!("case {name}"))
}

fn rows(c: &Value) -> Vec<Vec<f64>> {
    c["samples"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            r.as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect()
        })
        .collect()
}

fn p(c: &Value, k: &str) -> f64 {
    c["params"][k].as_f64().unwrap()
}

/// Tolerance of every comparison with the Python RK4: both sides evaluate the same formulas
/// in IEEE double, in a different operation order (and libm vs CPython's `math`), so samples
/// differ by rounding — ~1e-16 per operation, accumulated over ≤ 2000 steps of a
/// non-expanding flow, well below 1e-12 on values of order 1.
const PYTHON_RK4_TOL: f64 = 1e-12;

#[test]
fn rk4_matches_independent_python_pendulum() {
    let f = fixture();
    let c = case(&f, "pendulum");
    let (g, l, damp) = (p(c, "g"), p(c, "l"), p(c, "c"));
    let pend = FnDynamics::new(2, 1, move |_t, x: &[f64], u: &[f64], dx: &mut [f64]| {
        dx[0] = x[1];
        dx[1] = -(g / l) * x[0].sin() - damp * x[1] + u[0];
    });
    let input = Signal::sine(p(c, "u_amplitude"), p(c, "u_omega"), 0.0).unwrap();
    let dt = c["dt"].as_f64().unwrap();
    let steps = c["steps"].as_u64().unwrap() as usize;
    let x0: Vec<f64> = c["x0"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let opts = OdeOptions {
        integrator: Integrator::Rk4 { dt },
        ..Default::default()
    };
    let sim = simulate(&pend, &input, &x0, steps as f64 * dt, &opts).unwrap();
    let tr = &sim.trajectory;
    assert_eq!(tr.len(), steps + 1);
    assert_eq!(sim.stats.accepted_steps, steps);
    for r in rows(c) {
        let k = (r[0] / dt).round() as usize;
        assert!((tr.t()[k] - r[0]).abs() < 1e-12);
        for i in 0..2 {
            let e = (tr.x()[(k, i)] - r[1 + i]).abs();
            assert!(e < PYTHON_RK4_TOL, "t = {}, x{i}: error {e:e}", r[0]);
        }
        // The recorded input is u(t) at the sample.
        assert_eq!(tr.u()[(k, 0)], input.value(tr.t()[k]));
    }
}

#[test]
fn rk4_matches_independent_python_van_der_pol_and_kernels_agree() {
    let f = fixture();
    let c = case(&f, "van_der_pol");
    let mu = p(c, "mu");
    let vdp = FnDynamics::new(2, 0, move |_t, x: &[f64], _u: &[f64], dx: &mut [f64]| {
        dx[0] = x[1];
        dx[1] = mu * (1.0 - x[0] * x[0]) * x[1] - x[0];
    });
    let dt = c["dt"].as_f64().unwrap();
    let steps = c["steps"].as_u64().unwrap() as usize;
    let opts = OdeOptions {
        integrator: Integrator::Rk4 { dt },
        ..Default::default()
    };
    let sim = simulate_free(&vdp, &[2.0, 0.0], steps as f64 * dt, &opts).unwrap();
    let refs = rows(c);
    for r in &refs {
        let k = (r[0] / dt).round() as usize;
        for i in 0..2 {
            let e = (sim.trajectory.x()[(k, i)] - r[1 + i]).abs();
            assert!(e < PYTHON_RK4_TOL, "t = {}, x{i}: error {e:e}", r[0]);
        }
    }
    // The const-generic and slice kernels take the same steps.
    let mut xa = [2.0, 0.0];
    let mut xs = vec![2.0, 0.0];
    let mut w = Rk4Work::new(2);
    for k in 0..steps {
        rk4_step(&vdp, k as f64 * dt, &mut xa, &[], dt);
        rk4_step_slice(&vdp, k as f64 * dt, &mut xs, &[], dt, &mut w);
    }
    let last = refs.last().unwrap();
    for i in 0..2 {
        assert!((xa[i] - last[1 + i]).abs() < PYTHON_RK4_TOL);
        assert!((xs[i] - last[1 + i]).abs() < PYTHON_RK4_TOL);
    }
}

/// A lightly damped oscillator with a real mode: A = [[0, 1, 0], [−4, −0.1, 1], [0, 0, −0.5]].
fn linear_test_system() -> (Mat, pendulab_lti::StateSpace<pendulab_lti::Continuous>) {
    let a = Mat::from_row_slice(3, 3, &[0.0, 1.0, 0.0, -4.0, -0.1, 1.0, 0.0, 0.0, -0.5]);
    let sys = pendulab_lti::StateSpace::continuous(
        a.clone(),
        Mat::zeros(3, 1),
        Mat::identity(3, 3),
        Mat::zeros(3, 1),
    )
    .unwrap();
    (a, sys)
}

#[test]
fn dopri45_on_a_linear_system_meets_its_tolerance_against_expm() {
    let (a, sys) = linear_test_system();
    let x0 = [1.0, 0.0, 2.0];
    let times: Vec<f64> = (0..=100).map(|k| 0.1 * k as f64 + 0.0123).collect();
    let t_final = 10.1;
    let mut previous = f64::INFINITY;
    for tol in [1e-5, 1e-8, 1e-11] {
        let opts = OdeOptions {
            integrator: Integrator::dopri45(tol, tol),
            output: Output::Times(times.clone()),
            ..Default::default()
        };
        let sim = simulate_free(&sys, &x0, t_final, &opts).unwrap();
        assert_eq!(sim.trajectory.len(), times.len());
        let mut worst = 0.0f64;
        for (k, &t) in times.iter().enumerate() {
            let e = expm(&(&a * t)).unwrap() * nalgebra::DVector::from_row_slice(&x0);
            for i in 0..3 {
                worst = worst.max((sim.trajectory.x()[(k, i)] - e[i]).abs());
            }
        }
        // The controller bounds the local error per step by tol (scaled by atol + rtol|x|,
        // |x| ≤ 2.3); over ~10 s of a lightly damped flow the global error stays within a
        // small multiple of tol. 10·tol·(1 + max|x|) is the bound asserted, and the errors
        // must shrink with the tolerance (at least ×100 for a ×1000 tighter tolerance).
        assert!(worst <= 10.0 * tol * 3.3, "tol {tol:e}: error {worst:e}");
        assert!(
            worst < previous / 100.0,
            "tol {tol:e}: {worst:e} vs {previous:e}"
        );
        previous = worst;
        assert!(sim.stats.rejected_steps < sim.stats.accepted_steps);
    }
}

#[test]
fn dopri45_dense_output_is_fourth_order() {
    // One step of ẋ = λx with a fixed step h (no rejection possible with huge tolerances):
    // the interpolant at θ = 0.37 has a local error O(h⁵), so halving h divides it by ~32.
    let lambda = -1.3;
    let sys = FnDynamics::new(1, 0, move |_t, x: &[f64], _u: &[f64], dx: &mut [f64]| {
        dx[0] = lambda * x[0]
    });
    let err = |h: f64| {
        let opts = OdeOptions {
            integrator: Integrator::Dopri45 {
                rtol: 1e3,
                atol: 1e3,
                h_max: Some(h),
                h_init: Some(h),
                max_steps: 10,
            },
            output: Output::Times(vec![0.37 * h]),
            ..Default::default()
        };
        let sim = simulate_free(&sys, &[1.0], h, &opts).unwrap();
        assert_eq!(sim.stats.accepted_steps, 1);
        (sim.trajectory.x()[(0, 0)] - (lambda * 0.37 * h).exp()).abs()
    };
    let errors: Vec<f64> = [0.4, 0.2, 0.1, 0.05].iter().map(|&h| err(h)).collect();
    // A 5th-power law halves to 1/32; the higher-order terms, of the same sign here, make the
    // first ratios larger and fade as h shrinks. A 3rd-order interpolant (a wrong continuous
    // extension) would give ≤ 16.
    for w in errors.windows(2) {
        let r = w[0] / w[1];
        assert!((28.0..48.0).contains(&r), "ratio {r} ({errors:?})");
    }
    let last = errors[2] / errors[3];
    assert!((28.0..36.0).contains(&last), "{last}");
}

#[test]
fn falling_mass_hits_the_ground_at_the_closed_form_time() {
    // ÿ = −g from y0 = 10 m, v0 = 3 m/s: ground at t* = (v0 + √(v0² + 2 g y0))/g.
    let g = 9.81;
    let (y0, v0): (f64, f64) = (10.0, 3.0);
    let t_star = (v0 + (v0 * v0 + 2.0 * g * y0).sqrt()) / g;
    let sys = FnDynamics::new(2, 0, move |_t, x: &[f64], _u: &[f64], dx: &mut [f64]| {
        dx[0] = x[1];
        dx[1] = -g;
    });
    for integrator in [
        Integrator::dopri45(1e-8, 1e-10),
        Integrator::Rk4 { dt: 0.05 },
    ] {
        let opts = OdeOptions {
            integrator,
            events: vec![
                Event::new(|_t, x: &[f64]| x[0])
                    .direction(Direction::Falling)
                    .terminal(),
            ],
            ..Default::default()
        };
        let sim = simulate_free(&sys, &[y0, v0], 10.0, &opts).unwrap();
        let Status::Terminated { event, t } = sim.status else {
            panic!("no impact found: {:?}", sim.status)
        };
        assert_eq!(event, 0);
        // The solution is quadratic in t: both methods integrate it exactly and both dense
        // outputs (4th-order continuous extension, cubic Hermite) reproduce it exactly, so
        // the located time is limited only by rounding and Brent's tolerance (4ε|t|).
        assert!(
            (t - t_star).abs() < 1e-13,
            "{integrator:?}: {t} vs {t_star}"
        );
        let last = sim.trajectory.len() - 1;
        assert_eq!(sim.trajectory.t()[last], t);
        assert!(sim.trajectory.x()[(last, 0)].abs() < 1e-12);
        // Impact speed −√(v0² + 2 g y0).
        let v_star = -(v0 * v0 + 2.0 * g * y0).sqrt();
        assert!((sim.events[0].x[1] - v_star).abs() < 1e-12);
    }
}

#[test]
fn oscillator_zero_crossings_with_directions() {
    // x = cos(ωt): zeros at (2k+1)π/(2ω); falling for even k, rising for odd k.
    let w = 2.0f64;
    let sys = FnDynamics::new(2, 0, move |_t, x: &[f64], _u: &[f64], dx: &mut [f64]| {
        dx[0] = x[1];
        dx[1] = -w * w * x[0];
    });
    let opts = OdeOptions {
        integrator: Integrator::dopri45(1e-12, 1e-12),
        events: vec![
            Event::new(|_t, x: &[f64]| x[0]).direction(Direction::Rising),
            Event::new(|_t, x: &[f64]| x[0]).direction(Direction::Falling),
            Event::new(|_t, x: &[f64]| x[0]),
        ],
        ..Default::default()
    };
    let sim = simulate_free(&sys, &[1.0, 0.0], 10.0, &opts).unwrap();
    assert_eq!(sim.status, Status::Completed);
    let zeros: Vec<f64> = (0..)
        .map(|k| (2 * k + 1) as f64 * std::f64::consts::PI / (2.0 * w))
        .take_while(|&t| t <= 10.0)
        .collect();
    for (e, parity) in [(0usize, 1usize), (1, 0)] {
        let found: Vec<f64> = sim
            .events
            .iter()
            .filter(|h| h.event == e)
            .map(|h| h.t)
            .collect();
        let expect: Vec<f64> = zeros
            .iter()
            .enumerate()
            .filter(|(k, _)| k % 2 == parity)
            .map(|(_, &t)| t)
            .collect();
        assert_eq!(found.len(), expect.len(), "event {e}");
        for (a, b) in found.iter().zip(&expect) {
            // Dense-output accuracy at rtol = atol = 1e-12 over 10 s: ~1e-11 in x, and
            // |ẋ| = ω at the zeros, so the time error is of the same order.
            assert!((a - b).abs() < 1e-9, "event {e}: {a} vs {b}");
        }
    }
    assert_eq!(
        sim.events.iter().filter(|h| h.event == 2).count(),
        zeros.len()
    );
    // Events are reported in time order.
    assert!(sim.events.windows(2).all(|w| w[0].t <= w[1].t));
}

#[test]
fn bad_inputs_are_typed_errors() {
    let decay = FnDynamics::new(1, 0, |_t, x: &[f64], _u: &[f64], dx: &mut [f64]| {
        dx[0] = -x[0]
    });
    let o = OdeOptions::default();
    assert!(matches!(
        simulate_free(&decay, &[f64::NAN], 1.0, &o),
        Err(SimError::NonFiniteInitialState { index: 0, .. })
    ));
    assert!(matches!(
        simulate_free(&decay, &[1.0, 2.0], 1.0, &o),
        Err(SimError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        simulate_free(&decay, &[1.0], 0.0, &o),
        Err(SimError::InvalidTimeSpan { .. })
    ));
    assert!(matches!(
        simulate_free(&decay, &[1.0], f64::INFINITY, &o),
        Err(SimError::InvalidTimeSpan { .. })
    ));
    for integ in [
        Integrator::Rk4 { dt: 0.0 },
        Integrator::Rk4 { dt: f64::NAN },
        Integrator::dopri45(-1.0, 1e-6),
        Integrator::dopri45(1e-6, f64::NAN),
    ] {
        let o = OdeOptions {
            integrator: integ,
            ..Default::default()
        };
        assert!(simulate_free(&decay, &[1.0], 1.0, &o).is_err(), "{integ:?}");
    }
    let o = OdeOptions {
        output: Output::Times(vec![0.5, 0.2]),
        ..Default::default()
    };
    assert!(matches!(
        simulate_free(&decay, &[1.0], 1.0, &o),
        Err(SimError::InvalidArgument(_))
    ));
    let o = OdeOptions {
        output: Output::Times(vec![0.5, 2.0]),
        ..Default::default()
    };
    assert!(simulate_free(&decay, &[1.0], 1.0, &o).is_err());
    // Wrong input width.
    let two = vec![Signal::zero(), Signal::zero()];
    assert!(matches!(
        simulate(&decay, &two, &[1.0], 1.0, &OdeOptions::default()),
        Err(SimError::DimensionMismatch { .. })
    ));
    // Finite-time blow-up ẋ = x², x(0) = 1 (x = 1/(1 − t)): RK4 overflows shortly after
    // t = 1 and the error names a time past the singularity.
    let blow = FnDynamics::new(1, 0, |_t, x: &[f64], _u: &[f64], dx: &mut [f64]| {
        dx[0] = x[0] * x[0]
    });
    let o = OdeOptions {
        integrator: Integrator::Rk4 { dt: 0.01 },
        ..Default::default()
    };
    match simulate_free(&blow, &[1.0], 5.0, &o) {
        Err(SimError::NonFiniteState { t, index: 0, .. }) => assert!(t > 0.99 && t <= 5.0, "{t}"),
        other => panic!("expected NonFiniteState, got {other:?}"),
    }
    // The adaptive method cannot pass the singularity: step-size underflow (or the budget).
    let o = OdeOptions {
        integrator: Integrator::dopri45(1e-8, 1e-8),
        ..Default::default()
    };
    match simulate_free(&blow, &[1.0], 5.0, &o) {
        Err(SimError::StepSizeUnderflow { t, .. }) | Err(SimError::MaxStepsExceeded { t, .. }) => {
            assert!((t - 1.0).abs() < 1e-3, "{t}")
        }
        other => panic!("expected a step-size failure, got {other:?}"),
    }
}
