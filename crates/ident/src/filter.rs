//! The book's pre-filter `F(s) = 1/(T_f s + 1)³`, discretised exactly, causal or zero-phase.
//!
//! The least-squares relation `M p = N` (eq. 3.43/3.45) is linear in the parameters `p`, so
//! any *linear* operator applied to every column of `M` and to `N` preserves it:
//! `F(M) p = F(N)`. Filtering all columns with the same low-pass (same discretisation, same
//! zero initial state) therefore keeps the relation while removing the high-frequency noise
//! that three-point differentiation of quantised encoder signals produces (eq. 3.47 amplifies
//! an encoder step `q` into `q/(2 t_s)` and `q/(2 t_s)²`). The book uses `T_f = 0.075 s` and
//! filters with Simulink (forward Euler at 1 ms on interpolated samples, zero initial state).
//!
//! **Discretisation.** The cascade is realised as three first-order sections in series,
//! `ẋ₁ = (u − x₁)/T_f`, `ẋ₂ = (x₁ − x₂)/T_f`, `ẋ₃ = (x₂ − x₃)/T_f`, `y = x₃` — a single Jordan
//! block — and discretised *exactly* on the uniform grid for a stated input hold
//! ([`FilterHold`]):
//!
//! * [`FilterHold::Zoh`] (default): exact for inputs that are constant between samples. The
//!   rig's voltage *is* such a signal (a D/A converter held by the controller), and a
//!   zero-order-hold discretisation reproduces the continuous filter's step response exactly
//!   at the sample instants, `1 − e^{−t/T}(1 + t/T + t²/(2T²))` — the property the tests pin.
//!   Its only distortion on smooth signals is a half-sample delay, common to every column and
//!   therefore harmless to the regression.
//! * [`FilterHold::Foh`]: exact for inputs that are linear between samples (what Simulink's
//!   interpolating *From Workspace* block feeds the book's filter); second-order accurate for
//!   smooth signals, without the half-sample delay.
//!
//! (The cascade of three separately discretised first-order sections is *not* the exact
//! discretisation of the cube for either hold, because the intermediate signals are not
//! piecewise constant; that is why the whole third-order block is discretised at once.) The
//! matrices come from pendulab-lti's block exponentials (`zoh_integrals`, `foh_integrals`) and
//! are checked against the closed form of `exp(A t)` for the Jordan block in the tests.
//!
//! **Zero phase.** [`LowPass3::filter_zero_phase`] runs the filter forward, then backward over
//! the reversed result (each pass from a zero state): the overall response is
//! `|F(e^{jωt_s})|²`, real and non-negative, with no delay and DC gain 1. It is still one
//! linear operator applied to every column, so it preserves the regression; but it spreads
//! each sample's error both ways in time, so inconsistencies at the window ends (one-sided
//! derivatives, a step right at the start) weigh more than with the causal filter, whose
//! zero-state start de-weights the first `≈ 3 T_f` seconds.

use crate::error::{IdentError, Result};
use pendulab_lti::Mat;
use pendulab_lti::matrix_functions::{foh_integrals, zoh_integrals};

/// How the samples are interpolated when the continuous filter is discretised.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FilterHold {
    /// Zero-order hold (input constant between samples). Default.
    #[default]
    Zoh,
    /// First-order hold (input linear between samples).
    Foh,
}

/// Which pre-filter the regressions apply to every column.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Prefilter {
    /// No filtering (the book shows the estimates are then useless on real data).
    None,
    /// Causal `1/(T_f s + 1)³` from a zero state, as the book does.
    Causal {
        /// Time constant `T_f` in seconds (book: 0.075).
        tf: f64,
        /// Discretisation hold.
        hold: FilterHold,
    },
    /// Forward–backward (zero-phase) `|1/(T_f s + 1)³|²`.
    ZeroPhase {
        /// Time constant `T_f` in seconds.
        tf: f64,
        /// Discretisation hold.
        hold: FilterHold,
    },
}

