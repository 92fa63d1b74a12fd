//! The simulator's workloads: `sim-rk4`, `sim-batch` and `cartpole-step`.
//!
//! All three run the nonlinear cart pendulum of `pendulab-plants` (book table 3.5, `docs/model.md`
//! §1) under the LQR gain of its upright linearisation with `Q = diag(10, 10, 0, 0)`, `R = 1` (the
//! book's `cdip_lqr_sim` design, `u = −K x`):
//!
//! - `sim-rk4`: one 10 s closed-loop run from θ₀ = 15°, controller at 1 kHz with zero-order
//!   hold, classic RK4 at 1 ms, every sample recorded into the `Trajectory` (recycling the
//!   previous result's storage), by the fixed-size kernel `pendulab_sim::fast::FixedLoop`
//!   (`SampledLoop::fixed`: the loop monomorphised on `[f64; 4]`) over the kernel type
//!   `pendulab_plants::cart::fast::FastCart` with `Trig::Anchored`, whose step for short steps
//!   takes series sines and cosines at the three angles the
//!   step's start fixes, the later stages' accelerations by a small rotation (each sine and
//!   cosine within 2 ulp + 6·10⁻¹⁷ of libm), with fused multiply–adds where the processor has
//!   FMA (the kernel's FMA-compiled loop, chosen at run time; the check names the path).
//!   Figure: RK4 steps per second on one core, timed in rounds alternating with the same
//!   kernel forced onto the baseline loop (separate multiplications and additions). Check:
//!   the headline's largest deviation from the general `SampledLoop` run with libm (and the
//!   baseline loop's); the fixed-size kernel with libm (bit-identical to the general loop)
//!   and with the polynomial sine/cosine; the general loop's rate (recycled, freshly
//!   allocated, unrecorded); the run against the same loop integrated by Dormand–Prince at
//!   `rtol = 1e-12` (the RK4 error of the timed run); that it balances.
//! - `sim-batch`: the 100×100 grid θ₀ ∈ [−1.2, 1.2] rad × θ̇₀ ∈ [−3, 3] rad/s, 10 s each at
//!   1 kHz, on all cores (rayon), classifying each run as upright (`|θ| ≤ π/2` throughout) or
//!   fallen (the run stops at the first sample past π/2). Figure: trajectory-steps actually
//!   integrated per second by the lane kernel (`pendulab_sim::fast::lanes`: 8 runs stepped together
//!   in SIMD registers, `AnchoredSinCos`: the polynomial sine/cosine within 2 ulp of libm once
//!   per RK4 step, the later stages' by the addition theorem); the check also gives the
//!   wall time of the whole grid and the rate counted on the nominal 10⁸ steps, the rate with
//!   the polynomial sine/cosine at every stage (timed alternately), the upright
//!   fraction, the same grid through the general `SampledLoop` (rate, and the lane kernel with
//!   libm's sine/cosine, which must be bit-identical to it), and how far the headline's
//!   outcomes and final states are from the general loop's.
//! - `cartpole-step`: the Gymnasium-style environment (CartPole-v1 settings on this rig: one
//!   RK4 step of 20 ms per `step`, track ±0.4 m chosen here) driven by uniform random actions
//!   in ±5 V with resets at episode ends, like a random-policy rollout, through
//!   `pendulab_sim::env::FixedEnv` (the fixed-size RK4 kernel of `FixedDynamics`) over
//!   `FastCart` with `Trig::Anchored`: the first angle's sine/cosine by a series within 0.25 rad
//!   of upright, the later stages' by the addition theorem for offsets up to 1/8 rad (each
//!   within 2 ulp + 1.1·10⁻¹⁶ of libm; libm beyond). Figure: `step` calls per second,
//!   random actions included. Check: the general `Env` with libm (the previous headline),
//!   timed alternately with the headline; `FixedEnv` with libm (bit-identical to `Env` over
//!   10 000 steps); `Env` with the polynomial sine/cosine; the anchored environment against
//!   the libm one over 2000 episodes (episodes ending differently, largest state deviation,
//!   largest ratio to the documented bound `n · 10⁻¹⁴ · e^{8 n h}` after `n` steps);
//!   how often the anchored step falls back to libm in the rollout's episodes (and how often
//!   it would with the 1/32 rad series of the 1 ms loops); one step equals the RK4 kernel;
//!   an LQR policy survives the 500-step episode; the cost of drawing the random actions.

