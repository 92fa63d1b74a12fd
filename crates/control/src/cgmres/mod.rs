//! Nonlinear receding-horizon control by the continuation/GMRES method (C/GMRES).
//!
//! T. Ohtsuka, "A continuation/GMRES method for fast computation of nonlinear receding horizon
//! control", *Automatica* 40(4), 563–574, 2004.
//!
//! ## The problem
//! At each time `t` the controller minimises over the horizon `[t, t + T(t)]`
//! `J = φ(x(t + T)) + ∫ L(x(τ), u(τ)) dτ` subject to `ẋ = f(t, x, u)` and equality
//! constraints `C(x, u) = 0` (input bounds become equalities with dummy inputs, see
//! [`InputBounds`]). With the Hamiltonian `H = L + λᵀ f + ρᵀ C`, the horizon is split into `N`
//! steps of `Δτ = T(t)/N` and the optimality conditions of the Euler-discretised problem are
//!
//! ```text
//! x*₀ = x(t),           x*ᵢ₊₁ = x*ᵢ + f(τᵢ, x*ᵢ, uᵢ) Δτ,
//! λ*_N = φₓ(x*_N),      λ*ᵢ = λ*ᵢ₊₁ + Hₓ(τᵢ, x*ᵢ, uᵢ, λ*ᵢ₊₁) Δτ,
//! Fᵢ = H_u(τᵢ, x*ᵢ, uᵢ, λ*ᵢ₊₁) = 0,   i = 0 … N−1,   τᵢ = t + iΔτ,
//! ```
//!
//! which are exactly the Karush–Kuhn–Tucker conditions of
//! `min Σᵢ L(x*ᵢ, uᵢ)Δτ + φ(x*_N)` (the costates are the multipliers of the Euler steps).
//! Here `uᵢ` is the whole *stage vector* — inputs, dummy inputs and multipliers `ρ` — and
//! `H_u` includes `∂H/∂ρ = C`, so `F(U, x, t) = 0` with `U = [u₀; …; u_{N−1}]` is a square
//! system of `N·m` equations.
//!
//! ## The continuation
//! Instead of solving `F = 0` at every sample, C/GMRES integrates `U̇` from
//! `F_U U̇ = −ζ F − Fₓ ẋ − F_t`, which makes `F → 0` exponentially (rate `ζ`) along the
//! trajectory. The products with `F_U`, `Fₓ ẋ + F_t` are forward differences with step `h`,
//! `ẋ` comes from the model, the linear system is solved by `kmax` iterations of GMRES warm
//! started at the previous `U̇`, and `U ← U + U̇ Δt`. The horizon grows from zero,
//! `T(t) = T_f (1 − e^{−α t})` ([`Horizon::Growing`]), so that at `t = 0` all stages coincide
//! and the initial solution is a small Newton problem.
//!
//! ## What is here
//! - [`OptimalControlProblem`]: the problem as `f`, `Hₓ`, `H_u`, `φₓ`.
//! - [`InputBounds`]: the dummy-input transformation of box bounds on inputs.
//! - [`Cgmres`]: the solver — [`Cgmres::initialize`] (Newton–GMRES on the whole horizon),
//!   [`Cgmres::update`] (one continuation step, allocation-free), [`Cgmres::residual_norm`].
//! - [`NmpcController`]: the solver as a [`pendulab_sim::Controller`] of the sampled loop.
//! - [`TimedController`]: any controller with the wall-clock time of each update recorded.

mod bounds;
mod controller;

pub use bounds::{InputBound, InputBounds};
pub use controller::{NmpcController, NmpcStatistics, TimedController, UpdateTiming};

use crate::error::{ControlError, Result, check_param, check_vector};
use crate::gmres::{self, GmresReport, GmresWorkspace};

