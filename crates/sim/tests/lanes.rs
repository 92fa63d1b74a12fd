//! The lane kernel against the general sampled-data loop (bit-identical with libm's sine and
//! cosine) and the vectorisable sine/cosine against libm.

mod common;

use common::CartPendulum;
use pendulab_lti::Mat;
use pendulab_sim::controllers::StaticStateFeedback;
use pendulab_sim::fast::{
    LaneDynamics, LaneOptions, LibmSinCos, PolySinCos, SinCos, run_feedback_lanes, sin_cos_lanes,
};
use pendulab_sim::{Record, SampledLoop, SampledOptions, SimError, StayWithin};

/// The test cart of `common`, per lane, mirroring its scalar right-hand side operation by
/// operation.
struct Lanes(CartPendulum);

impl<const L: usize> LaneDynamics<4, L> for Lanes {
    fn derivative_lanes<M: SinCos>(&self, x: &[[f64; L]; 4], u: &[f64; L]) -> [[f64; L]; 4] {
        let p = &self.0;
        let (s, c) = M::sin_cos(&x[1]);
        let mut zdd = [0.0; L];
        let mut thdd = [0.0; L];
        for l in 0..L {
            zdd[l] = -p.ac * x[2][l] + p.bc * u[l];
            thdd[l] =
                (p.mp * p.g * p.lp * s[l] - p.mup * x[3][l] - p.mp * p.lp * c[l] * zdd[l]) / p.j();
        }
        [x[2], x[3], zdd, thdd]
    }
}

/// A stabilising gain of the upright cart (the book's cdip_lqr_sim K_q10, u = −K x).
const K: [f64; 4] = [-3.16228, -13.47175, -4.48137, -2.26289];

fn grid(n: usize) -> Vec<[f64; 4]> {
    let mut v = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let th = -1.2 + 2.4 * i as f64 / (n - 1) as f64;
            let w = -3.0 + 6.0 * j as f64 / (n - 1) as f64;
            v.push([0.0, th, 0.0, w]);
        }
    }
    v
}

#[test]
fn lanes_with_libm_are_bit_identical_to_the_general_loop() {
    let plant = CartPendulum::default();
    let x0s = grid(13);
    for (substeps, ts, t_final) in [(1, 1e-3, 3.0), (3, 2e-3, 2.0)] {
        let general = SampledLoop::new(
            plant,
            StaticStateFeedback::new(Mat::from_row_slice(1, 4, &K)).unwrap(),
            SampledOptions {
                ts,
                t_final,
                integrator: pendulab_sim::Integrator::Rk4 {
                    dt: ts / substeps as f64,
                },
                record: Record::Off,
                ..Default::default()
            },
        )
        .unwrap();
        let o = LaneOptions {
            ts,
            t_final,
            substeps,
            stay_within: Some((1, std::f64::consts::FRAC_PI_2)),
        };
        let lanes = run_feedback_lanes::<_, LibmSinCos, 4, 4>(&Lanes(plant), &K, &o, &x0s).unwrap();
        // An odd lane count and a queue that does not fill the last group.
        let lanes3 =
            run_feedback_lanes::<_, LibmSinCos, 4, 3>(&Lanes(plant), &K, &o, &x0s[..50]).unwrap();
        assert_eq!(lanes[..50], lanes3[..]);
        let (mut held, mut fell) = (0, 0);
        for (i, x0) in x0s.iter().enumerate() {
            let mut m = StayWithin::new(1, std::f64::consts::FRAC_PI_2);
            let r = general.clone().run_with(x0, &mut m).unwrap();
            assert_eq!(lanes[i].held, m.held(), "run {i}");
            assert_eq!(
                lanes[i].steps, r.diagnostics.integration.accepted_steps,
                "run {i}"
            );
            assert_eq!(
                lanes[i].final_state[..],
                r.diagnostics.final_state[..],
                "run {i}"
            );
            if m.held() { held += 1 } else { fell += 1 }
        }
        // The grid has both kinds of runs, so both paths are exercised.
        assert!(held > 10 && fell > 10, "{held} held, {fell} fell");
        // The vectorisable sine/cosine: same outcomes on this grid, states within rounding
        // amplified by the closed loop (the stable runs contract; 1e-9 leaves a wide margin
        // over the ~1e-15 per-step differences).
        let poly = run_feedback_lanes::<_, PolySinCos, 4, 4>(&Lanes(plant), &K, &o, &x0s).unwrap();
        for (a, b) in lanes.iter().zip(&poly) {
            assert_eq!((a.held, a.steps), (b.held, b.steps));
            for j in 0..4 {
                assert!((a.final_state[j] - b.final_state[j]).abs() <= 1e-9);
            }
        }
    }
}

