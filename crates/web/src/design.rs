//! Designs on a plant's upright linearisation: LQR (`n = 4`), the LQ integral servo (`n = 5`)
//! and pole placement, each giving the gain, the closed-loop poles and the controller spec that
//! runs the gain (`pendulab_control::spec`).
//!
//! The linearisation is the plant spec's own (`PlantParameters::linearize_upright`, the arm at
//! `θ₁ₑ = 0`; `docs/model.md` §1–2); the designs are `pendulab_lti::design::{lqr, lq_servo,
//! place}`, whose sign convention is the library's `u = −K x` (`docs/model.md` §4). The gain is
//! handed to the controller spec as `k` (or `k1`, `k2`) with the design record
//! (`designed_for`, `pendulab_control::spec::DesignRecord`), so the controller that runs in the
//! lab, in a response and in an exported controller file is the gain shown.

use crate::error::WebError;
use pendulab_control::spec::{
    ControllerSpec, DesignInput, DesignRecord, GainSpec, LqServoSpec, StateFeedbackSpec,
    SwingUpBalanceSpec,
};
use pendulab_lti::design::{lq_servo, lqr, place};
use pendulab_lti::linalg::Complex64;
use pendulab_lti::{Continuous, Mat, StateSpace};
use pendulab_plants::spec::PlantSpec;

/// The state count of both rigs' models, `[q₀, q₁, q̇₀, q̇₁]`.
pub const NX: usize = 4;

/// What to design.
#[derive(Debug, Clone, PartialEq)]
pub enum Method {
    /// LQR on `[q₀, q₁, q̇₀, q̇₁]`: `Q = diag(q)` (4 entries, finite, ≥ 0), `R = r` (> 0)
    /// \[1/V²\]; the continuous-time cost `∫ xᵀQx + R u² dt`.
    Lqr {
        /// Diagonal of `Q`.
        q: Vec<f64>,
        /// `R`.
        r: f64,
    },
    /// The LQ integral servo on `q₀` (book part 1 §6.3): LQR on `[x; w]`, `w = ∫(r − q₀) dt`,
    /// `Q = diag(q)` (5 entries), `R = r`.
    Servo {
        /// Diagonal of `Q` on `[x; w]`.
        q: Vec<f64>,
        /// `R`.
        r: f64,
    },
    /// Pole placement: `eig(A − BK)` = `poles` (4, complex ones with their conjugates) \[1/s\].
    Place {
        /// The closed-loop poles.
        poles: Vec<Complex64>,
    },
}

/// A design's result.
#[derive(Debug, Clone, PartialEq)]
pub struct Design {
    /// What was designed.
    pub method: Method,
    /// The gain in library sign (`u = −K x`): `K` (4 entries) or, for the servo, `[K₁, K₂]`
    /// (5 entries, `u = −K₁ x − K₂ w`) \[V per unit of each state\].
    pub gain: Vec<f64>,
    /// The closed-loop poles (4, or 5 for the servo) \[1/s\].
    pub poles: Vec<Complex64>,
    /// The open-loop poles, `eig(A)` \[1/s\].
    pub open_loop: Vec<Complex64>,
    /// The design record the controller spec carries (`designed_for`: the plant's kind,
    /// parameters and provenance, the upright operating point, the method and its inputs),
    /// which `pendulab rig run` and `simulate` check against the plant they run on.
    pub record: DesignRecord,
    /// The linearisation's `A` (4 × 4).
    pub a: Mat,
    /// The linearisation's `B` (4 × 1).
    pub b: Mat,
}

/// Which controller runs a design's gain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// The design's own: state feedback (LQR, placement) or the servo.
    Balance,
    /// Energy swing-up from the hanging rest, then the state-feedback gain
    /// (`swing-up-balance`; book part 2 §3.2). Not for the servo's gain.
    SwingUp,
}

/// The upright linearisation of `plant` (`C = I`).
///
/// # Errors
/// [`WebError::Plant`] when the model refuses the parameters.
pub fn linearization(plant: &PlantSpec) -> Result<StateSpace<Continuous>, WebError> {
    Ok(plant.parameters().linearize_upright(0.0)?)
}

fn check_weights(q: &[f64], n: usize, r: f64) -> Result<(), WebError> {
    if q.len() != n {
        return Err(WebError::Length {
            what: "q",
            got: q.len(),
            expected: n,
        });
    }
    if let Some(&v) = q.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
        return Err(WebError::OutOfRange {
            what: "q",
            value: v,
            range: "finite and ≥ 0",
        });
    }
    if !(r.is_finite() && r > 0.0) {
        return Err(WebError::OutOfRange {
            what: "r",
            value: r,
            range: "finite and > 0",
        });
    }
    Ok(())
}

