//! The one simulate path: a plant spec, a controller spec and a scenario spec in, a run as
//! plain arrays and its summary out (`docs/model.md` §6).
//!
//! [`simulate`] builds the nonlinear plant from the [`PlantSpec`]'s parameters, designs and
//! builds the controller through the factory ([`crate::spec`], on the same parameters), takes
//! the sensor and actuator chains from the plant's rig part with the scenario's imperfections
//! ([`RigSpec::chains`]), and runs `pendulab_sim`'s sampled-data loop: zero-order hold at the
//! sample time, `substeps` classical RK4 steps per sample, the delay in whole samples. The
//! command-line tools, the Python package and the browser lab all run a simulation through it.
//!
//! ```
//! use pendulab_control::scenario::simulate;
//! use pendulab_control::spec::{ControllerSpec, StateFeedbackSpec};
//! use pendulab_plants::{rig::PlantKind, spec::PlantSpec};
//! use pendulab_sim::scenario::{Imperfections, ScenarioSpec};
//! # fn main() -> Result<(), pendulab_control::scenario::ScenarioError> {
//! // The book's cart gain from 5° with the rig's quantisers, D/A and saturation.
//! let plant = PlantSpec::book(PlantKind::Cart);
//! let ctrl = ControllerSpec::StateFeedback(StateFeedbackSpec {
//!     k_book: Some(vec![3.16228, 13.47175, 4.48137, 2.26289]),
//!     ..Default::default()
//! });
//! let mut scenario = ScenarioSpec::new(vec![0.0, 5f64.to_radians(), 0.0, 0.0], 5.0);
//! scenario.imperfections = Imperfections::with_quantizer();
//! let run = simulate(&plant, &ctrl, &scenario)?;
//! assert_eq!(run.t.len(), 5001);
//! assert_eq!(run.summary.left_angle_window, Some(false));
//! assert!(run.summary.final_state[1].abs() < 1e-2);
//! # Ok(()) }
//! ```

use crate::spec::{Built, ControllerSpec, DURATION_MAX, DesignWarning, SpecError, build_with};
use pendulab_plants::rig::RigSpec;
use pendulab_plants::spec::{PlantParameters, PlantSpec};
use pendulab_plants::{ArmPendulum, CartPendulum, PlantError, wrap_about};
use pendulab_sim::scenario::{ScenarioSpec, ScenarioSpecError};
use pendulab_sim::{
    Delay, DisturbancePoint, Dynamics, Integrator, Monitor, RunStatus, SampledLoop, SampledOptions,
    SettlingTime, Signal, SimError,
};

/// The band of the settling time: 2 % of the largest deviation of `q₀` from its target.
pub const SETTLING_FRACTION: f64 = 0.02;

/// A simulated run, sample by sample (`k = 0 … N`, `t_k = k·ts`), and its summary.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// Sample times \[s\].
    pub t: Vec<f64>,
    /// The plant state `x(t_k)` (the plant's layout, e.g. `[z, θ, ż, θ̇]`).
    pub x: Vec<Vec<f64>>,
    /// The plant input `p_k` \[V\] applied from `t_k` (after saturation, D/A, disturbance).
    pub u: Vec<f64>,
    /// The controller's command `u_k` \[V\] before the actuator chain.
    pub command: Vec<f64>,
    /// The measurement `y_k` the controller saw (`[q₀, q₁, q̇₀, q̇₁]`).
    pub y: Vec<Vec<f64>>,
    /// The drive-position reference `r(t_k)` \[m or rad\] (the scenario's, else the spec's).
    pub reference: Vec<f64>,
    /// Sample time \[s\].
    pub ts: f64,
    /// Controller mode switches \[s\] (swing-up → balance).
    pub switch_times: Vec<f64>,
    /// What the run did, in a few numbers.
    pub summary: Summary,
    /// Where the plant or the loop differ from the model the controller was designed on
    /// (its `designed_for` record: parameter values, sample time); empty without a record or
    /// when they agree. A front end prints them.
    pub design_warnings: Vec<DesignWarning>,
}

