//! The fixed-size closed-loop kernel (`pendulab_sim::fast::fixed`) against the general sampled-data
//! loop: the reference is `SampledLoop::run_with` of the same configuration, an independent
//! implementation (slices, the controller and actuator objects, the generic RK4 stage code).
//! The kernel promises to perform the same operations in the same order, so every comparison
//! is exact equality of the whole `SampledRun` (trajectory, commands, status, diagnostics).

mod common;

use common::CartPendulum;
use pendulab_lti::Mat;
use pendulab_sim::controllers::{IntegrationRule, LqIntegralServo, StaticStateFeedback};
use pendulab_sim::fast::{FixedDynamics, Fused, MulAdd, MulAddPath, Separate};
use pendulab_sim::{
    Actuator, Delay, Dynamics, Integrator, Record, RunStatus, SampledLoop, SampledOptions,
    SensorChain, Signal, SimError, StayWithin,
};

/// The test plant on arrays: its own `Dynamics::derivative` (the contract of `FixedDynamics`).
impl FixedDynamics<4> for CartPendulum {
    fn derivative_fixed(&self, x: &[f64; 4], u: f64) -> [f64; 4] {
        let mut dx = [0.0; 4];
        self.derivative(0.0, x, &[u], &mut dx);
        dx
    }
}

/// The LQR gain of the upright linearisation, Q = diag(10, 10, 0, 0), R = 1 (the bench's).
fn lqr() -> StaticStateFeedback {
    let sys = CartPendulum::default().linear();
    let q = Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&[10.0, 10.0, 0.0, 0.0]));
    let k = pendulab_lti::design::lqr(&sys, &q, &Mat::identity(1, 1), None)
        .unwrap()
        .gain;
    StaticStateFeedback::new(k).unwrap()
}

fn general(
    controller: StaticStateFeedback,
    options: SampledOptions,
) -> SampledLoop<CartPendulum, StaticStateFeedback> {
    SampledLoop::new(CartPendulum::default(), controller, options).unwrap()
}

/// Both multiply–add paths of the kernel (the FMA-compiled loop where the processor has FMA,
/// the baseline loop forced), for a plant that keeps the provided RK4 step.
const PATHS: [MulAddPath; 2] = [MulAddPath::Fused, MulAddPath::Separate];

#[test]
fn lqr_run_is_bit_identical_to_the_general_loop_for_every_recording_mode() {
    let x0 = [0.0, 15f64.to_radians(), 0.0, 0.0];
    for (record, path) in [Record::EverySample, Record::Every(7), Record::Off]
        .into_iter()
        .flat_map(|r| PATHS.map(|p| (r, p)))
    {
        let opts = SampledOptions {
            record,
            ..Default::default()
        };
        let mut g = general(lqr(), opts);
        let mut f = g.fixed::<4>().unwrap().with_multiply_add(path);
        let a = f.run(&x0).unwrap();
        let b = g.run(&x0).unwrap();
        assert_eq!(a, b, "{record:?}, {path:?}");
        // The run is a real closed-loop run: 10 s at 1 kHz, balanced at the end.
        assert_eq!(a.diagnostics.integration.accepted_steps, 10_000);
        assert!(a.diagnostics.final_state[1].abs() < 1e-6);
        // Recycling the previous result's storage changes nothing.
        let c = f.run_recycling(&x0, &mut (), a.clone()).unwrap();
        assert_eq!(c, a);
    }
    assert_eq!(
        general(lqr(), SampledOptions::default())
            .fixed::<4>()
            .unwrap()
            .samples(),
        10_001
    );
}

