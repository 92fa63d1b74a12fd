//! The `gym` facet of the extension module: batches of environments stepped in Rust, behind
//! `pendulab.gym` (the Python side holds the Gymnasium classes, spaces and seeding).
//!
//! Two cores, each holding `n` environments and stepping all of them in one call with the GIL
//! released (on `threads` rayon threads when `threads > 1`):
//!
//! - [`ClassicCartPoleCore`]: Gymnasium's `CartPole-v1` model
//!   ([`pendulab_plants::ClassicCartPole`]). With `autoreset = false` each environment
//!   follows `CartPoleEnv.step` (reward 1 per step, 1 on the terminating step, 0 afterwards —
//!   or Sutton & Barto's 0/−1 — the dynamics continuing after termination, no truncation);
//!   with `autoreset = true` the batch follows `CartPoleVectorEnv.step` (autoreset on the next
//!   step, truncation at `max_episode_steps`, float32 rewards). Initial states come from the
//!   caller (NumPy's generator on the Python side, so that seeds give Gymnasium's states).
//! - [`RigCore`]: the book's cart or arm rig as `pendulab_sim::env` environments (voltage in,
//!   RK4 over the control period, `EnvConfig`'s termination and truncation, seeded ChaCha8
//!   resets), a balance or swing-up task, optionally the encoders' quantisation of the
//!   observed angles and positions; autoreset on the next step as Gymnasium's vector envs.

use std::collections::HashMap;

use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use rayon::prelude::*;

use pendulab_plants::{ArmPendulum, CartPendulum, ClassicCartPole, ClassicCartPoleParams, RigSpec};
use pendulab_sim::env::FixedEnv;
use pendulab_sim::{Env, EnvConfig, Quantizer, SimError, Step};

use crate::errors::{Kind, new_err};
use crate::plants::{arm_params, cart_params, plant_error, sim_error};

/// Environments per parallel task: large enough that a task outweighs its scheduling.
const CHUNK: usize = 512;

/// Adds this facet's classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<ClassicCartPoleCore>()?;
    m.add_class::<RigCore>()?;
    Ok(())
}

/// Runs `f` on matching chunks of `slots` and `out` (with the chunk's index offset), on the
/// global rayon pool when `threads > 1` and there is more than one chunk, in one go otherwise.
fn for_chunks<T: Send, O: Send, F>(threads: usize, slots: &mut [T], out: &mut [O], f: F)
where
    F: Fn(usize, &mut [T], &mut [O]) + Sync,
{
    if threads > 1 && slots.len() > CHUNK {
        slots
            .par_chunks_mut(CHUNK)
            .zip(out.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(|(c, (s, o))| f(c * CHUNK, s, o));
    } else {
        f(0, slots, out);
    }
}

/// Environments stepped between two looks at Python's signal handlers.
const SIGNAL_BLOCK: usize = 1 << 17;

/// Runs `f` on the index ranges of `n` environments, [`SIGNAL_BLOCK`] at a time, each with
/// the GIL released, and runs Python's signal handlers between them: Ctrl-C during the step
/// of a huge batch raises `KeyboardInterrupt` within one block's time (the environments of
/// the blocks already stepped stay stepped: reset them).
///
/// # Errors
/// `f`'s first error, or the exception a signal handler raised.
fn in_blocks<F>(py: Python<'_>, n: usize, mut f: F) -> PyResult<()>
where
    F: FnMut(std::ops::Range<usize>) -> PyResult<()> + Send,
{
    let mut start = 0;
    while start < n {
        let end = (start + SIGNAL_BLOCK).min(n);
        // The closure's error is a `PyErr`, which may cross threads (it is `Send`).
        py.detach(|| f(start..end))?;
        py.check_signals()?;
        start = end;
    }
    Ok(())
}

/// Builds a `(n, 4)` array from `n·4` values.
fn matrix<'py, T: numpy::Element>(
    py: Python<'py>,
    v: Vec<T>,
    n: usize,
) -> PyResult<Bound<'py, PyArray2<T>>> {
    v.into_pyarray(py).reshape([n, 4])
}

