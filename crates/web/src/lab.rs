//! The live rig: the nonlinear plant in closed loop with the designed controller at the rig's
//! sample time, one sample at a time, with the rig's imperfections switched on and off.
//!
//! The pieces are those of the one simulate path (`pendulab_control::scenario::simulate`,
//! `docs/model.md` §6): the plant from the [`PlantSpec`]'s parameters, the controller from a
//! [`ControllerSpec`] through the factory (`pendulab_control::spec::build_for`), the sensor
//! and actuator chains from the rig part and the [`Imperfections`] (`RigSpec::chains`). The
//! order of one sample is that of `pendulab_sim::SampledLoop`: at `t_k` the sensor chain
//! measures `y_k`, the controller returns `u_k`, the actuator chain gives the plant input `p_k`
//! (saturation, D/A, dead zone), and one RK4 step of `ts` carries the plant to `t_{k+1}` with
//! `p_{k−d}` held (`d` samples of delay, zero before the first command). A run of
//! [`Lab::advance`] therefore gives the samples [`simulate`](pendulab_control::scenario::simulate)
//! gives for the same specs (the crate's tests compare them); unlike it, the lab keeps going,
//! and the page may poke or hold the pendulum and change the design, reference or
//! imperfections between samples.

use crate::design::{Design, Mode};
use crate::error::WebError;
use pendulab_control::spec::{ControllerSpec, build_for};
use pendulab_plants::rig::{DriveFriction, RigSpec};
use pendulab_plants::spec::{PlantParameters, PlantSpec};
use pendulab_plants::{ArmPendulum, CartPendulum, wrap_angle};
use pendulab_sim::scenario::{Imperfections, NoiseSpec};
use pendulab_sim::{Controller, Dynamics, Friction, Rk4Work, WithDriveFriction, rk4_step_slice};
use std::collections::VecDeque;

/// Dead-zone width \[V\] of the lab's drive friction on a rig whose spec has none (the book's
/// rigs: the book gives no value, `docs/model.md` §3); the emulator's `noisy` preset uses the
/// same 0.1 V.
pub const LAB_DEAD_ZONE: f64 = 0.1;

/// Standard deviation of the lab's measurement noise, in encoder counts of each position
/// (`rig.encoders[i].step`); velocities get none of their own.
pub const LAB_NOISE_COUNTS: f64 = 2.0;

/// Seed of the lab's noise generator.
pub const LAB_NOISE_SEED: u64 = 1;

/// One recorded sample: `[t, q₀, q₁, q̇₀, q̇₁, u]` (s, the state, the plant input in V).
pub const RECORD: usize = 6;

/// The imperfections the page switches, by number (the C ABI's `which`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Effect {
    /// Encoder quantisation.
    Quantization = 0,
    /// The pseudo-differentiator for the velocities.
    PseudoDifferentiator = 1,
    /// Saturation at the input limit.
    Saturation = 2,
    /// D/A quantisation.
    Dac = 3,
    /// Drive friction (dead zone, [`LAB_DEAD_ZONE`] unless the rig spec has its own).
    DriveFriction = 4,
    /// The model's viscous pivot friction.
    PivotFriction = 5,
    /// Measurement noise ([`LAB_NOISE_COUNTS`] counts on each position).
    Noise = 6,
}

impl Effect {
    /// The effect numbered `n` (0 … 6), as listed.
    pub fn from_index(n: u32) -> Option<Self> {
        use Effect::*;
        [
            Quantization,
            PseudoDifferentiator,
            Saturation,
            Dac,
            DriveFriction,
            PivotFriction,
            Noise,
        ]
        .get(n as usize)
        .copied()
    }
}

/// The live rig (module documentation).
pub struct Lab {
    plant: PlantSpec,
    rig: RigSpec,
    model: Box<dyn Dynamics>,
    design: Design,
    mode: Mode,
    reference: f64,
    /// The time of the last rebuild: the servo's reference step time.
    step_time: f64,
    /// Whether the running design's record (its plant part) has been checked against the
    /// plant by the factory; designs of one `Designer` share it, so a slider move builds the
    /// controller without the record and the check runs once per plant.
    record_checked: bool,
    controller: Box<dyn Controller>,
    imperfections: Imperfections,
    sensor: pendulab_sim::SensorChain,
    actuator: pendulab_sim::Actuator,
    ts: f64,
    t: f64,
    sample: u64,
    x: Vec<f64>,
    before: Vec<f64>,
    y: Vec<f64>,
    command: [f64; 1],
    input: [f64; 1],
    queue: VecDeque<f64>,
    work: Rk4Work,
    hold: Option<f64>,
}

