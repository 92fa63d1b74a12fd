//! The streamed route of the regressions: with three-point derivatives and a causal (or no)
//! prefilter, each block of rows is differentiated, assembled, filtered and folded into the QR
//! factor in cache ([`stream_solve`]); with the input checks both routes share.

use super::LsOptions;
use super::positive;
use crate::differentiate::{Derivatives, Differentiator, three_point_at};
use crate::error::{IdentError, Result, SamplePos, UNNAMED};
use crate::filter::{BANK_BLOCK, FilterBank, Prefilter};
use crate::least_squares::{LeastSquares, QrAccumulator};

/// Three-point first and second derivatives of a signal on one block `[k0, k1)`, computed
/// from the neighbouring samples with exactly the formulas (and the operation order) of
/// [`crate::differentiate::three_point`] applied once and twice to the whole signal.
pub(super) struct BlockDerivatives {
    /// `ẋ` on `[lo, hi)` ⊇ the indices the block's second derivatives need.
    d1: Vec<f64>,
    n: usize,
    h: f64,
}

impl BlockDerivatives {
    pub(super) fn new(n: usize, ts: f64) -> Self {
        Self {
            d1: Vec::with_capacity(BANK_BLOCK + 4),
            n,
            h: 0.5 / ts,
        }
    }

    /// Writes `ẋ` and `ẍ` on `[k0, k1)` into `first[..k1−k0]` and `second[..k1−k0]`.
    pub(super) fn load(
        &mut self,
        x: &[f64],
        k0: usize,
        k1: usize,
        first: &mut [f64],
        second: &mut [f64],
    ) {
        let (n, h) = (self.n, self.h);
        let m = k1 - k0;
        let mut lo = k0.saturating_sub(1);
        let mut hi = (k1 + 1).min(n);
        if k0 == 0 {
            hi = hi.max(3);
        }
        if k1 == n {
            lo = lo.min(n - 3);
        }
        // ẋ on [lo, hi): interior by the central difference, ends by the one-sided formulas.
        self.d1.clear();
        let a = lo.max(1);
        let b = hi.min(n - 1);
        if lo == 0 {
            self.d1.push(three_point_at(x, h, 0));
        }
        self.d1
            .extend(x[a - 1..b + 1].windows(3).map(|w| (w[2] - w[0]) * h));
        if hi == n {
            self.d1.push(three_point_at(x, h, n - 1));
        }
        debug_assert_eq!(self.d1.len(), hi - lo);
        first[..m].copy_from_slice(&self.d1[k0 - lo..k1 - lo]);
        // ẍ on [k0, k1): the same formulas on ẋ.
        let d = &self.d1;
        let mut i = 0;
        if k0 == 0 {
            second[0] = (-3.0 * d[0] + 4.0 * d[1] - d[2]) * h;
            i = 1;
        }
        let (ia, ib) = (k0.max(1), k1.min(n - 1));
        if ib > ia {
            for (o, w) in second[i..i + (ib - ia)]
                .iter_mut()
                .zip(d[ia - 1 - lo..ib + 1 - lo].windows(3))
            {
                *o = (w[2] - w[0]) * h;
            }
            i += ib - ia;
        }
        if k1 == n {
            let e = n - lo;
            second[i] = (d[e - 3] - 4.0 * d[e - 2] + 3.0 * d[e - 1]) * h;
            i += 1;
        }
        debug_assert_eq!(i, m);
    }
}

/// `true` if every value is finite: `0·x` is (±)0 for finite `x` and NaN otherwise, and NaN
/// survives a sum (four partial sums, so the loop vectorises).
pub(super) fn all_finite(x: &[f64]) -> bool {
    let mut acc = [0.0f64; 4];
    let chunks = x.chunks_exact(4);
    let rest = chunks.remainder();
    for c in chunks {
        for l in 0..4 {
            acc[l] += 0.0 * c[l];
        }
    }
    let tail: f64 = rest.iter().map(|v| 0.0 * v).sum();
    (acc[0] + acc[1] + acc[2] + acc[3] + tail) == 0.0
}

/// `true` if the options allow the streamed route (three-point derivatives, causal or no
/// filter).
pub(super) fn streamable(opts: &LsOptions) -> bool {
    opts.differentiator == Differentiator::ThreePoint
        && !matches!(opts.prefilter, Prefilter::ZeroPhase { .. })
}

