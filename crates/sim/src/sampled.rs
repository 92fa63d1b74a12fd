//! The sampled-data loop: a continuous plant, a discrete controller called every `ts` with a
//! zero-order hold, and the rig's sensor and actuator chains in between.
//!
//! ```text
//!          t_k = t₀ + k·ts (computed from k: no accumulated drift)
//!   x(t_k) ─▶ SensorChain ─▶ y_k ─▶ Controller ─▶ u_k ─▶ Actuator ─▶ p_k ─(hold, delay)─▶ plant
//!     ▲                                                                                  │
//!     └────────────── integrator substeps on [t_k, t_{k+1}], never across t_{k+1} ◀──────┘
//! ```
//!
//! At every sample instant `t_k`, `k = 0, 1, …, N` with `N = ⌊(t_final − t₀)/ts⌋`:
//! 1. the sensor chain turns the true state `x(t_k)` into the measurement `y_k`;
//! 2. the controller computes `u_k` from `y_k`;
//! 3. the actuator chain turns `u_k` into the plant input `p_k` (saturation, D/A, disturbance,
//!    dead zone);
//! 4. the sample is recorded and shown to the [`Monitor`], which may stop the run;
//! 5. the plant is integrated from `t_k` to `t_{k+1}` with the input held:
//!    without delay `p_k` over all of `[t_k, t_{k+1})`; with a computation delay
//!    [`Delay::Time`]`(δ)`, `0 < δ ≤ ts`, `p_{k−1}` over `[t_k, t_k + δ)` and `p_k` over
//!    `[t_k + δ, t_{k+1})`; with [`Delay::Samples`]`(d)`, `p_{k−d}` over the whole interval.
//!    Before the first command takes effect the plant sees
//!    [`SampledOptions::initial_input`] (default zero).
//!
//! Each interval (or delay segment) is integrated in substeps that end exactly on its end
//! point: for [`Integrator::Rk4`]`{ dt }`, `dt` must divide `ts` (`ts/dt` an integer to within
//! 1e-9, else [`SimError::StepDoesNotDivide`]) and a delay segment of length `L` takes
//! `⌈L/dt⌉` equal substeps; [`Integrator::Dopri45`] adapts its steps inside each segment and
//! restarts its stage `k₁` at every segment boundary (the input jumps there).
//!
//! The trajectory holds, per recorded sample `k`: `t_k`, `x(t_k)`, the plant input `p_k`
//! computed at `t_k` (applied from `t_k + delay`) as `u`, and the measurement `y_k` as `y`;
//! the raw controller outputs `u_k` are in [`SampledRun::commands`].

use crate::actuator::{Actuator, Friction, WithDriveFriction};
use crate::buffer::{Buf, with_buffer};
use crate::controller::Controller;
use crate::dynamics::Dynamics;
use crate::error::{Result, SimError, check_initial_state, check_len, check_state};
use crate::integrate::dopri::Dopri;
use crate::integrate::rk4::{Rk4Scratch, step_generic};
use crate::integrate::{IntegrationStats, Integrator};
use crate::monitor::{Flow, Monitor};
use crate::sensor::SensorChain;
use pendulab_lti::{Mat, Trajectory};

/// Computation delay between a sample and the moment its command reaches the plant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Delay {
    /// The command computed at `t_k` acts from `t_k`.
    #[default]
    None,
    /// The command computed at `t_k` acts from `t_k + δ`, `0 ≤ δ ≤ ts` (s).
    Time(f64),
    /// The command computed at `t_k` acts over `[t_{k+d}, t_{k+d+1})` (whole samples).
    Samples(usize),
}

/// Which samples are stored in the trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Record {
    /// Every sample.
    #[default]
    EverySample,
    /// Every `n`-th sample (`k = 0, n, 2n, …`), `n ≥ 1`.
    Every(usize),
    /// Nothing (batch runs that only need a monitor's summary).
    Off,
}