impl std::fmt::Debug for Lab {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Lab")
            .field("kind", &self.plant.kind())
            .field("t", &self.t)
            .field("x", &self.x)
            .field("spec", &self.controller_spec())
            .finish_non_exhaustive()
    }
}

impl Lab {
    /// The lab on `plant` running `design` in `mode` from `x0`, with `imperfections` on.
    ///
    /// # Errors
    /// [`WebError`] from the plant model, the controller factory or the chains (a state of
    /// the wrong length or not finite is [`WebError::Length`]/[`WebError::OutOfRange`]).
    pub fn new(
        plant: PlantSpec,
        design: Design,
        mode: Mode,
        imperfections: Imperfections,
        x0: &[f64],
    ) -> Result<Self, WebError> {
        let mut rig = *plant.rig();
        if rig.friction.is_none() {
            rig.friction = Some(DriveFriction::DeadZone {
                width: LAB_DEAD_ZONE,
            });
        }
        let ts = rig.sample_time;
        let nx = rig.nx;
        let controller = build_for(&design.controller(mode, 0.0, 0.0), &plant, ts)?.controller;
        let mut lab = Self {
            model: model(&plant, &Imperfections::ideal(), None)?,
            sensor: pendulab_sim::SensorChain::full_state(nx),
            actuator: pendulab_sim::Actuator::ideal(),
            plant,
            rig,
            design,
            mode,
            reference: 0.0,
            step_time: 0.0,
            record_checked: true,
            controller,
            imperfections: Imperfections::ideal(),
            ts,
            t: 0.0,
            sample: 0,
            x: vec![0.0; nx],
            before: vec![0.0; nx],
            y: vec![0.0; nx],
            command: [0.0],
            input: [0.0],
            queue: VecDeque::new(),
            work: Rk4Work::new(nx),
            hold: None,
        };
        lab.set_imperfections(imperfections)?;
        lab.reset(x0)?;
        Ok(lab)
    }

    /// Back to `t = 0` at state `x0`: controller, sensor chain and delay line reset.
    ///
    /// # Errors
    /// [`WebError::Length`] or [`WebError::OutOfRange`] for a state of the wrong length or
    /// not finite.
    pub fn reset(&mut self, x0: &[f64]) -> Result<(), WebError> {
        if x0.len() != self.x.len() {
            return Err(WebError::Length {
                what: "initial state",
                got: x0.len(),
                expected: self.x.len(),
            });
        }
        if let Some(&v) = x0.iter().find(|v| !v.is_finite()) {
            return Err(WebError::OutOfRange {
                what: "initial state",
                value: v,
                range: "finite",
            });
        }
        self.x.copy_from_slice(x0);
        self.t = 0.0;
        self.sample = 0;
        self.hold = None;
        self.reference = 0.0;
        self.rebuild()?;
        self.sensor.reset();
        self.queue = std::iter::repeat_n(0.0, self.imperfections.delay_samples).collect();
        Ok(())
    }

    /// Runs the design `design` from now on. A design that only changes the gain of the
    /// running controller — same plant (one `Designer`), same mode, both the servo or both
    /// state feedback, the running record already checked — is a slider move: the running
    /// controller's gain is replaced in place (`Controller::retune`; the servo's integrator
    /// and the reference carry on, a bumpless retune). Anything else rebuilds the controller
    /// through the factory, its state reset.
    ///
    /// # Errors
    /// The factory's [`WebError::Controller`]; [`WebError::Simulation`] for a gain the
    /// running controller refuses (non-finite).
    pub fn set_design(&mut self, design: Design, mode: Mode) -> Result<(), WebError> {
        let same_plant = design.same_plant_record(&self.design);
        if self.record_checked
            && same_plant
            && mode == self.mode
            && design.is_servo() == self.design.is_servo()
            && self.controller.retune(&design.gain)?
        {
            self.design = design;
            return Ok(());
        }
        self.record_checked = self.record_checked && same_plant;
        self.design = design;
        self.mode = mode;
        self.rebuild()
    }

    /// Steps the drive-position reference to `r` \[m or rad\] now (the controller rebuilt
    /// with it; the servo's integrator restarts from 0).
    ///
    /// # Errors
    /// The factory's [`WebError::Controller`].
    pub fn set_reference(&mut self, r: f64) -> Result<(), WebError> {
        if !r.is_finite() {
            return Err(WebError::OutOfRange {
                what: "reference",
                value: r,
                range: "finite",
            });
        }
        self.reference = r;
        self.rebuild()
    }

