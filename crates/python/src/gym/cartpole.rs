//! [`ClassicCartPoleCore`]: `n` classic cart-poles (Gymnasium's `CartPole-v1` model) stepped in
//! one call, with `CartPoleEnv`'s single-environment reward rule or `CartPoleVectorEnv`'s
//! autoreset and truncation (the two conventions of the [parent module](super)).

use crate::convert::count;
use std::collections::HashMap;

use numpy::{PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use pendulab_plants::{ClassicCartPole, ClassicCartPoleParams};

use super::{Out, StepArrays, for_chunks, in_blocks, matrix, step_arrays};
use crate::errors::{Kind, new_err};
use crate::plants::plant_error;

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

type PoleOut = Out<f32>;

/// `n` classic cart-poles (Gymnasium's `CartPole-v1` dynamics) stepped together.
///
/// State per environment `[x, ẋ, θ, θ̇]` (m, m/s, rad, rad/s); actions 0 (push with
/// `−force_mag`) or 1 (`+force_mag`). See the [module documentation](super) for the two reward
/// and reset conventions.
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
        #[pyo3(from_py_with = count)] n: usize,
        autoreset: bool,
        max_episode_steps: u32,
        sutton_barto_reward: bool,
        #[pyo3(from_py_with = count)] threads: usize,
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
