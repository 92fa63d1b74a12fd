//! A Gymnasium-style environment (`reset`, `step`) over any [`Dynamics`], for reinforcement
//! learning with pendulab's plants as fast environments.
//!
//! [`Env`] follows the interface of Gymnasium's `CartPole-v1` (Barto, Sutton & Anderson 1983):
//!
//! - [`Env::reset`]`(seed)` draws the initial state uniformly in `nominal ± reset_half_width`
//!   from a ChaCha8 generator (re-seeded when a seed is given, continuing otherwise) and
//!   returns the observation;
//! - [`Env::step`]`(action)` clips the action to `±action_limit`, holds it for one control
//!   period `dt` (integrated by `substeps` classic RK4 steps on fixed-size arrays, no
//!   allocation) and returns a [`Step`]: the observation (the full state), the reward, and
//!   `terminated` / `truncated`.
//! - **Reward**: `+1` for every step taken, including the one that terminates (as
//!   CartPole-v1); `0` for steps requested after the episode ended (which change nothing).
//! - **Termination**: some `|x_i| > bound` of [`EnvConfig::limits`]; **truncation**: the
//!   episode reached [`EnvConfig::max_steps`].
//!
//! [`EnvConfig::cart_pole`] is CartPole-v1 with the cart rig's physics instead of the
//! classic frictionless model: the action is the motor voltage (continuous, ±5 V) rather than
//! a ±10 N force, `dt = 0.02 s`, episodes of at most 500 steps, initial states uniform in
//! ±0.05, termination at `|θ| > 12°` or when the cart leaves the track `|z| > track_half_length`.
//! Use it with the cart pendulum of `pendulab-plants` (state `[z, θ, ż, θ̇]`, θ from upright).
//!
//! [`FixedEnv`] is the same environment for a plant of the fixed-size kernel
//! ([`FixedDynamics`], e.g. `pendulab_plants::CartPendulum`), stepping with the plant's own
//! [`FixedDynamics::rk4_step_fixed`]: bit-identical to [`Env`] with the provided step, and the
//! fast path for the cart as `pendulab_plants::cart::fast::FastCart` with `Trig::Anchored`
//! (the later RK4 stages' sines from the step's
//! first one; see [`FixedEnv`] for how close that stays to [`Env`]). [`Env::fixed`] converts.

use crate::buffer::Buf;
use crate::dynamics::Dynamics;
use crate::error::{Result, SimError, check_len, check_positive};
use crate::fast::FixedDynamics;
use crate::integrate::rk4::{Rk4Scratch, step_generic};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Configuration of an [`Env`].
#[derive(Debug, Clone, PartialEq)]
pub struct EnvConfig {
    /// Control period (s): one `step` advances the plant by `dt`.
    pub dt: f64,
    /// RK4 substeps per control period (≥ 1).
    pub substeps: usize,
    /// Actions are clipped to `±action_limit` (units of the plant input).
    pub action_limit: f64,
    /// Centre of the initial-state distribution (length `nx`).
    pub nominal: Vec<f64>,
    /// Half-widths of the uniform initial-state distribution (length `nx`, ≥ 0).
    pub reset_half_width: Vec<f64>,
    /// Termination: `(state index, bound)`, the episode ends when `|x_i| > bound`.
    pub limits: Vec<(usize, f64)>,
    /// Truncation: the episode ends after this many steps (≥ 1).
    pub max_steps: usize,
}

impl EnvConfig {
    /// CartPole-v1's settings on the cart rig (see the module documentation): `dt = 0.02 s`,
    /// one RK4 step per period (the rig's fastest open-loop mode, |λ| ≈ 6.3 1/s, gives
    /// `|λ| dt ≈ 0.13`, RK4 local error ~(0.13)⁵/120 ≈ 3·10⁻⁷), ±5 V, start uniform in ±0.05
    /// around the upright rest, terminate at `|θ| > 12°` or `|z| > track_half_length`,
    /// at most 500 steps.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] unless `track_half_length > 0`.
    pub fn cart_pole(track_half_length: f64) -> Result<Self> {
        check_positive("track half-length", track_half_length)?;
        Ok(Self {
            dt: 0.02,
            substeps: 1,
            action_limit: 5.0,
            nominal: vec![0.0; 4],
            reset_half_width: vec![0.05; 4],
            limits: vec![(0, track_half_length), (1, 12f64.to_radians())],
            max_steps: 500,
        })
    }
}