#[test]
fn saturated_substepped_shifted_loop_is_bit_identical() {
    // ±1.5 V saturation that clips during the first swing, RK4 at ts/4, a start time that
    // is not a multiple of ts, and a reference offset of the cart.
    let opts = SampledOptions {
        ts: 1e-2,
        t0: 0.3,
        t_final: 6.3,
        integrator: Integrator::Rk4 { dt: 2.5e-3 },
        ..Default::default()
    };
    let k = lqr().with_reference(&[0.2, 0.0, 0.0, 0.0]).unwrap();
    let mut g = general(k, opts)
        .with_actuator(Actuator::ideal().saturation(1.5).unwrap())
        .unwrap();
    let x0 = [0.0, 0.2, 0.1, -0.3];
    let b = g.run(&x0).unwrap();
    for path in PATHS {
        let a = g
            .fixed::<4>()
            .unwrap()
            .with_multiply_add(path)
            .run(&x0)
            .unwrap();
        assert_eq!(a, b, "{path:?}");
    }
    let a = g.fixed::<4>().unwrap().run(&x0).unwrap();
    assert!(a.diagnostics.saturated_samples > 0);
    assert_eq!(a.diagnostics.integration.accepted_steps, 600 * 4);
    // An asymmetric range is carried over as well.
    let mut g = g
        .with_actuator(Actuator::ideal().saturation_range(-0.5, 2.0).unwrap())
        .unwrap();
    let a = g.fixed::<4>().unwrap().run(&x0).unwrap();
    assert_eq!(a, g.run(&x0).unwrap());
    assert!(a.trajectory.u().iter().all(|&v| (-0.5..=2.0).contains(&v)));
}

#[test]
fn monitor_stop_is_bit_identical() {
    // A weak gain loses the pendulum: the run stops at the first sample past 0.5 rad.
    let k = StaticStateFeedback::new(Mat::from_row_slice(1, 4, &[-0.1, -2.0, 0.0, 0.0])).unwrap();
    let mut g = general(k, SampledOptions::default());
    let mut f = g.fixed::<4>().unwrap();
    let x0 = [0.0, 0.2, 0.0, 0.0];
    let mut m1 = StayWithin::new(1, 0.5);
    let mut m2 = StayWithin::new(1, 0.5);
    let a = f.run_with(&x0, &mut m1).unwrap();
    let b = g.run_with(&x0, &mut m2).unwrap();
    assert!(matches!(a.status, RunStatus::Stopped { .. }));
    assert!(!m1.held());
    assert_eq!(a, b);
    assert_eq!(
        a.diagnostics.integration.accepted_steps,
        a.diagnostics.samples - 1
    );
}

/// The LQ integral servo (internal state, a reference signal, its own sample time) on the
/// nonlinear plant: a cart step of 0.1 m at t = 1 s, with each integration rule.
#[test]
fn lq_servo_run_is_bit_identical() {
    let ts = 0.01;
    let (cz, design) = common::cart_lq_servo(&CartPendulum::default());
    for rule in [
        IntegrationRule::ForwardEuler,
        IntegrationRule::BackwardEuler,
        IntegrationRule::Trapezoidal,
    ] {
        let servo = LqIntegralServo::from_design(
            &design,
            cz.c(),
            vec![Signal::step(1.0, 0.1).unwrap()],
            ts,
            rule,
        )
        .unwrap();
        let opts = SampledOptions {
            ts,
            t_final: 15.0,
            integrator: Integrator::Rk4 { dt: ts / 5.0 },
            ..Default::default()
        };
        let mut g = SampledLoop::new(CartPendulum::default(), servo, opts).unwrap();
        let mut f = g.fixed::<4>().unwrap();
        let x0 = [0.0, 0.05, 0.0, 0.0];
        let a = f.run(&x0).unwrap();
        assert_eq!(a, g.run(&x0).unwrap(), "{rule:?}");
        // A second run starts from a reset servo (same result), and the cart has followed
        // the step.
        assert_eq!(f.run(&x0).unwrap(), a);
        assert!((a.diagnostics.final_state[0] - 0.1).abs() < 1e-3);
    }
    // A servo designed for another sample time is refused as by the general loop.
    let servo = LqIntegralServo::from_design(
        &design,
        cz.c(),
        vec![Signal::constant(0.0).unwrap()],
        0.02,
        IntegrationRule::ForwardEuler,
    )
    .unwrap();
    assert!(matches!(
        pendulab_sim::fast::FixedLoop::<_, _, 4>::new(
            CartPendulum::default(),
            servo,
            &SampledOptions::default()
        ),
        Err(SimError::SampleTimeMismatch { .. })
    ));
}

