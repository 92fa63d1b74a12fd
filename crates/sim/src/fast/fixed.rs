//! The fixed-size closed-loop kernel: the common sampled-data loop — a single-input plant with
//! a compile-time state size `N`, static state feedback `u = −K (x − x_ref)` or the LQ
//! integral servo from the exact state ([`FixedController`]), zero-order hold, classic RK4
//! substeps, optionally a saturation — compiled into one monomorphised loop on `[f64; N]`: no
//! dynamic dispatch, no allocation and no slices of run-time length per step, recording into a
//! preallocated column-major (structure of arrays) trajectory.
//!
//! [`FixedLoop`] is built from the parts of a [`SampledLoop`] ([`SampledLoop::fixed`], which
//! refuses configurations the kernel does not cover) or directly ([`FixedLoop::new`]). Its
//! runs are **bit-identical** to [`SampledLoop::run_with`] of the same configuration: every
//! arithmetic operation of the general loop is performed in the same order (the sample times
//! `t_k = t₀ + k·ts`, the substep `h = t_{k+1} − t_k`, the controller's update, the RK4
//! stages of [`crate::rk4_step`], the saturation of [`crate::Actuator::apply`]), provided the
//! plant's [`FixedDynamics::derivative_fixed`] performs the operations of its
//! [`Dynamics::derivative`] and it keeps the provided [`FixedDynamics::rk4_step_fixed`] (as
//! `pendulab_plants::CartPendulum` does; its kernel type `pendulab_plants::cart::fast::FastCart`
//! with [`Trig::Anchored`](crate::fast::Trig::Anchored) overrides the step).
//! `tests/fixed.rs` checks the identity, records included, with and without saturation,
//! monitor stops, substeps and the LQ servo.
//!
//! **Fused multiply–add.** The loop is compiled twice: for the baseline target and, on
//! x86-64, inside a function compiled for FMA that a run takes when the processor has it
//! (detected at run time; [`FixedLoop::multiply_add`] tells which). The two differ only where
//! the plant's step asks for it: [`FixedDynamics::rk4_step_fixed_with`] receives the
//! multiply–add strategy ([`Fused`](crate::fast::Fused) or [`Separate`](crate::fast::Separate), see [`MulAdd`](crate::fast::MulAdd)), and a plant may
//! evaluate its `a·b + c` by `F::mul_add` — the cart's anchored step (`FastCart` with
//! [`Trig::Anchored`](crate::fast::Trig::Anchored)) does. Rust never contracts
//! `a * b + c` on its own, so every other operation rounds as in the baseline loop and the
//! provided steps stay bit-identical on either path (`tests/fixed.rs` runs both).
//!
//! ```
//! use pendulab_lti::Mat;
//! use pendulab_sim::controllers::StaticStateFeedback;
//! use pendulab_sim::fast::FixedDynamics;
//! use pendulab_sim::{Dynamics, SampledLoop, SampledOptions};
//! # fn main() -> Result<(), pendulab_sim::SimError> {
//! // A double integrator ẋ = [x₁, u] as a fixed-size plant.
//! #[derive(Clone)]
//! struct Di;
//! impl Dynamics for Di {
//!     fn nx(&self) -> usize { 2 }
//!     fn nu(&self) -> usize { 1 }
//!     fn derivative(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
//!         dx[0] = x[1];
//!         dx[1] = u[0];
//!     }
//! }
//! impl FixedDynamics<2> for Di {
//!     fn derivative_fixed(&self, x: &[f64; 2], u: f64) -> [f64; 2] { [x[1], u] }
//! }
//! let k = StaticStateFeedback::new(Mat::from_row_slice(1, 2, &[1.0, 1.5]))?;
//! let opts = SampledOptions { ts: 0.01, t_final: 20.0, ..Default::default() };
//! let mut general = SampledLoop::new(Di, k, opts)?;
//! let mut fast = general.fixed::<2>()?;
//! let a = fast.run(&[1.0, 0.0])?;
//! assert_eq!(a, general.run(&[1.0, 0.0])?); // bit for bit, trajectory included
//! assert!(a.diagnostics.final_state[0].abs() < 1e-3);
//! # Ok(()) }
//! ```