/// The result of one [`Env::step`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step<const N: usize> {
    /// The observation after the step (the state).
    pub obs: [f64; N],
    /// The reward of the step.
    pub reward: f64,
    /// A termination limit was crossed.
    pub terminated: bool,
    /// The step budget of the episode is used up.
    pub truncated: bool,
}

/// The episode state every environment shares: configuration, state, generator, counters.
#[derive(Debug, Clone)]
struct Episode<const N: usize> {
    config: EnvConfig,
    x: [f64; N],
    rng: ChaCha8Rng,
    steps: usize,
    done: bool,
    /// The RK4 step `dt / substeps`.
    h: f64,
}

/// What a `step` does before integrating: the clipped action, or the step's early answer.
enum Before<const N: usize> {
    Integrate(f64),
    Answer(Result<Step<N>>),
}

impl<const N: usize> Episode<N> {
    /// Validates `config` for a plant with `N` states (the plant's own sizes are checked by
    /// the caller).
    fn new(config: EnvConfig) -> Result<Self> {
        check_positive("dt", config.dt)?;
        check_positive("action limit", config.action_limit)?;
        if config.substeps == 0 || config.max_steps == 0 {
            return Err(SimError::InvalidParameter {
                what: "substeps / max_steps".into(),
                value: 0.0,
                requirement: "must be at least 1",
            });
        }
        check_len("nominal initial state", config.nominal.len(), N)?;
        check_len("reset half-widths", config.reset_half_width.len(), N)?;
        for (i, (&c, &w)) in config
            .nominal
            .iter()
            .zip(&config.reset_half_width)
            .enumerate()
        {
            crate::error::check_finite(&format!("nominal state {i}"), c)?;
            crate::error::check_nonnegative(&format!("reset half-width {i}"), w)?;
        }
        for &(i, b) in &config.limits {
            if i >= N {
                return Err(SimError::InvalidArgument(format!(
                    "termination limit on state {i}, but there are {N} states"
                )));
            }
            check_positive(&format!("termination bound of state {i}"), b)?;
        }
        let h = config.dt / config.substeps as f64;
        let mut x = [0.0; N];
        x.copy_from_slice(&config.nominal);
        Ok(Self {
            config,
            x,
            rng: ChaCha8Rng::seed_from_u64(0),
            steps: 0,
            done: false,
            h,
        })
    }

    fn reset(&mut self, seed: Option<u64>) -> [f64; N] {
        if let Some(s) = seed {
            self.rng = ChaCha8Rng::seed_from_u64(s);
        }
        for i in 0..N {
            let w = self.config.reset_half_width[i];
            let r: f64 = if w > 0.0 {
                self.rng.random_range(-w..=w)
            } else {
                0.0
            };
            self.x[i] = self.config.nominal[i] + r;
        }
        self.steps = 0;
        self.done = false;
        self.x
    }

    fn reset_to(&mut self, x: [f64; N]) -> Result<[f64; N]> {
        crate::error::check_initial_state(&x, N)?;
        self.x = x;
        self.steps = 0;
        self.done = false;
        Ok(self.x)
    }

    /// The NaN check, the answer after the episode's end, the clipping.
    #[inline(always)]
    fn before(&self, action: f64) -> Before<N> {
        if action.is_nan() {
            return Before::Answer(Err(SimError::NonFiniteCommand {
                t: self.steps as f64 * self.config.dt,
                index: 0,
                value: action,
            }));
        }
        if self.done {
            return Before::Answer(Ok(Step {
                obs: self.x,
                reward: 0.0,
                terminated: true,
                truncated: self.steps >= self.config.max_steps,
            }));
        }
        let lim = self.config.action_limit;
        Before::Integrate(action.clamp(-lim, lim))
    }

    /// Counts the step, checks the state, decides termination and truncation.
    #[inline(always)]
    fn after(&mut self) -> Result<Step<N>> {
        self.steps += 1;
        let t1 = self.steps as f64 * self.config.dt;
        crate::error::check_state(t1, self.x.s())?;
        let terminated = self.config.limits.iter().any(|&(i, b)| self.x[i].abs() > b);
        let truncated = self.steps >= self.config.max_steps;
        self.done = terminated || truncated;
        Ok(Step {
            obs: self.x,
            reward: 1.0,
            terminated,
            truncated,
        })
    }
}