use super::{BenchReport, Budget, Workload, time};
use anyhow::{Context, Result};
use pendulab_lti::Mat;
use pendulab_plants::cart::fast::FastCart;
use pendulab_plants::{CartEquilibrium, CartPendulum};
use pendulab_sim::batch::{Axis, grid, run_initial_states};
use pendulab_sim::controllers::StaticStateFeedback;
use pendulab_sim::env::FixedEnv;
use pendulab_sim::fast::{
    AnchoredSinCos, FixedDynamics, LaneOptions, LibmSinCos, MulAddPath, PolySinCos, SHIFT_LIMIT,
    Trig, run_feedback_lanes,
};
use pendulab_sim::{
    Dynamics, Env, EnvConfig, Integrator, Record, RunStatus, SampledLoop, SampledOptions,
    StayWithin, rk4_step,
};
use rand::{Rng, SeedableRng};
use serde_json::json;
use std::hint::black_box;
use std::time::Instant;

/// Runs per lane group of the batch kernel (8 fills two AVX2 registers per state).
const LANES: usize = 8;

/// The simulator's workloads.
pub fn workloads() -> Vec<Workload> {
    vec![
        Workload {
            name: "sim-rk4",
            description: "one 10 s closed loop: cart pendulum, LQR, ZOH 1 kHz, RK4 1 ms (steps/s)",
            run: run_rk4,
        },
        Workload {
            name: "sim-batch",
            description: "100x100 grid of initial states, 10 s each at 1 kHz, all cores (trajectory-steps/s)",
            run: run_batch,
        },
        Workload {
            name: "cartpole-step",
            description: "Gymnasium-style cart-pole step API, random actions (steps/s)",
            run: run_cartpole,
        },
    ]
}

fn lqr_gain(plant: &CartPendulum) -> Result<Mat> {
    let sys = plant.linearize(CartEquilibrium::upright())?;
    let q = Mat::from_diagonal(&nalgebra::DVector::from_row_slice(&[10.0, 10.0, 0.0, 0.0]));
    Ok(pendulab_lti::design::lqr(&sys, &q, &Mat::identity(1, 1), None)?.gain)
}

/// The sim-rk4 loop over the book's plant (libm).
fn closed_loop(
    record: Record,
    integrator: Integrator,
) -> Result<SampledLoop<CartPendulum, StaticStateFeedback>> {
    closed_loop_of(CartPendulum::book(), record, integrator)
}

/// The sim-rk4 loop over the book's plant as the kernel type with the sine/cosine `trig`.
fn closed_loop_with(
    record: Record,
    integrator: Integrator,
    trig: Trig,
) -> Result<SampledLoop<FastCart, StaticStateFeedback>> {
    closed_loop_of(
        FastCart::new(CartPendulum::book(), trig),
        record,
        integrator,
    )
}

fn closed_loop_of<P: Dynamics>(
    plant: P,
    record: Record,
    integrator: Integrator,
) -> Result<SampledLoop<P, StaticStateFeedback>> {
    let k = lqr_gain(&CartPendulum::book())?;
    Ok(SampledLoop::new(
        plant,
        StaticStateFeedback::new(k)?,
        SampledOptions {
            ts: 1e-3,
            t_final: 10.0,
            integrator,
            record,
            ..Default::default()
        },
    )?)
}

/// A recorded fixed-size kernel run of the sim-rk4 loop, timed with recycled storage.
fn time_fixed<P: Dynamics + FixedDynamics<4> + Clone>(
    budget: &Budget,
    lp: &SampledLoop<P, StaticStateFeedback>,
    x0: &[f64; 4],
) -> Result<(pendulab_sim::SampledRun, super::Timing)> {
    let mut fixed = lp.fixed::<4>()?;
    let mut last = Some(fixed.run(x0)?);
    let timing = time(budget, || {
        let previous = last.take().expect("previous run");
        last = Some(
            fixed
                .run_recycling(black_box(x0), &mut (), previous)
                .expect("closed-loop run"),
        );
    });
    Ok((last.context("ran at least once")?, timing))
}

