//! Part 2 ch. 1 — LMI and control: α-stability, the LMI LQ servo of the arm pendulum,
//! D-stability, polytopic robust design, input saturation and the gain-scheduled servo.
//!
//! Every LMI uses the margin ε = 1e-6 for strict inequalities (the M-files' `ep = 1e-6`). Gains are
//! reported in the book's convention `u = +K x` (pendulab's library uses `u = −K x`).

use super::common::*;
use super::mfile_refs::{OctaveDisplay, display_note, max_abs, short_half_unit};
use crate::error::BookError;
use crate::output::{ExampleOutput, Value};
use crate::registry::{Example, RunContext};
use pendulab_lmi::synthesis::{
    GainScheduleSpec, LpvPlant, LqWeights, Region, ScheduledGain, Vertex, gain_scheduled_lq,
};
use pendulab_lmi::{Expr, Problem, SolveOptions, Status};
use pendulab_lti::Mat;
use pendulab_lti::design::lqr;
use pendulab_lti::linalg::eigenvalues;
use pendulab_plants::{ArmPendulum, RigSpec};
use pendulab_plot::{Channel, GainCurves, PoleZeroMap, RegionBound, SignalPanel, TimeResponse};
use pendulab_sim::controllers::{IntegrationRule, LqIntegralServo};
use pendulab_sim::{
    Controller, RunStatus, SampledLoop, SampledOptions, SampledRun, Signal, StayWithin,
};
use std::f64::consts::PI;

mod alpha_servo;
mod gain_scheduled;
mod mfile;
mod robust;
mod saturation;
use alpha_servo::*;
use gain_scheduled::*;
use mfile::*;
use robust::*;
use saturation::*;

const EPS: f64 = 1e-6;
const DEG: f64 = 180.0 / PI;
const ARM: &str = "arm pendulum, book table 3.7";
const GAIN_NOTE: &str = "Gains in the book's convention u = +K x.";
/// What the α-region servo M-files' optimum determines and what it does not.
const ILL_DETERMINED_KT: &str = "trace(X) is certified; Kt = L X⁻¹ is not well determined by this objective: \
     near-optimal points with trace(X) within 1e-5 (relative) of the optimum give gains differing by 5–35 % \
     (pendulab-lmi's Clarabel backend and CVXPY + Clarabel stop there, \"almost solved\"; \
     tools/reference/p2c1_mfile_lmi_cvxpy.py), so the gain any solver reports for this M-file depends on where it stops.";

/// The chapter's examples, in book order.
pub(crate) fn examples() -> Vec<Example> {
    vec![
        Example {
            id: "p2c112_ex1_alpha_stability",
            title: "α-stability of a 2×2 matrix by an LMI (α = 1)",
            section: "Part 2 §1.1.2",
            parameters: "A = [[0, 1], [−2.25, −2.25]], α = 1",
            needs_data: None,
            run: p2c112_ex1,
        },
        Example {
            id: "p2c121_ex3_alpha_stability_opt",
            title: "α-stability LMI: minimise ξ1 + ξ2",
            section: "Part 2 §1.2.1",
            parameters: "A = [[0, 1], [−2.25, −2.25]], α = 1",
            needs_data: None,
            run: p2c121_ex3,
        },
        Example {
            id: "p2c122_ex4_adip_oc_servo",
            title: "Arm pendulum LQ servo by an LMI (guaranteed cost)",
            section: "Part 2 §1.2.2",
            parameters: ARM,
            needs_data: None,
            run: p2c122_ex4_servo,
        },
        Example {
            id: "p2c122_ex4_adip_oc_multiobjective_servo",
            title: "Arm pendulum servo: LQ cost with D-stability region",
            section: "Part 2 §1.2.2",
            parameters: ARM,
            needs_data: None,
            run: p2c122_ex4_multiobjective,
        },
        Example {
            id: "p2c13_ex5_adip_lqr_servo",
            title: "Nominal Riccati LQ servo at the four parameter vertices",
            section: "Part 2 §1.3",
            parameters: "arm pendulum, a1 ∈ [3.41, 8.99], b1 ∈ [8.69, 22.91]",
            needs_data: None,
            run: p2c13_lqr,
        },
        Example {
            id: "p2c13_ex5_adip_oc_nominal_servo",
            title: "Nominal LMI servo (α = 2, β = 40) at the four parameter vertices",
            section: "Part 2 §1.3",
            parameters: "arm pendulum, a1 ∈ [3.41, 8.99], b1 ∈ [8.69, 22.91]",
            needs_data: None,
            run: p2c13_nominal,
        },
        Example {
            id: "p2c13_ex5_adip_oc_robust_servo",
            title: "Robust LMI servo over the four parameter vertices (α = 2, β = 40)",
            section: "Part 2 §1.3",
            parameters: "arm pendulum, a1 ∈ [3.41, 8.99], b1 ∈ [8.69, 22.91]",
            needs_data: None,
            run: p2c13_robust,
        },
        Example {
            id: "p2c14_ex6_adip_oc_saturation",
            title: "State feedback under |u| ≤ 0.1 V saturation by invariant-ellipsoid conditions (K and H)",
            section: "Part 2 §1.4",
            parameters: ARM,
            needs_data: None,
            run: p2c14_ex6,
        },
        Example {
            id: "p2c15_ex7_adip_lqr_servo",
            title: "LQ servo on the nonlinear arm pendulum, r = 60° then 0",
            section: "Part 2 §1.5",
            parameters: ARM,
            needs_data: None,
            run: p2c15_lqr,
        },
        Example {
            id: "p2c15_ex7_adip_oc_gs_servo",
            title: "Gain-scheduled LQ servo (SOS, ρ = 1 − cos θ1), r = 60° then 0",
            section: "Part 2 §1.5",
            parameters: ARM,
            needs_data: None,
            run: p2c15_gs,
        },
    ]
}