use crate::controller::Controller;
use crate::controllers::{LqIntegralServo, StaticStateFeedback};
use crate::dynamics::Dynamics;
use crate::error::{Result, SimError, check_initial_state, check_len, check_state};
use crate::integrate::rk4::{Rk4Scratch, step_with};
use crate::integrate::{IntegrationStats, Integrator};
use crate::monitor::{Flow, Monitor};
use crate::sampled::{
    Record, RunStatus, SampledDiagnostics, SampledLoop, SampledOptions, SampledRun,
    validate_options,
};
use pendulab_lti::{Mat, Trajectory};

#[cfg(target_arch = "x86_64")]
use super::strategy::Fused;
use super::strategy::{MulAdd, MulAddPath, Separate};

/// An autonomous single-input plant `ẋ = f(x, u)` with `N` states, evaluated on arrays.
///
/// Contract: for the kernel to reproduce [`SampledLoop`] bit for bit, `derivative_fixed(x, u)`
/// must return what [`Dynamics::derivative`]`(t, x, &[u], ·)` writes, for every `t` (the plant
/// may not depend on time).
pub trait FixedDynamics<const N: usize> {
    /// `ẋ = f(x, u)`.
    fn derivative_fixed(&self, x: &[f64; N], u: f64) -> [f64; N];

    /// One classic RK4 step of `h` with `u` held, in place (provided: [`rk4_fixed`], the
    /// operations of [`crate::rk4_step`]). A plant may override it with a step that shares
    /// work between the stages (e.g. `pendulab_plants::cart::fast::FastCart` with
    /// [`crate::fast::Trig::Anchored`]); the kernel is then as close to the general loop as
    /// that override documents, no longer bit-identical.
    #[inline(always)]
    fn rk4_step_fixed(&self, x: &mut [f64; N], u: f64, h: f64) {
        rk4_fixed(self, x, u, h);
    }

    /// [`FixedDynamics::rk4_step_fixed`] for a kernel that offers the multiply–add strategy
    /// `F` ([`Fused`](crate::fast::Fused) inside [`FixedLoop`]'s FMA-compiled loop, [`Separate`](crate::fast::Separate) elsewhere):
    /// a plant's own step may evaluate its `a·b + c` by `F::mul_add`. Provided: the plain
    /// [`FixedDynamics::rk4_step_fixed`], which ignores `F` — a step that must stay
    /// bit-identical to the general loop keeps it.
    #[inline(always)]
    fn rk4_step_fixed_with<F: MulAdd>(&self, x: &mut [f64; N], u: f64, h: f64) {
        self.rk4_step_fixed(x, u, h);
    }

    /// Hands `visitor` the stepper a whole run takes ([`StepVisitor::visit`]), chosen once
    /// before the loop rather than at every step. Provided: the plant itself (its
    /// [`FixedDynamics::rk4_step_fixed_with`], through the blanket [`FixedStep`]). A plant
    /// whose step depends on a run-time switch (e.g. `pendulab_plants::cart::fast::FastCart`
    /// and its [`Trig`](crate::fast::Trig)) overrides it to pass one stepper type per choice,
    /// so that [`FixedLoop`] compiles one loop per choice with no branch per step. Every
    /// stepper passed must take the steps [`FixedDynamics::rk4_step_fixed_with`] takes.
    #[inline(always)]
    fn visit_stepper<V: StepVisitor<N>>(&self, visitor: V) -> V::Output
    where
        Self: Sized,
    {
        visitor.visit(self)
    }
}

/// One RK4 step of `h` with `u` held, in place, with the multiply–add strategy `F`: what
/// [`FixedLoop`]'s run loop calls per step. Implemented by every [`FixedDynamics`] plant (its
/// [`FixedDynamics::rk4_step_fixed_with`]) and by the stepper types a plant hands out from
/// [`FixedDynamics::visit_stepper`].
pub trait FixedStep<const N: usize> {
    /// One step from `x(t)` to `x(t + h)` (`h` in the plant's time unit, s).
    fn step<F: MulAdd>(&self, x: &mut [f64; N], u: f64, h: f64);
}

impl<P: FixedDynamics<N>, const N: usize> FixedStep<N> for P {
    #[inline(always)]
    fn step<F: MulAdd>(&self, x: &mut [f64; N], u: f64, h: f64) {
        self.rk4_step_fixed_with::<F>(x, u, h);
    }
}

