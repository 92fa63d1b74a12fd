//! Lane-batched sampled-data runs: `L` closed loops stepped together in
//! structure-of-arrays form (`x[i][l]` is state `i` of lane `l`), so the compiler turns the
//! per-lane arithmetic into SIMD instructions.
//!
//! The special case served here is the one batch studies need most: a single-input plant
//! under static state feedback `u = −K x` from the exact state, sampled every `ts` with
//! zero-order hold, RK4 substeps, and an optional "stay within `|x_i| ≤ bound`" stop — the
//! [`SampledLoop`](crate::SampledLoop) with [`StaticStateFeedback`](crate::controllers::StaticStateFeedback),
//! the full-state sensor, the ideal actuator and a [`StayWithin`](crate::StayWithin)
//! monitor. A lane whose run ends (bound crossed or all samples run) is refilled at once with
//! the next initial state of its queue, so the lanes stay busy; the plant must therefore be
//! autonomous (its right-hand side may not depend on `t`).
//!
//! Results: per initial state the same [`LaneOutcome`] as the general loop reports (held,
//! RK4 steps integrated, final state). With [`LibmSinCos`](crate::fast::LibmSinCos) every arithmetic operation is the
//! general loop's, in the same order, so outcomes and final states are **bit-identical** to
//! [`SampledLoop::run_with`](crate::SampledLoop::run_with) of the same configuration (the
//! plant implementation must mirror its scalar right-hand side operation by operation, as
//! `pendulab_plants::CartPendulum` does). With [`PolySinCos`](crate::fast::PolySinCos) the sines and cosines come
//! from [`sin_cos_lanes`](crate::fast::sin_cos_lanes) (vectorisable; within about 2 ulp of libm, see there), so
//! states differ from the general loop by rounding-level amounts that the closed loop's
//! stable dynamics keep small; runs that end near the bound can in principle end one sample
//! apart.
//!
//! ```
//! use pendulab_sim::fast::{LaneDynamics, LaneOptions, SinCos, run_feedback_lanes, LibmSinCos};
//! # fn main() -> Result<(), pendulab_sim::SimError> {
//! // ẋ = [x₁, u]: a double integrator under u = −(x₀ + 2x₁), four lanes.
//! struct DoubleIntegrator;
//! impl<const L: usize> LaneDynamics<2, L> for DoubleIntegrator {
//!     fn derivative_lanes<M: SinCos>(&self, x: &[[f64; L]; 2], u: &[f64; L]) -> [[f64; L]; 2] {
//!         [x[1], *u]
//!     }
//! }
//! let o = LaneOptions { ts: 1e-2, t_final: 10.0, substeps: 1, stay_within: None };
//! let out = run_feedback_lanes::<_, LibmSinCos, 2, 4>(
//!     &DoubleIntegrator, &[1.0, 2.0], &o, &[[1.0, 0.0], [0.0, 1.0]])?;
//! assert_eq!(out.len(), 2);
//! assert!(out.iter().all(|o| o.held && o.steps == 1000 && o.final_state[0].abs() < 1e-3));
//! # Ok(()) }
//! ```

use super::strategy::SinCos;
use crate::error::{Result, SimError, check_finite};
use rayon::prelude::*;

/// A plant whose right-hand side is evaluated for `L` states at once (structure of arrays),
/// with one input per lane. Autonomous: no time argument.
pub trait LaneDynamics<const N: usize, const L: usize>: Sync {
    /// `ẋ` of every lane; `M` supplies the sines and cosines.
    fn derivative_lanes<M: SinCos>(&self, x: &[[f64; L]; N], u: &[f64; L]) -> [[f64; L]; N];

    /// One classic RK4 step of every lane with the inputs held (provided: [`rk4_lanes`]).
    /// A plant may override it with a step that shares work between the stages when
    /// `M::ANCHORED` (e.g. `pendulab_plants::CartPendulum`); for other `M` the override must
    /// keep [`rk4_lanes`]'s operations.
    #[inline(always)]
    fn rk4_step_lanes<M: SinCos>(&self, x: &mut [[f64; L]; N], u: &[f64; L], h: &[f64; L])
    where
        Self: Sized,
    {
        rk4_lanes::<Self, M, N, L>(self, x, u, h);
    }
}

