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

// The Butcher tableau of RK5(4)7M, one row a line (Dormand–Prince 1980): the nodes `c₂…c₅`
// (`c₆ = c₇ = 1`); the rows `a₂…a₆` of `A` (`a₇ = b`: first same as last); the 5th-order
// weights `b` (`W`: `b₁, b₃…b₆`, as `b₂ = b₇ = 0`); the error weights `e = b − b̂` (`b̂` the
// embedded 4th-order weights; `e₁, e₃…e₇`, as `e₂ = 0`); the continuous extension's `d`
// (Hairer–Nørsett–Wanner §II.6, Shampine's 4th-order interpolant; `d₁, d₃…d₇`, as `d₂ = 0`).
#[rustfmt::skip]
mod tableau {
    pub(super) const C: [f64; 4] = [1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0];
    pub(super) const A2: [f64; 1] = [1.0 / 5.0];
    pub(super) const A3: [f64; 2] = [3.0 / 40.0, 9.0 / 40.0];
    pub(super) const A4: [f64; 3] = [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0];
    pub(super) const A5: [f64; 4] = [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0];
    pub(super) const A6: [f64; 5] = [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0];
    pub(super) const W: [f64; 5] = [35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0];
    pub(super) const E: [f64; 6] = [71.0 / 57600.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0];
    pub(super) const D: [f64; 6] = [-12715105075.0 / 11282082432.0, 87487479700.0 / 32700410799.0, -10690763975.0 / 1880347072.0, 701980252875.0 / 199316789632.0, -1453857185.0 / 822651844.0, 69997945.0 / 29380423.0];
}
use tableau::{A2, A3, A4, A5, A6, C, D, E, W};

/// `Σⱼ wⱼ vⱼ`, summed left to right (the order of a tableau row).
#[inline(always)]
fn dot<const N: usize>(w: &[f64; N], v: [f64; N]) -> f64 {
    let mut s = w[0] * v[0];
    for j in 1..N {
        s += w[j] * v[j];
    }
    s
}

/// `out = y + h·Σⱼ wⱼ kⱼ` componentwise: a stage's argument or the 5th-order solution.
#[inline(always)]
fn combine<const N: usize>(out: &mut [f64], y: &[f64], h: f64, w: &[f64; N], k: [&[f64]; N]) {
    for (i, o) in out.iter_mut().enumerate() {
        *o = y[i] + h * dot(w, k.map(|k| k[i]));
    }
}

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

    /// The stages the error estimate and the dense output weigh: `k₁, k₃…k₇` (`e₂ = d₂ = 0`).
    fn weighted_stages(&self) -> [&[f64]; 6] {
        let (k1, k3, k4, k5, k6, k7) = (&self.k1, &self.k3, &self.k4, &self.k5, &self.k6, &self.k7);
        [k1.s(), k3.s(), k4.s(), k5.s(), k6.s(), k7.s()]
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
        let Self {
            k1,
            k2,
            k3,
            k4,
            k5,
            k6,
            k7,
            y1,
            yt,
            ..
        } = self;
        combine(yt.m(), ys, h, &A2, [k1.s()]);
        sys.derivative(t + C[0] * h, yt.s(), u, k2.m());
        combine(yt.m(), ys, h, &A3, [k1.s(), k2.s()]);
        sys.derivative(t + C[1] * h, yt.s(), u, k3.m());
        combine(yt.m(), ys, h, &A4, [k1.s(), k2.s(), k3.s()]);
        sys.derivative(t + C[2] * h, yt.s(), u, k4.m());
        combine(yt.m(), ys, h, &A5, [k1.s(), k2.s(), k3.s(), k4.s()]);
        sys.derivative(t + C[3] * h, yt.s(), u, k5.m());
        combine(yt.m(), ys, h, &A6, [k1.s(), k2.s(), k3.s(), k4.s(), k5.s()]);
        sys.derivative(t + h, yt.s(), u, k6.m());
        combine(y1.m(), ys, h, &W, [k1.s(), k3.s(), k4.s(), k5.s(), k6.s()]);
        sys.derivative(t + h, y1.s(), u, k7.m());
        self.evaluations += 6;
        // Error estimate, scaled componentwise by atol + rtol·max(|y|, |y1|).
        let (k, y1) = (self.weighted_stages(), self.y1.s());
        let mut sum = 0.0;
        for i in 0..ys.len() {
            let e = h * dot(&E, k.map(|k| k[i]));
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
        let (k, y1) = (self.weighted_stages(), self.y1.s());
        for i in 0..y.len() {
            let dy = y1[i] - y[i];
            let b = h * k[0][i] - dy;
            let r4 = dy - h * k[5][i] - b;
            let r5 = h * dot(&D, k.map(|k| k[i]));
            out[i] = y[i] + theta * (dy + th1 * (b + theta * (r4 + th1 * r5)));
        }
    }
}