/// What runs with the stepper a plant chooses ([`FixedDynamics::visit_stepper`]): a generic
/// method, so the visitor's code is compiled once per stepper type.
pub trait StepVisitor<const N: usize> {
    /// The visit's result.
    type Output;
    /// Runs with `stepper`.
    fn visit<S: FixedStep<N>>(self, stepper: &S) -> Self::Output;
}

/// One classic RK4 step of `h` with `u` held: the crate's one RK4 stepper
/// ([`crate::integrate::rk4`], the operations of [`crate::rk4_step`]) on `[f64; N]` with the
/// plant's [`FixedDynamics::derivative_fixed`].
#[inline(always)]
pub fn rk4_fixed<P: FixedDynamics<N> + ?Sized, const N: usize>(
    plant: &P,
    x: &mut [f64; N],
    u: f64,
    h: f64,
) {
    let mut w = Rk4Scratch::<[f64; N]>::new(N);
    step_with(
        #[inline(always)]
        |_, x: &[f64; N], dx: &mut [f64; N]| *dx = plant.derivative_fixed(x, u),
        0.0,
        x,
        h,
        &mut w,
        false,
    );
}

/// A controller the fixed-size kernel runs: one command from the exact state of `N` entries.
///
/// Contract: `command(t, x)` returns what [`Controller::update`]`(t, x, u)` writes into its
/// single entry `u[0]` (and updates the internal state the same way). Implemented by
/// [`StaticStateFeedback`] (on arrays: the gain's `N` products summed in order) and
/// [`LqIntegralServo`] (its own `update`).
pub trait FixedController<const N: usize>: Controller {
    /// Whether [`FixedController::command`] returns a non-finite command for every state
    /// with a non-finite entry. [`FixedLoop`] then checks the state only where the command is
    /// not finite (same error, same time as the general loop's check after each step), not
    /// after every step. Default `false`.
    const NON_FINITE_STATE_GIVES_NON_FINITE_COMMAND: bool = false;
    /// The command `u_k` for the state `x(t_k)` at `t_k` (s).
    fn command(&mut self, t: f64, x: &[f64; N]) -> f64;
}

impl<const N: usize> FixedController<N> for StaticStateFeedback {
    /// `u = −Σ K_i (x_i − x_ref,i)` with finite `K` and `x_ref`: a non-finite `x_i` makes its
    /// term NaN or ±∞ (`0·∞` is NaN), and a sum with such a term is NaN or ±∞.
    const NON_FINITE_STATE_GIVES_NON_FINITE_COMMAND: bool = true;
    #[inline(always)]
    fn command(&mut self, _t: f64, x: &[f64; N]) -> f64 {
        let (k, r, zero_ref) = self.parts();
        // One length check each, then no more: `u = −(0 + Σ K_i (x_i − x_ref,i))` in the
        // order of `Controller::update` (`x − 0` is `x` bit for bit, so a zero reference is
        // skipped: the subtraction would lengthen the chain state → command → step, which
        // bounds the loop, by its latency).
        let (k, r) = (&k[..N], &r[..N]);
        let mut acc = 0.0;
        if zero_ref {
            for i in 0..N {
                acc += k[i] * x[i];
            }
        } else {
            for i in 0..N {
                acc += k[i] * (x[i] - r[i]);
            }
        }
        -acc
    }
}

impl<const N: usize> FixedController<N> for LqIntegralServo {
    #[inline(always)]
    fn command(&mut self, t: f64, x: &[f64; N]) -> f64 {
        let mut u = [0.0];
        self.update(t, x, &mut u);
        u[0]
    }
}

/// The fixed-size closed loop (see the module docs): plant `P` with `N` states, a
/// [`FixedController`] `C` on the exact state, ZOH every `ts`, RK4 substeps, optional
/// saturation of the plant input to `[lo, hi]`.
#[derive(Debug, Clone)]
pub struct FixedLoop<P, C, const N: usize> {
    plant: P,
    controller: C,
    saturation: Option<(f64, f64)>,
    ts: f64,
    t0: f64,
    samples: usize,
    nsub: usize,
    every: Option<usize>,
    fused: bool,
}

