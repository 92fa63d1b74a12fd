//! Integrators and open-loop simulation of any [`Dynamics`].
//!
//! | integrator | method | dense output | use |
//! |---|---|---|---|
//! | [`Integrator::Rk4`] | classic RK4, fixed step ([`rk4`]) | cubic Hermite (3rd order) | the sampled-data hot path, reproducible fixed grids |
//! | [`Integrator::Dopri45`] | Dormand–Prince 5(4), PI step control ([`dopri`]) | 4th-order continuous extension | accuracy-controlled runs, events |
//!
//! [`simulate`] integrates `ẋ = f(t, x, u(t))` from `x(t₀) = x₀` to `t_final` with an open-loop
//! [`Input`], records the solution at every step or on a requested time grid (through the
//! dense output), and locates [`Event`]s: zeros of a scalar function `g(t, x)` with a chosen
//! crossing direction, found by Brent's method on the dense output to rounding level (so an
//! event time is as accurate as the dense output, not limited by the step size), each either
//! recorded or terminal.
//!
//! Event detection compares the sign of `g` at consecutive step ends: two zeros inside one step
//! cancel out and are missed — bound the step with `h_max` if `g` can oscillate that fast.

pub mod dopri;
pub mod rk4;
mod root;

use crate::buffer::{Buf, with_buffer};
use crate::dynamics::Dynamics;
use crate::error::{Result, SimError, check_initial_state, check_len};
use crate::signal::Input;
use crate::systems::Driven;
use dopri::{Dopri, DopriParams};
use pendulab_lti::Trajectory;
use rk4::Rk4Scratch;

/// An integration method with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Integrator {
    /// Classic fourth-order Runge–Kutta with fixed step `dt` (s). In the sampled-data loop
    /// `dt` must divide the sample time.
    Rk4 {
        /// Step size in seconds (finite, > 0).
        dt: f64,
    },
    /// Adaptive Dormand–Prince 5(4) (Dormand & Prince 1980) with PI step control and
    /// 4th-order dense output. A step is accepted when the RMS of the error estimate scaled
    /// by `atol + rtol·|x|` is ≤ 1. Use [`Integrator::dopri45`] for the defaults.
    Dopri45 {
        /// Relative tolerance (> 0; below ~1e-14 the estimate drowns in rounding).
        rtol: f64,
        /// Absolute tolerance (≥ 0; `rtol` and `atol` not both tiny).
        atol: f64,
        /// Largest step (s); `None`: unbounded.
        h_max: Option<f64>,
        /// First step (s); `None`: chosen automatically (Hairer–Nørsett–Wanner §II.4).
        h_init: Option<f64>,
        /// Step budget per run (accepted + rejected); exceeding it is an error.
        max_steps: usize,
    },
}

impl Integrator {
    /// Dormand–Prince 5(4) with the given tolerances, no step bound, automatic first step and
    /// a budget of 10⁷ steps.
    pub fn dopri45(rtol: f64, atol: f64) -> Self {
        Integrator::Dopri45 {
            rtol,
            atol,
            h_max: None,
            h_init: None,
            max_steps: 10_000_000,
        }
    }

    /// Checks the parameters.
    ///
    /// # Errors
    /// [`SimError::InvalidStep`] for a non-positive or non-finite `dt`, `h_max` or `h_init`;
    /// [`SimError::InvalidParameter`] for bad tolerances or a zero step budget.
    pub fn validate(&self) -> Result<()> {
        match *self {
            Integrator::Rk4 { dt } => {
                if !(dt.is_finite() && dt > 0.0) {
                    return Err(SimError::InvalidStep {
                        what: "RK4 step dt",
                        value: dt,
                    });
                }
            }
            Integrator::Dopri45 {
                rtol,
                atol,
                h_max,
                h_init,
                max_steps,
            } => {
                if !(rtol.is_finite() && rtol > 0.0) {
                    return Err(SimError::InvalidParameter {
                        what: "rtol".into(),
                        value: rtol,
                        requirement: "must be finite and > 0",
                    });
                }
                if !(atol.is_finite() && atol >= 0.0) {
                    return Err(SimError::InvalidParameter {
                        what: "atol".into(),
                        value: atol,
                        requirement: "must be finite and >= 0",
                    });
                }
                for (what, v) in [("h_max", h_max), ("h_init", h_init)] {
                    if let Some(v) = v
                        && !(v.is_finite() && v > 0.0)
                    {
                        return Err(SimError::InvalidStep { what, value: v });
                    }
                }
                if max_steps == 0 {
                    return Err(SimError::InvalidParameter {
                        what: "max_steps".into(),
                        value: 0.0,
                        requirement: "must be >= 1",
                    });
                }
            }
        }
        Ok(())
    }