/// An optimal-control problem in the form C/GMRES needs (Ohtsuka's "rhfunc" interface).
///
/// The *stage vector* `u` (length [`nu`](Self::nu)) holds, in an order the problem chooses,
/// the plant inputs first ([`n_inputs`](Self::n_inputs) of them), then any dummy inputs and
/// constraint multipliers. `hamiltonian_u` returns `∂H/∂u` for all of them (for a multiplier
/// `ρ` that is the constraint value `C`).
///
/// Contract: every method is pure and allocation-free (they run several hundred times per
/// sample); slice lengths are `nx` for states, costates and `Hₓ`, `nu` for stage vectors and
/// `H_u`.
pub trait OptimalControlProblem {
    /// Number of states `n`.
    fn nx(&self) -> usize;
    /// Length `m` of the stage vector (inputs, dummy inputs, multipliers).
    fn nu(&self) -> usize;
    /// Number of leading entries of the stage vector that are plant inputs (default: all).
    fn n_inputs(&self) -> usize {
        self.nu()
    }
    /// The model `ẋ = f(t, x, u)` (uses only the plant inputs of `u`).
    fn state_equation(&self, t: f64, x: &[f64], u: &[f64], dx: &mut [f64]);
    /// `Hₓ = ∂H/∂x = Lₓ + fₓᵀ λ (+ Cₓᵀ ρ)` at `(t, x, u, λ)`.
    fn hamiltonian_x(&self, t: f64, x: &[f64], u: &[f64], lambda: &[f64], hx: &mut [f64]);
    /// `H_u = ∂H/∂u` for the whole stage vector at `(t, x, u, λ)`.
    fn hamiltonian_u(&self, t: f64, x: &[f64], u: &[f64], lambda: &[f64], hu: &mut [f64]);
    /// Gradient of the terminal cost `φₓ(x)` at time `t`.
    fn terminal_gradient(&self, t: f64, x: &[f64], phix: &mut [f64]);
    /// `Hₓ` and `H_u` together (the solver calls this one). The default calls
    /// [`hamiltonian_x`](Self::hamiltonian_x) and [`hamiltonian_u`](Self::hamiltonian_u);
    /// override it when both share expensive work (a Jacobian, trigonometric functions).
    #[inline]
    fn hamiltonian_xu(
        &self,
        t: f64,
        x: &[f64],
        u: &[f64],
        lambda: &[f64],
        hx: &mut [f64],
        hu: &mut [f64],
    ) {
        self.hamiltonian_x(t, x, u, lambda, hx);
        self.hamiltonian_u(t, x, u, lambda, hu);
    }
}

/// The prediction horizon `T(t)` as a function of the time elapsed since initialisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Horizon {
    /// `T(t) = length` (seconds) from the start; the initial solution then has to solve the
    /// full-horizon problem.
    Fixed {
        /// Horizon length in seconds (> 0).
        length: f64,
    },
    /// `T(t) = T_f (1 − e^{−α t})`: starts at zero, where the initial solution is trivial,
    /// and approaches `T_f` smoothly (Ohtsuka 2004, §5).
    Growing {
        /// `T_f` in seconds (> 0).
        final_length: f64,
        /// `α` in 1/s (> 0).
        rate: f64,
    },
}

impl Horizon {
    /// `T` after `elapsed` seconds (`elapsed ≥ 0`).
    #[inline]
    pub fn length(&self, elapsed: f64) -> f64 {
        match *self {
            Horizon::Fixed { length } => length,
            Horizon::Growing { final_length, rate } => {
                final_length * (1.0 - (-rate * elapsed.max(0.0)).exp())
            }
        }
    }

    fn validate(&self) -> Result<()> {
        match *self {
            Horizon::Fixed { length } => {
                check_param("horizon length", length, length > 0.0, "must be > 0 s")
            }
            Horizon::Growing { final_length, rate } => {
                check_param(
                    "horizon final length T_f",
                    final_length,
                    final_length > 0.0,
                    "must be > 0 s",
                )?;
                check_param("horizon rate α", rate, rate > 0.0, "must be > 0 1/s")
            }
        }
    }
}

/// Options of [`Cgmres`], with documented defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CgmresOptions {
    /// The horizon (default: the book's `T(t) = 0.5 (1 − e^{−0.5 t})`).
    pub horizon: Horizon,
    /// Number of grid points `N` on the horizon (default 25, ≥ 1).
    pub grid_points: usize,
    /// Stabilisation parameter `ζ` in 1/s: the optimality residual decays like `e^{−ζt}`
    /// (default 1000, i.e. `1/Δt` for 1 ms updates; `ζ Δt ≤ 1` keeps the explicit update
    /// stable).
    pub zeta: f64,
    /// Forward-difference step `h` in seconds / input units (default 1e-6).
    pub difference_step: f64,
    /// GMRES iterations per update `kmax` (default 5).
    pub gmres_iterations: usize,
}