/// One environment of [`ClassicCartPoleCore`].
#[derive(Debug, Clone, Copy, Default)]
struct PoleSlot {
    s: [f64; 4],
    steps: u32,
    /// Terminated or truncated on the previous step (autoreset on this one).
    prev_done: bool,
    /// Steps taken since termination (single-env reward rule).
    beyond: Option<u32>,
}

/// What one step of one environment produced (`T`: f32 for the cart-pole, f64 for the rigs).
#[derive(Debug, Clone, Copy, Default)]
struct Out<T> {
    obs: [T; 4],
    reward: T,
    terminated: bool,
    truncated: bool,
}

type PoleOut = Out<f32>;
type RigOut = Out<f64>;

/// `(obs (n, 4), reward (n,), terminated (n,), truncated (n,))` as NumPy arrays.
type StepArrays<'py, T> = (
    Bound<'py, PyArray2<T>>,
    Bound<'py, PyArray1<T>>,
    Bound<'py, PyArray1<bool>>,
    Bound<'py, PyArray1<bool>>,
);

/// The steps' results as NumPy arrays.
fn step_arrays<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    out: &[Out<T>],
) -> PyResult<StepArrays<'py, T>> {
    let obs: Vec<T> = out.iter().flat_map(|o| o.obs).collect();
    let reward: Vec<T> = out.iter().map(|o| o.reward).collect();
    let term: Vec<bool> = out.iter().map(|o| o.terminated).collect();
    let trunc: Vec<bool> = out.iter().map(|o| o.truncated).collect();
    Ok((
        matrix(py, obs, out.len())?,
        reward.into_pyarray(py),
        term.into_pyarray(py),
        trunc.into_pyarray(py),
    ))
}

/// `n` classic cart-poles (Gymnasium's `CartPole-v1` dynamics) stepped together.
///
/// State per environment `[x, ẋ, θ, θ̇]` (m, m/s, rad, rad/s); actions 0 (push with
/// `−force_mag`) or 1 (`+force_mag`). See the module documentation for the two reward and
/// reset conventions.
#[pyclass(module = "pendulab._native")]
pub struct ClassicCartPoleCore {
    plant: ClassicCartPole,
    slots: Vec<PoleSlot>,
    autoreset: bool,
    sutton_barto: bool,
    max_episode_steps: u32,
    threads: usize,
}

impl ClassicCartPoleCore {
    fn step_one(&self, slot: &mut PoleSlot, action: u8) -> PoleOut {
        let s = self.plant.step(&slot.s, action);
        slot.s = s;
        let terminated = self.plant.is_terminal(&s);
        let obs = s.map(|v| v as f32);
        if self.autoreset {
            slot.steps += 1;
            let truncated = slot.steps >= self.max_episode_steps;
            slot.prev_done = terminated || truncated;
            let reward = if self.sutton_barto {
                -f32::from(u8::from(terminated))
            } else {
                1.0
            };
            return PoleOut {
                obs,
                reward,
                terminated,
                truncated,
            };
        }
        let reward = match (terminated, slot.beyond) {
            (false, _) => {
                if self.sutton_barto {
                    0.0
                } else {
                    1.0
                }
            }
            (true, None) => {
                slot.beyond = Some(0);
                if self.sutton_barto { -1.0 } else { 1.0 }
            }
            (true, Some(k)) => {
                slot.beyond = Some(k + 1);
                if self.sutton_barto { -1.0 } else { 0.0 }
            }
        };
        PoleOut {
            obs,
            reward,
            terminated,
            truncated: false,
        }
    }
}