/// The largest absolute difference of two runs' recorded states.
fn max_state_deviation(a: &pendulab_sim::SampledRun, b: &pendulab_sim::SampledRun) -> f64 {
    let (xa, xb) = (a.trajectory.x(), b.trajectory.x());
    if xa.shape() != xb.shape() {
        return f64::INFINITY;
    }
    (xa - xb).abs().max()
}

fn run_rk4(budget: &Budget) -> Result<BenchReport> {
    let x0 = [0.0, 15f64.to_radians(), 0.0, 0.0];
    let rk4 = Integrator::Rk4 { dt: 1e-3 };
    // Headline: the fixed-size kernel with the anchored step, recording every sample into
    // the storage of the previous result (`run_recycling`), i.e. the simulation itself
    // without the operating system's cost of handing out ~0.9 MB of fresh pages per run; on
    // the multiply–add path this processor takes, timed in rounds of ~1/8 of the budget
    // alternating with the baseline loop (so that both see the same host load).
    let anchored = closed_loop_with(Record::EverySample, rk4, Trig::Anchored)?;
    let mut fast = anchored.fixed::<4>()?;
    let mut separate = anchored
        .fixed::<4>()?
        .with_multiply_add(MulAddPath::Separate);
    let path = fast.multiply_add();
    let (mut last, mut last_separate) = (Some(fast.run(&x0)?), Some(separate.run(&x0)?));
    let rounds = Budget {
        min_time: budget.min_time / 8,
    };
    let (mut t_fast, mut t_separate) = (Vec::new(), Vec::new());
    let start = Instant::now();
    while t_fast.len() < 4 || start.elapsed() < budget.min_time * 2 {
        t_fast.push(time(&rounds, || {
            let previous = last.take().expect("previous run");
            last = Some(
                fast.run_recycling(black_box(&x0), &mut (), previous)
                    .expect("closed-loop run"),
            );
        }));
        t_separate.push(time(&rounds, || {
            let previous = last_separate.take().expect("previous run");
            last_separate = Some(
                separate
                    .run_recycling(black_box(&x0), &mut (), previous)
                    .expect("closed-loop run"),
            );
        }));
    }
    let (timing, timing_separate) = (pooled(&t_fast), pooled(&t_separate));
    let run = last.context("ran at least once")?;
    let run_separate = last_separate.context("ran at least once")?;
    let steps = run.diagnostics.integration.accepted_steps;
    // The general loop with libm: recycled storage, fresh allocation, no recording.
    let mut lp = closed_loop(Record::EverySample, rk4)?;
    let mut last_general = Some(lp.run(&x0)?);
    let t_general = time(budget, || {
        let previous = last_general.take().expect("previous run");
        last_general = Some(
            lp.run_recycling(black_box(&x0), &mut (), previous)
                .expect("closed-loop run"),
        );
    });
    let general = last_general.context("ran at least once")?;
    let anchored_dev = max_state_deviation(&run, &general);
    let separate_dev = max_state_deviation(&run_separate, &general);
    let mut fresh = None;
    let t_fresh = time(budget, || {
        fresh = Some(lp.run(black_box(&x0)).expect("closed-loop run"));
    });
    let fresh_identical = fresh.as_ref() == Some(&general);
    let mut bare = closed_loop(Record::Off, rk4)?;
    let t_bare = time(budget, || {
        black_box(bare.run(black_box(&x0)).expect("run"));
    });
    // The fixed-size kernel with libm: bit-identical to the general loop.
    let (libm_run, t_libm) = time_fixed(budget, &lp, &x0)?;
    let libm_identical = libm_run == general;
    // ... and with the polynomial sine/cosine (bit-identical to the general loop with it).
    let mut poly_loop = closed_loop_with(Record::EverySample, rk4, Trig::Polynomial)?;
    let (poly_run, t_poly) = time_fixed(budget, &poly_loop, &x0)?;
    let poly_identical = poly_loop.run(&x0)? == poly_run;
    let poly_dev = max_state_deviation(&poly_run, &general);
    // Reference: the same sampled-data loop, plant integrated by Dormand–Prince at 1e-12.
    let mut reference = closed_loop(Record::EverySample, Integrator::dopri45(1e-12, 1e-14))?;
    let r = reference.run(&x0)?;
    let max_dev = max_state_deviation(&run, &r);
    let xf = &run.diagnostics.final_state;
    Ok(BenchReport {
        workload: "sim-rk4".into(),
        figure: steps as f64 / timing.median_s,
        unit: "steps/s".into(),
        check: json!({
            "figure_measures": "FixedLoop::run_recycling (SampledLoop::fixed: fixed-size kernel; FastCart with Trig::Anchored: series sin/cos at the three angles fixed by each RK4 step's start, later stages' accelerations by a small rotation; fused multiply-adds where the processor has FMA): 10 000 samples (LQR update, ZOH, RK4 1 ms step, every sample recorded into the recycled Trajectory), one core; median of alternately timed rounds",
            "multiply_add": match path {
                MulAddPath::Fused => "fused (FMA-compiled loop)",
                MulAddPath::Separate => "separate (baseline loop)",
            },
            "steps": steps,
            "median_s_per_run": timing.median_s,
            "min_s_per_run": timing.min_s,
            "runs": timing.iterations,
            "max_abs_deviation_from_general_loop_libm": anchored_dev,
            "separate_multiply_add_steps_per_s": steps as f64 / timing_separate.median_s,
            "separate_multiply_add_min_s_per_run": timing_separate.min_s,
            "separate_multiply_add_max_abs_deviation_from_general_loop_libm": separate_dev,
            "fixed_kernel_libm_steps_per_s": steps as f64 / t_libm.median_s,
            "fixed_kernel_libm_identical_to_general_loop": libm_identical,
            "fixed_kernel_polynomial_trig_steps_per_s": steps as f64 / t_poly.median_s,
            "fixed_kernel_polynomial_trig_identical_to_general_loop_with_it": poly_identical,
            "polynomial_trig_max_abs_deviation_from_libm_run": poly_dev,
            "general_loop_steps_per_s": steps as f64 / t_general.median_s,
            "general_loop_fresh_allocation_steps_per_s": steps as f64 / t_fresh.median_s,
            "fresh_allocation_run_identical": fresh_identical,
            "general_loop_unrecorded_steps_per_s": steps as f64 / t_bare.median_s,
            "theta0_deg": 15.0,
            "final_state": xf,
            "balanced": xf[1].abs() < 1e-3 && run.status == RunStatus::Completed,
            "max_abs_deviation_from_dopri45_1e-12": max_dev,
            "reference_steps": r.diagnostics.integration.accepted_steps,
        }),
    })
}