impl<P: FixedDynamics<N>, C: FixedController<N>, const N: usize> FixedLoop<P, C, N> {
    /// Closes `plant` with `controller` under `options`, full-state measurement, ideal
    /// actuator (add a saturation with [`FixedLoop::with_saturation`]).
    ///
    /// # Errors
    /// The errors of [`SampledLoop::new`] for the options; [`SimError::DimensionMismatch`]
    /// unless the controller has one command and `N` measurements;
    /// [`SimError::SampleTimeMismatch`] if the controller was designed for another `ts`;
    /// [`SimError::InvalidArgument`] for options the kernel does not cover: an integrator
    /// other than RK4, a computation delay (the initial input then plays no part).
    pub fn new(plant: P, controller: C, options: &SampledOptions) -> Result<Self> {
        let timing = validate_options(options, 1)?;
        check_len(
            "controller commands (fixed kernel: one)",
            controller.nu(),
            1,
        )?;
        check_len("controller measurements (the state)", controller.ny(), N)?;
        if !matches!(options.integrator, Integrator::Rk4 { .. }) {
            return Err(unsupported("an integrator other than RK4"));
        }
        if timing.split.is_some() || timing.ring > 0 {
            return Err(unsupported("a computation delay"));
        }
        if let Some(tc) = controller.sample_time()
            && (tc - options.ts).abs() > 1e-12 * options.ts
        {
            return Err(SimError::SampleTimeMismatch {
                controller: tc,
                sampled: options.ts,
            });
        }
        Ok(Self {
            plant,
            controller,
            saturation: None,
            ts: options.ts,
            t0: options.t0,
            samples: timing.samples,
            nsub: timing.nsub,
            every: match options.record {
                Record::EverySample => Some(1),
                Record::Every(n) => Some(n),
                Record::Off => None,
            },
            fused: true,
        })
    }

    /// Saturates the plant input to `[lo, hi]` (as [`crate::Actuator::saturation_range`]).
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] unless `lo < hi`, both finite.
    pub fn with_saturation(mut self, lo: f64, hi: f64) -> Result<Self> {
        crate::Actuator::ideal().saturation_range(lo, hi)?;
        self.saturation = Some((lo, hi));
        Ok(self)
    }

    /// The multiply–add the runs may offer the plant's step: [`MulAddPath::Fused`](crate::fast::MulAddPath::Fused) (the
    /// default) runs the loop compiled for FMA where the processor has it (detected at run
    /// time; elsewhere the baseline loop), [`MulAddPath::Separate`](crate::fast::MulAddPath::Separate) always the baseline loop.
    /// Only a plant that evaluates `a·b + c` by [`FixedDynamics::rk4_step_fixed_with`]'s
    /// strategy sees a difference; with the provided steps the runs are the same either way.
    pub fn with_multiply_add(mut self, path: MulAddPath) -> Self {
        self.fused = path == MulAddPath::Fused;
        self
    }

    /// The multiply–add a run takes on this processor ([`FixedLoop::with_multiply_add`]).
    pub fn multiply_add(&self) -> MulAddPath {
        if self.fused && fma_detected() {
            MulAddPath::Fused
        } else {
            MulAddPath::Separate
        }
    }

    /// The plant.
    pub fn plant(&self) -> &P {
        &self.plant
    }

    /// The controller.
    pub fn controller(&self) -> &C {
        &self.controller
    }

    /// Number of samples `N + 1` a complete run takes.
    pub fn samples(&self) -> usize {
        self.samples + 1
    }

    /// Runs from `x(t₀) = x0` (controller reset first).
    ///
    /// # Errors
    /// As [`SampledLoop::run`].
    pub fn run(&mut self, x0: &[f64]) -> Result<SampledRun> {
        self.run_inner(x0, &mut (), None)
    }

    crate::sampled::monitored_runs!();

    fn run_inner<M: Monitor + ?Sized>(
        &mut self,
        x0: &[f64],
        monitor: &mut M,
        storage: Option<SampledRun>,
    ) -> Result<SampledRun> {
        let fused = self.multiply_add() == MulAddPath::Fused;
        self.plant.visit_stepper(Run {
            settings: Settings {
                saturation: self.saturation,
                ts: self.ts,
                t0: self.t0,
                samples: self.samples,
                nsub: self.nsub,
                every: self.every,
            },
            fused,
            controller: &mut self.controller,
            x0,
            monitor,
            storage,
        })
    }
}

