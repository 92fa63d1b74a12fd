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
//!
//! The cores live in `gym/cartpole.rs` and `gym/rig.rs`; this file holds what both use: the
//! chunked parallel stepping, the signal checks between blocks and the NumPy step results.

mod cartpole;
mod rig;

pub use cartpole::ClassicCartPoleCore;
pub use rig::RigCore;

use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use rayon::prelude::*;

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

/// What one step of one environment produced (`T`: f32 for the cart-pole, f64 for the rigs).
#[derive(Debug, Clone, Copy, Default)]
struct Out<T> {
    obs: [T; 4],
    reward: T,
    terminated: bool,
    truncated: bool,
}

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