/// A run in a few numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// The settling time of `q₀` \[s\] ([`settling_time`] with [`SETTLING_FRACTION`]) to the
    /// final reference; `None` when the reference has no final value (a sine) or `q₀` was
    /// outside the band at the end.
    pub settling_time: Option<f64>,
    /// The overshoot of `q₀` past the final reference in percent of the step ([`overshoot`]);
    /// `None` when the reference has no final value or `q₀` starts at it.
    pub overshoot_percent: Option<f64>,
    /// The largest `|p_k|` applied to the plant \[V\].
    pub peak_input: f64,
    /// The largest `|u_k|` the controller asked for \[V\].
    pub peak_command: f64,
    /// Time during which the saturation clipped the command \[s\] (samples × `ts`).
    pub time_in_saturation: f64,
    /// The largest distance of the pendulum angle from the controller's centre \[rad\]
    /// (`ControllerSpec::pendulum_centre`: upright, or hanging for `pid`), the angle wrapped to
    /// within π of the centre.
    pub max_angle_deviation: f64,
    /// Whether the pendulum left the rig's angle window (`rig.angle_window_deg`) about the
    /// controller's centre; `None` for a swing-up controller, which starts outside it.
    pub left_angle_window: Option<bool>,
    /// Whether `|q₀|` exceeded the rig's travel limit (`rig.travel_limit`).
    pub left_travel: bool,
    /// The state at the last sample.
    pub final_state: Vec<f64>,
}

