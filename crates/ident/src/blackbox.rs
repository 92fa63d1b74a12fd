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
//!   crate's Householder QR ([`least_squares`](mod@crate::least_squares), with its rank and conditioning checks).
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
//! barely informative, identify the plant together.

use crate::error::{IdentError, Result, UNNAMED};
use crate::least_squares::{LeastSquares, QrAccumulator};
use crate::validation::fit_percent;
use nalgebra::DMatrix;
use pendulab_lti::response::{LsimOptions, lsim};
use pendulab_lti::{Discrete, Mat, StateSpace, TransferFunction};

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

/// One uniformly sampled multi-input multi-output record (for [`moesp`]): input and output
/// columns of equal length.
#[derive(Debug, Clone, PartialEq)]
pub struct IoRecord<'a> {
    /// Input columns `u_j(0…N−1)`, one slice per input.
    pub u: Vec<&'a [f64]>,
    /// Output columns `y_i(0…N−1)`, one slice per output.
    pub y: Vec<&'a [f64]>,
}

impl<'a> IoRecord<'a> {
    /// A single-input single-output record.
    pub fn siso(u: &'a [f64], y: &'a [f64]) -> Self {
        Self {
            u: vec![u],
            y: vec![y],
        }
    }

    fn len(&self) -> usize {
        self.y[0].len()
    }

    /// The inputs as a `N × n_u` matrix (rows = samples).
    fn u_mat(&self) -> Mat {
        Mat::from_fn(self.len(), self.u.len(), |t, j| self.u[j][t])
    }
}

/// Options of [`moesp`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MoespOptions {
    /// Block rows `k` of the past and of the future Hankel matrices (the horizon); the order
    /// can be at most `(k − 1) n_y`.
    pub horizon: usize,
    /// The model order; `None` reads it off the singular values (the largest ratio of
    /// consecutive singular values `σ_n/σ_{n+1}`, `n` in `1..=max_order`).
    pub order: Option<usize>,
    /// The largest order the selection from the singular values may choose (used only when
    /// `order` is `None`): it searches `n ∈ 1..=min(max_order, (k − 1) n_y)`. `None` is
    /// `(k − 1) n_y`, every order the horizon allows. Giving both `order` and `max_order`, or
    /// `max_order = 0`, is an [`IdentError::InvalidParameter`].
    pub max_order: Option<usize>,
}

impl Default for MoespOptions {
    /// Horizon 10, order from the singular values among all the horizon allows.
    fn default() -> Self {
        Self {
            horizon: 10,
            order: None,
            max_order: None,
        }
    }
}

/// A model identified by [`moesp`].
#[derive(Debug, Clone, PartialEq)]
pub struct Moesp {
    /// The identified system `x(k+1) = A x(k) + B u(k)`, `y(k) = C x(k) + D u(k)`.
    pub model: StateSpace<Discrete>,
    /// The singular values of `L₃₂` (the order is the number of dominant ones).
    pub singular_values: Vec<f64>,
    /// The order used.
    pub order: usize,
    /// The estimated initial state of each record.
    pub initial_states: Vec<Vec<f64>>,
    /// The least-squares fit of `B`, `D` and the initial states (condition, residual).
    pub lsq: LeastSquares,
}

impl Moesp {
    /// Simulates the model on a record's inputs from the zero initial state (a record that
    /// starts at rest) and returns MATLAB's `compare` fit ([`fit_percent`]) of each output.
    ///
    /// # Errors
    /// As [`moesp`] for the record; [`IdentError::Lti`] from the simulation.
    pub fn fit_percent(&self, record: &IoRecord<'_>) -> Result<Vec<f64>> {
        check_io(0, record, self.model.nu(), self.model.ny())?;
        let y = simulate(&self.model, record, None)?;
        (0..self.model.ny())
            .map(|i| fit_percent(record.y[i], y.column(i).as_slice()))
            .collect()
    }
}