/// Options of the sampled-data loop.
#[derive(Debug, Clone, PartialEq)]
pub struct SampledOptions {
    /// Sample time `ts` (s). Default 1e-3 (the rigs' 1 kHz).
    pub ts: f64,
    /// Start time `t₀` (s). Default 0.
    pub t0: f64,
    /// End time (s); the last sample is `t₀ + ⌊(t_final − t₀)/ts⌋·ts`. Default 10.
    pub t_final: f64,
    /// Plant integrator. Default `Rk4 { dt: 1e-3 }` (one substep per 1 ms sample).
    pub integrator: Integrator,
    /// Computation delay. Default none.
    pub delay: Delay,
    /// Plant input before the first (delayed) command takes effect; `None` (default): zero.
    pub initial_input: Option<Vec<f64>>,
    /// What to record. Default every sample.
    pub record: Record,
}

impl Default for SampledOptions {
    fn default() -> Self {
        Self {
            ts: 1e-3,
            t0: 0.0,
            t_final: 10.0,
            integrator: Integrator::Rk4 { dt: 1e-3 },
            delay: Delay::None,
            initial_input: None,
            record: Record::EverySample,
        }
    }
}

/// How a sampled-data run ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RunStatus {
    /// All samples up to `t_final` were run.
    Completed,
    /// The monitor stopped the run at sample time `t` (s) (e.g. a safety limit).
    Stopped {
        /// The sample time of the stop.
        t: f64,
    },
}

/// Diagnostics of a sampled-data run.
#[derive(Debug, Clone, PartialEq)]
pub struct SampledDiagnostics {
    /// Controller calls (samples run).
    pub samples: usize,
    /// Integrator work.
    pub integration: IntegrationStats,
    /// Samples at which the saturation clipped a command.
    pub saturated_samples: usize,
    /// Controller mode switches ([`Controller::switch_times`]).
    pub switch_times: Vec<f64>,
    /// Time of the last sample run (s).
    pub final_time: f64,
    /// State at the last sample run.
    pub final_state: Vec<f64>,
}

/// The result of a sampled-data run.
#[derive(Debug, Clone, PartialEq)]
pub struct SampledRun {
    /// Recorded samples: `t_k`, `x(t_k)`, plant input `p_k` (as `u`), measurement `y_k`.
    pub trajectory: Trajectory,
    /// Raw controller outputs `u_k` at the recorded samples (rows = samples).
    pub commands: Mat,
    /// How the run ended.
    pub status: RunStatus,
    /// Counters and final values.
    pub diagnostics: SampledDiagnostics,
}

/// Validated timing of a loop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Timing {
    pub(crate) samples: usize,
    /// RK4 substeps per full interval (0 for Dopri).
    pub(crate) nsub: usize,
    /// Delay split: (δ, substeps before, substeps after) for `Delay::Time`.
    pub(crate) split: Option<(f64, usize, usize)>,
    pub(crate) ring: usize,
}

/// The monitored run methods of a closed loop, over its private `run_inner(x0, monitor,
/// storage)`: shared by [`SampledLoop`] and the fixed-size kernel
/// ([`FixedLoop`](crate::fast::FixedLoop)), whose runs take the same arguments and give the
/// same results.
macro_rules! monitored_runs {
    () => {
        /// Runs from `x0` showing every sample to `monitor`, which may stop the run.
        ///
        /// # Errors
        /// As [`SampledLoop::run`](crate::SampledLoop::run).
        pub fn run_with<M: Monitor + ?Sized>(
            &mut self,
            x0: &[f64],
            monitor: &mut M,
        ) -> Result<SampledRun> {
            self.run_inner(x0, monitor, None)
        }

        /// As `run_with`, recording into the storage of an earlier result `previous` (which
        /// is consumed): repeated runs (tuning loops, benchmarks) then allocate nothing and
        /// touch no fresh memory pages.
        ///
        /// # Errors
        /// As [`SampledLoop::run`](crate::SampledLoop::run).
        pub fn run_recycling<M: Monitor + ?Sized>(
            &mut self,
            x0: &[f64],
            monitor: &mut M,
            previous: SampledRun,
        ) -> Result<SampledRun> {
            self.run_inner(x0, monitor, Some(previous))
        }
    };
}
pub(crate) use monitored_runs;