    pub(crate) fn dopri_params(&self) -> Option<DopriParams> {
        match *self {
            Integrator::Dopri45 {
                rtol,
                atol,
                h_max,
                h_init,
                max_steps,
            } => Some(DopriParams {
                rtol,
                atol,
                h_max: h_max.unwrap_or(f64::INFINITY),
                h_init,
                max_steps,
            }),
            Integrator::Rk4 { .. } => None,
        }
    }
}

impl Default for Integrator {
    /// `Dopri45` with `rtol = 1e-8`, `atol = 1e-10`.
    fn default() -> Self {
        Integrator::dopri45(1e-8, 1e-10)
    }
}

/// Which crossings of zero trigger an event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Direction {
    /// `g` goes from negative to non-negative.
    Rising,
    /// `g` goes from positive to non-positive.
    Falling,
    /// Either.
    #[default]
    Either,
}

type EventFunction = Box<dyn Fn(f64, &[f64]) -> f64 + Send + Sync>;

/// An event: a zero of the scalar function `g(t, x)` crossed in the given direction.
///
/// A terminal event stops the integration at the located time (the final sample of the
/// trajectory is the state there); a non-terminal one is only recorded.
pub struct Event {
    g: EventFunction,
    direction: Direction,
    terminal: bool,
}

impl Event {
    /// A non-terminal event on zeros of `g` crossed in either direction.
    pub fn new<G: Fn(f64, &[f64]) -> f64 + Send + Sync + 'static>(g: G) -> Self {
        Self {
            g: Box::new(g),
            direction: Direction::Either,
            terminal: false,
        }
    }
    /// Sets the crossing direction.
    pub fn direction(mut self, direction: Direction) -> Self {
        self.direction = direction;
        self
    }
    /// Makes the event terminal.
    pub fn terminal(mut self) -> Self {
        self.terminal = true;
        self
    }
    /// Evaluates `g(t, x)`.
    pub fn g(&self, t: f64, x: &[f64]) -> f64 {
        (self.g)(t, x)
    }
    fn triggered(&self, g0: f64, g1: f64) -> bool {
        let rising = g0 < 0.0 && g1 >= 0.0;
        let falling = g0 > 0.0 && g1 <= 0.0;
        match self.direction {
            Direction::Rising => rising,
            Direction::Falling => falling,
            Direction::Either => rising || falling,
        }
    }
}

impl std::fmt::Debug for Event {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Event")
            .field("direction", &self.direction)
            .field("terminal", &self.terminal)
            .finish_non_exhaustive()
    }
}

/// Where the solution is recorded.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Output {
    /// At `t₀` and at the end of every accepted step (and at a terminal event).
    #[default]
    Steps,
    /// At the given times (sorted, inside `[t₀, t_final]`), by dense output; a terminal
    /// event ends the list early and adds the event instant.
    Times(Vec<f64>),
}

/// Options of [`simulate`].
#[derive(Debug)]
pub struct OdeOptions {
    /// Start time `t₀` (s). Default 0.
    pub t0: f64,
    /// The integrator. Default [`Integrator::default`] (Dopri45, rtol 1e-8, atol 1e-10).
    pub integrator: Integrator,
    /// Output times. Default [`Output::Steps`].
    pub output: Output,
    /// Events to locate. Default none.
    pub events: Vec<Event>,
}

