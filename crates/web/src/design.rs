//! Designs on a plant's upright linearisation: LQR (`n = 4`), the LQ integral servo (`n = 5`),
//! pole placement and the LMI guaranteed-cost LQ design with a decay-rate pole region (`n = 4`
//! or the servo's 5), each giving the gain, the closed-loop poles and the controller spec that
//! runs the gain (`pendulab_control::spec`).
//!
//! The LMI design is `pendulab_lmi::synthesis::state_feedback` solved by pendulab-lmi's dense
//! interior-point method ([`pendulab_lmi::Backend::Dense`]): the browser's build of
//! pendulab-lmi has no Clarabel (`docs/web.md`, "LMIs in the browser"). Its certificate (the
//! solver's status, the recheck of every LMI on the returned `X`, `L`) comes with the gain
//! ([`LmiCertificate`]).
//!
//! The linearisation is the plant spec's own (`PlantParameters::linearize_upright`, the arm at
//! `θ₁ₑ = 0`; `docs/model.md` §1–2). The LQR and the servo (LQR on the augmentation of
//! `pendulab_lti::design::integral_augmentation`) are solved by
//! `pendulab_lti::equations::riccati::care_compact`, and a slider move from the last design's
//! poles by `pendulab_lti::design::SymmetricRootLocus` when it certifies its answer
//! ([`Designer::design_from`]); placement by `pendulab_lti::design::place`;
//! the sign convention is the library's `u = −K x` (`docs/model.md` §4). The gain is
//! handed to the controller spec as `k` (or `k1`, `k2`) with the design record
//! (`designed_for`, `pendulab_control::spec::DesignRecord`), so the controller that runs in the
//! lab, in a response and in an exported controller file is the gain shown.

use crate::error::WebError;
use pendulab_control::spec::design::{
    drive_servo_model, place_upright, pole_inputs, weight_inputs,
};
use pendulab_control::spec::{
    ControllerSpec, DesignInput, DesignRecord, GainSpec, LqServoSpec, StateFeedbackSpec,
    SwingUpBalanceSpec,
};
use pendulab_lmi::synthesis::{LqWeights, Region, StateFeedbackSpec as LmiSpec, Vertex};
use pendulab_lmi::{Backend, SolveOptions, Status};
use pendulab_lti::design::{SymmetricRootLocus, integral_augmentation};
use pendulab_lti::equations::riccati::{care_compact, care_compact_from};
use pendulab_lti::linalg::Complex64;
use pendulab_lti::{Continuous, Mat, StateSpace};
use pendulab_plants::spec::PlantSpec;
use std::rc::Rc;

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
    /// The LMI guaranteed-cost LQ design (book part 2 §1.2) with a decay-rate region: find
    /// `X ≻ 0`, `L` maximising `tr X` subject to the LQ cost LMI (`Q = diag(q)`, `R = r`) and,
    /// for `alpha > 0`, `He(AX + BL) + 2αX ≺ 0` (every closed-loop pole left of `−α`,
    /// Chilali–Gahinet); `K = −L X⁻¹`. With 4 weights on `[q₀, q₁, q̇₀, q̇₁]` the regulator,
    /// with 5 the integral servo on `[x; w]`, `w = ∫(r − q₀) dt` (the augmentation of
    /// [`Method::Servo`]; book part 2 §1.2.2, `p2c122_ex4`).
    Lmi {
        /// Diagonal of `Q` (4 or 5 entries, finite, ≥ 0).
        q: Vec<f64>,
        /// `R` (> 0) \[1/V²\].
        r: f64,
        /// The decay rate `α` \[1/s\] (finite, ≥ 0; 0 imposes no region).
        alpha: f64,
    },
}