/// A Gymnasium-style environment over a plant with `N` states (see the module docs).
#[derive(Debug, Clone)]
pub struct Env<P, const N: usize> {
    plant: P,
    ep: Episode<N>,
    u: Vec<f64>,
    w: Rk4Scratch<[f64; N]>,
}

impl<P: Dynamics, const N: usize> Env<P, N> {
    /// An environment for `plant` (which must have `N` states and at least one input; the
    /// action drives input 0, other inputs are held at zero).
    ///
    /// # Errors
    /// [`SimError::DimensionMismatch`] for a plant with another number of states, no input, or
    /// configuration vectors of the wrong length; [`SimError::InvalidParameter`] for
    /// non-positive `dt`, `action_limit`, zero `substeps`/`max_steps`, negative half-widths;
    /// [`SimError::InvalidArgument`] for a limit on a state that does not exist.
    pub fn new(plant: P, config: EnvConfig) -> Result<Self> {
        check_len("plant states (the environment's N)", plant.nx(), N)?;
        if plant.nu() == 0 {
            return Err(SimError::DimensionMismatch {
                what: "plant inputs (the action drives input 0)".into(),
                expected: 1,
                found: 0,
            });
        }
        let ep = Episode::new(config)?;
        let nu = plant.nu();
        Ok(Self {
            plant,
            ep,
            u: vec![0.0; nu],
            w: Rk4Scratch::new(N),
        })
    }

    /// Starts an episode; with `Some(seed)` the generator is re-seeded first (reproducible
    /// episodes), with `None` it continues. Returns the initial observation.
    pub fn reset(&mut self, seed: Option<u64>) -> [f64; N] {
        self.ep.reset(seed)
    }

    /// Sets the state directly (e.g. to evaluate a policy from chosen states) and starts an
    /// episode there.
    ///
    /// # Errors
    /// [`SimError::NonFiniteInitialState`].
    pub fn reset_to(&mut self, x: [f64; N]) -> Result<[f64; N]> {
        self.ep.reset_to(x)
    }

    /// Applies `action` (clipped to `±action_limit`) for one control period.
    ///
    /// # Errors
    /// [`SimError::NonFiniteCommand`] for a NaN action; [`SimError::NonFiniteState`] if the
    /// plant's state blows up.
    #[inline]
    pub fn step(&mut self, action: f64) -> Result<Step<N>> {
        let u = match self.ep.before(action) {
            Before::Integrate(u) => u,
            Before::Answer(a) => return a,
        };
        self.u[0] = u;
        let t0 = self.ep.steps as f64 * self.ep.config.dt;
        for j in 0..self.ep.config.substeps {
            step_generic(
                &self.plant,
                t0 + j as f64 * self.ep.h,
                &mut self.ep.x,
                &self.u,
                self.ep.h,
                &mut self.w,
                false,
            );
        }
        self.ep.after()
    }

    /// The same environment stepping with the fixed-size RK4 kernel of
    /// [`FixedDynamics::rk4_step_fixed`]: a [`FixedEnv`] with this configuration, state,
    /// generator state and episode counters (the two then continue independently).
    pub fn fixed(&self) -> FixedEnv<P, N>
    where
        P: FixedDynamics<N> + Clone,
    {
        FixedEnv {
            plant: self.plant.clone(),
            ep: self.ep.clone(),
        }
    }

    /// The current observation.
    pub fn observation(&self) -> [f64; N] {
        self.ep.x
    }
    /// Steps taken in this episode.
    pub fn steps(&self) -> usize {
        self.ep.steps
    }
    /// The configuration.
    pub fn config(&self) -> &EnvConfig {
        &self.ep.config
    }
    /// The plant.
    pub fn plant(&self) -> &P {
        &self.plant
    }
}

