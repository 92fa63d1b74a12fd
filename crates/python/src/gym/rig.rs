//! [`RigCore`]: `n` environments of the book's cart or arm rig (`pendulab_sim::env`: voltage in,
//! RK4 over the control period, seeded resets) for a balance or swing-up task, with the encoders'
//! quantisation of the observations and the D/A converter's of the actions optional, autoreset
//! on the next step as Gymnasium's vector envs (see the [parent module](super)).

use crate::convert::count;
use std::collections::HashMap;

use numpy::{PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use pendulab_plants::{ArmPendulum, CartPendulum, RigSpec};
use pendulab_sim::env::FixedEnv;
use pendulab_sim::{Env, EnvConfig, Quantizer, SimError, Step};

use super::{Out, StepArrays, for_chunks, in_blocks, matrix, step_arrays};
use crate::errors::{Kind, new_err};
use crate::plants::{arm_params, cart_params, plant_error, sim_error};

type RigOut = Out<f64>;

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

/// `n` environments of the book's cart or arm rig stepped together (see the [module
/// documentation](super)).
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
        #[pyo3(from_py_with = count)] n: usize,
        task: &str,
        autoreset: bool,
        dt: f64,
        #[pyo3(from_py_with = count)] substeps: usize,
        #[pyo3(from_py_with = count)] max_steps: usize,
        travel: Option<f64>,
        quantize: bool,
        dac: bool,
        params: Option<HashMap<String, f64>>,
        #[pyo3(from_py_with = count)] threads: usize,
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