/// A [`FixedLoop`]'s settings, copied for one run.
#[derive(Debug, Clone, Copy)]
struct Settings {
    saturation: Option<(f64, f64)>,
    ts: f64,
    t0: f64,
    samples: usize,
    nsub: usize,
    every: Option<usize>,
}

/// One run of a [`FixedLoop`]: its settings, the controller and the run's arguments, the
/// [`StepVisitor`] the plant hands its stepper to ([`FixedDynamics::visit_stepper`]), so the
/// loop is compiled once per stepper type (and once more for FMA) with the step fixed.
struct Run<'a, C, M: ?Sized> {
    settings: Settings,
    /// Whether to take the FMA-compiled loop ([`FixedLoop::multiply_add`] is `Fused`); read on
    /// x86-64 only, the one target with an FMA-compiled copy.
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    fused: bool,
    controller: &'a mut C,
    x0: &'a [f64],
    monitor: &'a mut M,
    storage: Option<SampledRun>,
}

impl<C: FixedController<N>, M: Monitor + ?Sized, const N: usize> StepVisitor<N> for Run<'_, C, M> {
    type Output = Result<SampledRun>;

    /// Hands the loop each reference as a parameter of its own (not inside the visitor), so
    /// that the compiler knows the controller, the monitor and the stepper apart from the
    /// recorded columns and keeps what it loads from them out of the loop.
    #[inline(always)]
    fn visit<S: FixedStep<N>>(self, stepper: &S) -> Result<SampledRun> {
        let Run {
            settings,
            fused,
            controller,
            x0,
            monitor,
            storage,
        } = self;
        #[cfg(target_arch = "x86_64")]
        if fused {
            // SAFETY: `fused` is set only if the processor supports FMA (detected at run
            // time by `FixedLoop::multiply_add`), the only requirement of calling a function
            // compiled with `target_feature(enable = "fma")`.
            return unsafe { run_fused(settings, controller, stepper, x0, monitor, storage) };
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = fused;
        run_loop::<Separate, C, S, M, N>(settings, controller, stepper, x0, monitor, storage)
    }
}

/// [`run_loop`] with [`Fused`](crate::fast::Fused), compiled for FMA. Rust does not contract
/// `a * b + c`, so only the stepper's `F::mul_add` differs from the baseline loop.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
fn run_fused<C: FixedController<N>, S: FixedStep<N>, M: Monitor + ?Sized, const N: usize>(
    settings: Settings,
    controller: &mut C,
    stepper: &S,
    x0: &[f64],
    monitor: &mut M,
    storage: Option<SampledRun>,
) -> Result<SampledRun> {
    run_loop::<Fused, C, S, M, N>(settings, controller, stepper, x0, monitor, storage)
}

/// The loop itself, the stepper's step with the multiply–add `F`.
#[inline(always)]
fn run_loop<
    F: MulAdd,
    C: FixedController<N>,
    S: FixedStep<N>,
    M: Monitor + ?Sized,
    const N: usize,
