//! The Dormand–Prince 5(4) embedded Runge–Kutta pair with its continuous extension.
//!
//! Method: J. R. Dormand and P. J. Prince, "A family of embedded Runge–Kutta formulae",
//! J. Comput. Appl. Math. 6 (1980) 19–26 (the 7-stage FSAL pair "RK5(4)7M"); step-size
//! control and dense output as described by E. Hairer, S. P. Nørsett and G. Wanner, *Solving
//! Ordinary Differential Equations I*, 2nd ed., Springer 1993, §II.4 (error norm, initial step),
//! §II.6 (the 4th-order continuous extension of DOPRI5) and §IV.2 (the PI step-size
//! controller of Gustafsson).
//!
//! - The 5th-order solution advances (local extrapolation); the embedded 4th-order one gives
//!   the error estimate `err = sqrt(mean((Δᵢ / (atol + rtol·max(|yᵢ|, |y⁺ᵢ|)))²))`; a step is
//!   accepted iff `err ≤ 1`.
//! - PI control: `h_new = h · clamp(0.9 · err^{−(0.2 − 0.75β)} · err_prev^{β}, 0.2, 10)`,
//!   `β = 0.04`, `err_prev` the error of the last accepted step (floored at 1e-4); after a
//!   rejection the step may not grow.
//! - Dense output on `[t, t + h]`, `θ = (s − t)/h`:
//!   `y(θ) = y + θ(Δy + (1 − θ)(b + θ(Δy − h k₇ − b + (1 − θ) h Σ dⱼ kⱼ)))`,
//!   `Δy = y⁺ − y`, `b = h k₁ − Δy` (4th order, continuous, C¹ at the step ends).

use crate::buffer::Buf;
use crate::dynamics::Dynamics;