    /// The controller rebuilt by the factory from the running design; its record is checked
    /// against the plant only when it has not been (`record_checked`).
    fn rebuild(&mut self) -> Result<(), WebError> {
        let record = (!self.record_checked).then(|| self.design.record());
        let spec = self
            .design
            .controller_with(self.mode, self.reference, self.t, record);
        self.controller = build_for(&spec, &self.plant, self.ts)?.controller;
        self.step_time = self.t;
        self.record_checked = true;
        Ok(())
    }

    /// Switches the imperfections to `imperfections` (the chains rebuilt; the delay line
    /// keeps its last commands, padded with the latest or cut).
    ///
    /// # Errors
    /// [`WebError::Simulation`] from the chains' builders.
    pub fn set_imperfections(&mut self, imperfections: Imperfections) -> Result<(), WebError> {
        let chains = self.rig.chains(&imperfections)?;
        let (mut sensor, actuator) = (chains.sensor, chains.actuator);
        sensor.prepare(self.x.len(), self.ts)?;
        actuator.validate(self.x.len(), 1)?;
        self.model = model(&self.plant, &imperfections, actuator.friction_model())?;
        self.sensor = sensor;
        self.actuator = actuator;
        let d = imperfections.delay_samples;
        let last = self.queue.back().copied().unwrap_or(0.0);
        self.queue.resize(d, last);
        self.imperfections = imperfections;
        Ok(())
    }

    /// Switches one effect on or off.
    ///
    /// # Errors
    /// As [`Lab::set_imperfections`].
    pub fn set_effect(&mut self, effect: Effect, on: bool) -> Result<(), WebError> {
        let mut imp = self.imperfections.clone();
        match effect {
            Effect::Quantization => imp.quantization = on,
            Effect::PseudoDifferentiator => imp.pseudo_differentiator = on,
            Effect::Saturation => imp.saturation = on,
            Effect::Dac => imp.dac = on,
            Effect::DriveFriction => imp.drive_friction = on,
            Effect::PivotFriction => imp.pivot_friction = on,
            Effect::Noise => {
                imp.noise = on.then(|| NoiseSpec {
                    std: noise_std(&self.rig),
                    seed: LAB_NOISE_SEED,
                })
            }
        }
        self.set_imperfections(imp)
    }

    /// Sets the computation delay to `samples` whole samples (0 … 1000).
    ///
    /// # Errors
    /// [`WebError::OutOfRange`] above `pendulab_sim::scenario::DELAY_SAMPLES_MAX`.
    pub fn set_delay(&mut self, samples: usize) -> Result<(), WebError> {
        if samples > pendulab_sim::scenario::DELAY_SAMPLES_MAX {
            return Err(WebError::OutOfRange {
                what: "delay",
                value: samples as f64,
                range: "at most 1000 samples",
            });
        }
        let mut imp = self.imperfections.clone();
        imp.delay_samples = samples;
        self.set_imperfections(imp)
    }

    /// Adds `dq1` \[rad\] to the pendulum angle (a poke) and `dq0` to the drive position.
    pub fn poke(&mut self, dq0: f64, dq1: f64) {
        if dq0.is_finite() && dq1.is_finite() {
            self.x[0] += dq0;
            self.x[1] += dq1;
        }
    }

    /// Holds the pendulum at angle `q1` \[rad\] at rest (a hand on it: the page's drag), or
    /// lets it go (`None`).
    pub fn hold(&mut self, q1: Option<f64>) {
        self.hold = q1.filter(|v| v.is_finite());
    }