impl Default for OdeOptions {
    fn default() -> Self {
        Self {
            t0: 0.0,
            integrator: Integrator::default(),
            output: Output::Steps,
            events: Vec::new(),
        }
    }
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Status {
    /// Reached `t_final`.
    Completed,
    /// Stopped by a terminal event.
    Terminated {
        /// Index of the event in [`OdeOptions::events`].
        event: usize,
        /// Time of the event (s).
        t: f64,
    },
}

/// One located event.
#[derive(Debug, Clone, PartialEq)]
pub struct EventHit {
    /// Index of the event in [`OdeOptions::events`].
    pub event: usize,
    /// Time of the zero crossing (s).
    pub t: f64,
    /// State at that time (dense output).
    pub x: Vec<f64>,
}

/// Work counters of an integration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IntegrationStats {
    /// Accepted steps.
    pub accepted_steps: usize,
    /// Rejected steps (adaptive integrators).
    pub rejected_steps: usize,
    /// Evaluations of `f`.
    pub evaluations: usize,
}

/// The result of [`simulate`].
#[derive(Debug, Clone, PartialEq)]
pub struct Simulation {
    /// States, inputs (`u(t)` at the recorded times) and outputs (if the system has an output
    /// map) at the recorded times.
    pub trajectory: Trajectory,
    /// How the run ended.
    pub status: Status,
    /// Every located event, in time order.
    pub events: Vec<EventHit>,
    /// Work counters.
    pub stats: IntegrationStats,
}

/// Integrates `ẋ = f(t, x, u(t))` from `x(t₀) = x₀` to `t_final` (see the module docs).
///
/// For [`Integrator::Rk4`] the steps are `t_k = t₀ + k·dt` (computed from `k`, so time does
/// not drift), the last one shortened to end exactly at `t_final`.
///
/// # Errors
/// [`SimError::DimensionMismatch`] if `x₀` or the input width does not fit the system;
/// [`SimError::NonFiniteInitialState`]; [`SimError::InvalidTimeSpan`] unless
/// `t₀ < t_final` are finite; integrator parameter errors ([`Integrator::validate`]);
/// [`SimError::InvalidArgument`] for output times that are unsorted or outside the span;
/// [`SimError::NonFiniteState`] naming the time at which the state blew up;
/// [`SimError::StepSizeUnderflow`], [`SimError::MaxStepsExceeded`] for the adaptive method.
#[doc(alias = "ode45")]
pub fn simulate<S, I>(
    sys: &S,
    input: &I,
    x0: &[f64],
    t_final: f64,
    options: &OdeOptions,
) -> Result<Simulation>
where
    S: Dynamics + ?Sized,
    I: Input + ?Sized,
{
    let nx = sys.nx();
    check_initial_state(x0, nx)?;
    check_len("input width", input.nu(), sys.nu())?;
    check_span(options.t0, t_final)?;
    options.integrator.validate()?;
    if let Output::Times(times) = &options.output {
        if let Some(i) = times.windows(2).position(|w| w[1] < w[0] || w[1].is_nan()) {
            return Err(SimError::InvalidArgument(format!(
                "output times must be sorted: times[{i}] = {} > times[{}] = {}",
                times[i],
                i + 1,
                times[i + 1]
            )));
        }
        if let Some(&t) = times.iter().find(|&&t| !(t >= options.t0 && t <= t_final)) {
            return Err(SimError::InvalidArgument(format!(
                "output time {t} lies outside [t0, t_final] = [{}, {t_final}]",
                options.t0
            )));
        }
    }
    let driven = Driven::new(sys, input)?;
    with_buffer!(nx, B => run_ode::<_, _, B>(&driven, sys, input, x0, t_final, options))
}

/// Integrates an autonomous system (or one whose inputs are all zero) — [`simulate`] with
/// zero input.
///
/// # Errors
/// As [`simulate`].
pub fn simulate_free<S: Dynamics + ?Sized>(
    sys: &S,
    x0: &[f64],
    t_final: f64,
    options: &OdeOptions,
) -> Result<Simulation> {
    simulate(
        sys,
        &crate::signal::ZeroInput(sys.nu()),
        x0,
        t_final,
        options,
    )
}