/// What certifies an LMI design: the status of pendulab-lmi's dense interior-point method and
/// the recheck of every constraint on the returned `X`, `L` (`pendulab_lmi::Solution`).
#[derive(Debug, Clone, PartialEq)]
pub struct LmiCertificate {
    /// The solver's status of the final solve (`Solved`, `AlmostSolved`).
    pub status: Status,
    /// Interior-point iterations, over the optimisation and the feasibility re-solve if one
    /// was run.
    pub iterations: u32,
    /// The rechecked constraints (`X ≻ 0`, the LQ cost LMI, the region).
    pub constraints: usize,
    /// The smallest `value − margin` over the rechecked constraints (≥ −tolerance when they
    /// hold; for `F ≺ 0` with margin `ε`, the smallest eigenvalue of `−F` minus `ε`).
    pub min_slack: f64,
    /// `tr X` of the final solve (the objective maximised).
    pub trace_x: f64,
    /// Whether every closed-loop pole lies left of `−α` (checked on `eig(A − BK)`).
    pub poles_in_region: bool,
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
    /// What every design of one [`Designer`] shares (the plant's part of the design record,
    /// the linearisation, its poles): a slider move copies none of it.
    plant: Rc<PlantPart>,
    /// The certificate of an LMI design ([`Method::Lmi`]); `None` for the others.
    pub lmi: Option<LmiCertificate>,
}

/// The part of a design that depends only on the plant ([`Designer`]).
#[derive(Debug, PartialEq)]
struct PlantPart {
    /// The plant's part of the design record (kind, parameters, provenance, operating
    /// point); [`Design::record`] completes it.
    record: DesignRecord,
    /// The upright linearisation's `A` (4 × 4) and `B` (4 × 1).
    a: Mat,
    b: Mat,
    /// `eig(A)`.
    open_loop: Vec<Complex64>,
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
/// or non-finite `q`, `r ≤ 0`, a negative `alpha`; [`WebError::Design`] when the design fails
/// (no stabilising Riccati solution, poles without their conjugates); [`WebError::Lmi`] when
/// the LMIs are not solved (infeasible for this `α`, or the solver's rechecks fail);
/// [`WebError::Plant`].
pub fn design(plant: &PlantSpec, method: &Method) -> Result<Design, WebError> {
    Designer::new(plant)?.design(method)
}

/// What every design on one plant shares, computed once per plant (the page redesigns on
/// every slider move): the upright linearisation, its open-loop poles, and the design record
/// of the plant (kind, parameters, provenance) that each design completes with its method and
/// inputs.
#[derive(Debug, Clone)]
pub struct Designer {
    sys: StateSpace<Continuous>,
    plant: Rc<PlantPart>,
    /// `A`, `B` (row-major) of the regulator (`n = 4`) and of the servo's augmentation on
    /// `[x; w]` (`n = 5`), for the compact Riccati solver of the slider moves.
    lqr_ab: ([f64; NX * NX], [f64; NX]),
    servo_ab: ([f64; (NX + 1) * (NX + 1)], [f64; NX + 1]),
    /// The symmetric root locus of each (`None` when `(A, B)` is not controllable enough
    /// for it; the Riccati path answers every move then).
    lqr_srl: Option<SymmetricRootLocus>,
    servo_srl: Option<SymmetricRootLocus>,
}

impl Designer {
    /// The shared part of the designs on `plant`.
    ///
    /// # Errors
    /// [`WebError::Plant`] when the model refuses the parameters; [`WebError::Design`] when
    /// the linearisation's eigenvalues cannot be computed.
    pub fn new(plant: &PlantSpec) -> Result<Self, WebError> {
        let sys = linearization(plant)?;
        let (a5, b5) = integral_augmentation(&drive_servo_model(&sys)?)?;
        let mut lqr_ab = ([0.0; NX * NX], [0.0; NX]);
        let mut servo_ab = ([0.0; (NX + 1) * (NX + 1)], [0.0; NX + 1]);
        for i in 0..NX {
            for j in 0..NX {
                lqr_ab.0[NX * i + j] = sys.a()[(i, j)];
            }
            lqr_ab.1[i] = sys.b()[(i, 0)];
        }
        for i in 0..=NX {
            for j in 0..=NX {
                servo_ab.0[(NX + 1) * i + j] = a5[(i, j)];
            }
            servo_ab.1[i] = b5[(i, 0)];
        }
        Ok(Self {
            plant: Rc::new(PlantPart {
                record: DesignRecord::new(plant, vec![0.0; NX], None, "", Default::default()),
                a: sys.a().clone(),
                b: sys.b().clone(),
                open_loop: sys.poles()?,
            }),
            sys,
            lqr_srl: SymmetricRootLocus::new(&lqr_ab.0, &lqr_ab.1, NX).ok(),
            servo_srl: SymmetricRootLocus::new(&servo_ab.0, &servo_ab.1, NX + 1).ok(),
            lqr_ab,
            servo_ab,
        })
    }