>(
    settings: Settings,
    controller: &mut C,
    stepper: &S,
    x0: &[f64],
    monitor: &mut M,
    storage: Option<SampledRun>,
) -> Result<SampledRun> {
    let Settings {
        saturation,
        ts,
        t0,
        samples: n_samples,
        nsub,
        every: record_every,
    } = settings;
    check_initial_state(x0, N)?;
    controller.reset();
    let mut x: [f64; N] = std::array::from_fn(|i| x0[i]);
    let cap = record_every.map_or(0, |e| n_samples / e + 1);
    let [mut bt, bx, bu, by, bc] = storage.map_or_else(Default::default, |r| r.into_storage());
    bt.resize(cap, 0.0);
    let (mut rx, mut ru, mut ry, mut rc) = (
        columns(bx, cap * N),
        columns(bu, cap),
        columns(by, cap * N),
        columns(bc, cap),
    );
    // One slice of exactly `cap` entries per recorded signal: a row index checked once
    // against `cap` is then in range for all of them.
    let (rt, ru_col, rc_col) = (&mut bt[..cap], &mut ru[..cap], &mut rc[..cap]);
    let xcols: [&mut [f64]; N] = split_columns(&mut rx, cap);
    let ycols: [&mut [f64]; N] = split_columns(&mut ry, cap);
    let mut saturated = 0usize;
    let mut status = RunStatus::Completed;
    let mut samples_run = 0usize;
    let mut next_record = if record_every.is_some() {
        0
    } else {
        usize::MAX
    };
    let every = record_every.unwrap_or(0);
    let mut row = 0usize;
    // `t_k = t₀ + k·ts`, carried from one sample to the next (the value the general loop
    // computes at each, one conversion and product per sample fewer). At most 10¹² + 1
    // samples (`validate_options`), so the exclusive range cannot overflow.
    let mut tk = t0;
    // The state's check after each step, as the general loop's: for a controller whose
    // command is not finite whenever the state is not
    // (`FixedController::NON_FINITE_STATE_GIVES_NON_FINITE_COMMAND`), the check of the next
    // command stands for it (the state checked first where the command fails: the same error
    // at the same time, since no step comes between). Otherwise a state whose sum is not finite
    // leaves the sample loop for the entry-by-entry check, which returns the error or, if
    // every entry is finite (the sum overflowed), resumes the loop after that sample. No call
    // inside the loop takes the state by reference, so it can stay in registers.
    let mut start = 0usize;
    loop {
        let mut unchecked = None;
        // `start ≤ n_samples`; the loop ends at `k == n_samples` (or a stop or an error).
        let mut k = start;
        // Each sample's command is computed right after the step that leads to it (the first
        // one here), from the new state still in registers: computed at the top of the loop,
        // it would read half of the state back from the stack, a store and a reload on the
        // chain state → command → step that bounds the loop.
        let mut ucmd = controller.command(tk, &x);
        loop {
            samples_run += 1;
            if !finite(ucmd) {
                if C::NON_FINITE_STATE_GIVES_NON_FINITE_COMMAND {
                    check_state_copy(tk, x)?;
                }
                return Err(SimError::NonFiniteCommand {
                    t: tk,
                    index: 0,
                    value: ucmd,
                });
            }
            let p = match saturation {
                None => ucmd,
                Some((lo, hi)) => {
                    let mut v = ucmd;
                    if v > hi {
                        v = hi;
                        saturated += 1;
                    } else if v < lo {
                        v = lo;
                        saturated += 1;
                    }
                    // The actuator adds its (zero) disturbance after the saturation.
                    v + 0.0
                }
            };
            if next_record == k && row < cap {
                next_record += every;
                rt[row] = tk;
                for i in 0..N {
                    xcols[i][row] = x[i];
                    ycols[i][row] = x[i];
                }
                ru_col[row] = p;
                rc_col[row] = ucmd;
                row += 1;
            }
            if monitor.observe(tk, &x, &x, &[p]) == Flow::Stop {
                status = RunStatus::Stopped { t: tk };
                break;
            }
            if k == n_samples {
                break;
            }
            // `k + 1 ≤ 10¹² + 1 < 2⁵³` converts exactly either way; the signed conversion is
            // one instruction on x86-64 (the unsigned one takes several without AVX-512).
            let tk1 = t0 + (k + 1) as i64 as f64 * ts;
            if nsub == 1 {
                stepper.step::<F>(&mut x, p, tk1 - tk);
            } else {
                let h = (tk1 - tk) / nsub as f64;
                for _ in 0..nsub {
                    stepper.step::<F>(&mut x, p, h);
                }
            }
            if !C::NON_FINITE_STATE_GIVES_NON_FINITE_COMMAND && !x.iter().sum::<f64>().is_finite() {
                unchecked = Some((k, tk1));
                break;
            }
            tk = tk1;
            k += 1;
            ucmd = controller.command(tk, &x);
        }
        match unchecked {
            None => break,
            Some((k, tk1)) => {
                check_state_copy(tk1, x)?;
                tk = tk1;
                start = k + 1;
            }
        }
    }
    bt.truncate(row);
    let trajectory = Trajectory::new(
        bt,
        into_mat(rx, cap, row, N),
        into_mat(ru, cap, row, 1),
        into_mat(ry, cap, row, N),
    )?;
    // Every sample but the last one run is followed by one interval of `nsub` steps.
    let steps = (samples_run - 1) * nsub;
    Ok(SampledRun {
        trajectory,
        commands: into_mat(rc, cap, row, 1),
        status,
        diagnostics: SampledDiagnostics {
            samples: samples_run,
            integration: IntegrationStats {
                accepted_steps: steps,
                evaluations: 4 * steps,
                ..Default::default()
            },
            saturated_samples: saturated,
            switch_times: controller.switch_times().to_vec(),
            // Every exit of the sample loop is at the last sample run, `tk`.
            final_time: tk,
            final_state: x.to_vec(),
        },
    })
}