#[pymethods]
impl ClassicCartPoleCore {
    /// `n` environments with Gymnasium's `CartPole-v1` parameters, each overridable by
    /// keyword (`gravity`, `masscart`, `masspole`, `length`, `force_mag`, `tau`,
    /// `x_threshold`, `theta_threshold`) and `semi_implicit` for the semi-implicit Euler step.
    ///
    /// Raises `ValueError` for `n = 0`, `max_episode_steps = 0`, an unknown or invalid
    /// parameter (the message names it).
    #[new]
    #[pyo3(signature = (n, *, autoreset, max_episode_steps = 500, sutton_barto_reward = false, threads = 1, semi_implicit = false, params = None))]
    fn new(
        n: usize,
        autoreset: bool,
        max_episode_steps: u32,
        sutton_barto_reward: bool,
        threads: usize,
        semi_implicit: bool,
        params: Option<HashMap<String, f64>>,
    ) -> PyResult<Self> {
        if n == 0 || max_episode_steps == 0 {
            return Err(new_err(
                Kind::InvalidArgument,
                "num_envs and max_episode_steps must be at least 1".into(),
                None,
            ));
        }
        let mut p = ClassicCartPoleParams::gymnasium();
        for (k, v) in params.unwrap_or_default() {
            let field = match k.as_str() {
                "gravity" => &mut p.gravity,
                "masscart" => &mut p.masscart,
                "masspole" => &mut p.masspole,
                "length" => &mut p.length,
                "force_mag" => &mut p.force_mag,
                "tau" => &mut p.tau,
                "x_threshold" => &mut p.x_threshold,
                "theta_threshold" => &mut p.theta_threshold,
                _ => {
                    return Err(new_err(
                        Kind::InvalidArgument,
                        format!("classic cart-pole: unknown parameter {k:?}"),
                        None,
                    ));
                }
            };
            *field = v;
        }
        if semi_implicit {
            p.integrator = pendulab_plants::CartPoleIntegrator::SemiImplicitEuler;
        }
        let plant = ClassicCartPole::new(p).map_err(|e| plant_error(&e))?;
        Ok(Self {
            plant,
            slots: vec![PoleSlot::default(); n],
            autoreset,
            sutton_barto: sutton_barto_reward,
            max_episode_steps,
            threads: threads.max(1),
        })
    }

    /// Number of environments.
    #[getter]
    fn num_envs(&self) -> usize {
        self.slots.len()
    }

    /// The states as an `(n, 4)` float64 array.
    #[getter]
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let v: Vec<f64> = self.slots.iter().flat_map(|s| s.s).collect();
        matrix(py, v, self.slots.len())
    }

    /// How many environments the next `step` resets (those done on the last step).
    #[getter]
    fn pending_resets(&self) -> usize {
        if self.autoreset {
            self.slots.iter().filter(|s| s.prev_done).count()
        } else {
            0
        }
    }

    /// Starts every episode at `states` (`(n, 4)`, Gymnasium's order); returns the float32
    /// observations. Raises `ValueError` for a wrong shape or a non-finite state.
    fn reset_to<'py>(
        &mut self,
        py: Python<'py>,
        states: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let n = self.slots.len();
        let a = states.as_array();
        if a.shape() != [n, 4] {
            return Err(new_err(
                Kind::Shape,
                format!("states: expected shape ({n}, 4), got {:?}", a.shape()),
                None,
            ));
        }
        if let Some(((i, j), v)) = a.indexed_iter().find(|(_, v)| !v.is_finite()) {
            return Err(new_err(
                Kind::NotFinite,
                format!("states[{i}, {j}] = {v} is not finite"),
                None,
            ));
        }
        let mut obs = Vec::with_capacity(4 * n);
        for (i, slot) in self.slots.iter_mut().enumerate() {
            let s = [a[[i, 0]], a[[i, 1]], a[[i, 2]], a[[i, 3]]];
            *slot = PoleSlot {
                s,
                ..PoleSlot::default()
            };
            obs.extend(s.map(|v| v as f32));
        }
        matrix(py, obs, n)
    }

    /// Steps every environment with `actions` (`n` integers, each 0 or 1). With autoreset,
    /// the environments done on the previous step instead start again at the columns of
    /// `fresh` (`(4, k)`, `k = pending_resets`, in index order) with reward 0 and no
    /// termination or truncation. Returns `(obs (n, 4) float32, reward (n,) float32,
    /// terminated (n,), truncated (n,))`.
    ///
    /// Raises `ValueError` for a wrong number of actions, an action other than 0 or 1, or a
    /// `fresh` array of the wrong shape (nothing is stepped then).
    #[pyo3(signature = (actions, fresh = None))]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray1<'py, i64>,
        fresh: Option<PyReadonlyArray2<'py, f64>>,
    ) -> PyResult<StepArrays<'py, f32>> {
        let n = self.slots.len();
        let acts = actions.as_slice()?;
        if acts.len() != n {
            return Err(new_err(
                Kind::Shape,
                format!("actions: expected {n} actions, got {}", acts.len()),
                None,
            ));
        }
        if let Some((i, a)) = acts.iter().enumerate().find(|(_, a)| !matches!(a, 0 | 1)) {
            return Err(new_err(
                Kind::InvalidArgument,
                format!("actions[{i}] = {a}: a cart-pole action is 0 or 1"),
                None,
            ));
        }
        let k = self.pending_resets();
        let fresh = match (k, fresh) {
            (0, _) => None,
            (k, Some(f)) if f.shape() == [4, k] => Some(f.as_array().to_owned()),
            (k, f) => {
                return Err(new_err(
                    Kind::Shape,
                    format!(
                        "fresh: expected initial states of shape (4, {k}), got {:?}",
                        f.map(|f| f.shape().to_vec())
                    ),
                    None,
                ));
            }
        };
        let mut out = vec![PoleOut::default(); n];
        let mut slots = std::mem::take(&mut self.slots);
        let this = &*self;
        let reset = py.detach(|| {
            // The resets first (sequential: column j goes to the j-th pending environment).
            let mut reset = vec![false; n];
            if let Some(f) = &fresh {
                let mut j = 0;
                for (i, slot) in slots.iter_mut().enumerate() {
                    if slot.prev_done {
                        let s = [f[[0, j]], f[[1, j]], f[[2, j]], f[[3, j]]];
                        *slot = PoleSlot {
                            s,
                            ..PoleSlot::default()
                        };
                        out[i].obs = s.map(|v| v as f32);
                        reset[i] = true;
                        j += 1;
                    }
                }
            }
            reset
        });
        let result = in_blocks(py, n, |r| {
            let (s, o) = (&mut slots[r.clone()], &mut out[r.clone()]);
            for_chunks(this.threads, s, o, |off, slots, out| {
                let off = r.start + off;
                for (i, (slot, o)) in slots.iter_mut().zip(out.iter_mut()).enumerate() {
                    if !reset[off + i] {
                        *o = this.step_one(slot, acts[off + i] as u8);
                    }
                }
            });
            Ok(())
        });
        self.slots = slots;
        result?;
        step_arrays(py, &out)
    }
}