/// `Q = diag(0.1, 1, 0.001, 0.001, 4)`, `R = 1` of the arm servo.
fn servo_weights() -> (Mat, Mat) {
    (diag(&[0.1, 1.0, 0.001, 0.001, 4.0]), diag(&[1.0]))
}

/// The Riccati LQ servo gain on the augmented nominal model (library sign, 1 × 5).
fn riccati_servo_gain(
    id: &str,
    at: &Mat,
    bt: &Mat,
) -> Result<pendulab_lti::design::Lqr, BookError> {
    let (q, r) = servo_weights();
    let sys = pendulab_lti::StateSpace::continuous(
        at.clone(),
        bt.clone(),
        Mat::identity(5, 5),
        Mat::zeros(5, 1),
    )
    .ctx(id)?;
    lqr(&sys, &q, &r, None).ctx(id)
}

fn nominal_servo(id: &str) -> Result<(Mat, Mat), BookError> {
    let p = pendulab_plants::ArmPendulumParams::book();
    arm_servo_model(id, p.a1, p.b1)
}

/// The servo `u = −K₁ x − K₂ w` (library sign) on the nonlinear arm pendulum, quantised rig
/// preset, 1 ms, with reference `r` for θ₁.
fn arm_servo_run(
    id: &str,
    params: pendulab_plants::ArmPendulumParams,
    k: &Mat,
    r: Signal,
    t_final: f64,
) -> Result<SampledRun, BookError> {
    let k1 = k.columns(0, 4).into_owned();
    let k2 = k.columns(4, 1).into_owned();
    let cs = Mat::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]);
    let c = LqIntegralServo::new(&k1, &k2, &cs, vec![r], 1e-3, IntegrationRule::ForwardEuler)
        .ctx(id)?;
    run_arm(id, params, c, t_final, &[0.0, 0.0, 0.0, 0.0])
}

fn run_arm<C: Controller>(
    id: &str,
    params: pendulab_plants::ArmPendulumParams,
    c: C,
    t_final: f64,
    x0: &[f64],
) -> Result<SampledRun, BookError> {
    let plant = ArmPendulum::new(params).ctx(id)?;
    // The rig's safety stop: the run ends when the pendulum falls past 90°.
    let mut fall = StayWithin::new(1, PI / 2.0);
    let mut l = SampledLoop::new(
        plant,
        c,
        SampledOptions {
            t_final,
            ..Default::default()
        },
    )
    .ctx(id)?
    .with_rig(quantized_rig(id, &RigSpec::arm())?)
    .ctx(id)?;
    l.run_with(x0, &mut fall).ctx(id)
}

/// The time the pendulum fell (the run was stopped), if it did.
fn fell_at(run: &SampledRun) -> Option<f64> {
    match run.status {
        RunStatus::Stopped { t } => Some(t),
        RunStatus::Completed => None,
    }
}

/// θ₁, θ₂ (degrees) and u panels of arm runs.
fn arm_response(
    title: &str,
    runs: &[(&str, &SampledRun)],
    reference: Option<f64>,
) -> Result<pendulab_plot::Figure, pendulab_plot::PlotError> {
    let mut tr = TimeResponse::new().title(title);
    for (name, run) in runs {
        tr = tr.run(*name, &run.trajectory);
    }
    let mut th1 = SignalPanel::new(Channel::State(0), "θ1 [deg]").scaled(DEG);
    if let Some(r) = reference {
        th1 = th1.reference(r, Some("reference"));
    }
    tr.panel(th1)
        .panel(SignalPanel::new(Channel::State(1), "θ2 [deg]").scaled(DEG))
        .panel(SignalPanel::new(Channel::Input(0), "u [V]"))
        .figure()
}

/// The book's `Kt` (u = +Kt x) as the library gain (u = −K x).
fn library_gain(kt: &Mat) -> Mat {
    -kt
}

/// `eig(At + Bt*Kt)`, sorted.
fn poles_of(
    id: &str,
    a: &Mat,
    b: &Mat,
    kt: &Mat,
) -> Result<Vec<pendulab_lti::Complex64>, BookError> {
    Ok(sorted(eigenvalues(&(a + b * kt)).ctx(id)?))
}

/// The LMI servo of the p2c122 M-files on the nominal model, with its `Kt`, poles and the
/// Riccati comparison (`Kt_LQ = -lqr(At, Bt, Q, R)`, `poles_LQ`).
fn lmi_servo_values(
    id: &str,
    spec: &MfileLmi,
    at: &Mat,
    bt: &Mat,
    out: &mut ExampleOutput,
) -> Result<(MfileSolution, Mat, Mat), BookError> {
    let s = solve_mfile(id, spec, &SolveOptions::default())?;
    let kt = s.kt(id)?;
    report_solution(id, &s, "trace_invX", out)?;
    let poles = poles_of(id, at, bt, &kt)?;
    let lq = riccati_servo_gain(id, at, bt)?;
    let kt_lq = library_gain(&lq.gain);
    out.value("Kt", Value::Vector(row(&kt)))
        .value("K1", Value::Vector(row(&kt)[..4].to_vec()))
        .value("K2", Value::Number(kt[(0, 4)]))
        .value("poles", Value::Complex(poles))
        .value("Kt_LQ", Value::Vector(row(&kt_lq)))
        .value("poles_LQ", Value::Complex(poles_of(id, at, bt, &kt_lq)?));
    Ok((s, kt, kt_lq))
}