    /// [`design`] on this plant.
    ///
    /// # Errors
    /// As [`design`].
    pub fn design(&self, method: &Method) -> Result<Design, WebError> {
        self.design_from(method.clone(), None)
    }

    /// [`Designer::design`] after `previous` (the design a slider move replaces): an LQR or
    /// servo design whose previous design was of the same kind on this designer's plant is
    /// solved from it — first by the symmetric root locus from the previous closed-loop poles
    /// (`pendulab_lti::design::SymmetricRootLocus`: a few hundred flops, answered only with a
    /// forward error bound below `SRL_TOLERANCE`), else by the Riccati solve from the previous
    /// gain (`pendulab_lti::equations::riccati::care_compact_from`: a few small Lyapunov
    /// solves instead of the sign function; the cold path whenever the warm one is refused).
    /// Every path gives the same gain to the tolerance of `pendulab lqr`'s.
    ///
    /// # Errors
    /// As [`design`].
    pub fn design_from(
        &self,
        method: Method,
        previous: Option<&Design>,
    ) -> Result<Design, WebError> {
        // The previous design of the same kind and plant (`Design::plant` is this designer's).
        let start = |n: usize| {
            previous.filter(|p| {
                Rc::ptr_eq(&p.plant, &self.plant)
                    && p.gain.len() == n
                    && p.poles.len() == n
                    && matches!(p.method, Method::Lqr { .. } | Method::Servo { .. })
            })
        };
        // LQR on (A, B) with weights already checked ([`check_weights`]).
        let lq = |ab: (&[f64], &[f64]), srl: &Option<SymmetricRootLocus>, q: &[f64], r: f64| {
            let from = start(q.len());
            if let (Some(srl), Some(p)) = (srl, from)
                && let Some(s) = srl.solve(q, r, &p.poles)?
            {
                return Ok((s.gain().to_vec(), s.poles().to_vec()));
            }
            lq_compact(ab.0, ab.1, q, r, from.map(|p| p.gain.as_slice()))
        };
        let sys = &self.sys;
        let mut lmi = None;
        let (gain, poles) = match &method {
            Method::Lmi { q, r, alpha } => {
                let (gain, poles, cert) = lmi_design(sys, q, *r, *alpha)?;
                lmi = Some(cert);
                (gain, poles)
            }
            Method::Lqr { q, r } => {
                check_weights(q, NX, *r)?;
                lq((&self.lqr_ab.0, &self.lqr_ab.1), &self.lqr_srl, q, *r)?
            }
            Method::Servo { q, r } => {
                check_weights(q, NX + 1, *r)?;
                lq((&self.servo_ab.0, &self.servo_ab.1), &self.servo_srl, q, *r)?
            }
            Method::Place { poles } => {
                if poles.len() != NX {
                    return Err(WebError::Length {
                        what: "poles",
                        got: poles.len(),
                        expected: NX,
                    });
                }
                let d = place_upright(sys, poles)?;
                (d.gain.iter().copied().collect(), d.poles)
            }
        };
        Ok(Design {
            plant: Rc::clone(&self.plant),
            method,
            gain,
            poles,
            lmi,
        })
    }
}

/// [`Method::Lmi`] on the linearisation `sys` (`C = I`): the gain (4 or 5 entries), its
/// closed-loop poles and the certificate.
fn lmi_design(
    sys: &StateSpace<Continuous>,
    q: &[f64],
    r: f64,
    alpha: f64,
) -> Result<(Vec<f64>, Vec<Complex64>, LmiCertificate), WebError> {
    let n = if q.len() == NX + 1 { NX + 1 } else { NX };
    check_weights(q, n, r)?;
    if !(alpha.is_finite() && alpha >= 0.0) {
        return Err(WebError::OutOfRange {
            what: "alpha",
            value: alpha,
            range: "finite and ≥ 0 [1/s]",
        });
    }
    let (a, b) = if n == NX {
        (sys.a().clone(), sys.b().clone())
    } else {
        integral_augmentation(&drive_servo_model(sys)?)?
    };
    let spec = LmiSpec {
        lq: Some(LqWeights {
            q: diag(q),
            r: Mat::from_element(1, 1, r),
        }),
        regions: if alpha > 0.0 {
            vec![Region::DecayRate { alpha }]
        } else {
            Vec::new()
        },
        ..LmiSpec::default()
    };
    let options = SolveOptions {
        backend: Backend::Dense,
        ..SolveOptions::default()
    };
    let d = pendulab_lmi::synthesis::state_feedback(&[Vertex { a, b }], &spec, &options)?;
    let last = d.refined.as_ref().unwrap_or(&d.solution);
    let Some(f) = d.feedback else {
        return Err(WebError::Lmi(match &d.status {
            Status::Infeasible { certificate, .. } => format!(
                "the LMIs are infeasible for Q = diag({q:?}), R = {r}, α = {alpha} 1/s (Farkas certificate, stationarity residual {:.1e})",
                certificate.stationarity_residual
            ),
            s if s.is_solved() => format!(
                "the solution for α = {alpha} 1/s fails its recheck ({} of {} constraints hold)",
                last.checks.iter().filter(|c| c.satisfied).count(),
                last.checks.len()
            ),
            s => format!("not solved for α = {alpha} 1/s: {s:?}"),
        }));
    };
    let cert = LmiCertificate {
        status: d.status.clone(),
        iterations: d.solution.iterations + d.refined.as_ref().map_or(0, |s| s.iterations),
        constraints: last.checks.len(),
        min_slack: last
            .checks
            .iter()
            .map(|c| c.value - c.margin)
            .fold(f64::INFINITY, f64::min),
        trace_x: f.x.trace(),
        poles_in_region: f.poles_in_regions,
    };
    let poles = f.closed_loop_poles.into_iter().next().unwrap_or_default();
    Ok((f.gain.iter().copied().collect(), poles, cert))
}

/// LQR on `(A, B)` (`n × n`, `n × 1`, row-major; `n` = 4, or 5 for the servo's augmentation)
/// with `Q = diag(q)`, `R = r`: the gain and the closed-loop poles by
/// `pendulab_lti::equations::riccati::care_compact` — the same stabilising solution as
/// `pendulab_lti::design::lqr` (the general solver answers whatever the compact path refuses),
/// with a fraction of the code run, which is what a slider move's time depends on
/// (`docs/web.md`, "Redesign time"); from the gain `k0` when given
/// (`care_compact_from`). The weights are checked by [`check_weights`] (a diagonal `Q ⪰ 0`,
/// `R > 0`: LQ weights).
fn lq_compact(
    a: &[f64],
    b: &[f64],
    q: &[f64],
    r: f64,
    k0: Option<&[f64]>,
) -> Result<(Vec<f64>, Vec<Complex64>), WebError> {
    let n = q.len();
    let mut qm = [0.0; (NX + 1) * (NX + 1)];
    for (i, v) in q.iter().enumerate() {
        qm[n * i + i] = *v;
    }
    let sol = match k0 {
        Some(k0) => care_compact_from(a, b, &qm[..n * n], &[r], n, k0)?,
        None => care_compact(a, b, &qm[..n * n], &[r], n)?,
    };
    Ok((sol.gain().to_vec(), sol.poles().to_vec()))
}

fn diag(q: &[f64]) -> Mat {
    Mat::from_diagonal(&nalgebra::DVector::from_row_slice(q))
}

impl Design {
    /// The design record the controller spec carries (`designed_for`: the plant's kind,
    /// parameters and provenance, the upright operating point, the method and its inputs),
    /// which `pendulab rig run` and `simulate` check against the plant they run on. Built on
    /// demand from the plant's part (shared by the designs of one [`Designer`]) and the
    /// method: a slider move copies no record.
    pub fn record(&self) -> DesignRecord {
        let mut record = self.plant.record.clone();
        let (name, inputs) = match &self.method {
            Method::Lqr { q, r } => ("lqr", weight_inputs(q, *r)),
            Method::Servo { q, r } => (
                pendulab_control::spec::design::SERVO_METHOD,
                weight_inputs(q, *r),
            ),
            Method::Place { poles } => ("place", pole_inputs(poles)),
            Method::Lmi { q, r, alpha } => {
                let mut w = weight_inputs(q, *r);
                w.insert("decay_rate".into(), DesignInput::Number(*alpha));
                (if q.len() == NX { "lmi-lq" } else { "lmi-servo" }, w)
            }
        };
        record.method = name.to_string();
        record.inputs = inputs;
        record
    }