fn run_batch(budget: &Budget) -> Result<BenchReport> {
    let n = 100;
    let x0s = grid(
        &[0.0; 4],
        &[Axis::new(1, -1.2, 1.2, n), Axis::new(3, -3.0, 3.0, n)],
    )?;
    let plant = CartPendulum::book();
    let k = lqr_gain(&plant)?;
    let gain = [k[(0, 0)], k[(0, 1)], k[(0, 2)], k[(0, 3)]];
    let bound = std::f64::consts::FRAC_PI_2;
    let options = LaneOptions {
        ts: 1e-3,
        t_final: 10.0,
        substeps: 1,
        stay_within: Some((1, bound)),
    };
    let x0a: Vec<[f64; 4]> = x0s.iter().map(|x| [x[0], x[1], x[2], x[3]]).collect();
    // Headline: the lane kernel (8 runs per lane group, vectorisable sine/cosine), rayon on
    // all cores. Each grid takes well under a second: repeat for the budget (at least 3
    // times), keep the median.
    // The headline step takes the later RK4 stages' sines from the step's first ones
    // (`AnchoredSinCos`); the polynomial sine/cosine at every stage (`PolySinCos`) is timed
    // alternately in the same loop.
    let mut out = Vec::new();
    let mut poly = Vec::new();
    let mut seconds = Vec::new();
    let mut seconds_poly = Vec::new();
    let start = Instant::now();
    while seconds.len() < 3 || start.elapsed() < budget.min_time {
        let s = Instant::now();
        out = run_feedback_lanes::<_, AnchoredSinCos, 4, LANES>(&plant, &gain, &options, &x0a)?;
        seconds.push(s.elapsed().as_secs_f64());
        let s = Instant::now();
        poly = run_feedback_lanes::<_, PolySinCos, 4, LANES>(&plant, &gain, &options, &x0a)?;
        seconds_poly.push(s.elapsed().as_secs_f64());
    }
    seconds.sort_by(|a, b| a.total_cmp(b));
    seconds_poly.sort_by(|a, b| a.total_cmp(b));
    let median = seconds[seconds.len() / 2];
    let median_poly = seconds_poly[seconds_poly.len() / 2];
    let poly_steps: usize = poly.iter().map(|o| o.steps).sum();
    let executed: usize = out.iter().map(|o| o.steps).sum();
    let upright = out.iter().filter(|o| o.held).count();
    // The closed loop is odd, and the grid is mirror-exact: the map is point-symmetric.
    let symmetric = (0..out.len()).all(|i| {
        let (a, b) = (&out[i], &out[out.len() - 1 - i]);
        (a.held, a.steps) == (b.held, b.steps)
    });
    // The same grid through the general loop (`SampledLoop` + `StayWithin`, one run per
    // initial state), once, timed.
    let template = closed_loop(Record::Off, Integrator::Rk4 { dt: 1e-3 })?;
    let monitor = |_| StayWithin::new(1, bound);
    let classify = |_, m: StayWithin, run: &pendulab_sim::SampledRun| {
        (
            m.held(),
            run.diagnostics.integration.accepted_steps,
            run.diagnostics.final_state.clone(),
        )
    };
    let s = Instant::now();
    let general = run_initial_states(&template, &x0s, monitor, classify)?;
    let t_general = s.elapsed().as_secs_f64();
    // The lane kernel with libm's sine/cosine: bit-identical to the general loop.
    let s = Instant::now();
    let exact = run_feedback_lanes::<_, LibmSinCos, 4, LANES>(&plant, &gain, &options, &x0a)?;
    let t_exact = s.elapsed().as_secs_f64();
    let exact_identical = exact
        .iter()
        .zip(&general)
        .all(|(a, g)| a.held == g.0 && a.steps == g.1 && a.final_state[..] == g.2[..]);
    // The headline against the general loop: runs with another outcome (held, steps) and the
    // largest final-state difference of the others.
    let mut differing = 0usize;
    let mut max_dev = 0.0f64;
    for (a, g) in out.iter().zip(&general) {
        if (a.held, a.steps) != (g.0, g.1) {
            differing += 1;
        } else {
            for j in 0..4 {
                max_dev = max_dev.max((a.final_state[j] - g.2[j]).abs());
            }
        }
    }
    let general_steps: usize = general.iter().map(|g| g.1).sum();
    let nominal = (n * n * 10_000) as f64;
    Ok(BenchReport {
        workload: "sim-batch".into(),
        figure: executed as f64 / median,
        unit: "trajectory-steps/s".into(),
        check: json!({
            "figure_measures": "RK4 steps integrated (runs stop at the first sample with |theta| > pi/2) per wall second: lane kernel (pendulab_sim::fast::lanes, 8 runs per lane group, AnchoredSinCos: polynomial sin/cos once per RK4 step, the later stages' by the addition theorem, AVX2 when available), rayon on all cores",
            "poly_lanes_steps_per_s": poly_steps as f64 / median_poly,
            "poly_lanes_grid_seconds_median": median_poly,
            "threads": rayon::current_num_threads(),
            "lanes": LANES,
            "grid": [n, n],
            "grid_seconds_median": median,
            "grid_seconds_min": seconds[0],
            "grids_timed": seconds.len(),
            "executed_steps": executed,
            "nominal_steps": nominal,
            "nominal_steps_per_s": nominal / median,
            "upright_fraction": upright as f64 / out.len() as f64,
            "map_point_symmetric": symmetric,
            "general_loop_steps_per_s": general_steps as f64 / t_general,
            "general_loop_grid_seconds": t_general,
            "libm_lanes_steps_per_s": general_steps as f64 / t_exact,
            "libm_lanes_identical_to_general_loop": exact_identical,
            "runs_with_other_outcome_than_general_loop": differing,
            "max_abs_final_state_deviation_from_general_loop": max_dev,
        }),
    })
}