pub(crate) fn check_span(t0: f64, t_final: f64) -> Result<()> {
    if !(t0.is_finite() && t_final.is_finite()) {
        return Err(SimError::InvalidTimeSpan {
            what: "times must be finite",
            t0,
            t_final,
        });
    }
    if t_final <= t0 {
        return Err(SimError::InvalidTimeSpan {
            what: "t_final must be later than t0",
            t0,
            t_final,
        });
    }
    Ok(())
}

/// One-step integrator with a dense output over its last step.
enum Stepper<B: Buf> {
    Rk4 {
        dt: f64,
        k: u64,
        w: Rk4Scratch<B>,
        y1: B,
        f1: B,
        h: f64,
        k1_known: bool,
        evaluations: usize,
        steps: usize,
    },
    Dopri {
        d: Box<Dopri<B>>,
        h: f64,
        fsal: bool,
    },
}

impl<B: Buf> Stepper<B> {
    fn new(integrator: &Integrator, n: usize) -> Self {
        match integrator {
            Integrator::Rk4 { dt } => Stepper::Rk4 {
                dt: *dt,
                k: 0,
                w: Rk4Scratch::new(n),
                y1: B::zeros(n),
                f1: B::zeros(n),
                h: 0.0,
                k1_known: false,
                evaluations: 0,
                steps: 0,
            },
            Integrator::Dopri45 { .. } => {
                let p = integrator.dopri_params().expect("Dopri45 parameters");
                Stepper::Dopri {
                    d: Box::new(Dopri::new(n, p)),
                    h: 0.0,
                    fsal: false,
                }
            }
        }
    }

    /// Takes one accepted step from `(t, y)`; returns its end time. `t0` is the start of the
    /// run (for the drift-free RK4 grid).
    fn step<S: Dynamics + ?Sized>(
        &mut self,
        sys: &S,
        t0: f64,
        t: f64,
        y: &B,
        t_final: f64,
    ) -> Result<f64> {
        match self {
            Stepper::Rk4 {
                dt,
                k,
                w,
                y1,
                f1,
                h,
                k1_known,
                evaluations,
                steps,
            } => {
                let mut t1 = t0 + (*k + 1) as f64 * *dt;
                // Land exactly on t_final (also when the grid overshoots it by rounding).
                if t1 >= t_final - 1e-9 * *dt {
                    t1 = t_final;
                }
                *h = t1 - t;
                y1.m().copy_from_slice(y.s());
                if *k1_known {
                    std::mem::swap(&mut w.k1, f1);
                }
                rk4::step_generic(sys, t, y1, &[], *h, w, *k1_known);
                *evaluations += if *k1_known { 3 } else { 4 };
                crate::error::check_state(t1, y1.s())?;
                // f at the step end: the Hermite interpolant's end slope and the next k1.
                sys.derivative(t1, y1.s(), &[], f1.m());
                *evaluations += 1;
                *k1_known = true;
                *k += 1;
                *steps += 1;
                Ok(t1)
            }
            Stepper::Dopri { d, h, fsal } => {
                let span = t_final - t;
                if *fsal {
                    std::mem::swap(&mut d.k1, &mut d.k7);
                } else {
                    sys.derivative(t, y.s(), &[], d.k1.m());
                    d.evaluations += 1;
                }
                if *h <= 0.0 {
                    *h = match d.params.h_init {
                        Some(h0) => h0.min(span),
                        None => d.initial_step(sys, t, y, &[], span),
                    };
                }
                let mut after_reject = false;
                loop {
                    if d.accepted + d.rejected >= d.params.max_steps {
                        return Err(SimError::MaxStepsExceeded {
                            t,
                            max_steps: d.params.max_steps,
                        });
                    }
                    let mut hs = h.min(d.params.h_max);
                    // Stretch a step that would leave a sliver before t_final.
                    let last = hs >= span * (1.0 - 1e-12) || span - hs < 1e-3 * hs;
                    if last {
                        hs = span;
                    }
                    if hs <= 4.0 * f64::EPSILON * t.abs().max(1.0) {
                        return Err(SimError::StepSizeUnderflow { t, h: hs });
                    }
                    let att = d.attempt(sys, t, y, &[], hs);
                    let ok = att.err <= 1.0 && d.y1.s().iter().all(|v| v.is_finite());
                    if ok {
                        *h = d.next_step(att.err, hs, true, after_reject);
                        d.accepted += 1;
                        *fsal = true;
                        // The step size actually used (for the dense output).
                        d.h_used = hs;
                        let t1 = if last { t_final } else { t + hs };
                        return Ok(t1);
                    }
                    *h = d.next_step(att.err, hs, false, after_reject);
                    d.rejected += 1;
                    after_reject = true;
                }
            }
        }
    }