impl Default for CgmresOptions {
    fn default() -> Self {
        Self {
            horizon: Horizon::Growing {
                final_length: 0.5,
                rate: 0.5,
            },
            grid_points: 25,
            zeta: 1000.0,
            difference_step: 1e-6,
            gmres_iterations: 5,
        }
    }
}

/// Options of [`Cgmres::initialize`], with documented defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitOptions {
    /// Stop when `‖F‖₂ ≤ tolerance` (default 1e-8).
    pub tolerance: f64,
    /// Maximum Newton iterations (default 50).
    pub max_iterations: usize,
}

impl Default for InitOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-8,
            max_iterations: 50,
        }
    }
}

/// What [`Cgmres::initialize`] achieved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitReport {
    /// Newton iterations performed.
    pub iterations: usize,
    /// `‖F(U, x₀, t₀)‖₂` at the returned sequence.
    pub residual: f64,
    /// Horizon length at `t₀`.
    pub horizon: f64,
}

/// What one [`Cgmres::update`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UpdateReport {
    /// `‖F(U, x, t)‖₂` on entry — how far the sequence the controller applies at `t` is from
    /// optimality.
    pub optimality_residual: f64,
    /// The GMRES solve of `F_U U̇ = b`.
    pub gmres: GmresReport,
    /// Horizon length `T(t)` in seconds.
    pub horizon: f64,
}

/// Buffers of one evaluation of `F(U, x, t)`.
#[derive(Debug, Clone)]
struct Kernel {
    nx: usize,
    m: usize,
    n: usize,
    xs: Vec<f64>,
    lmd: Vec<f64>,
    hx: Vec<f64>,
}

impl Kernel {
    fn new(nx: usize, m: usize, n: usize) -> Self {
        Self {
            nx,
            m,
            n,
            xs: vec![0.0; (n + 1) * nx],
            lmd: vec![0.0; nx],
            hx: vec![0.0; nx],
        }
    }

    /// `out = F(u, x, t)` with horizon length `horizon`.
    fn residual<P: OptimalControlProblem + ?Sized>(
        &mut self,
        p: &P,
        t: f64,
        x: &[f64],
        u: &[f64],
        horizon: f64,
        out: &mut [f64],
    ) {
        let (nx, m, n) = (self.nx, self.m, self.n);
        let dtau = horizon / n as f64;
        self.xs[..nx].copy_from_slice(x);
        for i in 0..n {
            let (cur, next) = self.xs.split_at_mut((i + 1) * nx);
            let xi = &cur[i * nx..];
            let dx = &mut next[..nx];
            let ti = t + i as f64 * dtau;
            p.state_equation(ti, xi, &u[i * m..(i + 1) * m], dx);
            for k in 0..nx {
                dx[k] = xi[k] + dx[k] * dtau;
            }
        }
        p.terminal_gradient(t + horizon, &self.xs[n * nx..], &mut self.lmd);
        for i in (0..n).rev() {
            let ti = t + i as f64 * dtau;
            let xi = &self.xs[i * nx..(i + 1) * nx];
            let ui = &u[i * m..(i + 1) * m];
            p.hamiltonian_xu(
                ti,
                xi,
                ui,
                &self.lmd,
                &mut self.hx,
                &mut out[i * m..(i + 1) * m],
            );
            for k in 0..nx {
                self.lmd[k] += self.hx[k] * dtau;
            }
        }
    }
}

#[inline]
fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// The C/GMRES solver for a problem `P` (Ohtsuka 2004).
///
/// Construct with [`Cgmres::new`], set the starting sequence with [`Cgmres::initialize`],
/// then call [`Cgmres::update`] once per sample. All storage is allocated by `new`;
/// `initialize` and `update` do not allocate.
#[derive(Debug, Clone)]
pub struct Cgmres<P> {
    problem: P,
    options: CgmresOptions,
    nx: usize,
    m: usize,
    dim: usize,
    t0: f64,
    initialized: bool,
    u: Vec<f64>,
    udot: Vec<f64>,
    kernel: Kernel,
    f0: Vec<f64>,
    f1: Vec<f64>,
    rhs: Vec<f64>,
    shifted: Vec<f64>,
    x1: Vec<f64>,
    dx: Vec<f64>,
    ws: GmresWorkspace,
    init_ws: GmresWorkspace,
    delta: Vec<f64>,
}