impl Default for Prefilter {
    /// The book's choice: causal, `T_f = 0.075 s`, zero-order hold.
    fn default() -> Self {
        Prefilter::Causal {
            tf: BOOK_TF,
            hold: FilterHold::Zoh,
        }
    }
}

/// The book's pre-filter time constant, seconds.
pub const BOOK_TF: f64 = 0.075;

impl Prefilter {
    /// The filter and whether it runs forward–backward (`None` for [`Prefilter::None`]).
    ///
    /// # Errors
    /// [`IdentError::InvalidParameter`] for a bad `tf` or `ts`.
    pub fn design(&self, ts: f64) -> Result<Option<(LowPass3, bool)>> {
        Ok(match *self {
            Prefilter::None => None,
            Prefilter::Causal { tf, hold } => Some((LowPass3::new(tf, ts, hold)?, false)),
            Prefilter::ZeroPhase { tf, hold } => Some((LowPass3::new(tf, ts, hold)?, true)),
        })
    }

    /// Applies the filter to one column (a copy for [`Prefilter::None`]).
    ///
    /// # Errors
    /// As [`Prefilter::design`].
    pub fn apply(&self, x: &[f64], ts: f64) -> Result<Vec<f64>> {
        Ok(match self.design(ts)? {
            None => x.to_vec(),
            Some((f, false)) => f.filter(x),
            Some((f, true)) => f.filter_zero_phase(x),
        })
    }
}

/// `1/(T_f s + 1)³` discretised exactly at sample time `t_s`:
/// `x[k+1] = Φ x[k] + Γ_a u[k] + Γ_b u[k+1]`, `y[k] = x₃[k]`, `x[0] = 0`
/// (`Γ_b = 0` for the zero-order hold).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LowPass3 {
    tf: f64,
    ts: f64,
    hold: FilterHold,
    phi: [[f64; 3]; 3],
    ga: [f64; 3],
    gb: [f64; 3],
    /// Pole `e = e^{−t_s/T_f}` of the running realisation.
    e: f64,
    /// Output weights `[d, c₁, c₂, c₃]` of the running realisation (see [`LowPass3::filter_many`]).
    c: [f64; 4],
}