/// A random-policy rollout of `CALLS` steps: uniform actions in ±5 V, reset at episode ends.
/// Returns the episodes finished.
macro_rules! rollout {
    ($env:expr, $rng:expr) => {{
        let mut finished = 0usize;
        for _ in 0..CALLS {
            let a: f64 = $rng.random_range(-5.0..5.0);
            let s = $env.step(a).expect("step");
            if s.terminated || s.truncated {
                $env.reset(None);
                finished += 1;
            }
        }
        finished
    }};
}

/// Alternately timed rounds pooled: the median of the rounds' medians, the fastest batch.
fn pooled(rounds: &[super::Timing]) -> super::Timing {
    let mut medians: Vec<f64> = rounds.iter().map(|t| t.median_s).collect();
    medians.sort_by(|a, b| a.total_cmp(b));
    super::Timing {
        iterations: rounds.iter().map(|t| t.iterations).sum(),
        median_s: medians[medians.len() / 2],
        min_s: rounds.iter().map(|t| t.min_s).fold(f64::INFINITY, f64::min),
    }
}

/// Steps per timed batch of the cart-pole rollouts.
const CALLS: usize = 100_000;

/// How often the anchored RK4 step falls back to libm in the random-policy episodes of the
/// cart-pole rollout: the first angle `θ` and the stage offsets `(h/2)·θ̇₁`, `(h/2)·θ̇₂`,
/// `h·θ̇₃` of each step recomputed from the libm plant's stages, counted against the ranges
/// of the anchored series (`first_range`, `shift_range`). Returns
/// `(steps, [first angle, stage 2, stage 3, stage 4, any])`.
fn anchored_fallbacks(
    plant: &CartPendulum,
    episodes: usize,
    (first_range, shift_range): (f64, f64),
) -> Result<(usize, [usize; 5])> {
    let mut env = Env::<_, 4>::new(*plant, EnvConfig::cart_pole(0.4)?)?;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let h = env.config().dt;
    let mut counts = [0usize; 5];
    let mut steps = 0usize;
    env.reset(Some(1));
    let mut done = 0;
    while done < episodes {
        let a: f64 = rng.random_range(-5.0..5.0);
        let x = env.observation();
        let u = a.clamp(-5.0, 5.0);
        let k1 = plant.derivative_fixed(&x, u);
        let x2: [f64; 4] = std::array::from_fn(|i| x[i] + 0.5 * h * k1[i]);
        let k2 = plant.derivative_fixed(&x2, u);
        let x3: [f64; 4] = std::array::from_fn(|i| x[i] + 0.5 * h * k2[i]);
        let out = [
            x[1].abs() > first_range,
            (0.5 * h * x[3]).abs() > shift_range,
            (0.5 * h * x2[3]).abs() > shift_range,
            (h * x3[3]).abs() > shift_range,
        ];
        for (c, o) in counts.iter_mut().zip(out) {
            *c += usize::from(o);
        }
        counts[4] += usize::from(out.iter().any(|&o| o));
        steps += 1;
        let s = env.step(a)?;
        if s.terminated || s.truncated {
            env.reset(None);
            done += 1;
        }
    }
    Ok((steps, counts))
}