impl<P: OptimalControlProblem> Cgmres<P> {
    /// A solver for `problem` with `options`.
    ///
    /// # Errors
    /// [`ControlError::InvalidParameter`] for a horizon that is not positive, `N = 0`,
    /// `ζ ≤ 0`, `h ≤ 0`, `kmax = 0`, or a problem with no states or no stage entries (or
    /// more inputs than stage entries).
    pub fn new(problem: P, options: CgmresOptions) -> Result<Self> {
        options.horizon.validate()?;
        let n = options.grid_points;
        check_param("grid points N", n as f64, n >= 1, "must be ≥ 1")?;
        check_param("ζ", options.zeta, options.zeta > 0.0, "must be > 0 1/s")?;
        check_param(
            "difference step h",
            options.difference_step,
            options.difference_step > 0.0,
            "must be > 0",
        )?;
        check_param(
            "GMRES iterations kmax",
            options.gmres_iterations as f64,
            options.gmres_iterations >= 1,
            "must be ≥ 1",
        )?;
        let (nx, m) = (problem.nx(), problem.nu());
        check_param("problem state dimension", nx as f64, nx >= 1, "must be ≥ 1")?;
        check_param("problem stage dimension", m as f64, m >= 1, "must be ≥ 1")?;
        let ni = problem.n_inputs();
        check_param(
            "problem input count",
            ni as f64,
            ni <= m,
            "must not exceed the stage dimension",
        )?;
        let dim = n * m;
        Ok(Self {
            problem,
            options,
            nx,
            m,
            dim,
            t0: 0.0,
            initialized: false,
            u: vec![0.0; dim],
            udot: vec![0.0; dim],
            kernel: Kernel::new(nx, m, n),
            f0: vec![0.0; dim],
            f1: vec![0.0; dim],
            rhs: vec![0.0; dim],
            shifted: vec![0.0; dim],
            x1: vec![0.0; nx],
            dx: vec![0.0; nx],
            ws: GmresWorkspace::new(dim, options.gmres_iterations),
            init_ws: GmresWorkspace::new(dim, dim),
            delta: vec![0.0; dim],
        })
    }

    /// The problem.
    pub fn problem(&self) -> &P {
        &self.problem
    }

    /// The options.
    pub fn options(&self) -> &CgmresOptions {
        &self.options
    }

    /// Whether [`initialize`](Self::initialize) has succeeded since construction or
    /// [`invalidate`](Self::invalidate).
    pub fn is_initialized(&self) -> bool {
        self.initialized
    }

    /// Marks the solver as needing a new [`initialize`](Self::initialize) (keeps storage).
    pub fn invalidate(&mut self) {
        self.initialized = false;
    }

    /// The current stage sequence `U = [u₀; …; u_{N−1}]` (`N·m` entries, stage-major).
    pub fn sequence(&self) -> &[f64] {
        &self.u
    }

    /// The current `U̇` (`N·m` entries).
    pub fn sequence_rate(&self) -> &[f64] {
        &self.udot
    }

    /// The first stage vector `u₀` (inputs, dummies, multipliers).
    pub fn first_stage(&self) -> &[f64] {
        &self.u[..self.m]
    }

    /// The plant inputs of the first stage: the command to apply now.
    pub fn input(&self) -> &[f64] {
        &self.u[..self.problem.n_inputs()]
    }

    /// Horizon length at absolute time `t`.
    pub fn horizon_at(&self, t: f64) -> f64 {
        self.options.horizon.length(t - self.t0)
    }

