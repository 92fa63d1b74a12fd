//! Black-box identification of sampled linear systems: ARX by least squares and subspace
//! identification by PO-MOESP, from one or several input–output records.
//!
//! Where the book's identification (part 1 §3.2, eqs 3.43–3.47) fits the physical parameters
//! of a model derived from the equations of motion, these methods assume only linearity and a
//! sample time: they return a discrete model (`pendulab-lti`'s [`TransferFunction`] and
//! [`StateSpace`]) whose physical meaning is read off afterwards (poles, `d2c`).
//!
//! * [`arx`]: the equation-error model `A(q⁻¹) y(k) = B(q⁻¹) u(k − n_k) + e(k)` with
//!   `A = 1 + a₁ q⁻¹ + … + a_{n_a} q^{−n_a}` and `B = b₀ + b₁ q⁻¹ + … + b_{n_b−1} q^{−n_b+1}`
//!   (MATLAB's `arx(data, [na nb nk])` convention), linear in its parameters and solved by the
//!   crate's Householder QR ([`crate::least_squares`], with its rank and conditioning checks).
//! * [`arx_order_selection`]: every `(n_a, n_b, n_k)` of given ranges on the same rows, ranked
//!   by Akaike's information criterion `AIC = N ln V + 2d` (V the mean squared residual, d the
//!   number of parameters, N the rows; L. Ljung, *System Identification*, 2nd ed., 1999,
//!   §16.4, eq. 16.33 — minimising it is MATLAB `selstruc(arxstruc(…), 'aic')`, which minimises
//!   `ln V + 2d/N`).
//! * [`moesp`]: M. Verhaegen's past-output MOESP (*Automatica* 30 (1994) 61–74; T. Katayama,
//!   *Subspace Methods for System Identification*, 2005, §9.4): block Hankel matrices of past
//!   and future inputs and outputs, their LQ decomposition, the SVD of the block `L₃₂` whose
//!   left singular vectors span the extended observability matrix (the order is read off its
//!   singular values, which are returned), `A` and `C` from the shift invariance of that
//!   matrix, then `B`, `D` and each record's initial state by linear least squares on the
//!   simulated output. MIMO systems are handled alike.
//!
//! Several records (experiments) are combined without crossing their boundaries (MATLAB
//! `merge`): this is how closed-loop records under different feedback gains, each alone
//! uninformative, identify the plant together.

use crate::error::{IdentError, Result, UNNAMED};
use crate::least_squares::{LeastSquares, QrAccumulator};
use crate::validation::fit_percent;
use pendulab_lti::{Discrete, StateSpace, TransferFunction};

/// One uniformly sampled input–output record of a SISO system (for [`arx`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Experiment<'a> {
    /// Input samples `u(0…N−1)` (e.g. volts).
    pub u: &'a [f64],
    /// Output samples `y(0…N−1)`, same length (e.g. metres).
    pub y: &'a [f64],
}

impl<'a> Experiment<'a> {
    /// A record from an input and an output column.
    pub fn new(u: &'a [f64], y: &'a [f64]) -> Self {
        Self { u, y }
    }
}

/// ARX model orders in MATLAB's convention `[na nb nk]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ArxOrders {
    /// Number of `A` coefficients `a₁…a_{n_a}` (poles).
    pub na: usize,
    /// Number of `B` coefficients `b₀…b_{n_b−1}`.
    pub nb: usize,
    /// Input delay in samples (`0` for a direct feedthrough).
    pub nk: usize,
}

impl ArxOrders {
    /// The orders `[na nb nk]`.
    pub fn new(na: usize, nb: usize, nk: usize) -> Self {
        Self { na, nb, nk }
    }
    /// Number of parameters `n_a + n_b`.
    pub fn parameters(&self) -> usize {
        self.na + self.nb
    }
    /// The largest lag used, `max(n_a, n_k + n_b − 1)`: the first usable row of a record.
    pub fn lag(&self) -> usize {
        self.na.max((self.nk + self.nb).saturating_sub(1))
    }
    fn check(&self) -> Result<()> {
        if self.na == 0 && self.nb == 0 {
            return Err(IdentError::InvalidParameter {
                name: "ARX orders na + nb".into(),
                value: 0.0,
                reason: "na = 0 and nb = 0 leave no parameter to estimate".into(),
            });
        }
        Ok(())
    }
}

/// An identified ARX model and its diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct Arx {
    /// The orders.
    pub orders: ArxOrders,
    /// `A(q⁻¹)` coefficients `[1, a₁, …, a_{n_a}]`.
    pub a: Vec<f64>,
    /// `B(q⁻¹)` coefficients `[b₀, …, b_{n_b−1}]` (acting on `u(k − n_k − i)`).
    pub b: Vec<f64>,
    /// Standard errors of `a₁…a_{n_a}` then `b₀…b_{n_b−1}` (white equation error assumed).
    pub std_error: Vec<f64>,
    /// Residual (noise) variance `‖e‖²/(N − d)`, output units squared.
    pub noise_variance: f64,
    /// The least-squares solution (estimate, covariance, condition numbers).
    pub lsq: LeastSquares,
    /// Sample time, s.
    pub ts: f64,
}

