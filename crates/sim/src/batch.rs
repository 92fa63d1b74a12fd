//! Batch runs on all cores (rayon): grids of initial conditions and Monte Carlo over
//! parameters, each run summarised by a user-supplied classifier.
//!
//! - [`grid`] builds the Cartesian product of [`Axis`] values over a nominal state
//!   (row-major: the last axis varies fastest).
//! - [`monte_carlo`] draws `n` parameter samples, sample `i` from its own ChaCha8 stream
//!   (`seed`, stream `i`), so the draws do not depend on the number of threads or on the
//!   order in which runs finish.
//! - [`par_map`] runs a closure on every case in parallel and returns the outcomes in case
//!   order (the first error, by case index, if any run fails).
//! - [`run_initial_states`] runs one [`SampledLoop`] (cloned per run) from each initial state
//!   with a fresh [`Monitor`] and turns each run into an outcome — e.g. a region-of-attraction
//!   map with [`StayWithin`](crate::monitor::StayWithin).

use crate::controller::Controller;
use crate::dynamics::Dynamics;
use crate::error::{Result, SimError, check_finite};
use crate::monitor::Monitor;
use crate::sampled::{SampledLoop, SampledRun};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// One axis of a grid: state `index` takes `points` equally spaced values from `lo` to `hi`
/// (both included; a single point sits at `lo`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    /// Which state.
    pub index: usize,
    /// First value.
    pub lo: f64,
    /// Last value.
    pub hi: f64,
    /// Number of values (≥ 1).
    pub points: usize,
}

impl Axis {
    /// `points` values of state `index` from `lo` to `hi`.
    pub fn new(index: usize, lo: f64, hi: f64, points: usize) -> Self {
        Self {
            index,
            lo,
            hi,
            points,
        }
    }
    /// Value `j` of the axis: `lo + j (hi − lo)/(points − 1)`, computed about the midpoint as
    /// `m + h (2j − (points − 1))/(points − 1)`, `m = (lo + hi)/2`, `h = (hi − lo)/2`, with the
    /// end points exact — so a symmetric range `[−a, a]` gives exactly mirrored values
    /// (`value(points − 1 − j) = −value(j)`), and odd dynamics give exactly mirrored runs.
    pub fn value(&self, j: usize) -> f64 {
        if self.points <= 1 || j == 0 {
            return self.lo;
        }
        if j + 1 == self.points {
            return self.hi;
        }
        let (m, h) = (0.5 * (self.lo + self.hi), 0.5 * (self.hi - self.lo));
        let n1 = (self.points - 1) as f64;
        m + h * ((2 * j) as f64 - n1) / n1
    }
}

/// The grid of initial states: `nominal` with the axes' states replaced by every combination
/// of their values, row-major (last axis fastest).
///
/// # Errors
/// [`SimError::InvalidArgument`] for an axis with no points or a state index out of range;
/// [`SimError::InvalidParameter`] for non-finite bounds or nominal values.
pub fn grid(nominal: &[f64], axes: &[Axis]) -> Result<Vec<Vec<f64>>> {
    for (i, &v) in nominal.iter().enumerate() {
        check_finite(&format!("nominal state {i}"), v)?;
    }
    for a in axes {
        if a.points == 0 {
            return Err(SimError::InvalidArgument(format!(
                "grid axis on state {} has no points",
                a.index
            )));
        }
        if a.index >= nominal.len() {
            return Err(SimError::InvalidArgument(format!(
                "grid axis on state {} but the state has {} entries",
                a.index,
                nominal.len()
            )));
        }
        check_finite("grid axis lower bound", a.lo)?;
        check_finite("grid axis upper bound", a.hi)?;
    }
    let total: usize = axes.iter().map(|a| a.points).product();
    let mut out = Vec::with_capacity(total);
    for flat in 0..total {
        let mut x = nominal.to_vec();
        let mut rem = flat;
        for a in axes.iter().rev() {
            let j = rem % a.points;
            rem /= a.points;
            x[a.index] = a.value(j);
        }
        out.push(x);
    }
    Ok(out)
}

/// `n` samples `draw(rng, i)`, sample `i` drawn from a ChaCha8 generator seeded with `seed`
/// on stream `i` (reproducible and independent of threading).
pub fn monte_carlo<T, F>(seed: u64, n: usize, draw: F) -> Vec<T>
where
    T: Send,
    F: Fn(&mut ChaCha8Rng, usize) -> T + Sync,
{
    (0..n)
        .into_par_iter()
        .map(|i| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(i as u64);
            draw(&mut rng, i)
        })
        .collect()
}