/// A continuous plant in closed loop with a discrete controller (see the module docs).
///
/// ```
/// use pendulab_sim::{SampledLoop, SampledOptions, controllers::StaticStateFeedback};
/// use pendulab_lti::{Mat, StateSpace};
/// # fn main() -> Result<(), pendulab_sim::SimError> {
/// // A double integrator under discrete state feedback u = −[1, 1.5] x at 10 Hz.
/// let plant = StateSpace::continuous(
///     Mat::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]),
///     Mat::from_row_slice(2, 1, &[0.0, 1.0]),
///     Mat::identity(2, 2),
///     Mat::zeros(2, 1),
/// )?;
/// let k = StaticStateFeedback::new(Mat::from_row_slice(1, 2, &[1.0, 1.5]))?;
/// let opts = SampledOptions { ts: 0.1, t_final: 20.0, ..Default::default() };
/// let mut cl = SampledLoop::new(plant, k, opts)?;
/// let run = cl.run(&[1.0, 0.0])?;
/// assert!(run.diagnostics.final_state[0].abs() < 1e-3);
/// # Ok(()) }
/// ```
#[derive(Debug, Clone)]
pub struct SampledLoop<P, C> {
    plant: P,
    controller: C,
    sensor: SensorChain,
    actuator: Actuator,
    options: SampledOptions,
    timing: Timing,
}

impl<P: Dynamics, C: Controller> SampledLoop<P, C> {
    /// Closes `plant` with `controller` under `options`, with the ideal sensor (`y = x`) and
    /// actuator. A controller that expects another measurement than the full state needs its
    /// sensor chain ([`SampledLoop::with_sensor`]) before it can run; [`SampledLoop::run`]
    /// checks it.
    ///
    /// # Errors
    /// [`SimError::InvalidSampleTime`]; [`SimError::InvalidTimeSpan`] for a span shorter
    /// than one sample; integrator errors ([`Integrator::validate`],
    /// [`SimError::StepDoesNotDivide`]); [`SimError::InvalidParameter`] for a delay outside
    /// `[0, ts]`; [`SimError::DimensionMismatch`] if the controller's `nu` does not fit the
    /// plant or the initial input has the wrong length;
    /// [`SimError::SampleTimeMismatch`] if the controller was designed for another `ts`.
    pub fn new(plant: P, controller: C, options: SampledOptions) -> Result<Self> {
        let nx = plant.nx();
        let timing = validate_options(&options, plant.nu())?;
        let mut me = Self {
            plant,
            controller,
            sensor: SensorChain::full_state(nx),
            actuator: Actuator::ideal(),
            options,
            timing,
        };
        me.check_shapes(false)?;
        Ok(me)
    }

    /// Replaces the sensor chain.
    ///
    /// # Errors
    /// As [`SensorChain::validate`]; [`SimError::DimensionMismatch`] if its `ny` is not the
    /// controller's.
    pub fn with_sensor(mut self, sensor: SensorChain) -> Result<Self> {
        self.sensor = sensor;
        self.check_shapes(true)?;
        Ok(self)
    }

    /// Replaces both chains by a rig preset ([`crate::rig::RigChains`]).
    ///
    /// # Errors
    /// As [`SampledLoop::with_sensor`] and [`SampledLoop::with_actuator`].
    pub fn with_rig(self, rig: crate::rig::RigChains) -> Result<Self> {
        self.with_sensor(rig.sensor)?.with_actuator(rig.actuator)
    }

    /// Replaces the actuator chain.
    ///
    /// # Errors
    /// As [`Actuator::validate`].
    pub fn with_actuator(mut self, actuator: Actuator) -> Result<Self> {
        self.actuator = actuator;
        self.check_shapes(false)?;
        Ok(self)
    }