    /// The state at the end of the last step.
    fn y1(&self) -> &B {
        match self {
            Stepper::Rk4 { y1, .. } => y1,
            Stepper::Dopri { d, .. } => &d.y1,
        }
    }

    /// Dense output of the last step `[t, t1]` from `y` at time `s`.
    fn dense(&self, t: f64, t1: f64, y: &B, s: f64, out: &mut [f64]) {
        match self {
            Stepper::Rk4 { w, y1, f1, .. } => {
                // Cubic Hermite interpolation through (y, f(t, y)) and (y1, f(t1, y1)).
                let h = t1 - t;
                let th = ((s - t) / h).clamp(0.0, 1.0);
                let (th2, th3) = (th * th, th * th * th);
                let h00 = 2.0 * th3 - 3.0 * th2 + 1.0;
                let h10 = th3 - 2.0 * th2 + th;
                let h01 = -2.0 * th3 + 3.0 * th2;
                let h11 = th3 - th2;
                let (y0, f0, y1, f1) = (y.s(), w.k1.s(), y1.s(), f1.s());
                for i in 0..out.len() {
                    out[i] = h00 * y0[i] + h10 * h * f0[i] + h01 * y1[i] + h11 * h * f1[i];
                }
            }
            Stepper::Dopri { d, .. } => {
                let h = d.h_used;
                let th = ((s - t) / h).clamp(0.0, 1.0);
                d.dense(y.s(), h, th, out);
            }
        }
    }

    fn stats(&self) -> IntegrationStats {
        match self {
            Stepper::Rk4 {
                evaluations, steps, ..
            } => IntegrationStats {
                accepted_steps: *steps,
                rejected_steps: 0,
                evaluations: *evaluations,
            },
            Stepper::Dopri { d, .. } => IntegrationStats {
                accepted_steps: d.accepted,
                rejected_steps: d.rejected,
                evaluations: d.evaluations,
            },
        }
    }
}

/// Row-major recording buffers.
struct Recorder {
    t: Vec<f64>,
    x: Vec<f64>,
    u: Vec<f64>,
    y: Vec<f64>,
    ubuf: Vec<f64>,
    ybuf: Vec<f64>,
}

impl Recorder {
    fn push<S: Dynamics + ?Sized, I: Input + ?Sized>(
        &mut self,
        sys: &S,
        input: &I,
        t: f64,
        x: &[f64],
    ) {
        self.t.push(t);
        self.x.extend_from_slice(x);
        input.eval(t, &mut self.ubuf);
        self.u.extend_from_slice(&self.ubuf);
        if !self.ybuf.is_empty() {
            sys.output(t, x, &self.ubuf, &mut self.ybuf);
            self.y.extend_from_slice(&self.ybuf);
        }
    }
}

