//! Bad input to the ready syntheses is a typed error naming the problem, never a panic or
//! a hang; an unstabilisable plant is a status, not an error.

mod common;

use pendulab_lmi::synthesis::{
    GainScheduleSpec, LpvPlant, LqWeights, Region, StateFeedbackSpec, Vertex, alpha_stability,
    gain_scheduled_lq, lq_state_feedback, state_feedback,
};
use pendulab_lmi::{LmiError, SolveOptions};
use pendulab_lti::Mat;

#[test]
fn bad_data_are_typed_errors() {
    let (a, b) = common::arm(common::A1, common::B1, 0.0);
    let q = Mat::identity(4, 4);
    let r = Mat::identity(1, 1);
    let o = SolveOptions::default();
    let nan_q = Mat::from_element(4, 4, f64::NAN);
    assert!(matches!(
        lq_state_feedback(&a, &b, &nan_q, &r, &o),
        Err(LmiError::NonFinite { .. })
    ));
    assert!(matches!(
        lq_state_feedback(&a, &b, &q, &Mat::from_element(1, 1, -1.0), &o),
        Err(LmiError::InvalidArgument { .. })
    ));
    assert!(matches!(
        lq_state_feedback(&a, &Mat::zeros(3, 1), &q, &r, &o),
        Err(LmiError::ShapeMismatch { .. })
    ));
    let not_psd = Mat::from_diagonal(&pendulab_lti::Vector::from_vec(vec![1.0, -1.0, 1.0, 1.0]));
    assert!(matches!(
        lq_state_feedback(&a, &b, &not_psd, &r, &o),
        Err(LmiError::InvalidArgument { .. })
    ));
    let spec = StateFeedbackSpec {
        regions: vec![Region::Sector { theta: 2.0 }],
        ..StateFeedbackSpec::default()
    };
    assert!(matches!(
        state_feedback(
            &[Vertex {
                a: a.clone(),
                b: b.clone()
            }],
            &spec,
            &o
        ),
        Err(LmiError::InvalidArgument { .. })
    ));
    assert!(matches!(
        state_feedback(&[], &StateFeedbackSpec::default(), &o),
        Err(LmiError::InvalidArgument { .. })
    ));
    assert!(matches!(
        alpha_stability(&Mat::zeros(2, 3), 1.0, 1e-6, &o),
        Err(LmiError::NotSquare { .. })
    ));
    let (a0, a1, b0, b1) = common::lpv_servo();
    let (qs, rs) = common::servo_weights();
    let spec = GainScheduleSpec {
        rho_range: (0.5, 0.1),
        rho0_range: (0.0, 0.5),
        rho_dot_bound: 0.75,
        lq: LqWeights { q: qs, r: rs },
        margin: 1e-6,
        gamma_relax: 0.06,
        balance: true,
    };
    assert!(matches!(
        gain_scheduled_lq(&LpvPlant { a0, a1, b0, b1 }, &spec, &o),
        Err(LmiError::InvalidArgument { .. })
    ));
}

/// B = 0 with an unstable A: no stabilising gain exists; the design reports it through its
/// status and returns no gain.
#[test]
fn an_unstabilisable_plant_is_reported_not_an_error() {
    let (a, _) = common::arm(common::A1, common::B1, 0.0);
    let d = lq_state_feedback(
        &a,
        &Mat::zeros(4, 1),
        &Mat::identity(4, 4),
        &Mat::identity(1, 1),
        &SolveOptions::default(),
    )
    .unwrap();
    assert!(d.feedback.is_none());
    assert!(!d.status.is_solved(), "{:?}", d.status);
}