/// Runs `f(i, &cases[i])` for every case on all cores; outcomes in case order.
///
/// # Errors
/// The error of the lowest-index failing case.
pub fn par_map<T, O, F>(cases: &[T], f: F) -> Result<Vec<O>>
where
    T: Sync,
    O: Send,
    F: Fn(usize, &T) -> Result<O> + Sync + Send,
{
    let results: Vec<Result<O>> = cases.par_iter().enumerate().map(|(i, c)| f(i, c)).collect();
    results.into_iter().collect()
}

/// Runs `template` (cloned per worker run) from every initial state in `x0s` with the monitor
/// `make_monitor(i)` and returns `outcome(i, monitor, &run)` for each, in order.
///
/// Set [`SampledOptions::record`](crate::SampledOptions) to
/// [`Record::Off`](crate::Record::Off) in the template when only the monitors' summaries are
/// needed: then nothing is stored per sample.
///
/// # Errors
/// The error of the lowest-index failing run.
pub fn run_initial_states<P, C, M, O, FM, FO>(
    template: &SampledLoop<P, C>,
    x0s: &[Vec<f64>],
    make_monitor: FM,
    outcome: FO,
) -> Result<Vec<O>>
where
    P: Dynamics + Clone + Send + Sync,
    C: Controller + Clone + Send + Sync,
    M: Monitor,
    O: Send,
    FM: Fn(usize) -> M + Sync + Send,
    FO: Fn(usize, M, &SampledRun) -> O + Sync + Send,
{
    let results: Vec<Result<O>> = x0s
        .par_iter()
        .enumerate()
        .map_init(
            || template.clone(),
            |lp, (i, x0)| {
                let mut m = make_monitor(i);
                let run = lp.run_with(x0, &mut m)?;
                Ok(outcome(i, m, &run))
            },
        )
        .collect();
    results.into_iter().collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng;

    #[test]
    fn grid_layout() {
        let g = grid(
            &[0.0, 9.0, 0.0],
            &[Axis::new(0, -1.0, 1.0, 3), Axis::new(2, 0.0, 1.0, 2)],
        )
        .unwrap();
        assert_eq!(g.len(), 6);
        assert_eq!(g[0], vec![-1.0, 9.0, 0.0]);
        assert_eq!(g[1], vec![-1.0, 9.0, 1.0]);
        assert_eq!(g[5], vec![1.0, 9.0, 1.0]);
        let a = Axis::new(0, -1.2, 1.2, 15);
        assert_eq!((a.value(0), a.value(14)), (-1.2, 1.2));
        assert!((0..15).all(|j| a.value(14 - j) == -a.value(j)));
        assert!((a.value(3) - (-1.2 + 2.4 * 3.0 / 14.0)).abs() < 1e-15);
        assert!(grid(&[0.0], &[Axis::new(1, 0.0, 1.0, 2)]).is_err());
        assert!(grid(&[0.0], &[Axis::new(0, 0.0, 1.0, 0)]).is_err());
        assert!(grid(&[0.0], &[Axis::new(0, f64::NAN, 1.0, 2)]).is_err());
    }

    #[test]
    fn monte_carlo_is_reproducible_and_streams_differ() {
        let a = monte_carlo(7, 50, |rng, _| rng.random::<f64>());
        let b = monte_carlo(7, 50, |rng, _| rng.random::<f64>());
        assert_eq!(a, b);
        // Sample i equals a sequential draw from stream i.
        let mut r3 = ChaCha8Rng::seed_from_u64(7);
        r3.set_stream(3);
        assert_eq!(a[3], r3.random::<f64>());
        assert_ne!(a[0], a[1]);
        let c = monte_carlo(8, 50, |rng, _| rng.random::<f64>());
        assert_ne!(a, c);
    }

    #[test]
    fn par_map_keeps_order_and_reports_first_error() {
        let v: Vec<usize> = (0..100).collect();
        let out = par_map(&v, |i, &x| Ok(i * 1000 + x)).unwrap();
        assert!(out.iter().enumerate().all(|(i, &o)| o == i * 1001));
        let err = par_map(&v, |i, _| {
            if i % 30 == 29 {
                Err(SimError::InvalidSampleTime(i as f64))
            } else {
                Ok(i)
            }
        })
        .unwrap_err();
        assert_eq!(err, SimError::InvalidSampleTime(29.0));
    }
}