fn run_ode<D, S, B>(
    driven: &D,
    sys: &S,
    input: &(impl Input + ?Sized),
    x0: &[f64],
    t_final: f64,
    options: &OdeOptions,
) -> Result<Simulation>
where
    D: Dynamics + ?Sized,
    S: Dynamics + ?Sized,
    B: Buf,
{
    let nx = x0.len();
    let t0 = options.t0;
    let mut rec = Recorder {
        t: Vec::new(),
        x: Vec::new(),
        u: Vec::new(),
        y: Vec::new(),
        ubuf: vec![0.0; sys.nu()],
        ybuf: vec![0.0; sys.ny()],
    };
    let mut y = B::zeros(nx);
    y.m().copy_from_slice(x0);
    let mut stepper = Stepper::<B>::new(&options.integrator, nx);
    let events = &options.events;
    let mut g_prev: Vec<f64> = events.iter().map(|e| e.g(t0, x0)).collect();
    let mut g_new = vec![0.0; events.len()];
    let mut hits: Vec<EventHit> = Vec::new();
    let mut scratch = vec![0.0; nx];
    let mut next_out = 0usize;
    let times: &[f64] = match &options.output {
        Output::Times(ts) => ts,
        Output::Steps => &[],
    };
    let steps_mode = matches!(options.output, Output::Steps);
    // Outputs at t0.
    if steps_mode {
        rec.push(sys, input, t0, x0);
    } else {
        while next_out < times.len() && times[next_out] <= t0 {
            rec.push(sys, input, times[next_out], x0);
            next_out += 1;
        }
    }
    let mut t = t0;
    let mut status = Status::Completed;
    while t < t_final {
        let t1 = stepper.step(driven, t0, t, &y, t_final)?;
        // Events in (t, t1].
        let mut stop: Option<(usize, f64)> = None;
        let first_hit = hits.len();
        if !events.is_empty() {
            for (e, ev) in events.iter().enumerate() {
                g_new[e] = ev.g(t1, stepper.y1().s());
            }
            for (e, ev) in events.iter().enumerate() {
                if !ev.triggered(g_prev[e], g_new[e]) {
                    continue;
                }
                let tol = 4.0 * f64::EPSILON * t1.abs().max(1.0);
                let te = root::brent(
                    |s| {
                        stepper.dense(t, t1, &y, s, &mut scratch);
                        ev.g(s, &scratch)
                    },
                    t,
                    t1,
                    g_prev[e],
                    g_new[e],
                    tol,
                    200,
                );
                stepper.dense(t, t1, &y, te, &mut scratch);
                hits.push(EventHit {
                    event: e,
                    t: te,
                    x: scratch.clone(),
                });
                if ev.terminal && stop.is_none_or(|(_, ts)| te < ts) {
                    stop = Some((e, te));
                }
            }
            hits[first_hit..].sort_by(|a, b| a.t.total_cmp(&b.t));
            if let Some((_, ts)) = stop {
                // Keep only the events up to the terminal one.
                hits.truncate(
                    first_hit + hits[first_hit..].iter().take_while(|h| h.t <= ts).count(),
                );
            }
            std::mem::swap(&mut g_prev, &mut g_new);
        }
        let t_end = stop.map_or(t1, |(_, ts)| ts);
        // Outputs in (t, t_end].
        if steps_mode {
            if stop.is_some() {
                stepper.dense(t, t1, &y, t_end, &mut scratch);
                rec.push(sys, input, t_end, &scratch);
            } else {
                rec.push(sys, input, t1, stepper.y1().s());
            }
        } else {
            while next_out < times.len() && times[next_out] <= t_end {
                let s = times[next_out];
                if s >= t1 {
                    rec.push(sys, input, s, stepper.y1().s());
                } else {
                    stepper.dense(t, t1, &y, s, &mut scratch);
                    rec.push(sys, input, s, &scratch);
                }
                next_out += 1;
            }
            if stop.is_some() && rec.t.last().is_none_or(|&tl| tl < t_end) {
                stepper.dense(t, t1, &y, t_end, &mut scratch);
                rec.push(sys, input, t_end, &scratch);
            }
        }
        if let Some((event, te)) = stop {
            status = Status::Terminated { event, t: te };
            break;
        }
        y.m().copy_from_slice(stepper.y1().s());
        t = t1;
    }
    let ny = rec.ybuf.len();
    let trajectory =
        Trajectory::from_row_major(rec.t, (nx, &rec.x), (rec.ubuf.len(), &rec.u), (ny, &rec.y))?;
    Ok(Simulation {
        trajectory,
        status,
        events: hits,
        stats: stepper.stats(),
    })
}