/// Solves `M p = N` streamed block by block: `fill(k0, m, raw)` writes rows `k0 … k0+m−1` of
/// the `W − 1` regressor columns and the target (last) into `raw[c][..m]`.
pub(super) fn stream_solve<const W: usize>(
    signals: &[(&str, &[f64])],
    ts: f64,
    needed: usize,
    prefilter: &Prefilter,
    names: &[&str],
    target: &str,
    mut fill: impl FnMut(usize, usize, &mut [[f64; BANK_BLOCK]; W]),
) -> Result<LeastSquares> {
    debug_assert_eq!(names.len() + 1, W);
    let n = check_signals_with(signals, ts, needed, false)?;
    let mut bank = prefilter.design(ts)?.map(|(f, _)| FilterBank::<W>::new(&f));
    let mut acc = QrAccumulator::new(names, target)?;
    let mut raw = [[0.0; BANK_BLOCK]; W];
    let mut out = [[0.0; BANK_BLOCK]; W];
    let mut k0 = 0;
    while k0 < n {
        let m = (n - k0).min(BANK_BLOCK);
        fill(k0, m, &mut raw);
        if !raw.iter().all(|c| all_finite(&c[..m])) {
            // Name the offending input sample (a NaN/∞ in the data); a non-finite value
            // computed from finite data (overflow) is named by its regressor column.
            check_signals(signals, ts, needed)?;
            let (c, i) = (0..W)
                .find_map(|c| {
                    raw[c][..m]
                        .iter()
                        .position(|v| !v.is_finite())
                        .map(|i| (c, i))
                })
                .expect("a non-finite value was seen");
            return Err(IdentError::NonFinite {
                source_name: UNNAMED.into(),
                column: if c + 1 < W { names[c] } else { target }.to_string(),
                at: SamplePos::index(k0 + i),
                value: raw[c][i],
            });
        }
        match bank.as_mut() {
            Some(b) => {
                b.process(&raw, &mut out, m);
                acc.push_scratch(&mut out, m);
            }
            None => acc.push_scratch(&mut raw, m),
        }
        k0 += m;
    }
    acc.finish()
}

/// Checks lengths, finiteness and the sample count of named input signals.
pub(super) fn check_signals(signals: &[(&str, &[f64])], ts: f64, needed: usize) -> Result<usize> {
    check_signals_with(signals, ts, needed, true)
}

/// As [`check_signals`]; with `finite = false` the values are not scanned (the streamed route
/// checks each block in cache and calls the full check only to name a bad sample).
pub(super) fn check_signals_with(
    signals: &[(&str, &[f64])],
    ts: f64,
    needed: usize,
    finite: bool,
) -> Result<usize> {
    positive("sample time ts", ts)?;
    let n = signals[0].1.len();
    for (name, s) in signals {
        if s.len() != n {
            return Err(IdentError::LengthMismatch {
                source_name: UNNAMED.into(),
                column: name.to_string(),
                expected: n,
                found: s.len(),
            });
        }
        if !finite {
            continue;
        }
        if let Some(k) = s.iter().position(|v| !v.is_finite()) {
            return Err(IdentError::NonFinite {
                source_name: UNNAMED.into(),
                column: name.to_string(),
                at: SamplePos::index(k),
                value: s[k],
            });
        }
    }
    if n < needed {
        return Err(IdentError::TooFewSamples {
            source_name: UNNAMED.into(),
            what: "the least-squares identification".into(),
            needed,
            found: n,
        });
    }
    Ok(n)
}

pub(super) fn needed(opts: &LsOptions) -> usize {
    opts.differentiator.min_samples().max(3)
}

pub(super) fn derivs(opts: &LsOptions, x: &[f64], ts: f64) -> Result<Derivatives> {
    opts.differentiator.derivatives(x, ts)
}

/// Adds the meaning of each column to a rank-deficiency error.
pub(super) fn describe_rank(e: IdentError, names: &[&str], signals: &[&str]) -> IdentError {
    match e {
        IdentError::RankDeficient {
            columns,
            condition,
            scaled_condition,
            limit,
            detail,
        } => IdentError::RankDeficient {
            detail: format!(
                "{detail} (columns: {})",
                names
                    .iter()
                    .zip(signals)
                    .map(|(n, s)| format!("{n} multiplies {s}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            columns,
            condition,
            scaled_condition,
            limit,
        },
        other => other,
    }
}