    fn check_shapes(&mut self, measurement: bool) -> Result<()> {
        let (nx, nu) = (self.plant.nx(), self.plant.nu());
        check_len(
            "controller commands (plant inputs)",
            self.controller.nu(),
            nu,
        )?;
        if measurement {
            self.check_measurement()?;
        }
        if let Some(tc) = self.controller.sample_time()
            && (tc - self.options.ts).abs() > 1e-12 * self.options.ts
        {
            return Err(SimError::SampleTimeMismatch {
                controller: tc,
                sampled: self.options.ts,
            });
        }
        self.sensor.prepare(nx, self.options.ts)?;
        self.actuator.validate(nx, nu)?;
        if nu > crate::systems::MAX_INPUTS {
            return Err(SimError::DimensionMismatch {
                what: "plant inputs of a sampled-data loop (at most MAX_INPUTS)".into(),
                expected: crate::systems::MAX_INPUTS,
                found: nu,
            });
        }
        Ok(())
    }

    fn check_measurement(&self) -> Result<()> {
        check_len(
            "controller measurements (sensor channels)",
            self.controller.ny(),
            self.sensor.ny(),
        )
    }

    /// The plant.
    pub fn plant(&self) -> &P {
        &self.plant
    }
    /// The controller.
    pub fn controller(&self) -> &C {
        &self.controller
    }
    /// The controller, mutably (e.g. to retune between runs).
    pub fn controller_mut(&mut self) -> &mut C {
        &mut self.controller
    }
    /// The options.
    pub fn options(&self) -> &SampledOptions {
        &self.options
    }
    /// The sensor chain.
    pub fn sensor(&self) -> &SensorChain {
        &self.sensor
    }
    /// The actuator chain.
    pub fn actuator(&self) -> &Actuator {
        &self.actuator
    }
    /// Number of samples `N + 1` a complete run takes.
    pub fn samples(&self) -> usize {
        self.timing.samples + 1
    }

    /// Runs from `x(t₀) = x0` (controller and sensor chain reset first).
    ///
    /// # Errors
    /// [`SimError::DimensionMismatch`], [`SimError::NonFiniteInitialState`] for a bad `x0`;
    /// [`SimError::DimensionMismatch`] if the controller's measurement length is not the
    /// sensor chain's;
    /// [`SimError::NonFiniteCommand`] if the controller returns NaN/∞;
    /// [`SimError::NonFiniteState`] naming the time at which the state blew up; adaptive
    /// integrator failures.
    pub fn run(&mut self, x0: &[f64]) -> Result<SampledRun> {
        self.run_with(x0, &mut ())
    }

    monitored_runs!();

    fn run_inner<M: Monitor + ?Sized>(
        &mut self,
        x0: &[f64],
        monitor: &mut M,
        storage: Option<SampledRun>,
    ) -> Result<SampledRun> {
        let nx = self.plant.nx();
        check_initial_state(x0, nx)?;
        self.check_measurement()?;
        self.controller.reset();
        self.sensor.reset();
        let Self {
            plant,
            controller,
            sensor,
            actuator,
            options,
            timing,
        } = self;
        match actuator.friction_model() {
            Some(f @ Friction::Coulomb { .. }) => {
                let wrapped = WithDriveFriction::new(&*plant, f)?;
                with_buffer!(nx, B => run_core::<B, _, _, M>(
                    &wrapped, controller, sensor, actuator, options, timing, x0, monitor, storage
                ))
            }
            _ => with_buffer!(nx, B => run_core::<B, _, _, M>(
                &*plant, controller, sensor, actuator, options, timing, x0, monitor, storage
            )),
        }
    }
}