    /// The linearisation's `A` (4 × 4).
    pub fn a(&self) -> &Mat {
        &self.plant.a
    }

    /// The linearisation's `B` (4 × 1).
    pub fn b(&self) -> &Mat {
        &self.plant.b
    }

    /// The open-loop poles, `eig(A)` \[1/s\].
    pub fn open_loop(&self) -> &[Complex64] {
        &self.plant.open_loop
    }

    /// Whether two designs share the plant part of their records (designed by one
    /// [`Designer`], hence on one plant).
    pub fn same_plant_record(&self, other: &Design) -> bool {
        Rc::ptr_eq(&self.plant, &other.plant)
    }

    /// Whether the gain is the servo's `[K₁, K₂]` (5 entries).
    pub fn is_servo(&self) -> bool {
        self.gain.len() == NX + 1
    }

    /// The controller spec that runs this gain in `mode`, tracking the drive-position
    /// reference `reference` \[m or rad\] (state feedback: `[r, 0, 0, 0]`; the servo: `r` from
    /// `step_time` \[s\] on; none for the swing-up, which balances at `q₀ = 0`). A servo gain
    /// in [`Mode::SwingUp`] runs as the servo.
    pub fn controller(&self, mode: Mode, reference: f64, step_time: f64) -> ControllerSpec {
        self.controller_with(mode, reference, step_time, Some(self.record()))
    }