/// The task a [`RigCore`] rewards.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Task {
    /// Reward 1 per step (as CartPole-v1); start near upright, end beyond 12° or the travel.
    Balance,
    /// Reward `(1 + cos θ)/2` of the pendulum angle (1 upright, 0 hanging); start near
    /// hanging, end beyond the travel only.
    SwingUp,
}

/// One environment of a rig, stepped by `pendulab_sim::env`.
trait RigEnv: Send {
    fn reset(&mut self, seed: Option<u64>) -> [f64; 4];
    fn step(&mut self, action: f64) -> Result<Step<4>, SimError>;
}

impl RigEnv for FixedEnv<CartPendulum, 4> {
    fn reset(&mut self, seed: Option<u64>) -> [f64; 4] {
        FixedEnv::reset(self, seed)
    }
    #[inline]
    fn step(&mut self, action: f64) -> Result<Step<4>, SimError> {
        FixedEnv::step(self, action)
    }
}

impl RigEnv for Env<ArmPendulum, 4> {
    fn reset(&mut self, seed: Option<u64>) -> [f64; 4] {
        Env::reset(self, seed)
    }
    #[inline]
    fn step(&mut self, action: f64) -> Result<Step<4>, SimError> {
        Env::step(self, action)
    }
}

/// One rig environment with its autoreset flag.
struct RigSlot<E> {
    env: E,
    prev_done: bool,
}

/// The rig's environments, by plant.
enum RigEnvs {
    Cart(Vec<RigSlot<FixedEnv<CartPendulum, 4>>>),
    Arm(Vec<RigSlot<Env<ArmPendulum, 4>>>),
}