pub(crate) fn validate_options(o: &SampledOptions, nu: usize) -> Result<Timing> {
    let ts = o.ts;
    if !(ts.is_finite() && ts > 0.0) {
        return Err(SimError::InvalidSampleTime(ts));
    }
    crate::integrate::check_span(o.t0, o.t_final)?;
    let ratio = (o.t_final - o.t0) / ts;
    let samples = (ratio + 1e-9).floor();
    if samples < 1.0 {
        return Err(SimError::InvalidTimeSpan {
            what: "the run is shorter than one sample time",
            t0: o.t0,
            t_final: o.t_final,
        });
    }
    if samples > 1e12 {
        return Err(SimError::InvalidTimeSpan {
            what: "more than 1e12 samples",
            t0: o.t0,
            t_final: o.t_final,
        });
    }
    o.integrator.validate()?;
    let nsub = match o.integrator {
        Integrator::Rk4 { dt } => {
            let r = ts / dt;
            let n = r.round();
            if n < 1.0 || (r - n).abs() > 1e-9 * r {
                return Err(SimError::StepDoesNotDivide { dt, ts, ratio: r });
            }
            n as usize
        }
        Integrator::Dopri45 { .. } => 0,
    };
    let substeps = |len: f64| -> usize {
        match o.integrator {
            Integrator::Rk4 { dt } => ((len / dt) * (1.0 - 1e-9)).ceil().max(1.0) as usize,
            Integrator::Dopri45 { .. } => 0,
        }
    };
    let (split, ring) = match o.delay {
        Delay::None => (None, 0),
        Delay::Time(d) => {
            if !(d.is_finite() && (0.0..=ts).contains(&d)) {
                return Err(SimError::InvalidParameter {
                    what: "computation delay".into(),
                    value: d,
                    requirement: "must lie in [0, ts]",
                });
            }
            if d == 0.0 {
                (None, 0)
            } else if d >= ts * (1.0 - 1e-12) {
                (None, 1)
            } else {
                (Some((d, substeps(d), substeps(ts - d))), 0)
            }
        }
        Delay::Samples(n) => (None, n),
    };
    if let Some(u0) = &o.initial_input {
        crate::error::check_finite_vector("initial plant input", "initial plant input", u0, nu)?;
    }
    if o.record == Record::Every(0) {
        return Err(SimError::InvalidParameter {
            what: "recording interval".into(),
            value: 0.0,
            requirement: "must be at least 1 sample",
        });
    }
    Ok(Timing {
        samples: samples as usize,
        nsub,
        split,
        ring,
    })
}

/// The plant integrator of the loop: RK4 substeps or an adaptive Dormand–Prince run per
/// segment.
enum Segments<B: Buf> {
    Rk4(Rk4Scratch<B>),
    Dopri { d: Box<Dopri<B>>, h: f64 },
}