    /// [`Design::controller`] carrying `record` as its design record (`None`: none, so the
    /// factory checks nothing of the plant — for a design whose record was already checked
    /// against the plant it runs on).
    pub fn controller_with(
        &self,
        mode: Mode,
        reference: f64,
        step_time: f64,
        record: Option<DesignRecord>,
    ) -> ControllerSpec {
        let k = || Some(self.gain[..NX].to_vec());
        let nonzero = |v: Vec<f64>| (reference != 0.0).then_some(v);
        if self.is_servo() {
            return ControllerSpec::LqServo(LqServoSpec {
                k1: k(),
                k2: Some(self.gain[NX]),
                reference: nonzero(vec![reference]),
                step_time: (reference != 0.0 && step_time > 0.0).then_some(step_time),
                designed_for: record,
                ..Default::default()
            });
        }
        match mode {
            Mode::Balance => ControllerSpec::StateFeedback(StateFeedbackSpec {
                k: k(),
                reference: nonzero(vec![reference, 0.0, 0.0, 0.0]),
                designed_for: record,
                ..Default::default()
            }),
            Mode::SwingUp => ControllerSpec::SwingUpBalance(SwingUpBalanceSpec {
                balance: Some(GainSpec {
                    k: k(),
                    ..Default::default()
                }),
                designed_for: record,
                ..Default::default()
            }),
        }
    }
}