/// Designs `method` on `plant`'s upright linearisation (module documentation).
///
/// # Errors
/// [`WebError::Length`]/[`WebError::OutOfRange`] for weights of the wrong length, a negative
/// or non-finite `q`, `r ≤ 0`; [`WebError::Design`] when the design fails (no stabilising
/// Riccati solution, poles without their conjugates); [`WebError::Plant`].
pub fn design(plant: &PlantSpec, method: &Method) -> Result<Design, WebError> {
    let sys = linearization(plant)?;
    let (a, b) = (sys.a().clone(), sys.b().clone());
    let (gain, poles) = match method {
        Method::Lqr { q, r } => {
            check_weights(q, NX, *r)?;
            let d = lqr(&sys, &diag(q), &Mat::from_element(1, 1, *r), None)?;
            (d.gain.iter().copied().collect(), d.closed_loop_poles)
        }
        Method::Servo { q, r } => {
            check_weights(q, NX + 1, *r)?;
            let c = Mat::from_row_slice(1, NX, &[1.0, 0.0, 0.0, 0.0]);
            let on_q0 = StateSpace::continuous(a.clone(), b.clone(), c, Mat::zeros(1, 1))?;
            let d = lq_servo(&on_q0, &diag(q), &Mat::from_element(1, 1, *r))?;
            (
                d.lqr.gain.iter().copied().collect(),
                d.lqr.closed_loop_poles,
            )
        }
        Method::Place { poles } => {
            if poles.len() != NX {
                return Err(WebError::Length {
                    what: "poles",
                    got: poles.len(),
                    expected: NX,
                });
            }
            let d = place(&a, &b, poles)?;
            (d.gain.iter().copied().collect(), d.achieved_poles)
        }
    };
    let (name, inputs) = match method {
        Method::Lqr { q, r } => ("lqr", weights(q, *r)),
        Method::Servo { q, r } => ("lq-servo", weights(q, *r)),
        Method::Place { poles } => (
            "place",
            [(
                "poles".to_string(),
                DesignInput::Rows(poles.iter().map(|p| vec![p.re, p.im]).collect()),
            )]
            .into(),
        ),
    };
    Ok(Design {
        record: DesignRecord::new(plant, vec![0.0; NX], None, name, inputs),
        method: method.clone(),
        gain,
        poles,
        open_loop: sys.poles()?,
        a,
        b,
    })
}

fn weights(q: &[f64], r: f64) -> std::collections::BTreeMap<String, DesignInput> {
    [
        ("q".to_string(), DesignInput::List(q.to_vec())),
        ("r".to_string(), DesignInput::Number(r)),
    ]
    .into()
}

fn diag(q: &[f64]) -> Mat {
    Mat::from_diagonal(&nalgebra::DVector::from_row_slice(q))
}

impl Design {
    /// Whether the gain is the servo's `[K₁, K₂]`.
    pub fn is_servo(&self) -> bool {
        matches!(self.method, Method::Servo { .. })
    }

    /// The controller spec that runs this gain in `mode`, tracking the drive-position
    /// reference `reference` \[m or rad\] (state feedback: `[r, 0, 0, 0]`; the servo: `r` from
    /// `step_time` \[s\] on; none for the swing-up, which balances at `q₀ = 0`). A servo gain
    /// in [`Mode::SwingUp`] runs as the servo.
    pub fn controller(&self, mode: Mode, reference: f64, step_time: f64) -> ControllerSpec {
        let k = || Some(self.gain[..NX].to_vec());
        let nonzero = |v: Vec<f64>| (reference != 0.0).then_some(v);
        if self.is_servo() {
            return ControllerSpec::LqServo(LqServoSpec {
                k1: k(),
                k2: Some(self.gain[NX]),
                reference: nonzero(vec![reference]),
                step_time: (reference != 0.0 && step_time > 0.0).then_some(step_time),
                designed_for: Some(self.record.clone()),
                ..Default::default()
            });
        }
        match mode {
            Mode::Balance => ControllerSpec::StateFeedback(StateFeedbackSpec {
                k: k(),
                reference: nonzero(vec![reference, 0.0, 0.0, 0.0]),
                designed_for: Some(self.record.clone()),
                ..Default::default()
            }),
            Mode::SwingUp => ControllerSpec::SwingUpBalance(SwingUpBalanceSpec {
                balance: Some(GainSpec {
                    k: k(),
                    ..Default::default()
                }),
                designed_for: Some(self.record.clone()),
                ..Default::default()
            }),
        }
    }
}