impl<B: Buf> Segments<B> {
    /// Integrates `x` from `ta` to `tb` with input `u` held (`n` RK4 substeps).
    #[inline(always)]
    fn advance<S: Dynamics + ?Sized>(
        &mut self,
        sys: &S,
        ta: f64,
        tb: f64,
        n: usize,
        x: &mut B,
        u: &[f64],
        stats: &mut IntegrationStats,
    ) -> Result<()> {
        match self {
            Segments::Rk4(w) => {
                if n == 1 {
                    step_generic(sys, ta, x, u, tb - ta, w, false);
                } else {
                    let h = (tb - ta) / n as f64;
                    for j in 0..n {
                        step_generic(sys, ta + j as f64 * h, x, u, h, w, false);
                    }
                }
                stats.accepted_steps += n;
                stats.evaluations += 4 * n;
                Ok(())
            }
            Segments::Dopri { d, h } => dopri_segment(d, h, sys, ta, tb, x, u, stats),
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn dopri_segment<S: Dynamics + ?Sized, B: Buf>(
    d: &mut Dopri<B>,
    h: &mut f64,
    sys: &S,
    ta: f64,
    tb: f64,
    x: &mut B,
    u: &[f64],
    stats: &mut IntegrationStats,
) -> Result<()> {
    sys.derivative(ta, x.s(), u, d.k1.m());
    d.evaluations += 1;
    let mut t = ta;
    if *h <= 0.0 {
        *h = match d.params.h_init {
            Some(h0) => h0,
            None => d.initial_step(sys, t, x, u, tb - ta),
        };
    }
    let mut after_reject = false;
    loop {
        let span = tb - t;
        if d.accepted + d.rejected >= d.params.max_steps {
            return Err(SimError::MaxStepsExceeded {
                t,
                max_steps: d.params.max_steps,
            });
        }
        let mut hs = h.min(d.params.h_max);
        let last = hs >= span * (1.0 - 1e-12) || span - hs < 1e-3 * hs;
        if last {
            hs = span;
        }
        if hs <= 4.0 * f64::EPSILON * t.abs().max(1.0) {
            return Err(SimError::StepSizeUnderflow { t, h: hs });
        }
        let att = d.attempt(sys, t, x, u, hs);
        let ok = att.err <= 1.0 && d.y1.s().iter().all(|v| v.is_finite());
        if ok {
            let hn = d.next_step(att.err, hs, true, after_reject);
            // A step shortened to land on tb says little about the next one: keep the larger.
            *h = if last { hn.max(*h) } else { hn };
            d.accepted += 1;
            x.m().copy_from_slice(d.y1.s());
            if last {
                break;
            }
            std::mem::swap(&mut d.k1, &mut d.k7);
            t += hs;
            after_reject = false;
        } else {
            *h = d.next_step(att.err, hs, false, after_reject);
            d.rejected += 1;
            after_reject = true;
        }
    }
    stats.accepted_steps = d.accepted;
    stats.rejected_steps = d.rejected;
    stats.evaluations = d.evaluations;
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn run_core<B, S, C, M>(
    sys: &S,
    controller: &mut C,
    sensor: &mut SensorChain,
    actuator: &Actuator,
    options: &SampledOptions,
    timing: &Timing,
    x0: &[f64],
    monitor: &mut M,
    storage: Option<SampledRun>,
) -> Result<SampledRun>
where
    B: Buf,
    S: Dynamics + ?Sized,
    C: Controller + ?Sized,
    M: Monitor + ?Sized,
{
    let (nx, nu, ny) = (sys.nx(), sys.nu(), sensor.ny());
    let ts = options.ts;
    let t0 = options.t0;
    let n_samples = timing.samples;
    let mut x = B::zeros(nx);
    x.m().copy_from_slice(x0);
    let mut seg = match options.integrator.dopri_params() {
        None => Segments::Rk4(Rk4Scratch::<B>::new(nx)),
        Some(p) => Segments::Dopri {
            d: Box::new(Dopri::new(nx, p)),
            h: 0.0,
        },
    };
    let mut y = vec![0.0; ny];
    let mut ucmd = vec![0.0; nu];
    let mut p = vec![0.0; nu];
    let initial = options
        .initial_input
        .clone()
        .unwrap_or_else(|| vec![0.0; nu]);
    // Previous plant input (Delay::Time) and the ring of delayed inputs (Delay::Samples).
    let mut prev = initial.clone();
    let ring_len = timing.ring;
    let mut ring: Vec<f64> = (0..ring_len)
        .flat_map(|_| initial.iter().copied())
        .collect();
    let mut applied = vec![0.0; nu];
    let every = match options.record {
        Record::EverySample => Some(1),
        Record::Every(n) => Some(n),
        Record::Off => None,
    };
    let cap = every.map_or(0, |e| n_samples / e + 1);
    let [bt, bx, bu, by, bc] = storage.map_or_else(Default::default, |r| r.into_storage());
    let mut rt = bt;
    rt.clear();
    rt.reserve(cap);
    let mut rx = Columns::recycled(bx, cap, nx);
    let mut ru = Columns::recycled(bu, cap, nu);
    let mut ry = Columns::recycled(by, cap, ny);
    let mut rc = Columns::recycled(bc, cap, nu);
    let mut stats = IntegrationStats::default();
    let mut saturated = 0usize;
    let mut status = RunStatus::Completed;
    let transparent = actuator.is_transparent();
    let mut last_t = t0;
    let mut samples_run = 0usize;
    let mut next_record = 0usize;
    for k in 0..=n_samples {
        let tk = t0 + k as f64 * ts;
        last_t = tk;
        sensor.measure(x.s(), &mut y);
        controller.update(tk, &y, &mut ucmd);
        samples_run += 1;
        if let Some((index, &value)) = ucmd.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(SimError::NonFiniteCommand {
                t: tk,
                index,
                value,
            });
        }
        // The plant input: the command itself through a transparent actuator (no copy).
        if !transparent && actuator.apply(tk, &ucmd, &mut p) {
            saturated += 1;
        }
        let pk: &[f64] = if transparent { &ucmd } else { &p };
        // Record every `e`-th sample (a countdown, no division in the loop).
        if let Some(e) = every
            && next_record == k
        {
            next_record += e;
            let row = rt.len();
            rt.push(tk);
            rx.set_row(row, x.s());
            ru.set_row(row, pk);
            ry.set_row(row, &y);
            rc.set_row(row, &ucmd);
        }
        if monitor.observe(tk, x.s(), &y, pk) == Flow::Stop {
            status = RunStatus::Stopped { t: tk };
            break;
        }
        if k == n_samples {
            break;
        }
        let tk1 = t0 + (k + 1) as f64 * ts;
        if let Some((d, n1, n2)) = timing.split {
            let tm = tk + d;
            seg.advance(sys, tk, tm, n1, &mut x, &prev, &mut stats)?;
            seg.advance(sys, tm, tk1, n2, &mut x, pk, &mut stats)?;
            prev.copy_from_slice(pk);
        } else if ring_len > 0 {
            let slot = (k % ring_len) * nu;
            applied.copy_from_slice(&ring[slot..slot + nu]);
            ring[slot..slot + nu].copy_from_slice(pk);
            seg.advance(sys, tk, tk1, timing.nsub, &mut x, &applied, &mut stats)?;
        } else {
            seg.advance(sys, tk, tk1, timing.nsub, &mut x, pk, &mut stats)?;
        }
        check_state(tk1, x.s())?;
    }
    let rows = rt.len();
    let trajectory = Trajectory::new(rt, rx.into_mat(rows), ru.into_mat(rows), ry.into_mat(rows))?;
    let commands = rc.into_mat(rows);
    Ok(SampledRun {
        trajectory,
        commands,
        status,
        diagnostics: SampledDiagnostics {
            samples: samples_run,
            integration: stats,
            saturated_samples: saturated,
            switch_times: controller.switch_times().to_vec(),
            final_time: last_t,
            final_state: x.s().to_vec(),
        },
    })
}

impl SampledRun {
    /// The allocations of the trajectory and commands, emptied, for reuse.
    pub(crate) fn into_storage(self) -> [Vec<f64>; 5] {
        let (t, x, u, y) = self.trajectory.into_parts();
        [
            t,
            Vec::from(x.data),
            Vec::from(u.data),
            Vec::from(y.data),
            Vec::from(self.commands.data),
        ]
    }
}

/// Column-major recording buffer for `cap` rows of `w` signals: a sample is written in place
/// (`data[i·cap + row]`), and the finished buffer becomes a matrix without copying (after
/// compaction if fewer rows were written).
struct Columns {
    data: Vec<f64>,
    cap: usize,
    w: usize,
}

impl Columns {
    /// Reuses `data`'s allocation (no fresh pages to fault in when it is large enough). A
    /// buffer of the right length is taken as it is, without zeroing: every row below the
    /// final row count is written before the matrix is formed, and `into_mat` cuts the rest.
    fn recycled(mut data: Vec<f64>, cap: usize, w: usize) -> Self {
        if data.len() != cap * w {
            data.clear();
            data.resize(cap * w, 0.0);
        }
        Self { data, cap, w }
    }

    #[inline(always)]
    fn set_row(&mut self, row: usize, v: &[f64]) {
        for (i, &vi) in v.iter().enumerate() {
            self.data[i * self.cap + row] = vi;
        }
    }

    fn into_mat(mut self, rows: usize) -> Mat {
        if rows < self.cap {
            for i in 1..self.w {
                self.data
                    .copy_within(i * self.cap..i * self.cap + rows, i * rows);
            }
            self.data.truncate(rows * self.w);
        }
        Mat::from_vec(rows, self.w, self.data)
    }
}