    /// Runs `samples` samples, appending every `every`-th as a [`RECORD`] to `out` (none for
    /// `every = 0`).
    ///
    /// # Errors
    /// [`WebError::Simulation`] when the controller returns a non-finite command or the state
    /// blows up (the lab then stays at the last finite state).
    pub fn advance(
        &mut self,
        samples: usize,
        every: usize,
        out: &mut Vec<f64>,
    ) -> Result<(), WebError> {
        for _ in 0..samples {
            if let Some(q1) = self.hold {
                self.x[1] = q1;
                self.x[3] = 0.0;
            }
            self.sensor.measure(&self.x, &mut self.y);
            self.controller.update(self.t, &self.y, &mut self.command);
            if !self.command[0].is_finite() {
                return Err(WebError::Simulation(
                    pendulab_sim::SimError::NonFiniteCommand {
                        t: self.t,
                        index: 0,
                        value: self.command[0],
                    },
                ));
            }
            self.actuator.apply(self.t, &self.command, &mut self.input);
            let applied = match self.queue.pop_front() {
                Some(old) => {
                    self.queue.push_back(self.input[0]);
                    old
                }
                None => self.input[0],
            };
            let k = self.sample;
            if every > 0 && k.is_multiple_of(every as u64) {
                out.push(self.t);
                out.extend_from_slice(&self.x);
                out.push(self.input[0]);
            }
            self.before.copy_from_slice(&self.x);
            // The step is t_{k+1} − t_k on the grid t_k = k·ts, as the sampled loop takes it.
            let next = (k + 1) as f64 * self.ts;
            rk4_step_slice(
                &*self.model,
                self.t,
                &mut self.x,
                &[applied],
                next - self.t,
                &mut self.work,
            );
            if let Some((index, &value)) = self.x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                self.x.copy_from_slice(&self.before);
                return Err(WebError::Simulation(
                    pendulab_sim::SimError::NonFiniteState {
                        t: next,
                        index,
                        value,
                    },
                ));
            }
            self.t = next;
            self.sample = k + 1;
        }
        Ok(())
    }

    /// Simulated time \[s\].
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The plant state `[q₀, q₁, q̇₀, q̇₁]`.
    pub fn state(&self) -> &[f64] {
        &self.x
    }

    /// The plant input of the last sample \[V\].
    pub fn input(&self) -> f64 {
        self.input[0]
    }

    /// The pendulum angle from upright, wrapped to `(−π, π]` \[rad\].
    pub fn angle(&self) -> f64 {
        wrap_angle(self.x[1])
    }

    /// The controller spec running now.
    pub fn controller_spec(&self) -> ControllerSpec {
        self.design
            .controller(self.mode, self.reference, self.step_time)
    }

    /// Whether the controller swings up from hanging before balancing (the mode is
    /// [`Mode::SwingUp`] and the gain is not the servo's).
    pub fn swings_up(&self) -> bool {
        self.mode == Mode::SwingUp && !self.design.is_servo()
    }

    /// The design running now.
    pub fn design(&self) -> &Design {
        &self.design
    }

    /// The plant spec.
    pub fn plant(&self) -> &PlantSpec {
        &self.plant
    }

    /// The imperfections switched on.
    pub fn imperfections(&self) -> &Imperfections {
        &self.imperfections
    }

    /// Where the parts are for drawing \[m\] (origin at the drive's pivot, `y` up): the cart's
    /// pivot and the pendulum's tip, or the arm's tip and the pendulum's tip, each `[x, y]`,
    /// from the plant's own `pose` (`CartPendulum::pose`, `ArmPendulum::pose`).
    ///
    /// # Errors
    /// [`WebError::Plant`] (not for a lab that was built).
    pub fn pose(&self) -> Result<[[f64; 2]; 2], WebError> {
        let s: [f64; 4] = [self.x[0], self.x[1], self.x[2], self.x[3]];
        Ok(match self.plant.parameters() {
            PlantParameters::Cart(p) => {
                let pose = CartPendulum::new(*p)?.pose(&s.into());
                [pose.pivot, pose.tip]
            }
            PlantParameters::Arm(p) => {
                let pose = ArmPendulum::new(*p)?.pose(&s.into());
                [pose.arm_tip, pose.pendulum_tip]
            }
        })
    }
}

/// The noise of [`Effect::Noise`]: [`LAB_NOISE_COUNTS`] counts on each encoder's state.
fn noise_std(rig: &RigSpec) -> Vec<f64> {
    let mut std = vec![0.0; rig.nx];
    for e in &rig.encoders {
        std[e.state] = LAB_NOISE_COUNTS * e.step;
    }
    std
}

/// The nonlinear plant of `plant` with the imperfections' pivot friction (as
/// `pendulab_control::scenario::simulate`: off sets `μ_p`/`μ₂` to 0) and, when the actuator
/// chain carries a Coulomb drive friction, inside the stick–slip wrapper `WithDriveFriction`
/// (as `pendulab_sim::SampledLoop`; a dead zone acts in the actuator itself).
fn model(
    plant: &PlantSpec,
    imp: &Imperfections,
    friction: Option<Friction>,
) -> Result<Box<dyn Dynamics>, WebError> {
    let mut params = *plant.parameters();
    if !imp.pivot_friction {
        match &mut params {
            PlantParameters::Cart(p) => p.mu_p = 0.0,
            PlantParameters::Arm(p) => p.mu2 = 0.0,
        }
    }
    let coulomb = friction.filter(|f| matches!(f, Friction::Coulomb { .. }));
    Ok(match (params, coulomb) {
        (PlantParameters::Cart(p), None) => Box::new(CartPendulum::new(p)?),
        (PlantParameters::Arm(p), None) => Box::new(ArmPendulum::new(p)?),
        (PlantParameters::Cart(p), Some(f)) => {
            Box::new(WithDriveFriction::new(CartPendulum::new(p)?, f)?)
        }
        (PlantParameters::Arm(p), Some(f)) => {
            Box::new(WithDriveFriction::new(ArmPendulum::new(p)?, f)?)
        }
    })
}