/// `n` environments of the book's cart or arm rig stepped together (see the module docs).
///
/// State and observation `[z, θ, ż, θ̇]` (cart: m, rad, m/s, rad/s) or `[θ₁, θ₂, θ̇₁, θ̇₂]`
/// (arm: rad, rad/s), angles from upright; action the motor voltage (V), clipped to ±5 V.
#[pyclass(module = "pendulab._native")]
pub struct RigCore {
    envs: RigEnvs,
    task: Task,
    autoreset: bool,
    /// The encoders' quantisers of states 0 and 1, if observations are quantised.
    encoders: Option<[Quantizer; 2]>,
    /// The rig's D/A converter (`RigSpec::dac`), if actions are quantised by it.
    dac: Option<Quantizer>,
    threads: usize,
    config: EnvConfig,
    travel: f64,
}

/// The environment configuration of a rig and task (see [`RigCore::new`]).
fn rig_config(
    rig: &str,
    task: Task,
    dt: f64,
    substeps: usize,
    max_steps: usize,
    travel: f64,
) -> PyResult<EnvConfig> {
    let upright_window = 12f64.to_radians();
    let (nominal, limits) = match task {
        Task::Balance => (vec![0.0; 4], vec![(0, travel), (1, upright_window)]),
        Task::SwingUp => (vec![0.0, std::f64::consts::PI, 0.0, 0.0], vec![(0, travel)]),
    };
    if !matches!(rig, "cart" | "arm") {
        return Err(new_err(
            Kind::InvalidArgument,
            format!("rig {rig:?}: expected \"cart\" or \"arm\""),
            None,
        ));
    }
    Ok(EnvConfig {
        dt,
        substeps,
        action_limit: RigSpec::cart().input_limit,
        nominal,
        reset_half_width: vec![0.05; 4],
        limits,
        max_steps,
    })
}

impl RigCore {
    fn out(&self, step: Step<4>) -> RigOut {
        let reward = match (self.task, step.reward > 0.0) {
            (_, false) => 0.0,
            (Task::Balance, true) => step.reward,
            (Task::SwingUp, true) => 0.5 * (1.0 + step.obs[1].cos()),
        };
        RigOut {
            obs: self.observe(step.obs),
            reward,
            terminated: step.terminated,
            truncated: step.truncated,
        }
    }

    fn observe(&self, mut x: [f64; 4]) -> [f64; 4] {
        if let Some(q) = &self.encoders {
            x[0] = q[0].apply(x[0]);
            x[1] = q[1].apply(x[1]);
        }
        x
    }

    fn step_all<E: RigEnv>(
        &self,
        slots: &mut [RigSlot<E>],
        acts: &[f64],
        out: &mut [RigOut],
    ) -> Result<(), SimError> {
        let first_error = std::sync::Mutex::new(None::<(usize, SimError)>);
        for_chunks(self.threads, slots, out, |off, slots, out| {
            for (i, (slot, o)) in slots.iter_mut().zip(out.iter_mut()).enumerate() {
                if self.autoreset && slot.prev_done {
                    slot.prev_done = false;
                    let x = slot.env.reset(None);
                    *o = RigOut {
                        obs: self.observe(x),
                        ..RigOut::default()
                    };
                    continue;
                }
                match slot.env.step(acts[off + i]) {
                    Ok(s) => {
                        *o = self.out(s);
                        slot.prev_done = s.terminated || s.truncated;
                    }
                    Err(e) => {
                        let mut g = first_error.lock().unwrap_or_else(|p| p.into_inner());
                        if g.as_ref().is_none_or(|(j, _)| off + i < *j) {
                            *g = Some((off + i, e));
                        }
                    }
                }
            }
        });
        match first_error.into_inner().unwrap_or_else(|p| p.into_inner()) {
            Some((_, e)) => Err(e),
            None => Ok(()),
        }
    }
}

/// Builds `n` environments of one plant.
fn slots<E>(n: usize, make: impl Fn() -> Result<E, SimError>) -> PyResult<Vec<RigSlot<E>>> {
    (0..n)
        .map(|_| {
            Ok(RigSlot {
                env: make().map_err(|e| sim_error(&e))?,
                prev_done: false,
            })
        })
        .collect()
}