#[test]
fn sin_cos_lanes_is_within_two_ulp_of_libm() {
    // Reference: the platform libm (glibc's sin/cos are within 1 ulp). Points: a dense sweep
    // of [−20, 20], the quadrant boundaries k·π/4 and their neighbours, tiny and large values;
    // beyond 1e5 the function falls back to libm itself.
    let mut xs: Vec<f64> = (0..=400_000).map(|i| -20.0 + 1e-4 * i as f64).collect();
    for k in -64..=64 {
        let b = k as f64 * std::f64::consts::FRAC_PI_4;
        xs.extend([b, b.next_up(), b.next_down()]);
    }
    xs.extend([
        0.0, -0.0, 1e-300, -1e-12, 1e-8, 12345.678, -99999.0, 3e5, 1e300,
    ]);
    let ulp = |v: f64| (v.abs().next_up() - v.abs()).max(f64::MIN_POSITIVE);
    let mut worst: f64 = 0.0;
    for ch in xs.chunks(4) {
        let mut a = [0.0; 4];
        a[..ch.len()].copy_from_slice(ch);
        let (s, c) = sin_cos_lanes(&a);
        for l in 0..ch.len() {
            let (rs, rc) = a[l].sin_cos();
            // 2 ulp of the result, plus 4e-17·max(1, |x|) absolute: near the zeros of sin and
            // cos the result is the reduced argument r = x − n·π/2 itself, whose rounding
            // (a fraction of ulp(1) ≈ 2.2e-16 for |x| of order 1, growing with |x|)
            // dominates the relative error.
            let tol_s = 2.0 * ulp(rs) + 4e-17 * a[l].abs().max(1.0);
            let tol_c = 2.0 * ulp(rc) + 4e-17 * a[l].abs().max(1.0);
            assert!(
                (s[l] - rs).abs() <= tol_s,
                "sin({}) = {} vs {}",
                a[l],
                s[l],
                rs
            );
            assert!(
                (c[l] - rc).abs() <= tol_c,
                "cos({}) = {} vs {}",
                a[l],
                c[l],
                rc
            );
            worst = worst
                .max((s[l] - rs).abs() / ulp(rs))
                .max((c[l] - rc).abs() / ulp(rc));
        }
    }
    // Non-finite input gives NaN like libm.
    let (s, c) = sin_cos_lanes(&[f64::NAN, f64::INFINITY]);
    assert!(s.iter().chain(&c).all(|v| v.is_nan()));
    assert!(
        worst > 0.0,
        "a polynomial that agreed bit for bit everywhere would be suspect"
    );
}

#[test]
fn bad_lane_options_are_typed_errors() {
    let p = Lanes(CartPendulum::default());
    let o = LaneOptions {
        ts: 1e-3,
        t_final: 1.0,
        substeps: 1,
        stay_within: None,
    };
    let run = |o: LaneOptions, x0: [f64; 4]| {
        run_feedback_lanes::<_, LibmSinCos, 4, 2>(&p, &K, &o, &[x0]).map(|_| ())
    };
    assert!(matches!(
        run(LaneOptions { ts: 0.0, ..o }, [0.0; 4]),
        Err(SimError::InvalidSampleTime(_))
    ));
    assert!(matches!(
        run(LaneOptions { ts: -1e-3, ..o }, [0.0; 4]),
        Err(SimError::InvalidSampleTime(_))
    ));
    assert!(matches!(
        run(LaneOptions { t_final: 1e-4, ..o }, [0.0; 4]),
        Err(SimError::InvalidTimeSpan { .. })
    ));
    assert!(matches!(
        run(LaneOptions { substeps: 0, ..o }, [0.0; 4]),
        Err(SimError::InvalidParameter { .. })
    ));
    assert!(matches!(
        run(
            LaneOptions {
                stay_within: Some((4, 1.0)),
                ..o
            },
            [0.0; 4]
        ),
        Err(SimError::InvalidArgument(_))
    ));
    assert!(matches!(
        run(o, [0.0, f64::NAN, 0.0, 0.0]),
        Err(SimError::NonFiniteInitialState { index: 1, .. })
    ));
    assert!(matches!(
        run_feedback_lanes::<_, LibmSinCos, 4, 2>(&p, &[f64::NAN, 0.0, 0.0, 0.0], &o, &[[0.0; 4]]),
        Err(SimError::InvalidParameter { .. })
    ));
}