impl<P: Dynamics + Clone, C: Controller + Clone> SampledLoop<P, C> {
    /// The same loop as a [`FixedLoop`] (bit-identical runs, see [`crate::fixed`]).
    ///
    /// # Errors
    /// [`SimError::DimensionMismatch`] if the plant does not have `N` states and one input;
    /// [`SimError::InvalidArgument`] naming the part the kernel does not cover: a sensor
    /// chain other than the exact state, an actuator chain with more than a saturation, an
    /// integrator other than RK4, a computation delay.
    pub fn fixed<const M: usize>(&self) -> Result<FixedLoop<P, C, M>>
    where
        P: FixedDynamics<M>,
        C: FixedController<M>,
    {
        check_len("plant states (fixed kernel size)", self.plant().nx(), M)?;
        check_len("plant inputs (fixed kernel: one)", self.plant().nu(), 1)?;
        if !self.sensor().is_identity() {
            return Err(unsupported("a sensor chain other than the exact state"));
        }
        let Some(saturation) = self.actuator().saturation_only() else {
            return Err(unsupported(
                "an actuator chain with D/A, disturbance or friction",
            ));
        };
        let me = FixedLoop::new(
            self.plant().clone(),
            self.controller().clone(),
            self.options(),
        )?;
        match saturation {
            Some((lo, hi)) => me.with_saturation(lo, hi),
            None => Ok(me),
        }
    }
}

/// Whether the processor has FMA (x86-64, detected at run time and cached by `std`); `false`
/// elsewhere, where the kernel has no FMA-compiled loop.
fn fma_detected() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

fn unsupported(what: &str) -> SimError {
    SimError::InvalidArgument(format!(
        "the fixed-size closed-loop kernel does not cover {what}; use SampledLoop::run"
    ))
}

/// `v.is_finite()` as `|v| ≤ f64::MAX` (false for NaN): a mask, a comparison and a branch
/// where the loop tests it, rather than moving the bits to an integer register and comparing
/// them there (one instruction fewer per sample, measured under callgrind).
#[inline(always)]
fn finite(v: f64) -> bool {
    v.abs() <= f64::MAX
}

/// [`check_state`] on a copy of the state: the loop's state is then never borrowed by a call,
/// so the compiler can keep it in registers from one step to the next.
#[cold]
#[inline(never)]
fn check_state_copy<const N: usize>(t: f64, x: [f64; N]) -> Result<()> {
    check_state(t, &x)
}

/// A column-major buffer of `len` entries, reusing `data`'s allocation (entries below the final
/// row count are all written before the matrix is formed).
fn columns(mut data: Vec<f64>, len: usize) -> Vec<f64> {
    if data.len() != len {
        data.clear();
        data.resize(len, 0.0);
    }
    data
}

/// `data` (`N·cap` entries) as `N` consecutive slices of `cap` entries.
fn split_columns<const N: usize>(data: &mut [f64], cap: usize) -> [&mut [f64]; N] {
    let mut rest = data;
    std::array::from_fn(|_| {
        let (column, tail) = std::mem::take(&mut rest).split_at_mut(cap);
        rest = tail;
        column
    })
}

/// The first `rows` of each of the `w` columns of a `cap`-row buffer as a matrix.
fn into_mat(mut data: Vec<f64>, cap: usize, rows: usize, w: usize) -> Mat {
    if rows < cap {
        for i in 1..w {
            data.copy_within(i * cap..i * cap + rows, i * rows);
        }
        data.truncate(rows * w);
    }
    Mat::from_vec(rows, w, data)
}

#[cfg(test)]
mod tests;