#[pymethods]
impl RigCore {
    /// `n` environments of `rig` (`"cart"` or `"arm"`) for `task` (`"balance"` or
    /// `"swingup"`): control period `dt` (s) with `substeps` RK4 steps, at most `max_steps`
    /// steps, the drive's travel `travel` (m for the cart, rad for the arm; beyond it the
    /// episode terminates), the plant's parameters (`params`: a dict of the book's symbols,
    /// unspecified ones from the book's table), the observed positions quantised by the
    /// rig's encoders if `quantize`, the voltage quantised by the rig's D/A converter
    /// (`RigSpec::dac`: 16 bits over ±5 V, step `10/2¹⁶` V, round to nearest; applied with the
    /// ±5 V saturation, whose bounds are converter levels, so the order does not matter) if
    /// `dac`.
    ///
    /// Raises `ValueError` naming the offending argument or parameter.
    #[new]
    #[pyo3(signature = (rig, n, *, task = "balance", autoreset = false, dt = 0.02, substeps = 1, max_steps = 500, travel = None, quantize = false, dac = false, params = None, threads = 1))]
    fn new(
        rig: &str,
        n: usize,
        task: &str,
        autoreset: bool,
        dt: f64,
        substeps: usize,
        max_steps: usize,
        travel: Option<f64>,
        quantize: bool,
        dac: bool,
        params: Option<HashMap<String, f64>>,
        threads: usize,
    ) -> PyResult<Self> {
        if n == 0 {
            return Err(new_err(
                Kind::InvalidArgument,
                "num_envs must be at least 1".into(),
                None,
            ));
        }
        let task = match task {
            "balance" => Task::Balance,
            "swingup" => Task::SwingUp,
            _ => {
                return Err(new_err(
                    Kind::InvalidArgument,
                    format!("task {task:?}: expected \"balance\" or \"swingup\""),
                    None,
                ));
            }
        };
        // The rig's travel (`RigSpec::travel_limit`; docs/model.md).
        let rig_spec = if rig == "arm" {
            RigSpec::arm()
        } else {
            RigSpec::cart()
        };
        let travel = travel.unwrap_or(rig_spec.travel_limit);
        let config = rig_config(rig, task, dt, substeps, max_steps, travel)?;
        let (envs, spec) = if rig == "cart" {
            let plant =
                CartPendulum::new(cart_params(params.as_ref())?).map_err(|e| plant_error(&e))?;
            let envs = slots(n, || FixedEnv::new(plant, config.clone()))?;
            (RigEnvs::Cart(envs), RigSpec::cart())
        } else {
            let plant =
                ArmPendulum::new(arm_params(params.as_ref())?).map_err(|e| plant_error(&e))?;
            let envs = slots(n, || Env::new(plant, config.clone()))?;
            (RigEnvs::Arm(envs), RigSpec::arm())
        };
        let encoders = if quantize {
            let q = |i: usize| Quantizer::new(spec.encoders[i].step).map_err(|e| sim_error(&e));
            Some([q(0)?, q(1)?])
        } else {
            None
        };
        let dac = if dac {
            let d = spec.dac;
            Some(Quantizer::from_bits(d.bits, d.max - d.min).map_err(|e| sim_error(&e))?)
        } else {
            None
        };
        Ok(Self {
            envs,
            task,
            autoreset,
            encoders,
            dac,
            threads: threads.max(1),
            config,
            travel,
        })
    }

    /// Number of environments.
    #[getter]
    fn num_envs(&self) -> usize {
        match &self.envs {
            RigEnvs::Cart(v) => v.len(),
            RigEnvs::Arm(v) => v.len(),
        }
    }

    /// The drive's travel (m or rad) beyond which an episode terminates.
    #[getter]
    fn travel(&self) -> f64 {
        self.travel
    }

    /// Control period (s).
    #[getter]
    fn dt(&self) -> f64 {
        self.config.dt
    }

    /// Steps per episode before truncation.
    #[getter]
    fn max_steps(&self) -> usize {
        self.config.max_steps
    }