impl LowPass3 {
    /// Designs the filter.
    ///
    /// # Errors
    /// [`IdentError::InvalidParameter`] unless `tf` and `ts` are finite and positive.
    pub fn new(tf: f64, ts: f64, hold: FilterHold) -> Result<Self> {
        for (name, v) in [("filter time constant T_f", tf), ("sample time ts", ts)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(IdentError::InvalidParameter {
                    name: name.into(),
                    value: v,
                    reason: "must be finite and > 0 s".into(),
                });
            }
        }
        let a = Mat::from_row_slice(
            3,
            3,
            &[
                -1.0 / tf,
                0.0,
                0.0,
                1.0 / tf,
                -1.0 / tf,
                0.0,
                0.0,
                1.0 / tf,
                -1.0 / tf,
            ],
        );
        let b = Mat::from_row_slice(3, 1, &[1.0 / tf, 0.0, 0.0]);
        let (phi, ga, gb) = match hold {
            FilterHold::Zoh => {
                let (phi, g) = zoh_integrals(&a, &b, ts)?;
                (phi, g, Mat::zeros(3, 1))
            }
            FilterHold::Foh => {
                let (phi, g0, g1) = foh_integrals(&a, &b, ts)?;
                (phi, &g0 - &g1, g1)
            }
        };
        let mut out = Self {
            tf,
            ts,
            hold,
            phi: [[0.0; 3]; 3],
            ga: [0.0; 3],
            gb: [0.0; 3],
            e: 0.0,
            c: [0.0; 4],
        };
        for i in 0..3 {
            for j in 0..3 {
                out.phi[i][j] = phi[(i, j)];
            }
            out.ga[i] = ga[(i, 0)];
            out.gb[i] = gb[(i, 0)];
        }
        // The transfer function is N(z)/(z − e)³; write N(z) = d(z−e)³ + c₁(z−e)² + c₂(z−e) + c₃
        // and match the first four Markov parameters h₀…h₃ of the state-space recursion:
        // h₀ = d, h₁ = c₁, h₂ = c₁e + c₂, h₃ = c₁e² + 2c₂e + c₃.
        let e = out.phi[0][0];
        let h = out.impulse_response::<4>();
        let c1 = h[1];
        let c2 = h[2] - e * c1;
        let c3 = h[3] - e * e * c1 - 2.0 * e * c2;
        out.e = e;
        out.c = [h[0], c1, c2, c3];
        Ok(out)
    }

    /// Time constant `T_f`, seconds.
    pub fn tf(&self) -> f64 {
        self.tf
    }
    /// Sample time, seconds.
    pub fn ts(&self) -> f64 {
        self.ts
    }
    /// The discretisation hold.
    pub fn hold(&self) -> FilterHold {
        self.hold
    }
    /// The transition matrix `Φ = exp(A t_s)` (row-major).
    pub fn phi(&self) -> [[f64; 3]; 3] {
        self.phi
    }
    /// Input vectors `(Γ_a, Γ_b)` of the recursion.
    pub fn gammas(&self) -> ([f64; 3], [f64; 3]) {
        (self.ga, self.gb)
    }

    /// The first `K` samples of the impulse response of the state-space recursion.
    fn impulse_response<const K: usize>(&self) -> [f64; K] {
        let mut x = [0.0; 3];
        let mut h = [0.0; K];
        for (k, hk) in h.iter_mut().enumerate() {
            let u = if k == 0 { 1.0 } else { 0.0 };
            let s: [f64; 3] = std::array::from_fn(|i| x[i] + self.gb[i] * u);
            *hk = s[2];
            x = std::array::from_fn(|i| {
                (0..3).map(|j| self.phi[i][j] * s[j]).sum::<f64>() + self.ga[i] * u
            });
        }
        h
    }

    /// DC gain of the discrete filter, `C (I − Φ)⁻¹ (Γ_a + Γ_b)` (1 up to rounding).
    pub fn dc_gain(&self) -> f64 {
        // Φ is lower triangular (a cascade); forward substitution on (I − Φ) x = Γ.
        let g: Vec<f64> = (0..3).map(|i| self.ga[i] + self.gb[i]).collect();
        let mut x = [0.0; 3];
        for i in 0..3 {
            let mut acc = g[i];
            for (j, xj) in x.iter().enumerate().take(i) {
                acc += self.phi[i][j] * xj;
            }
            x[i] = acc / (1.0 - self.phi[i][i]);
        }
        x[2]
    }

    /// Causal filtering of `u` from a zero state; the output has the length of `u`.
    pub fn filter(&self, u: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; u.len()];
        self.filter_many(&[u], &mut [&mut y]);
        y
    }

    /// Causal filtering of several columns at once (the independent recursions interleave,
    /// which hides their latency); `outputs[i]` receives the filtered `inputs[i]`.
    ///
    /// The recursion runs in the equivalent cascade realisation of the same transfer function
    /// `N(z)/(z − e)³`: `w₁ ← e w₁ + u`, `w₂ ← e w₂ + w₁`, `w₃ ← e w₃ + w₂`,
    /// `y = d u + c₁ w₁ + c₂ w₂ + c₃ w₃` — 11 operations per sample instead of 15, with the
    /// weights matched to the exact discretisation's impulse response. For this low-pass every
    /// weight is positive (the zeros of `N` are negative real), so the output sums positive
    /// terms and the realisation is as accurate as the state-space one (the tests compare
    /// both with the closed-form step response and SciPy to 1e-12).
    ///
    /// # Panics
    /// If the counts or lengths of `inputs` and `outputs` differ (a programming error).
    pub fn filter_many(&self, inputs: &[&[f64]], outputs: &mut [&mut [f64]]) {
        assert_eq!(inputs.len(), outputs.len(), "one output per input");
        let mut i = 0;
        while i < inputs.len() {
            let m = (inputs.len() - i).min(4);
            match m {
                4 => self.run_group::<4>(&inputs[i..i + 4], &mut outputs[i..i + 4]),
                3 => self.run_group::<3>(&inputs[i..i + 3], &mut outputs[i..i + 3]),
                2 => self.run_group::<2>(&inputs[i..i + 2], &mut outputs[i..i + 2]),
                _ => self.run_group::<1>(&inputs[i..i + 1], &mut outputs[i..i + 1]),
            }
            i += m;
        }
    }

    /// `G` recursions side by side.
    fn run_group<const G: usize>(&self, inputs: &[&[f64]], outputs: &mut [&mut [f64]]) {
        let n = inputs[0].len();
        for c in 0..G {
            assert_eq!(inputs[c].len(), n, "inputs of equal length");
            assert_eq!(outputs[c].len(), n, "outputs as long as the inputs");
        }
        let mut bank = FilterBank::<G>::new(self);
        let ins: [&[f64]; G] = std::array::from_fn(|c| &inputs[c][..n]);
        let mut k = 0;
        let mut u = [[0.0; BANK_BLOCK]; G];
        let mut y = [[0.0; BANK_BLOCK]; G];
        while k < n {
            let m = (n - k).min(BANK_BLOCK);
            for c in 0..G {
                u[c][..m].copy_from_slice(&ins[c][k..k + m]);
            }
            bank.process(&u, &mut y, m);
            for c in 0..G {
                outputs[c][k..k + m].copy_from_slice(&y[c][..m]);
            }
            k += m;
        }
    }

    /// Zero-phase (forward–backward) filtering of `u`: filter, reverse, filter, reverse; each
    /// pass from a zero state.
    pub fn filter_zero_phase(&self, u: &[f64]) -> Vec<f64> {
        let mut y = self.filter(u);
        y.reverse();
        let mut z = self.filter(&y);
        z.reverse();
        z
    }
}