    /// Computes `F(U, x, t)` for the current sequence into `out` (`N·m` entries) and returns
    /// its norm — the defining residual of the discretised optimality conditions.
    ///
    /// # Errors
    /// [`ControlError::DimensionMismatch`] / [`ControlError::NonFinite`] for `x` or `out`.
    pub fn residual(&mut self, t: f64, x: &[f64], out: &mut [f64]) -> Result<f64> {
        check_vector("state x", x, self.nx)?;
        if out.len() != self.dim {
            return Err(ControlError::DimensionMismatch {
                what: "residual output".into(),
                expected: self.dim,
                found: out.len(),
            });
        }
        let horizon = self.horizon_at(t);
        self.kernel
            .residual(&self.problem, t, x, &self.u, horizon, out);
        Ok(norm(out))
    }

    /// `‖F(U, x, t)‖₂` for the current sequence.
    ///
    /// # Errors
    /// As [`residual`](Self::residual).
    pub fn residual_norm(&mut self, t: f64, x: &[f64]) -> Result<f64> {
        let mut out = std::mem::take(&mut self.f0);
        let r = self.residual(t, x, &mut out);
        self.f0 = out;
        r
    }

    /// Sets the starting time `t₀` of the horizon schedule and the whole sequence `U`
    /// (`N·m` entries, stage-major) — a warm start from a known solution; `U̇` is reset to
    /// zero and the solver counts as initialised (check [`residual_norm`](Self::residual_norm)
    /// if the sequence may not be optimal).
    ///
    /// # Errors
    /// Dimension/finiteness errors for `sequence`; a non-finite `t0`.
    pub fn set_sequence(&mut self, t0: f64, sequence: &[f64]) -> Result<()> {
        check_vector("sequence U", sequence, self.dim)?;
        check_param("t0", t0, true, "must be finite")?;
        self.t0 = t0;
        self.u.copy_from_slice(sequence);
        self.udot.iter_mut().for_each(|v| *v = 0.0);
        self.initialized = true;
        Ok(())
    }

    /// Sets the starting time `t₀` of the horizon schedule and solves `F(U, x₀, t₀) = 0` by
    /// Newton's method with GMRES inner solves (forward-difference Jacobian products, up to
    /// `N·m` Krylov iterations), starting from every stage equal to `stage_guess` (length
    /// `m`). With [`Horizon::Growing`] the horizon is zero at `t₀`, all stages see the same
    /// state and costate, and this is the small problem of Ohtsuka's initialisation. `U̇` is
    /// reset to zero.
    ///
    /// # Errors
    /// Dimension/finiteness errors for `x0` and `stage_guess`;
    /// [`ControlError::InitialisationFailed`] when the tolerance is not met.
    pub fn initialize(
        &mut self,
        t0: f64,
        x0: &[f64],
        stage_guess: &[f64],
        options: &InitOptions,
    ) -> Result<InitReport> {
        check_vector("initial state x0", x0, self.nx)?;
        check_vector("initial stage guess", stage_guess, self.m)?;
        check_param("t0", t0, true, "must be finite")?;
        check_param(
            "initialisation tolerance",
            options.tolerance,
            options.tolerance > 0.0,
            "must be > 0",
        )?;
        self.t0 = t0;
        for stage in self.u.chunks_mut(self.m) {
            stage.copy_from_slice(stage_guess);
        }
        self.udot.iter_mut().for_each(|v| *v = 0.0);
        let horizon = self.horizon_at(t0);
        let h = self.options.difference_step;
        let mut iterations = 0;
        let Self {
            problem,
            kernel,
            u,
            f0,
            f1,
            shifted,
            init_ws,
            delta,
            rhs,
            ..
        } = self;
        kernel.residual(problem, t0, x0, u, horizon, f0);
        let mut res = norm(f0);
        while res > options.tolerance && iterations < options.max_iterations && res.is_finite() {
            for (r, f) in rhs.iter_mut().zip(f0.iter()) {
                *r = -f;
            }
            delta.iter_mut().for_each(|d| *d = 0.0);
            let f0r: &[f64] = f0;
            let ur: &[f64] = u;
            gmres::solve(
                init_ws,
                |v, y| {
                    for ((s, ui), vi) in shifted.iter_mut().zip(ur).zip(v) {
                        *s = ui + h * vi;
                    }
                    kernel.residual(problem, t0, x0, shifted, horizon, y);
                    for (yi, fi) in y.iter_mut().zip(f0r) {
                        *yi = (*yi - fi) / h;
                    }
                },
                rhs,
                delta,
                1e-3 * res,
            );
            // Newton step with backtracking on ‖F‖ (halving, at most 20 times).
            let mut step = 1.0;
            let mut accepted = false;
            for _ in 0..20 {
                for ((s, ui), di) in shifted.iter_mut().zip(u.iter()).zip(delta.iter()) {
                    *s = ui + step * di;
                }
                kernel.residual(problem, t0, x0, shifted, horizon, f1);
                let trial = norm(f1);
                if trial.is_finite() && trial < res {
                    u.copy_from_slice(shifted);
                    f0.copy_from_slice(f1);
                    res = trial;
                    accepted = true;
                    break;
                }
                step *= 0.5;
            }
            iterations += 1;
            if !accepted {
                break;
            }
        }
        if res.is_nan() || res > options.tolerance {
            self.initialized = false;
            return Err(ControlError::InitialisationFailed {
                residual: res,
                iterations,
                tolerance: options.tolerance,
            });
        }
        self.initialized = true;
        Ok(InitReport {
            iterations,
            residual: res,
            horizon,
        })
    }