/// [`Env`] for a [`FixedDynamics`] plant (autonomous, one input, `N` states by its type):
/// the same Gymnasium semantics — configuration checks, seeded resets drawing the same
/// initial states from the same seeds, clipping, reward, termination, truncation, errors —
/// with each RK4 step taken by the plant's [`FixedDynamics::rk4_step_fixed`] on `[f64; N]`
/// (no slices, no scratch, no time argument).
///
/// With the provided [`FixedDynamics::rk4_step_fixed`] ([`crate::fast::rk4_fixed`]) every
/// step is bit-identical to [`Env::step`]'s for the same plant (the operations of
/// [`crate::rk4_step`] in the same order; `tests/env.rs` checks whole episodes). A plant
/// that overrides the step — `pendulab_plants::cart::fast::FastCart` with
/// [`Trig::Anchored`](crate::fast::Trig::Anchored): the later stages' sines and cosines from
/// the step's first ones by the addition theorem — is then as close to [`Env`] as that
/// override documents (each sine/cosine within 2 ulp + 6·10⁻¹⁷ of libm's), not
/// bit-identical; an episode can then end one step earlier or later only if the state
/// crosses a termination bound within those roundings.
///
/// ```
/// use pendulab_sim::env::FixedEnv;
/// use pendulab_sim::fast::FixedDynamics;
/// use pendulab_sim::{Dynamics, Env, EnvConfig};
/// # fn main() -> Result<(), pendulab_sim::SimError> {
/// // A double integrator ẋ = [x₁, u].
/// #[derive(Clone)]
/// struct Di;
/// impl Dynamics for Di {
///     fn nx(&self) -> usize { 2 }
///     fn nu(&self) -> usize { 1 }
///     fn derivative(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
///         dx[0] = x[1];
///         dx[1] = u[0];
///     }
/// }
/// impl FixedDynamics<2> for Di {
///     fn derivative_fixed(&self, x: &[f64; 2], u: f64) -> [f64; 2] { [x[1], u] }
/// }
/// let config = EnvConfig {
///     dt: 0.1, substeps: 2, action_limit: 1.0, nominal: vec![0.0; 2],
///     reset_half_width: vec![0.5; 2], limits: vec![(0, 2.0)], max_steps: 100,
/// };
/// let mut general = Env::<_, 2>::new(Di, config.clone())?;
/// let mut fast = FixedEnv::<_, 2>::new(Di, config)?;
/// assert_eq!(general.reset(Some(3)), fast.reset(Some(3)));
/// for a in [0.3, -2.0, 0.9] {
///     assert_eq!(general.step(a)?, fast.step(a)?); // bit for bit
/// }
/// # Ok(()) }
/// ```
#[derive(Debug, Clone)]
pub struct FixedEnv<P, const N: usize> {
    plant: P,
    ep: Episode<N>,
}

impl<P: FixedDynamics<N>, const N: usize> FixedEnv<P, N> {
    /// An environment for `plant` (see [`FixedEnv`]; the action is the plant's input).
    ///
    /// # Errors
    /// As [`Env::new`] for the configuration: [`SimError::DimensionMismatch`] for
    /// configuration vectors of the wrong length; [`SimError::InvalidParameter`] for
    /// non-positive `dt`, `action_limit`, zero `substeps`/`max_steps`, negative half-widths;
    /// [`SimError::InvalidArgument`] for a limit on a state that does not exist.
    pub fn new(plant: P, config: EnvConfig) -> Result<Self> {
        Ok(Self {
            plant,
            ep: Episode::new(config)?,
        })
    }

    /// As [`Env::reset`].
    pub fn reset(&mut self, seed: Option<u64>) -> [f64; N] {
        self.ep.reset(seed)
    }

    /// As [`Env::reset_to`].
    ///
    /// # Errors
    /// [`SimError::NonFiniteInitialState`].
    pub fn reset_to(&mut self, x: [f64; N]) -> Result<[f64; N]> {
        self.ep.reset_to(x)
    }

    /// As [`Env::step`], each of the `substeps` RK4 steps by
    /// [`FixedDynamics::rk4_step_fixed`].
    ///
    /// # Errors
    /// [`SimError::NonFiniteCommand`] for a NaN action; [`SimError::NonFiniteState`] if the
    /// plant's state blows up.
    #[inline]
    pub fn step(&mut self, action: f64) -> Result<Step<N>> {
        let u = match self.ep.before(action) {
            Before::Integrate(u) => u,
            Before::Answer(a) => return a,
        };
        let h = self.ep.h;
        if self.ep.config.substeps == 1 {
            self.plant.rk4_step_fixed(&mut self.ep.x, u, h);
        } else {
            for _ in 0..self.ep.config.substeps {
                self.plant.rk4_step_fixed(&mut self.ep.x, u, h);
            }
        }
        self.ep.after()
    }

    /// The current observation.
    pub fn observation(&self) -> [f64; N] {
        self.ep.x
    }
    /// Steps taken in this episode.
    pub fn steps(&self) -> usize {
        self.ep.steps
    }
    /// The configuration.
    pub fn config(&self) -> &EnvConfig {
        &self.ep.config
    }
    /// The plant.
    pub fn plant(&self) -> &P {
        &self.plant
    }
}