/// Lanes of a [`FilterBank`]: the most columns one bank filters.
pub(crate) const LANES: usize = 4;

/// Rows per block of [`FilterBank::process`].
pub(crate) const BANK_BLOCK: usize = crate::least_squares::BLOCK;

/// `W` causal recursions of one [`LowPass3`] run side by side on blocks of samples, keeping
/// their states between blocks (so a long record can be filtered block by block, in cache).
/// Runs the cascade realisation documented at [`LowPass3::filter_many`]; every state's own
/// recurrence is one multiply and one add, and the `W` columns' work overlaps.
#[derive(Debug, Clone)]
pub(crate) struct FilterBank<const W: usize> {
    /// States `w₁, w₂, w₃` of each column, in [`LANES`] lanes (lanes `≥ W` stay zero).
    w: [[f64; LANES]; 3],
    e: f64,
    c: [f64; 4],
}

impl<const W: usize> FilterBank<W> {
    pub(crate) fn new(f: &LowPass3) -> Self {
        const { assert!(W <= LANES, "at most LANES columns per bank") };
        Self {
            w: [[0.0; LANES]; 3],
            e: f.e,
            c: f.c,
        }
    }

    /// Filters `m` samples of each column `u[c][..m]` into `y[c][..m]`.
    pub(crate) fn process(
        &mut self,
        u: &[[f64; BANK_BLOCK]; W],
        y: &mut [[f64; BANK_BLOCK]; W],
        m: usize,
    ) {
        if self.c[0] != 0.0 {
            self.run::<true>(u, y, m);
        } else {
            self.run::<false>(u, y, m);
        }
    }