    /// One continuation step at time `t` with the measured (or estimated) state `x`, for the
    /// sample period `dt` (seconds): computes `U̇` from
    /// `F_U U̇ = −ζF − (F(U, x + hẋ, t + h) − F(U, x, t))/h` by `kmax` GMRES iterations
    /// (Jacobian products by forward differences, warm start at the previous `U̇`,
    /// `ẋ = f(t, x, u₀)` from the model) and advances `U ← U + U̇ dt`. The returned report
    /// holds `‖F(U, x, t)‖` on entry. Allocation-free.
    ///
    /// Call [`input`](Self::input) *before* `update` for the command that the sequence
    /// optimal at `t` prescribes (what [`NmpcController`] applies).
    ///
    /// # Errors
    /// [`ControlError::NotApplicable`] before a successful initialisation;
    /// dimension/finiteness errors for `x`; [`ControlError::InvalidParameter`] for `dt ≤ 0`.
    pub fn update(&mut self, t: f64, x: &[f64], dt: f64) -> Result<UpdateReport> {
        if !self.initialized {
            return Err(ControlError::NotApplicable {
                reason: "C/GMRES update before a successful initialisation".into(),
            });
        }
        check_vector("state x", x, self.nx)?;
        check_param("sample period dt", dt, dt > 0.0, "must be > 0 s")?;
        let h = self.options.difference_step;
        let zeta = self.options.zeta;
        let horizon = self.horizon_at(t);
        let horizon1 = self.horizon_at(t + h);
        let m = self.m;
        let Self {
            problem,
            kernel,
            u,
            udot,
            f0,
            f1,
            rhs,
            shifted,
            x1,
            dx,
            ws,
            ..
        } = self;
        problem.state_equation(t, x, &u[..m], dx);
        for k in 0..x.len() {
            x1[k] = x[k] + h * dx[k];
        }
        let t1 = t + h;
        kernel.residual(problem, t, x, u, horizon, f0);
        kernel.residual(problem, t1, x1, u, horizon1, f1);
        for i in 0..rhs.len() {
            rhs[i] = -zeta * f0[i] - (f1[i] - f0[i]) / h;
        }
        let f1r: &[f64] = f1;
        let ur: &[f64] = u;
        let x1r: &[f64] = x1;
        let gm = gmres::solve(
            ws,
            |v, y| {
                for ((s, ui), vi) in shifted.iter_mut().zip(ur).zip(v) {
                    *s = ui + h * vi;
                }
                kernel.residual(problem, t1, x1r, shifted, horizon1, y);
                for (yi, fi) in y.iter_mut().zip(f1r) {
                    *yi = (*yi - fi) / h;
                }
            },
            rhs,
            udot,
            0.0,
        );
        for (ui, di) in u.iter_mut().zip(udot.iter()) {
            *ui += di * dt;
        }
        Ok(UpdateReport {
            optimality_residual: norm(f0),
            gmres: gm,
            horizon,
        })
    }
}