// Nodes and coefficients of RK5(4)7M.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
// 5th-order weights (= the last row of A: first same as last).
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
// Error weights b − b̂ (b̂ the embedded 4th-order weights).
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Continuous extension (Hairer–Nørsett–Wanner §II.6, Shampine's 4th-order interpolant).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// PI controller constants.
const SAFETY: f64 = 0.9;
const FAC_MIN: f64 = 0.2;
const FAC_MAX: f64 = 10.0;
const BETA: f64 = 0.04;

/// Tolerances and limits of the adaptive integrator (validated by the caller).
#[derive(Debug, Clone, Copy)]
pub(crate) struct DopriParams {
    pub rtol: f64,
    pub atol: f64,
    pub h_max: f64,
    pub h_init: Option<f64>,
    pub max_steps: usize,
}

/// Scratch and controller state of the stepper.
#[derive(Clone)]
pub(crate) struct Dopri<B: Buf> {
    pub(crate) k1: B,
    k2: B,
    k3: B,
    k4: B,
    k5: B,
    k6: B,
    pub(crate) k7: B,
    pub(crate) y1: B,
    yt: B,
    /// The size of the last accepted step (for its dense output).
    pub(crate) h_used: f64,
    err_prev: f64,
    pub(crate) params: DopriParams,
    pub(crate) accepted: usize,
    pub(crate) rejected: usize,
    pub(crate) evaluations: usize,
}

/// The outcome of one step attempt.
pub(crate) struct Attempt {
    pub err: f64,
}

impl<B: Buf> Dopri<B> {
    pub(crate) fn new(n: usize, params: DopriParams) -> Self {
        Self {
            k1: B::zeros(n),
            k2: B::zeros(n),
            k3: B::zeros(n),
            k4: B::zeros(n),
            k5: B::zeros(n),
            k6: B::zeros(n),
            k7: B::zeros(n),
            y1: B::zeros(n),
            yt: B::zeros(n),
            h_used: 0.0,
            err_prev: 1e-4,
            params,
            accepted: 0,
            rejected: 0,
            evaluations: 0,
        }
    }

    /// Weighted RMS norm with the scale `atol + rtol·|y|`.
    fn norm(&self, v: &[f64], y: &[f64]) -> f64 {
        let n = v.len().max(1) as f64;
        let s: f64 = v
            .iter()
            .zip(y)
            .map(|(vi, yi)| {
                let sc = self.params.atol + self.params.rtol * yi.abs();
                (vi / sc) * (vi / sc)
            })
            .sum();
        (s / n).sqrt()
    }

    /// Initial step size (Hairer–Nørsett–Wanner §II.4, "starting step size"), needs `k1`
    /// valid. Bounded by `h_max` and `span`.
    pub(crate) fn initial_step<S: Dynamics + ?Sized>(
        &mut self,
        sys: &S,
        t: f64,
        y: &B,
        u: &[f64],
        span: f64,
    ) -> f64 {
        let d0 = self.norm(y.s(), y.s());
        let d1 = self.norm(self.k1.s(), y.s());
        let mut h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        };
        h0 = h0.min(self.params.h_max).min(span);
        for ((yt, &yi), &k) in self.yt.m().iter_mut().zip(y.s()).zip(self.k1.s()) {
            *yt = yi + h0 * k;
        }
        sys.derivative(t + h0, self.yt.s(), u, self.k2.m());
        self.evaluations += 1;
        let mut diff = self.k2.clone();
        for (d, &k) in diff.m().iter_mut().zip(self.k1.s()) {
            *d -= k;
        }
        let d2 = self.norm(diff.s(), y.s()) / h0;
        let dm = d1.max(d2);
        let h1 = if dm <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / dm).powf(0.2)
        };
        (100.0 * h0).min(h1).min(self.params.h_max).min(span)
    }

    /// One step attempt from `(t, y)` with step `h`, `k1 = f(t, y, u)` already in place.
    /// Writes `y1` (5th order) and `k7 = f(t + h, y1)`; returns the scaled error.
    #[inline]
    pub(crate) fn attempt<S: Dynamics + ?Sized>(
        &mut self,
        sys: &S,
        t: f64,
        y: &B,
        u: &[f64],
        h: f64,
    ) -> Attempt {
        let ys = y.s();
        for (i, yt) in self.yt.m().iter_mut().enumerate() {
            *yt = ys[i] + h * (A21 * self.k1.s()[i]);
        }
        sys.derivative(t + C2 * h, self.yt.s(), u, self.k2.m());
        {
            let (k1, k2) = (self.k1.s(), self.k2.s());
            for (i, yt) in self.yt.m().iter_mut().enumerate() {
                *yt = ys[i] + h * (A31 * k1[i] + A32 * k2[i]);
            }
        }
        sys.derivative(t + C3 * h, self.yt.s(), u, self.k3.m());
        {
            let (k1, k2, k3) = (self.k1.s(), self.k2.s(), self.k3.s());
            for (i, yt) in self.yt.m().iter_mut().enumerate() {
                *yt = ys[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
            }
        }
        sys.derivative(t + C4 * h, self.yt.s(), u, self.k4.m());
        {
            let (k1, k2, k3, k4) = (self.k1.s(), self.k2.s(), self.k3.s(), self.k4.s());
            for (i, yt) in self.yt.m().iter_mut().enumerate() {
                *yt = ys[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
            }
        }
        sys.derivative(t + C5 * h, self.yt.s(), u, self.k5.m());
        {
            let (k1, k2, k3, k4, k5) = (
                self.k1.s(),
                self.k2.s(),
                self.k3.s(),
                self.k4.s(),
                self.k5.s(),
            );
            for (i, yt) in self.yt.m().iter_mut().enumerate() {
                *yt = ys[i]
                    + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]);
            }
        }
        sys.derivative(t + h, self.yt.s(), u, self.k6.m());
        {
            let (k1, k3, k4, k5, k6) = (
                self.k1.s(),
                self.k3.s(),
                self.k4.s(),
                self.k5.s(),
                self.k6.s(),
            );
            for (i, y1) in self.y1.m().iter_mut().enumerate() {
                *y1 = ys[i] + h * (B1 * k1[i] + B3 * k3[i] + B4 * k4[i] + B5 * k5[i] + B6 * k6[i]);
            }
        }
        sys.derivative(t + h, self.y1.s(), u, self.k7.m());
        self.evaluations += 6;
        // Error estimate, scaled componentwise by atol + rtol·max(|y|, |y1|).
        let (k1, k3, k4, k5, k6, k7, y1) = (
            self.k1.s(),
            self.k3.s(),
            self.k4.s(),
            self.k5.s(),
            self.k6.s(),
            self.k7.s(),
            self.y1.s(),
        );
        let mut sum = 0.0;
        for i in 0..ys.len() {
            let e =
                h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
            let sc = self.params.atol + self.params.rtol * ys[i].abs().max(y1[i].abs());
            sum += (e / sc) * (e / sc);
        }
        Attempt {
            err: (sum / ys.len().max(1) as f64).sqrt(),
        }
    }

    /// Step-size update after an attempt with error `err` and step `h`; returns the next
    /// step size (for an accepted step: the proposal for the next step; for a rejected one:
    /// the retry size).
    #[inline]
    pub(crate) fn next_step(
        &mut self,
        err: f64,
        h: f64,
        accepted: bool,
        after_reject: bool,
    ) -> f64 {
        let expo = 0.2 - 0.75 * BETA;
        let fac11 = if err > 0.0 { err.powf(expo) } else { 0.0 };
        if accepted {
            // h_new = h · clamp(SAFETY · err^{−expo} · err_prev^{β}, FAC_MIN, FAC_MAX).
            let grow = if fac11 == 0.0 {
                FAC_MAX
            } else {
                (SAFETY * self.err_prev.powf(BETA) / fac11).clamp(FAC_MIN, FAC_MAX)
            };
            self.err_prev = err.max(1e-4);
            let mut hn = h * grow;
            if after_reject {
                hn = hn.min(h);
            }
            hn.min(self.params.h_max)
        } else if err.is_finite() {
            h * (SAFETY / fac11).clamp(FAC_MIN, 1.0)
        } else {
            // A non-finite trial state: cut hard.
            h * FAC_MIN
        }
    }

    /// Dense output at `θ ∈ [0, 1]` of the last attempted step from `y` with step `h`
    /// (valid after an accepted attempt, before `k`s are overwritten).
    pub(crate) fn dense(&self, y: &[f64], h: f64, theta: f64, out: &mut [f64]) {
        let th1 = 1.0 - theta;
        let (k1, k3, k4, k5, k6, k7, y1) = (
            self.k1.s(),
            self.k3.s(),
            self.k4.s(),
            self.k5.s(),
            self.k6.s(),
            self.k7.s(),
            self.y1.s(),
        );
        for i in 0..y.len() {
            let dy = y1[i] - y[i];
            let b = h * k1[i] - dy;
            let r4 = dy - h * k7[i] - b;
            let r5 =
                h * (D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] + D6 * k6[i] + D7 * k7[i]);
            out[i] = y[i] + theta * (dy + th1 * (b + theta * (r4 + th1 * r5)));
        }
    }
}