impl Arx {
    /// The discrete transfer function `G(z) = z^{−n_k} B(z⁻¹)/A(z⁻¹)`, both polynomials
    /// multiplied by `z^m`, `m` = [`ArxOrders::lag`] (poles at `z = 0` are kept, as MATLAB's
    /// `tf(arx(…))` does).
    ///
    /// # Errors
    /// [`IdentError::Lti`] if the coefficients are rejected (non-finite).
    pub fn transfer_function(&self) -> Result<TransferFunction<Discrete>> {
        let m = self.orders.lag();
        let mut den = vec![0.0; m + 1];
        den[..self.a.len()].copy_from_slice(&self.a);
        let mut num = vec![0.0; m + 1];
        for (i, b) in self.b.iter().enumerate() {
            num[self.orders.nk + i] = *b;
        }
        Ok(TransferFunction::discrete(&num, &den, self.ts)?)
    }

    /// A state-space realisation of [`Arx::transfer_function`].
    ///
    /// # Errors
    /// As [`Arx::transfer_function`].
    pub fn state_space(&self) -> Result<StateSpace<Discrete>> {
        Ok(self.transfer_function()?.to_state_space()?)
    }

    /// Simulates the model on the input `u` (no noise): `ŷ(k) = −Σ a_i ŷ(k−i) + Σ b_j
    /// u(k−n_k−j)`, starting from the measured outputs `ŷ(k) = y(k)` for `k < m`
    /// ([`ArxOrders::lag`]) and inputs taken as zero before the record.
    ///
    /// # Errors
    /// [`IdentError::LengthMismatch`] for columns of different lengths;
    /// [`IdentError::NonFinite`] for NaN or infinite samples.
    pub fn simulate(&self, u: &[f64], y: &[f64]) -> Result<Vec<f64>> {
        check_record(0, u, y)?;
        let m = self.orders.lag().min(y.len());
        let mut yh = y[..m].to_vec();
        for k in m..y.len() {
            let mut v = 0.0;
            for i in 1..=self.orders.na {
                v -= self.a[i] * yh[k - i];
            }
            for (j, b) in self.b.iter().enumerate() {
                if let Some(idx) = k.checked_sub(self.orders.nk + j) {
                    v += b * u[idx];
                }
            }
            yh.push(v);
        }
        Ok(yh)
    }

    /// MATLAB `compare` fit (percent, [`fit_percent`]) of [`Arx::simulate`] on a validation
    /// record, over the samples after the first `m` ([`ArxOrders::lag`]).
    ///
    /// # Errors
    /// As [`Arx::simulate`] and [`fit_percent`].
    pub fn fit_percent(&self, u: &[f64], y: &[f64]) -> Result<f64> {
        let yh = self.simulate(u, y)?;
        let m = self.orders.lag().min(y.len());
        fit_percent(&y[m..], &yh[m..])
    }
}

fn check_record(e: usize, u: &[f64], y: &[f64]) -> Result<()> {
    if u.len() != y.len() {
        return Err(IdentError::LengthMismatch {
            source_name: format!("experiment {e}"),
            column: "u".into(),
            expected: y.len(),
            found: u.len(),
        });
    }
    for (name, col) in [("u", u), ("y", y)] {
        if let Some(k) = col.iter().position(|v| !v.is_finite()) {
            return Err(IdentError::NonFinite {
                source_name: format!("experiment {e}"),
                column: name.into(),
                at: crate::error::SamplePos::index(k),
                value: col[k],
            });
        }
    }
    Ok(())
}

fn check_ts(ts: f64) -> Result<()> {
    if !(ts.is_finite() && ts > 0.0) {
        return Err(IdentError::InvalidParameter {
            name: "sample time".into(),
            value: ts,
            reason: "must be a positive finite number of seconds".into(),
        });
    }
    Ok(())
}