    /// The states as an `(n, 4)` float64 array (not quantised).
    #[getter]
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let v: Vec<f64> = match &self.envs {
            RigEnvs::Cart(s) => s.iter().flat_map(|s| s.env.observation()).collect(),
            RigEnvs::Arm(s) => s.iter().flat_map(|s| s.env.observation()).collect(),
        };
        matrix(py, v, self.num_envs())
    }

    /// Starts every episode: environment `i` re-seeded with `seeds[i]` (reproducible), or,
    /// with `seeds = None`, continuing its generator. Initial states uniform in ±0.05 around
    /// upright (balance) or hanging (swing-up). Returns the `(n, 4)` observations.
    #[pyo3(signature = (seeds = None))]
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seeds: Option<Vec<u64>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let n = self.num_envs();
        if let Some(s) = &seeds
            && s.len() != n
        {
            return Err(new_err(
                Kind::Shape,
                format!("seeds: expected {n} seeds, got {}", s.len()),
                None,
            ));
        }
        let seed = |i: usize| seeds.as_ref().map(|s| s[i]);
        let xs: Vec<[f64; 4]> = match &mut self.envs {
            RigEnvs::Cart(v) => v
                .iter_mut()
                .enumerate()
                .map(|(i, s)| {
                    s.prev_done = false;
                    s.env.reset(seed(i))
                })
                .collect(),
            RigEnvs::Arm(v) => v
                .iter_mut()
                .enumerate()
                .map(|(i, s)| {
                    s.prev_done = false;
                    s.env.reset(seed(i))
                })
                .collect(),
        };
        let obs: Vec<f64> = xs.into_iter().flat_map(|x| self.observe(x)).collect();
        matrix(py, obs, n)
    }

    /// Starts every episode at `states` (`(n, 4)`). Raises `ValueError` for a wrong shape or
    /// a non-finite state.
    fn reset_to<'py>(
        &mut self,
        py: Python<'py>,
        states: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let n = self.num_envs();
        let a = states.as_array();
        if a.shape() != [n, 4] {
            return Err(new_err(
                Kind::Shape,
                format!("states: expected shape ({n}, 4), got {:?}", a.shape()),
                None,
            ));
        }
        let row = |i: usize| [a[[i, 0]], a[[i, 1]], a[[i, 2]], a[[i, 3]]];
        let mut obs = Vec::with_capacity(4 * n);
        for i in 0..n {
            let x = match &mut self.envs {
                RigEnvs::Cart(v) => {
                    v[i].prev_done = false;
                    v[i].env.reset_to(row(i))
                }
                RigEnvs::Arm(v) => {
                    v[i].prev_done = false;
                    v[i].env.reset_to(row(i))
                }
            }
            .map_err(|e| sim_error(&e))?;
            obs.extend(self.observe(x));
        }
        matrix(py, obs, n)
    }

    /// Steps every environment with its voltage `actions[i]` (V, clipped to ±5 V, and
    /// quantised by the D/A converter if the core was made with `dac`). With
    /// autoreset, the environments done on the previous step start a new episode instead
    /// (their generators continuing), with reward 0 and no termination or truncation.
    /// Returns `(obs (n, 4), reward (n,), terminated (n,), truncated (n,))`.
    ///
    /// Raises `ValueError` for a wrong number of actions or a NaN action (nothing is stepped
    /// then), or if a plant's state stops being finite.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<StepArrays<'py, f64>> {
        let n = self.num_envs();
        let acts = actions.as_slice()?;
        if acts.len() != n {
            return Err(new_err(
                Kind::Shape,
                format!("actions: expected {n} actions, got {}", acts.len()),
                None,
            ));
        }
        if let Some((i, a)) = acts.iter().enumerate().find(|(_, a)| a.is_nan()) {
            return Err(new_err(
                Kind::NotFinite,
                format!("actions[{i}] = {a}: the voltage must be a number"),
                None,
            ));
        }
        let quantised: Vec<f64>;
        let acts = match &self.dac {
            Some(q) => {
                quantised = acts.iter().map(|&a| q.apply(a)).collect();
                &quantised[..]
            }
            None => acts,
        };
        let mut out = vec![RigOut::default(); n];
        let mut envs = std::mem::replace(&mut self.envs, RigEnvs::Cart(Vec::new()));
        let this = &*self;
        let result = in_blocks(py, n, |r| {
            let (a, o) = (&acts[r.clone()], &mut out[r.clone()]);
            match &mut envs {
                RigEnvs::Cart(v) => this.step_all(&mut v[r], a, o),
                RigEnvs::Arm(v) => this.step_all(&mut v[r], a, o),
            }
            .map_err(|e| sim_error(&e))
        });
        self.envs = envs;
        result?;
        step_arrays(py, &out)
    }
}