/// What [`simulate`] refuses or where it failed, naming the key of the spec at fault.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ScenarioError {
    /// The scenario is invalid.
    #[error(transparent)]
    Scenario(#[from] ScenarioSpecError),
    /// The initial state does not fit the plant.
    #[error("scenario.initial_state has {got} entries; the {plant} plant has {expected} states")]
    InitialState {
        /// The plant (`cart`, `arm`).
        plant: &'static str,
        /// Its state count.
        expected: usize,
        /// Entries given.
        got: usize,
    },
    /// The run is longer than [`DURATION_MAX`].
    #[error("scenario.duration = {0}: must be at most {DURATION_MAX} s")]
    Duration(f64),
    /// The controller spec is invalid or its design failed.
    #[error(transparent)]
    Controller(#[from] SpecError),
    /// The plant model refused its parameters.
    #[error("plant: {0}")]
    Plant(#[from] PlantError),
    /// The rig's chains refused the scenario's imperfections (friction on a rig without
    /// friction, a noise list of the wrong length).
    #[error("scenario.imperfections: {0}")]
    Imperfections(SimError),
    /// The simulation refused its set-up or failed (a blow-up names its time).
    #[error("simulation: {0}")]
    Simulation(SimError),
}

/// Simulates `controller` on `plant` through `scenario` (module documentation).
///
/// The controller is designed on `plant`'s parameters at the scenario's sample time (default
/// the rig's). A controller spec with a design record (`designed_for`,
/// [`crate::spec::DesignRecord`]) is checked against `plant` first: a record of the other
/// plant kind is an error; different parameter values or another sample time are returned in
/// [`Run::design_warnings`]. A non-zero scenario reference is the drive position's
/// reference `r(t)` (the controller spec must then have none of its own); the disturbance is
/// added to the plant input after the amplifier; `imperfections.pivot_friction = false` sets
/// the model's `μ_p`/`μ₂` to 0.
///
/// # Errors
/// [`ScenarioError`]: an invalid scenario (naming the key), a controller designed for the
/// other plant kind ([`SpecError::WrongPlant`]), an initial state of the wrong length,
/// a run longer than [`DURATION_MAX`], the controller's [`SpecError`], imperfections
/// the rig part cannot provide, or a failed simulation.
pub fn simulate(
    plant: &PlantSpec,
    controller: &ControllerSpec,
    scenario: &ScenarioSpec,
) -> Result<Run, ScenarioError> {
    scenario.validate()?;
    let mut design_warnings = controller.check_plant(plant)?;
    let rig = plant.rig();
    let ts = scenario.sample_time.unwrap_or(rig.sample_time);
    design_warnings.extend(
        controller
            .designed_for()
            .and_then(|r| r.check_sample_time(ts)),
    );
    let mut params = *plant.parameters();
    if !scenario.imperfections.pivot_friction {
        match &mut params {
            PlantParameters::Cart(p) => p.mu_p = 0.0,
            PlantParameters::Arm(p) => p.mu2 = 0.0,
        }
    }
    let reference = if scenario.reference.is_zero() {
        None
    } else {
        Some(scenario.reference.to_signal("scenario.reference")?)
    };
    let built = build_with(controller, &params, ts, reference)?;
    let mut run = match params {
        PlantParameters::Cart(p) => {
            simulate_on(CartPendulum::new(p)?, rig, controller, built, scenario)
        }
        PlantParameters::Arm(p) => {
            simulate_on(ArmPendulum::new(p)?, rig, controller, built, scenario)
        }
    }?;
    run.design_warnings = design_warnings;
    Ok(run)
}

/// The loop of [`simulate`] on any plant with the rig's state layout (`[q₀, q₁, q̇₀, q̇₁]`,
/// one input in volts): `built` (from `controller` through the factory) in closed loop with
/// `plant` through `rig`'s chains under `scenario`. [`simulate`] calls it with the nonlinear
/// plant; with the plant's linearisation it runs the linear sampled-data loop.
///
/// # Errors
/// As [`simulate`].
pub fn simulate_on<P: Dynamics>(
    plant: P,
    rig: &RigSpec,
    controller: &ControllerSpec,
    built: Built,
    scenario: &ScenarioSpec,
) -> Result<Run, ScenarioError> {
    scenario.validate()?;
    if scenario.duration > DURATION_MAX {
        return Err(ScenarioError::Duration(scenario.duration));
    }
    if scenario.initial_state.len() != plant.nx() {
        return Err(ScenarioError::InitialState {
            plant: if rig.encoders[0].coordinate == pendulab_plants::Coordinate::Z {
                "cart"
            } else {
                "arm"
            },
            expected: plant.nx(),
            got: scenario.initial_state.len(),
        });
    }
    let ts = scenario.sample_time.unwrap_or(rig.sample_time);
    let imp = &scenario.imperfections;
    let mut chains = rig.chains(imp).map_err(ScenarioError::Imperfections)?;
    if !scenario.disturbance.is_zero() {
        let d = scenario.disturbance.to_signal("scenario.disturbance")?;
        chains.actuator = chains
            .actuator
            .disturbance(vec![d], DisturbancePoint::AfterSaturation);
    }
    let options = SampledOptions {
        ts,
        t_final: scenario.duration,
        integrator: Integrator::Rk4 {
            dt: ts / scenario.substeps as f64,
        },
        delay: if imp.delay_samples > 0 {
            Delay::Samples(imp.delay_samples)
        } else {
            Delay::None
        },
        ..Default::default()
    };
    let centre = built.pendulum_centre;
    let swing_up = built.swing_up;
    let sim = ScenarioError::Simulation;
    let out = SampledLoop::new(plant, built.controller, options)
        .and_then(|l| l.with_rig(chains))
        .and_then(|mut l| l.run(&scenario.initial_state))
        .map_err(sim)?;

    let traj = &out.trajectory;
    let rows = |m: &pendulab_lti::Mat| -> Vec<Vec<f64>> {
        (0..m.nrows())
            .map(|i| m.row(i).iter().copied().collect())
            .collect()
    };
    let t = traj.t().to_vec();
    let x = rows(traj.x());
    let y = rows(traj.y());
    let u: Vec<f64> = traj.u().column(0).iter().copied().collect();
    let command: Vec<f64> = out.commands.column(0).iter().copied().collect();
    let r_signal = drive_reference(controller, scenario)?;
    let reference: Vec<f64> = t.iter().map(|&tk| r_signal.value(tk)).collect();

    let q0: Vec<f64> = x.iter().map(|s| s[0]).collect();
    let target = if scenario.reference.is_zero() {
        spec_reference(controller)
    } else {
        scenario.reference.final_value()
    };
    let max_angle_deviation = x
        .iter()
        .map(|s| (wrap_about(s[1], centre) - centre).abs())
        .fold(0.0, f64::max);
    let peak = |v: &[f64]| v.iter().map(|a| a.abs()).fold(0.0, f64::max);
    let summary = Summary {
        settling_time: target.and_then(|r| settling_time(&t, &q0, r, SETTLING_FRACTION)),
        overshoot_percent: target.and_then(|r| overshoot(&q0, r)),
        peak_input: peak(&u),
        peak_command: peak(&command),
        time_in_saturation: out.diagnostics.saturated_samples as f64 * ts,
        max_angle_deviation,
        left_angle_window: (!swing_up).then(|| max_angle_deviation > rig.angle_window()),
        left_travel: peak(&q0) > rig.travel_limit,
        final_state: out.diagnostics.final_state.clone(),
    };
    if let RunStatus::Stopped { t } = out.status {
        // No monitor is installed, so a run always completes; a stop would be a logic error
        // of the loop, reported as such.
        return Err(ScenarioError::Simulation(SimError::InvalidArgument(
            format!("the run stopped at t = {t} s without a monitor"),
        )));
    }
    Ok(Run {
        t,
        x,
        u,
        command,
        y,
        reference,
        ts,
        switch_times: out.diagnostics.switch_times.clone(),
        summary,
        design_warnings: Vec::new(),
    })
}

/// The final drive-position reference the controller spec itself sets (state feedback's
/// `reference[0]`, the servo's `reference[0]`; 0 otherwise).
fn spec_reference(controller: &ControllerSpec) -> Option<f64> {
    let first = |r: &Option<Vec<f64>>| r.as_ref().and_then(|v| v.first().copied());
    Some(match controller {
        ControllerSpec::StateFeedback(c) => first(&c.reference).unwrap_or(0.0),
        ControllerSpec::LqServo(c) => first(&c.reference).unwrap_or(0.0),
        ControllerSpec::Pid(c) => first(&c.reference).unwrap_or(0.0),
        ControllerSpec::GainScheduled(c) => first(&c.reference).unwrap_or(0.0),
        _ => 0.0,
    })
}

/// The drive-position reference as a signal: the scenario's, else the spec's (the servo's as a
/// step at `step_time`).
fn drive_reference(
    controller: &ControllerSpec,
    scenario: &ScenarioSpec,
) -> Result<Signal, ScenarioError> {
    if !scenario.reference.is_zero() {
        return Ok(scenario.reference.to_signal("scenario.reference")?);
    }
    let r = spec_reference(controller).unwrap_or(0.0);
    let at = match controller {
        ControllerSpec::LqServo(c) => c.step_time.unwrap_or(0.0),
        ControllerSpec::Pid(c) => c.step_time.unwrap_or(0.0),
        ControllerSpec::GainScheduled(c) => c.step_time.unwrap_or(0.0),
        _ => 0.0,
    };
    Signal::step(at, r).map_err(ScenarioError::Simulation)
}

/// The settling time of the samples `q` at times `t` to `target` \[s\]: the first sample time
/// after which every sample stays within `fraction` of the largest deviation
/// `max_k |q_k − target|` (`pendulab_sim::SettlingTime` on that band). `Some(t[0])` when `q`
/// never leaves the target; `None` for no samples or a last sample outside the band.
pub fn settling_time(t: &[f64], q: &[f64], target: f64, fraction: f64) -> Option<f64> {
    let peak = q.iter().map(|v| (v - target).abs()).fold(0.0, f64::max);
    let mut m = SettlingTime::new(0, target, fraction * peak);
    for (&tk, &qk) in t.iter().zip(q) {
        m.observe(tk, &[qk], &[], &[]);
    }
    m.settling_time()
}

/// The overshoot of `q` past `target` in percent of the step `target − q[0]`:
/// `100 · max_k (q_k − target)·sign(target − q_0) / |target − q_0|`, 0 when `q` never
/// passes the target; `None` for no samples or `q[0] = target`.
pub fn overshoot(q: &[f64], target: f64) -> Option<f64> {
    let step = target - *q.first()?;
    if step == 0.0 {
        return None;
    }
    let past = q
        .iter()
        .map(|v| (v - target) * step.signum())
        .fold(0.0, f64::max);
    Some(100.0 * past / step.abs())
}