/// The anchored environment against the general one with libm over `episodes` random-policy
/// episodes (same seeds, same actions): episodes whose length or ending differs, the largest
/// state difference of the others, and the largest ratio of a step's difference to the
/// documented bound after `n` steps, `n · 10⁻¹⁴ · e^{8 n h}` (per step at most 10⁻¹⁴ from the
/// anchored sines' 2 ulp + 1.1·10⁻¹⁶, amplified at most like e^{8 t} by the falling pendulum;
/// derived in `pendulab-plants`' `tests/env.rs`).
fn anchored_agreement(episodes: usize) -> Result<(usize, f64, f64)> {
    let config = EnvConfig::cart_pole(0.4)?;
    let h = config.dt;
    let mut general = Env::<_, 4>::new(CartPendulum::book(), config.clone())?;
    let mut fast =
        FixedEnv::<_, 4>::new(FastCart::new(CartPendulum::book(), Trig::Anchored), config)?;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2);
    let mut differing = 0usize;
    let (mut max_dev, mut max_ratio) = (0.0f64, 0.0f64);
    for e in 0..episodes {
        let seed = Some(e as u64);
        general.reset(seed);
        fast.reset(seed);
        let mut ended = false;
        let mut n = 0usize;
        while !ended {
            let a: f64 = rng.random_range(-5.0..5.0);
            let (sa, sb) = (general.step(a)?, fast.step(a)?);
            n += 1;
            let ends = |s: &pendulab_sim::Step<4>| (s.terminated, s.truncated);
            if ends(&sa) != ends(&sb) {
                differing += 1;
                break;
            }
            ended = sa.terminated || sa.truncated;
            let bound = n as f64 * 1e-14 * (8.0 * n as f64 * h).exp();
            for j in 0..4 {
                let d = (sa.obs[j] - sb.obs[j]).abs();
                max_dev = max_dev.max(d);
                max_ratio = max_ratio.max(d / bound);
            }
        }
    }
    Ok((differing, max_dev, max_ratio))
}