#[test]
fn configurations_the_kernel_does_not_cover_are_refused_with_a_reason() {
    let refused = |r: Result<_, SimError>| match r {
        Err(SimError::InvalidArgument(msg)) => msg,
        Err(e) => panic!("unexpected error {e}"),
        Ok(_) => panic!("accepted"),
    };
    let dopri = general(
        lqr(),
        SampledOptions {
            integrator: Integrator::dopri45(1e-9, 1e-12),
            ..Default::default()
        },
    );
    assert!(refused(dopri.fixed::<4>()).contains("RK4"));
    let delayed = general(
        lqr(),
        SampledOptions {
            delay: Delay::Samples(1),
            ..Default::default()
        },
    );
    assert!(refused(delayed.fixed::<4>()).contains("delay"));
    let dac = general(lqr(), SampledOptions::default())
        .with_actuator(Actuator::rig(5.0, 16).unwrap())
        .unwrap();
    assert!(refused(dac.fixed::<4>()).contains("actuator"));
    let sensor = SensorChain::encoders(&[(0, 1e-6), (1, 1e-3), (2, 1e-6), (3, 1e-3)]).unwrap();
    let encoders = general(lqr(), SampledOptions::default())
        .with_sensor(sensor)
        .unwrap();
    assert!(refused(encoders.fixed::<4>()).contains("sensor"));
    // Bad initial states are refused as by the general loop.
    let mut f = general(lqr(), SampledOptions::default())
        .fixed::<4>()
        .unwrap();
    assert!(matches!(
        f.run(&[0.0, f64::NAN, 0.0, 0.0]),
        Err(SimError::NonFiniteInitialState { index: 1, .. })
    ));
    assert!(matches!(
        f.run(&[0.0; 3]),
        Err(SimError::DimensionMismatch { .. })
    ));
}

/// The multiply–add strategies against closed forms: with `a = 1 + 2⁻³⁰`, `b = 1 − 2⁻³⁰`,
/// `a·b = 1 − 2⁻⁶⁰` exactly, which rounds to 1; so `a·b − 1` is `−2⁻⁶⁰` rounded once (fused)
/// and 0 rounded twice (separate).
#[test]
fn multiply_add_strategies_round_once_and_twice() {
    let (a, b) = (1.0 + 2f64.powi(-30), 1.0 - 2f64.powi(-30));
    assert_eq!(Fused::mul_add(a, b, -1.0), -(2f64.powi(-60)));
    assert_eq!(Separate::mul_add(a, b, -1.0), 0.0);
    assert_eq!(Fused::PATH, MulAddPath::Fused);
    assert_eq!(Separate::PATH, MulAddPath::Separate);
}

/// The path a run takes: the FMA-compiled loop exactly where the processor has FMA (x86-64,
/// detected at run time) unless the baseline loop is forced.
#[test]
fn multiply_add_path_follows_the_processor_unless_forced() {
    let f = general(lqr(), SampledOptions::default())
        .fixed::<4>()
        .unwrap();
    #[cfg(target_arch = "x86_64")]
    let has_fma = std::arch::is_x86_feature_detected!("fma");
    #[cfg(not(target_arch = "x86_64"))]
    let has_fma = false;
    let expected = if has_fma {
        MulAddPath::Fused
    } else {
        MulAddPath::Separate
    };
    assert_eq!(f.multiply_add(), expected);
    let f = f.with_multiply_add(MulAddPath::Separate);
    assert_eq!(f.multiply_add(), MulAddPath::Separate);
    assert_eq!(
        f.with_multiply_add(MulAddPath::Fused).multiply_add(),
        expected
    );
}