fn check_io(e: usize, r: &IoRecord<'_>, nu: usize, ny: usize) -> Result<()> {
    if r.u.len() != nu || r.y.len() != ny {
        return Err(IdentError::LengthMismatch {
            source_name: format!("experiment {e}"),
            column: "input/output columns".into(),
            expected: nu + ny,
            found: r.u.len() + r.y.len(),
        });
    }
    let n = r.y.first().map_or(0, |y| y.len());
    let named = r.u.iter().enumerate().map(|(j, c)| (format!("u{j}"), c));
    for (name, col) in named.chain(r.y.iter().enumerate().map(|(i, c)| (format!("y{i}"), c))) {
        if col.len() != n {
            return Err(IdentError::LengthMismatch {
                source_name: format!("experiment {e}"),
                column: name,
                expected: n,
                found: col.len(),
            });
        }
        if let Some(k) = col.iter().position(|v| !v.is_finite()) {
            return Err(IdentError::NonFinite {
                source_name: format!("experiment {e}"),
                column: name,
                at: crate::error::SamplePos::index(k),
                value: col[k],
            });
        }
    }
    Ok(())
}

/// The outputs (`N × n_y`) of `sys` on the record's inputs from `x0` (zero if `None`).
fn simulate(sys: &StateSpace<Discrete>, r: &IoRecord<'_>, x0: Option<&[f64]>) -> Result<Mat> {
    let t: Vec<f64> = (0..r.len()).map(|k| k as f64 * sys.ts()).collect();
    let tr = lsim(sys, &r.u_mat(), &t, x0, &LsimOptions::default())?;
    Ok(tr.y().clone())
}