fn run_cartpole(budget: &Budget) -> Result<BenchReport> {
    // Headline: the fixed-size environment with the plant's anchored RK4 step.
    let plant = CartPendulum::book();
    let anchored = FastCart::new(plant, Trig::Anchored);
    let mut env = FixedEnv::<_, 4>::new(anchored, EnvConfig::cart_pole(0.4)?)?;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    env.reset(Some(1));
    let mut episodes = 0usize;
    let mut steps_total = 0usize;
    // The general environment with libm's sine/cosine, timed alternately with the headline
    // (rounds of ~50 ms each) so that both see the same host load.
    let mut general = Env::<_, 4>::new(plant, EnvConfig::cart_pole(0.4)?)?;
    let mut rng_general = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    general.reset(Some(1));
    let rounds = Budget {
        min_time: budget.min_time / 8,
    };
    let (mut t_fast, mut t_general) = (Vec::new(), Vec::new());
    let start = Instant::now();
    while t_fast.len() < 4 || start.elapsed() < budget.min_time * 2 {
        t_fast.push(time(&rounds, || {
            steps_total += CALLS;
            episodes += rollout!(env, rng);
        }));
        t_general.push(time(&rounds, || {
            black_box(rollout!(general, rng_general));
        }));
    }
    let timing = pooled(&t_fast);
    let timing_general = pooled(&t_general);
    // The fixed-size environment with libm (bit-identical to the general one).
    let mut fixed_libm = FixedEnv::<_, 4>::new(plant, EnvConfig::cart_pole(0.4)?)?;
    let mut rng_libm = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    fixed_libm.reset(Some(1));
    let t_libm = time(budget, || {
        black_box(rollout!(fixed_libm, rng_libm));
    });
    // The general environment with the plant's polynomial sine/cosine (within 2 ulp of libm).
    let mut poly_env = Env::<_, 4>::new(
        FastCart::new(plant, Trig::Polynomial),
        EnvConfig::cart_pole(0.4)?,
    )?;
    let mut rng_poly = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    poly_env.reset(Some(1));
    let t_poly = time(budget, || {
        black_box(rollout!(poly_env, rng_poly));
    });
    // The random actions alone: what the rollout spends outside the environment.
    let mut rng_only = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let t_rng = time(budget, || {
        let mut acc = 0.0;
        for _ in 0..CALLS {
            acc += rng_only.random_range(-5.0..5.0);
        }
        black_box(acc);
    });
    // A step is one RK4 step of 20 ms with the clipped action held; the fixed-size
    // environment with libm repeats the general one bit for bit over whole episodes.
    let x0 = general.reset_to([0.01, 0.02, -0.03, 0.04])?;
    let s = general.step(7.0)?;
    let mut x = x0;
    rk4_step(&plant, 0.0, &mut x, &[5.0], 0.02);
    let step_is_rk4 = s.obs == x;
    let mut a = Env::<_, 4>::new(plant, EnvConfig::cart_pole(0.4)?)?;
    let mut b = a.fixed();
    let mut rng_a = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let mut rng_b = rng_a.clone();
    a.reset(Some(3));
    b.reset(Some(3));
    let mut libm_identical = true;
    for _ in 0..10_000 {
        let (ua, ub): (f64, f64) = (rng_a.random_range(-6.0..6.0), rng_b.random_range(-6.0..6.0));
        let (sa, sb) = (a.step(ua)?, b.step(ub)?);
        libm_identical &= sa == sb;
        if sa.terminated || sa.truncated {
            libm_identical &= a.reset(None) == b.reset(None);
        }
    }
    // The anchored environment against the general one, and how often its step takes libm.
    let (differing, anchored_dev, anchored_ratio) = anchored_agreement(2000)?;
    let (counted_steps, fallbacks) = anchored_fallbacks(
        &plant,
        2000,
        (
            FastCart::ANCHORED_ANGLE_LIMIT,
            FastCart::ANCHORED_SHIFT_LIMIT,
        ),
    )?;
    // ... and how often the narrower series of the 1 ms loops (1/32 rad) alone would have.
    let (_, narrow) = anchored_fallbacks(&plant, 2000, (SHIFT_LIMIT, SHIFT_LIMIT))?;
    let frac = |n: usize| n as f64 / counted_steps as f64;
    // An LQR policy balances through a whole episode.
    let k = lqr_gain(&plant)?;
    let mut obs = env.reset(Some(9));
    let mut survived = 0;
    loop {
        let u = -(0..4).map(|j| k[(0, j)] * obs[j]).sum::<f64>();
        let s = env.step(u)?;
        survived += 1;
        obs = s.obs;
        if s.terminated || s.truncated {
            break;
        }
    }
    Ok(BenchReport {
        workload: "cartpole-step".into(),
        figure: CALLS as f64 / timing.median_s,
        unit: "steps/s".into(),
        check: json!({
            "figure_measures": "FixedEnv::step (pendulab_sim::env, fixed-size RK4 kernel; FastCart with Trig::Anchored: later RK4 stages' sin/cos from the step's first by the addition theorem) with a uniform random action in [-5, 5] V (ChaCha8) and reset at episode ends, one core",
            "median_s_per_100k_steps": timing.median_s,
            "min_s_per_100k_steps": timing.min_s,
            "episodes": episodes,
            "mean_episode_length": steps_total as f64 / episodes.max(1) as f64,
            "general_env_libm_steps_per_s": CALLS as f64 / timing_general.median_s,
            "general_env_libm_min_s_per_100k_steps": timing_general.min_s,
            "fixed_env_libm_steps_per_s": CALLS as f64 / t_libm.median_s,
            "fixed_env_libm_identical_to_general_env_10k_steps": libm_identical,
            "general_env_polynomial_trig_steps_per_s": CALLS as f64 / t_poly.median_s,
            "anchored_vs_general_libm_episodes": 2000,
            "anchored_vs_general_libm_episodes_ending_differently": differing,
            "anchored_vs_general_libm_max_abs_state_deviation": anchored_dev,
            "anchored_vs_general_libm_worst_deviation_over_documented_bound": anchored_ratio,
            "anchored_within_documented_bound": anchored_ratio <= 1.0 && differing == 0,
            "anchored_libm_fallback_steps_counted": counted_steps,
            "anchored_libm_fallback_fraction_first_angle": frac(fallbacks[0]),
            "anchored_libm_fallback_fraction_stage_2": frac(fallbacks[1]),
            "anchored_libm_fallback_fraction_stage_3": frac(fallbacks[2]),
            "anchored_libm_fallback_fraction_stage_4": frac(fallbacks[3]),
            "anchored_libm_fallback_fraction_any": frac(fallbacks[4]),
            "anchored_series_ranges_rad": [FastCart::ANCHORED_ANGLE_LIMIT, FastCart::ANCHORED_SHIFT_LIMIT],
            "beyond_1_32_rad_fraction_first_angle": frac(narrow[0]),
            "beyond_1_32_rad_fraction_stage_4": frac(narrow[3]),
            "beyond_1_32_rad_fraction_any": frac(narrow[4]),
            "step_equals_rk4_kernel": step_is_rk4,
            "lqr_policy_steps": survived,
            "lqr_policy_survives_500": survived == 500,
            "random_actions_only_per_s": CALLS as f64 / t_rng.median_s,
            "env_without_random_actions_steps_per_s":
                CALLS as f64 / (timing.median_s - t_rng.median_s).max(f64::MIN_POSITIVE),
        }),
    })
}