    #[inline(always)]
    fn run<const DIRECT: bool>(
        &mut self,
        u: &[[f64; BANK_BLOCK]; W],
        y: &mut [[f64; BANK_BLOCK]; W],
        m: usize,
    ) {
        let e = self.e;
        let [d, c1, c2, c3] = self.c;
        let [mut w1, mut w2, mut w3] = self.w;
        // Every lane runs the same operations in the same order whatever `W`, so the fixed
        // width changes no result; written as whole-lane operations, the lanes stay in vector
        // registers instead of `3 W` scalars.
        let scale = |a: [f64; LANES], k: f64| -> [f64; LANES] { std::array::from_fn(|c| a[c] * k) };
        let add = |a: [f64; LANES], b: [f64; LANES]| -> [f64; LANES] {
            std::array::from_fn(|c| a[c] + b[c])
        };
        for i in 0..m.min(BANK_BLOCK) {
            let uu: [f64; LANES] = std::array::from_fn(|c| if c < W { u[c][i] } else { 0.0 });
            let o = add(add(scale(w1, c1), scale(w2, c2)), scale(w3, c3));
            let out = if DIRECT { add(o, scale(uu, d)) } else { o };
            w3 = add(scale(w3, e), w2);
            w2 = add(scale(w2, e), w1);
            w1 = add(scale(w1, e), uu);
            for c in 0..W {
                y[c][i] = out[c];
            }
        }
        self.w = [w1, w2, w3];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bank_lanes_equal_single_recursions_bit_for_bit() {
        // Three columns filtered side by side in the padded lanes give exactly what each
        // column gives alone through the cascade recursion written out here.
        let f = LowPass3::new(0.075, 1e-3, FilterHold::Zoh).unwrap();
        let n = 700;
        let cols: Vec<Vec<f64>> = (0..3)
            .map(|c| {
                (0..n)
                    .map(|k| ((k * (c + 2)) as f64 * 0.01).sin() + c as f64)
                    .collect()
            })
            .collect();
        let mut outs = vec![vec![0.0; n]; 3];
        {
            let ins: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
            let mut o: Vec<&mut [f64]> = outs.iter_mut().map(|c| c.as_mut_slice()).collect();
            f.filter_many(&ins, &mut o);
        }
        let [d, c1, c2, c3] = f.c;
        for (u, y) in cols.iter().zip(&outs) {
            let (mut w1, mut w2, mut w3) = (0.0, 0.0, 0.0);
            for (uk, yk) in u.iter().zip(y) {
                let expect = c1 * w1 + c2 * w2 + c3 * w3 + d * uk;
                assert_eq!(expect.to_bits(), yk.to_bits());
                w3 = f.e * w3 + w2;
                w2 = f.e * w2 + w1;
                w1 = f.e * w1 + uk;
            }
        }
    }

    #[test]
    fn matches_closed_form_jordan_block() {
        // exp(A h) for A = (−I + N)/T (N the subdiagonal shift): e^{−r}(I + rN + r²N²/2),
        // r = h/T; the ZOH input vector is the step response of each stage at h:
        // 1 − e^{−r}, 1 − e^{−r}(1 + r), 1 − e^{−r}(1 + r + r²/2).
        let (tf, ts) = (0.075, 0.001);
        let f = LowPass3::new(tf, ts, FilterHold::Zoh).unwrap();
        let r: f64 = ts / tf;
        let e = (-r).exp();
        let phi = [[e, 0.0, 0.0], [e * r, e, 0.0], [e * r * r / 2.0, e * r, e]];
        let g = [
            1.0 - e,
            1.0 - e * (1.0 + r),
            1.0 - e * (1.0 + r + r * r / 2.0),
        ];
        let (ga, gb) = f.gammas();
        for i in 0..3 {
            for j in 0..3 {
                // Block exponential vs closed form: a few ulps of entries ≤ 1.
                assert!((f.phi()[i][j] - phi[i][j]).abs() < 1e-14, "phi {i}{j}");
            }
            // The small entries (g[2] ≈ 2e-6) are cancellation-free in the block exponential
            // but not in the closed form 1 − e^{−r}(…): compare relative to 1e-9.
            assert!((ga[i] - g[i]).abs() < 1e-9 * g[i].max(1e-300), "ga {i}");
            assert_eq!(gb[i], 0.0);
        }
        // The running cascade realisation: pole e, no feedthrough for the ZOH, positive
        // weights (so its output sums positive terms); with the FOH a positive feedthrough.
        assert!((f.e - e).abs() < 1e-15);
        assert_eq!(f.c[0], 0.0);
        assert!(f.c[1..].iter().all(|c| *c > 0.0), "{:?}", f.c);
        let g = LowPass3::new(tf, ts, FilterHold::Foh).unwrap();
        assert!(g.c.iter().all(|c| *c > 0.0), "{:?}", g.c);
    }
}