/// Options of [`run_feedback_lanes`] (the general loop's [`SampledOptions`](crate::SampledOptions)
/// with `t₀ = 0`, RK4 and no delay, plus the stop rule).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaneOptions {
    /// Sample time (s), finite and > 0.
    pub ts: f64,
    /// End time (s); `⌊t_final/ts⌋` sample intervals are run, at least one.
    pub t_final: f64,
    /// RK4 substeps per sample (≥ 1).
    pub substeps: usize,
    /// Stop a run at the first sample with `|x_i| > bound` or `x_i` NaN: `Some((i, bound))`.
    pub stay_within: Option<(usize, f64)>,
}

/// The outcome of one run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaneOutcome<const N: usize> {
    /// `true` if no sample crossed the bound (always `true` without a bound).
    pub held: bool,
    /// RK4 steps integrated (substeps × sample intervals run).
    pub steps: usize,
    /// The state at the last sample seen (the first one past the bound for a stopped run).
    pub final_state: [f64; N],
}

/// Runs `u = −K x` (`gain` = the row `K`) with zero-order hold from every initial state in
/// `x0s`, `L` runs at a time per thread (rayon), and returns the outcomes in input order.
///
/// # Errors
/// [`SimError::InvalidSampleTime`], [`SimError::InvalidTimeSpan`],
/// [`SimError::InvalidParameter`] for bad options or a non-finite gain;
/// [`SimError::InvalidArgument`] for a bound on a state that does not exist;
/// [`SimError::NonFiniteInitialState`] for a bad initial state; [`SimError::NonFiniteCommand`]
/// / [`SimError::NonFiniteState`] (of the lowest-index failing run) if a run blows up.
pub fn run_feedback_lanes<P, M, const N: usize, const L: usize>(
    plant: &P,
    gain: &[f64; N],
    options: &LaneOptions,
    x0s: &[[f64; N]],
) -> Result<Vec<LaneOutcome<N>>>
where
    P: LaneDynamics<N, L>,
    M: SinCos,
{
    let ts = options.ts;
    if !(ts.is_finite() && ts > 0.0) {
        return Err(SimError::InvalidSampleTime(ts));
    }
    crate::integrate::check_span(0.0, options.t_final)?;
    let samples = (options.t_final / ts + 1e-9).floor();
    if !(1.0..=1e12).contains(&samples) {
        return Err(SimError::InvalidTimeSpan {
            what: "the run must span 1 to 1e12 samples",
            t0: 0.0,
            t_final: options.t_final,
        });
    }
    if options.substeps == 0 {
        return Err(SimError::InvalidParameter {
            what: "RK4 substeps per sample".into(),
            value: 0.0,
            requirement: "must be at least 1",
        });
    }
    if let Some((i, b)) = options.stay_within {
        if i >= N {
            return Err(SimError::InvalidArgument(format!(
                "stay-within bound on state {i}, but there are {N} states"
            )));
        }
        if b.is_nan() || b < 0.0 {
            return Err(SimError::InvalidParameter {
                what: format!("bound on state {i}"),
                value: b,
                requirement: "must be ≥ 0",
            });
        }
    }
    for (j, &g) in gain.iter().enumerate() {
        check_finite(&format!("gain entry {j}"), g)?;
    }
    for x0 in x0s {
        crate::error::check_initial_state(x0, N)?;
    }
    let n_samples = samples as usize;
    let cfg = Config {
        steps: (0..n_samples)
            .map(|k| {
                let span = (k + 1) as f64 * ts - k as f64 * ts;
                if options.substeps == 1 {
                    span
                } else {
                    span / options.substeps as f64
                }
            })
            .collect(),
        substeps: options.substeps,
        samples: n_samples,
        ts,
        stay: options.stay_within,
    };
    // Queues of a few hundred runs per task: enough to amortise the lane start-up and to
    // balance the threads.
    let per_task = (64 * L).max(1);
    let parts: Vec<Result<Vec<LaneOutcome<N>>>> = x0s
        .par_chunks(per_task)
        .map(|chunk| run_queue_dispatch::<P, M, N, L>(plant, gain, &cfg, chunk))
        .collect();
    let mut out = Vec::with_capacity(x0s.len());
    for p in parts {
        out.extend(p?);
    }
    Ok(out)
}