/// Identifies a discrete state-space model from one or several records by Verhaegen's
/// past-output MOESP (module documentation).
///
/// With `k` = `opts.horizon`, each record of length `N` gives `N − 2k + 1` columns of the
/// block Hankel matrices `U_p, Y_p` (samples `t … t+k−1`) and `U_f, Y_f` (`t+k … t+2k−1`);
/// the columns of all records are stacked. The LQ decomposition
/// `[U_f; W_p; Y_f] = L Q` (`W_p = [U_p; Y_p]`, computed as the QR decomposition of the
/// transpose) gives `L₃₂`, whose column space is that of the extended observability matrix
/// `Γ_k` when the noise is white and the input persistently exciting. `Γ_k = U₁ Σ₁^{1/2}` from
/// the `n` dominant singular triplets; `C` is its first block row and `A` the least-squares
/// solution of `Γ_k↑ A = Γ_k↓` (the shift invariance). `B`, `D` and the initial state of each
/// record are then the least-squares fit of the output, which is linear in them for known
/// `A`, `C`.
///
/// # Errors
/// [`IdentError::InvalidParameter`] for no record, a horizon below 2, a bad sample time, an
/// order of 0 or above `(k − 1) n_y`, a `max_order` of 0 or given with the order; [`IdentError::LengthMismatch`] /
/// [`IdentError::NonFinite`] naming the record and column; [`IdentError::TooFewSamples`] if
/// the records give fewer Hankel columns than rows; the least-squares errors of [`arx`] for
/// `B`, `D`; [`IdentError::Lti`] if the identified matrices are rejected.
pub fn moesp(records: &[IoRecord<'_>], ts: f64, opts: MoespOptions) -> Result<Moesp> {
    check_ts(ts)?;
    let first = records
        .first()
        .ok_or_else(|| IdentError::InvalidParameter {
            name: "number of records".into(),
            value: 0.0,
            reason: "at least one record is needed".into(),
        })?;
    let (m, l, k) = (first.u.len(), first.y.len(), opts.horizon);
    if l == 0 {
        return Err(IdentError::InvalidParameter {
            name: "number of outputs".into(),
            value: 0.0,
            reason: "at least one output column is needed".into(),
        });
    }
    if k < 2 {
        return Err(IdentError::InvalidParameter {
            name: "MOESP horizon".into(),
            value: k as f64,
            reason: "at least 2 block rows are needed for the shift invariance".into(),
        });
    }
    match (opts.order, opts.max_order) {
        (Some(n), Some(c)) => {
            return Err(IdentError::InvalidParameter {
                name: "MOESP max_order".into(),
                value: c as f64,
                reason: format!("give either the order ({n}) or max_order, not both"),
            });
        }
        (None, Some(0)) => {
            return Err(IdentError::InvalidParameter {
                name: "MOESP max_order".into(),
                value: 0.0,
                reason: "must be at least 1".into(),
            });
        }
        _ => {}
    }
    for (e, r) in records.iter().enumerate() {
        check_io(e, r, m, l)?;
    }
    let width = 2 * k * (m + l);
    let cols: usize = records
        .iter()
        .map(|r| (r.len() + 1).saturating_sub(2 * k))
        .sum();
    if cols < width {
        return Err(IdentError::TooFewSamples {
            source_name: UNNAMED.into(),
            what: format!("MOESP with horizon {k} ({width} Hankel rows)"),
            needed: 2 * k - 1 + width,
            found: records.iter().map(IoRecord::len).max().unwrap_or(0),
        });
    }
    // Transposed Hankel matrix: one row per Hankel column, blocks [U_f, U_p, Y_p, Y_f].
    let mut h = DMatrix::<f64>::zeros(cols, width);
    let mut row = 0;
    for r in records {
        for t in 0..(r.len() + 1).saturating_sub(2 * k) {
            for i in 0..k {
                for j in 0..m {
                    h[(row, i * m + j)] = r.u[j][t + k + i];
                    h[(row, k * m + i * m + j)] = r.u[j][t + i];
                }
                for j in 0..l {
                    h[(row, 2 * k * m + i * l + j)] = r.y[j][t + i];
                    h[(row, 2 * k * m + k * l + i * l + j)] = r.y[j][t + k + i];
                }
            }
            row += 1;
        }
    }
    let rr = h.qr().r();
    // L₃₂ = (R block (W_p rows, Y_f columns))ᵀ.
    let (wp0, yf0) = (k * m, 2 * k * m + k * l);
    let l32 = rr
        .view((wp0, yf0), (k * (m + l), k * l))
        .transpose()
        .into_owned();
    let svd = l32.svd(true, false);
    let u = svd.u.as_ref().ok_or_else(|| IdentError::NonFiniteResult {
        what: "left singular vectors of L32".into(),
        value: f64::NAN,
        reason: "the SVD did not return them (non-finite data)".into(),
    })?;
    // nalgebra does not sort the singular values: order them.
    let mut idx: Vec<usize> = (0..svd.singular_values.len()).collect();
    idx.sort_by(|&a, &b| svd.singular_values[b].total_cmp(&svd.singular_values[a]));
    let sv: Vec<f64> = idx.iter().map(|&i| svd.singular_values[i]).collect();
    let max_order = (k - 1) * l;
    let n = match opts.order {
        Some(n) => n,
        None => gap_order(&sv, opts.max_order.unwrap_or(max_order).min(max_order)),
    };
    if n == 0 || n > max_order {
        return Err(IdentError::InvalidParameter {
            name: "MOESP order".into(),
            value: n as f64,
            reason: format!("must lie in 1..={max_order} ((horizon − 1) × outputs)"),
        });
    }
    let gamma = Mat::from_fn(k * l, n, |i, j| u[(i, idx[j])] * sv[j].sqrt());
    let c = gamma.rows(0, l).into_owned();
    let up = gamma.rows(0, (k - 1) * l).into_owned();
    let down = gamma.rows(l, (k - 1) * l).into_owned();
    let a = up
        .svd(true, true)
        .solve(&down, f64::EPSILON * (k * l) as f64)
        .map_err(|reason| IdentError::InvalidParameter {
            name: "MOESP shift equation".into(),
            value: n as f64,
            reason: reason.into(),
        })?;
    let (b, d, initial_states, lsq) = fit_b_d(records, ts, &a, &c, m)?;
    let model = StateSpace::discrete(a, b, c, d, ts)?;
    Ok(Moesp {
        model,
        singular_values: sv,
        order: n,
        initial_states,
        lsq,
    })
}

/// The order `n ∈ 1..=max` with the largest ratio `σ_n/σ_{n+1}` of consecutive singular
/// values (`σ` descending; a zero `σ_{n+1}` read as `ε σ₁`), 1 when there is no ratio to take.
fn gap_order(sv: &[f64], max: usize) -> usize {
    let floor = sv.first().copied().unwrap_or(0.0) * f64::EPSILON;
    (1..=max.min(sv.len().saturating_sub(1)))
        .max_by(|&a, &b| {
            let ra = sv[a - 1] / sv[a].max(floor);
            let rb = sv[b - 1] / sv[b].max(floor);
            ra.total_cmp(&rb)
        })
        .unwrap_or(1)
}

/// `B`, `D` and the records' initial states by least squares for known `A`, `C`: the output
/// is `Σ_ij B_ij y^{B_ij} + Σ_ij D_ij y^{D_ij} + Σ_i x0_i y^{x0_i}`, each term the response
/// of `(A, e_i, C)` to `u_j`, `u_j` itself in output `i`, or the free response from `e_i`.
type BdFit = (Mat, Mat, Vec<Vec<f64>>, LeastSquares);

fn fit_b_d(records: &[IoRecord<'_>], ts: f64, a: &Mat, c: &Mat, m: usize) -> Result<BdFit> {
    let (n, l) = (a.nrows(), c.nrows());
    let total: usize = records.iter().map(|r| r.len() * l).sum();
    let mut names = Vec::new();
    let mut cols: Vec<Vec<f64>> = Vec::new();
    let mut offsets = Vec::new();
    let mut off = 0;
    for r in records {
        offsets.push(off);
        off += r.len() * l;
    }
    // Output rows: record by record, sample by sample, output by output.
    let place = |col: &mut Vec<f64>, ri: usize, y: &Mat| {
        for t in 0..y.nrows() {
            for i in 0..l {
                col[offsets[ri] + t * l + i] = y[(t, i)];
            }
        }
    };
    for i in 0..n {
        for j in 0..m {
            let mut bij = Mat::zeros(n, m);
            bij[(i, j)] = 1.0;
            let sys = StateSpace::discrete(a.clone(), bij, c.clone(), Mat::zeros(l, m), ts)?;
            let mut col = vec![0.0; total];
            for (ri, r) in records.iter().enumerate() {
                place(&mut col, ri, &simulate(&sys, r, None)?);
            }
            names.push(format!("B[{i},{j}]"));
            cols.push(col);
        }
    }
    for i in 0..l {
        for j in 0..m {
            let mut col = vec![0.0; total];
            for (ri, r) in records.iter().enumerate() {
                for (t, v) in r.u[j].iter().enumerate() {
                    col[offsets[ri] + t * l + i] = *v;
                }
            }
            names.push(format!("D[{i},{j}]"));
            cols.push(col);
        }
    }
    let free = StateSpace::discrete(a.clone(), Mat::zeros(n, m), c.clone(), Mat::zeros(l, m), ts)?;
    for (ri, r) in records.iter().enumerate() {
        for i in 0..n {
            let mut x0 = vec![0.0; n];
            x0[i] = 1.0;
            let mut col = vec![0.0; total];
            place(&mut col, ri, &simulate(&free, r, Some(&x0))?);
            names.push(format!("x0[{ri}][{i}]"));
            cols.push(col);
        }
    }
    let mut target = vec![0.0; total];
    for (ri, r) in records.iter().enumerate() {
        for t in 0..r.len() {
            for i in 0..l {
                target[offsets[ri] + t * l + i] = r.y[i][t];
            }
        }
    }
    let refs: Vec<&str> = names.iter().map(String::as_str).collect();
    let mut qr = QrAccumulator::new(&refs, "y")?;
    let colrefs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    qr.push(&colrefs, &target)?;
    let lsq = qr.finish()?;
    lsq.check()?;
    let p = &lsq.estimate;
    let b = Mat::from_fn(n, m, |i, j| p[i * m + j]);
    let d = Mat::from_fn(l, m, |i, j| p[n * m + i * m + j]);
    let x0 = (0..records.len())
        .map(|ri| p[n * m + l * m + ri * n..n * m + l * m + (ri + 1) * n].to_vec())
        .collect();
    Ok((b, d, x0, lsq))
}
