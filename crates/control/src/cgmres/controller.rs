//! C/GMRES as a sampled-data controller, and update timing for any controller.

use super::{Cgmres, InitOptions, OptimalControlProblem};
use crate::error::{Result, check_param};
use pendulab_sim::Controller;
use std::time::Instant;

/// Running statistics of an [`NmpcController`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NmpcStatistics {
    /// Continuation updates performed.
    pub updates: usize,
    /// Samples at which the initialisation failed (the command was 0 then).
    pub initialisation_failures: usize,
    /// Samples whose measurement was rejected (wrong length or non-finite); the previous
    /// command was held.
    pub rejected_measurements: usize,
    /// Largest `‖F(U, x, t)‖` seen on entry to an update.
    pub max_optimality_residual: f64,
    /// `‖F(U, x, t)‖` at the last update.
    pub last_optimality_residual: f64,
    /// Sum of `‖F‖` over the updates (divide by `updates` for the mean).
    pub sum_optimality_residual: f64,
    /// Largest GMRES residual of the linear solve for `U̇`.
    pub max_gmres_residual: f64,
}

/// Nonlinear receding-horizon control by C/GMRES as a [`Controller`]: the measurement is the
/// full state `x` (length `nx`), the command the plant inputs of the first stage (length
/// `n_inputs`).
///
/// At each sample `t` it applies `u₀` of the sequence the continuation holds for `t` and then
/// advances the sequence by [`Cgmres::update`] with the controller's sample period. At the
/// first sample (and after [`Controller::reset`]) it initialises the solver at `(t, x)` from
/// the stage guess given at construction; if that fails the command is zero and the next
/// sample tries again (counted in [`NmpcStatistics::initialisation_failures`]). The command is
/// not clipped: input bounds are the problem's business ([`super::InputBounds`]), and what the
/// solver produced is what the plant sees.
#[derive(Debug, Clone)]
pub struct NmpcController<P> {
    solver: Cgmres<P>,
    ts: f64,
    stage_guess: Vec<f64>,
    init: InitOptions,
    stats: NmpcStatistics,
    last: Vec<f64>,
}

impl<P: OptimalControlProblem> NmpcController<P> {
    /// A controller updating every `ts` seconds, initialised from `stage_guess` (length of the
    /// stage vector).
    ///
    /// # Errors
    /// [`crate::ControlError::InvalidParameter`] for `ts ≤ 0`;
    /// [`crate::ControlError::DimensionMismatch`] for a guess of the wrong length.
    pub fn new(
        solver: Cgmres<P>,
        ts: f64,
        stage_guess: Vec<f64>,
        init: InitOptions,
    ) -> Result<Self> {
        check_param("sample period ts", ts, ts > 0.0, "must be > 0 s")?;
        crate::error::check_vector("stage guess", &stage_guess, solver.problem().nu())?;
        let ni = solver.problem().n_inputs();
        Ok(Self {
            solver,
            ts,
            stage_guess,
            init,
            stats: NmpcStatistics::default(),
            last: vec![0.0; ni],
        })
    }

    /// Initialises the solver at `(t0, x0)` now, from the stage guess given at construction
    /// (otherwise the first [`Controller::update`] does it), surfacing a failure as an error.
    ///
    /// # Errors
    /// As [`Cgmres::initialize`].
    pub fn initialize(&mut self, t0: f64, x0: &[f64]) -> Result<super::InitReport> {
        self.solver
            .initialize(t0, x0, &self.stage_guess, &self.init)
    }

    /// The solver (sequence, residuals, options).
    pub fn solver(&self) -> &Cgmres<P> {
        &self.solver
    }

    /// Mutable access to the solver.
    pub fn solver_mut(&mut self) -> &mut Cgmres<P> {
        &mut self.solver
    }

    /// Statistics since construction or the last reset.
    pub fn statistics(&self) -> &NmpcStatistics {
        &self.stats
    }