struct Config {
    /// RK4 step of each sample interval: `((k + 1)·ts − k·ts) / substeps`.
    steps: Vec<f64>,
    substeps: usize,
    samples: usize,
    ts: f64,
    stay: Option<(usize, f64)>,
}

/// [`run_queue`] compiled for AVX2 when the processor has it (detected at run time), else for
/// the baseline target. AVX2 only widens the vectors: there is no fused multiply–add (Rust
/// never contracts `a·b + c`, and FMA is not enabled), so every operation rounds as in the
/// baseline code and the results are bit-identical.
fn run_queue_dispatch<P, M, const N: usize, const L: usize>(
    plant: &P,
    gain: &[f64; N],
    cfg: &Config,
    queue: &[[f64; N]],
) -> Result<Vec<LaneOutcome<N>>>
where
    P: LaneDynamics<N, L>,
    M: SinCos,
{
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor supports AVX2 (checked just above), the only requirement of
        // calling a function compiled with `target_feature(enable = "avx2")`.
        return unsafe { run_queue_avx2::<P, M, N, L>(plant, gain, cfg, queue) };
    }
    run_queue::<P, M, N, L>(plant, gain, cfg, queue)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_queue_avx2<P, M, const N: usize, const L: usize>(
    plant: &P,
    gain: &[f64; N],
    cfg: &Config,
    queue: &[[f64; N]],
) -> Result<Vec<LaneOutcome<N>>>
where
    P: LaneDynamics<N, L>,
    M: SinCos,
{
    run_queue::<P, M, N, L>(plant, gain, cfg, queue)
}