/// Least-squares ARX fit on rows `k ≥ start` of every record (`start ≥` the orders' lag).
fn arx_rows(experiments: &[Experiment<'_>], ts: f64, o: ArxOrders, start: usize) -> Result<Arx> {
    o.check()?;
    check_ts(ts)?;
    let names: Vec<String> = (1..=o.na)
        .map(|i| format!("a{i}"))
        .chain((0..o.nb).map(|j| format!("b{j}")))
        .collect();
    let refs: Vec<&str> = names.iter().map(String::as_str).collect();
    let mut qr = QrAccumulator::new(&refs, "y")?;
    let d = o.parameters();
    let mut available = 0;
    for (e, ex) in experiments.iter().enumerate() {
        check_record(e, ex.u, ex.y)?;
        let n = ex.y.len();
        if n <= start {
            continue;
        }
        available += n - start;
        let cols: Vec<Vec<f64>> = (1..=o.na)
            .map(|i| (start..n).map(|k| -ex.y[k - i]).collect())
            .chain((0..o.nb).map(|j| (start..n).map(|k| ex.u[k - o.nk - j]).collect()))
            .collect();
        let colrefs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
        qr.push(&colrefs, &ex.y[start..])?;
    }
    if available <= d {
        return Err(IdentError::TooFewSamples {
            source_name: UNNAMED.into(),
            what: format!(
                "an ARX({}, {}, {}) fit ({d} parameters, the first {start} samples of each record used as lags)",
                o.na, o.nb, o.nk
            ),
            needed: start + d + 1,
            found: experiments.iter().map(|e| e.y.len()).max().unwrap_or(0),
        });
    }
    let lsq = qr.finish()?;
    lsq.check()?;
    let mut a = vec![1.0];
    a.extend_from_slice(&lsq.estimate[..o.na]);
    let b = lsq.estimate[o.na..].to_vec();
    let noise_variance = lsq.residual_norm.powi(2) / (lsq.samples - d) as f64;
    Ok(Arx {
        orders: o,
        a,
        b,
        std_error: lsq.std_error.clone(),
        noise_variance,
        lsq,
        ts,
    })
}

/// Fits `A(q⁻¹) y(k) = B(q⁻¹) u(k − n_k) + e(k)` to one or several records (see the module
/// documentation) by QR least squares over the rows `k ≥ max(n_a, n_k + n_b − 1)` of each.
///
/// `ts` is the sample time in seconds (used only by the returned transfer function).
///
/// # Errors
/// [`IdentError::InvalidParameter`] for `n_a = n_b = 0` or a bad sample time;
/// [`IdentError::LengthMismatch`] / [`IdentError::NonFinite`] naming the experiment, column
/// and sample; [`IdentError::TooFewSamples`] if the records leave no residual degree of
/// freedom; [`IdentError::RankDeficient`] / [`IdentError::IllConditioned`] if the input does
/// not excite the model (a constant input, or closed-loop data under one static gain).
pub fn arx(experiments: &[Experiment<'_>], ts: f64, orders: ArxOrders) -> Result<Arx> {
    arx_rows(experiments, ts, orders, orders.lag())
}

/// One candidate of [`arx_order_selection`].
#[derive(Debug, Clone, PartialEq)]
pub struct ArxCandidate {
    /// The orders.
    pub orders: ArxOrders,
    /// Mean squared residual `V = ‖e‖²/N` on the common rows.
    pub loss: f64,
    /// `AIC = N ln V + 2d`.
    pub aic: f64,
}

/// The result of [`arx_order_selection`].
#[derive(Debug, Clone, PartialEq)]
pub struct ArxOrderSelection {
    /// Every candidate that could be fitted, in the order tried.
    pub candidates: Vec<ArxCandidate>,
    /// The candidate of least AIC.
    pub best: ArxCandidate,
    /// The model of the best orders.
    pub model: Arx,
}

/// Fits every ARX model with `n_a ∈ na`, `n_b ∈ nb`, `n_k ∈ nk` on the same rows (those
/// usable by the largest lag) and picks the least `AIC = N ln V + 2d` (module documentation).
/// Candidates whose regressor is rank deficient or ill conditioned are skipped.
///
/// # Errors
/// As [`arx`] for the data; [`IdentError::InvalidParameter`] if a range is empty or no
/// candidate could be fitted.
pub fn arx_order_selection(
    experiments: &[Experiment<'_>],
    ts: f64,
    na: std::ops::RangeInclusive<usize>,
    nb: std::ops::RangeInclusive<usize>,
    nk: std::ops::RangeInclusive<usize>,
) -> Result<ArxOrderSelection> {
    let mut all = Vec::new();
    for a in na.clone() {
        for b in nb.clone() {
            for k in nk.clone() {
                let o = ArxOrders::new(a, b, k);
                if o.check().is_ok() {
                    all.push(o);
                }
            }
        }
    }
    let start =
        all.iter()
            .map(ArxOrders::lag)
            .max()
            .ok_or_else(|| IdentError::InvalidParameter {
                name: "ARX order ranges".into(),
                value: 0.0,
                reason: "the ranges of na, nb, nk give no candidate with a parameter".into(),
            })?;
    let mut candidates = Vec::new();
    let mut best: Option<(ArxCandidate, Arx)> = None;
    for o in all {
        let model = match arx_rows(experiments, ts, o, start) {
            Ok(m) => m,
            Err(IdentError::RankDeficient { .. } | IdentError::IllConditioned { .. }) => continue,
            Err(e) => return Err(e),
        };
        let n = model.lsq.samples as f64;
        let loss = model.lsq.residual_norm.powi(2) / n;
        let c = ArxCandidate {
            orders: o,
            loss,
            aic: n * loss.ln() + 2.0 * o.parameters() as f64,
        };
        if best.as_ref().is_none_or(|(b, _)| c.aic < b.aic) {
            best = Some((c.clone(), model));
        }
        candidates.push(c);
    }
    let (best, model) = best.ok_or_else(|| IdentError::InvalidParameter {
        name: "ARX order ranges".into(),
        value: candidates.len() as f64,
        reason: "no candidate could be fitted (every regressor rank deficient)".into(),
    })?;
    Ok(ArxOrderSelection {
        candidates,
        best,
        model,
    })
}