    /// The sample period in seconds.
    pub fn sample_time(&self) -> f64 {
        self.ts
    }
}

impl<P: OptimalControlProblem> Controller for NmpcController<P> {
    fn ny(&self) -> usize {
        self.solver.problem().nx()
    }

    fn nu(&self) -> usize {
        self.solver.problem().n_inputs()
    }

    fn reset(&mut self) {
        self.solver.invalidate();
        self.stats = NmpcStatistics::default();
        self.last.iter_mut().for_each(|v| *v = 0.0);
    }

    fn sample_time(&self) -> Option<f64> {
        Some(self.ts)
    }

    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        if y.len() != self.solver.problem().nx() || y.iter().any(|v| !v.is_finite()) {
            self.stats.rejected_measurements += 1;
            u.copy_from_slice(&self.last);
            return;
        }
        if !self.solver.is_initialized()
            && self
                .solver
                .initialize(t, y, &self.stage_guess, &self.init)
                .is_err()
        {
            self.stats.initialisation_failures += 1;
            u.iter_mut().for_each(|v| *v = 0.0);
            self.last.iter_mut().for_each(|v| *v = 0.0);
            return;
        }
        u.copy_from_slice(self.solver.input());
        self.last.copy_from_slice(u);
        match self.solver.update(t, y, self.ts) {
            Ok(r) => {
                let s = &mut self.stats;
                s.updates += 1;
                s.last_optimality_residual = r.optimality_residual;
                s.sum_optimality_residual += r.optimality_residual;
                s.max_optimality_residual = s.max_optimality_residual.max(r.optimality_residual);
                s.max_gmres_residual = s.max_gmres_residual.max(r.gmres.residual);
            }
            Err(_) => self.stats.rejected_measurements += 1,
        }
    }
}

/// Wall-clock statistics of controller updates.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct UpdateTiming {
    /// Updates timed.
    pub count: u64,
    /// Total time in seconds.
    pub total_seconds: f64,
    /// Longest single update in seconds.
    pub max_seconds: f64,
}

impl UpdateTiming {
    /// Mean seconds per update (0 when nothing was timed).
    pub fn mean_seconds(&self) -> f64 {
        if self.count == 0 {
            0.0
        } else {
            self.total_seconds / self.count as f64
        }
    }
}

/// Any controller with the wall-clock duration of each [`Controller::update`] recorded
/// ([`std::time::Instant`], no allocation). The figures depend on the machine and its load;
/// they are diagnostics, not test oracles.
#[derive(Debug, Clone)]
pub struct TimedController<C> {
    inner: C,
    timing: UpdateTiming,
}

impl<C: Controller> TimedController<C> {
    /// Wraps `inner`.
    pub fn new(inner: C) -> Self {
        Self {
            inner,
            timing: UpdateTiming::default(),
        }
    }

    /// The wrapped controller.
    pub fn inner(&self) -> &C {
        &self.inner
    }

    /// Unwraps.
    pub fn into_inner(self) -> C {
        self.inner
    }

    /// Timing since construction or the last reset.
    pub fn timing(&self) -> &UpdateTiming {
        &self.timing
    }
}

impl<C: Controller> Controller for TimedController<C> {
    fn ny(&self) -> usize {
        self.inner.ny()
    }

    fn nu(&self) -> usize {
        self.inner.nu()
    }

    fn reset(&mut self) {
        self.inner.reset();
        self.timing = UpdateTiming::default();
    }

    fn sample_time(&self) -> Option<f64> {
        self.inner.sample_time()
    }

    fn switch_times(&self) -> &[f64] {
        self.inner.switch_times()
    }

    fn update(&mut self, t: f64, y: &[f64], u: &mut [f64]) {
        let start = Instant::now();
        self.inner.update(t, y, u);
        let s = start.elapsed().as_secs_f64();
        self.timing.count += 1;
        self.timing.total_seconds += s;
        self.timing.max_seconds = self.timing.max_seconds.max(s);
    }
}