/// The runs of `queue` through `L` lanes, refilling a lane as soon as its run ends.
#[inline(always)]
fn run_queue<P, M, const N: usize, const L: usize>(
    plant: &P,
    gain: &[f64; N],
    cfg: &Config,
    queue: &[[f64; N]],
) -> Result<Vec<LaneOutcome<N>>>
where
    P: LaneDynamics<N, L>,
    M: SinCos,
{
    let mut out = vec![
        LaneOutcome {
            held: true,
            steps: 0,
            final_state: [0.0; N],
        };
        queue.len()
    ];
    let mut x = [[0.0; L]; N];
    // Per lane: which run it carries (usize::MAX: idle) and the sample index reached.
    let mut run = [usize::MAX; L];
    let mut k = [0usize; L];
    let mut next = 0usize;
    let mut busy = 0usize;
    let load = |l: usize, x: &mut [[f64; L]; N], i: usize| {
        for (j, xj) in x.iter_mut().enumerate() {
            xj[l] = queue[i][j];
        }
    };
    for l in 0..L {
        if next < queue.len() {
            load(l, &mut x, next);
            run[l] = next;
            next += 1;
            busy += 1;
        }
    }
    let ts = cfg.ts;
    let mut u = [0.0; L];
    let mut h = [0.0; L];
    while busy > 0 {
        // Sample instant of every lane: the monitor and the end of a run, first tested for all
        // lanes at once (vectorised), then handled lane by lane where needed.
        let mut any_end = false;
        for l in 0..L {
            let stop = match cfg.stay {
                Some((i, b)) => {
                    let v = x[i][l];
                    v.abs() > b || v.is_nan()
                }
                None => false,
            };
            any_end |= stop | (k[l] >= cfg.samples);
        }
        if any_end {
            for l in 0..L {
                // A lane may need several refills in a row (a run that starts past the bound).
                while run[l] != usize::MAX {
                    let stop = match cfg.stay {
                        Some((i, b)) => {
                            let v = x[i][l];
                            v.abs() > b || v.is_nan()
                        }
                        None => false,
                    };
                    if !stop && k[l] < cfg.samples {
                        break;
                    }
                    let o = &mut out[run[l]];
                    o.held = !stop;
                    o.steps = k[l] * cfg.substeps;
                    for j in 0..N {
                        o.final_state[j] = x[j][l];
                    }
                    k[l] = 0;
                    if next < queue.len() {
                        load(l, &mut x, next);
                        run[l] = next;
                        next += 1;
                    } else {
                        // Idle from now on: park the lane at the origin (its work is
                        // discarded) and keep it out of the monitor.
                        for xj in x.iter_mut() {
                            xj[l] = 0.0;
                        }
                        run[l] = usize::MAX;
                        k[l] = 0;
                        busy -= 1;
                    }
                }
            }
            if busy == 0 {
                break;
            }
        }
        // The controller: u = −(Σ_j K_j x_j), accumulated as StaticStateFeedback does; and the
        // step of the general loop, t_{k+1} − t_k with t_k = k·ts (not exactly ts), per
        // substep.
        let mut bad = false;
        for l in 0..L {
            let mut acc = 0.0;
            for j in 0..N {
                acc += gain[j] * (x[j][l] - 0.0);
            }
            u[l] = -acc;
            bad |= !u[l].is_finite();
            h[l] = cfg.steps[k[l].min(cfg.samples - 1)];
        }
        if bad && let Some(l) = (0..L).find(|&l| run[l] != usize::MAX && !u[l].is_finite()) {
            return Err(SimError::NonFiniteCommand {
                t: k[l] as f64 * ts,
                index: 0,
                value: u[l],
            });
        }
        for _ in 0..cfg.substeps {
            plant.rk4_step_lanes::<M>(&mut x, &u, &h);
        }
        let mut bad = false;
        for l in 0..L {
            k[l] += 1;
            for xj in x.iter() {
                bad |= !xj[l].is_finite();
            }
        }
        if bad {
            for l in 0..L {
                if run[l] == usize::MAX {
                    continue;
                }
                if let Some(j) = (0..N).find(|&j| !x[j][l].is_finite()) {
                    return Err(SimError::NonFiniteState {
                        t: k[l] as f64 * ts,
                        index: j,
                        value: x[j][l],
                    });
                }
            }
        }
    }
    Ok(out)
}

/// One classic RK4 step of every lane with the inputs held, in the operation order of the
/// general kernel (`crate::integrate::rk4`).
#[inline(always)]
pub fn rk4_lanes<P, M, const N: usize, const L: usize>(
    plant: &P,
    x: &mut [[f64; L]; N],
    u: &[f64; L],
    h: &[f64; L],
) where
    P: LaneDynamics<N, L>,
    M: SinCos,
{
    let mut half = [0.0; L];
    let mut sixth = [0.0; L];
    for l in 0..L {
        half[l] = 0.5 * h[l];
        sixth[l] = h[l] / 6.0;
    }
    let stage = |k: &[[f64; L]; N], s: &[f64; L]| {
        let mut xt = [[0.0; L]; N];
        for j in 0..N {
            for l in 0..L {
                xt[j][l] = x[j][l] + s[l] * k[j][l];
            }
        }
        xt
    };
    let k1 = plant.derivative_lanes::<M>(x, u);
    let k2 = plant.derivative_lanes::<M>(&stage(&k1, &half), u);
    let k3 = plant.derivative_lanes::<M>(&stage(&k2, &half), u);
    let k4 = plant.derivative_lanes::<M>(&stage(&k3, h), u);
    for j in 0..N {
        for l in 0..L {
            x[j][l] += sixth[l] * (k1[j][l] + 2.0 * k2[j][l] + 2.0 * k3[j][l] + k4[j][l]);
        }
    }
}
