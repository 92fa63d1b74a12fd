//! The classic fourth-order Runge–Kutta method (Kutta 1901), fixed step, input held over the
//! step:
//!
//! ```text
//! k₁ = f(t, x, u)            k₂ = f(t + h/2, x + h/2·k₁, u)
//! k₃ = f(t + h/2, x + h/2·k₂, u)   k₄ = f(t + h, x + h·k₃, u)
//! x⁺ = x + h/6 · (k₁ + 2k₂ + 2k₃ + k₄)
//! ```
//!
//! Two public kernels: [`rk4_step`] on `[f64; N]` (state size known at compile time; the loops
//! unroll, everything lives on the stack) and [`rk4_step_slice`] on slices with a reusable
//! [`Rk4Work`]. Neither allocates.

use crate::buffer::Buf;
use crate::dynamics::Dynamics;

/// Scratch of the generic kernel: the four stages and the stage state.
#[derive(Debug, Clone)]
pub(crate) struct Rk4Scratch<B: Buf> {
    pub(crate) k1: B,
    k2: B,
    k3: B,
    k4: B,
    xt: B,
}

impl<B: Buf> Rk4Scratch<B> {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            k1: B::zeros(n),
            k2: B::zeros(n),
            k3: B::zeros(n),
            k4: B::zeros(n),
            xt: B::zeros(n),
        }
    }
}

/// One RK4 step in place. If `k1_known`, `w.k1` already holds `f(t, x, u)` (e.g. from the
/// previous step's end when the input did not change).
#[inline(always)]
pub(crate) fn step_generic<S: Dynamics + ?Sized, B: Buf>(
    sys: &S,
    t: f64,
    x: &mut B,
    u: &[f64],
    h: f64,
    w: &mut Rk4Scratch<B>,
    k1_known: bool,
) {
    let half = 0.5 * h;
    if !k1_known {
        sys.derivative(t, x.s(), u, w.k1.m());
    }
    for ((xt, &xi), &k) in w.xt.m().iter_mut().zip(x.s()).zip(w.k1.s()) {
        *xt = xi + half * k;
    }
    sys.derivative(t + half, w.xt.s(), u, w.k2.m());
    for ((xt, &xi), &k) in w.xt.m().iter_mut().zip(x.s()).zip(w.k2.s()) {
        *xt = xi + half * k;
    }
    sys.derivative(t + half, w.xt.s(), u, w.k3.m());
    for ((xt, &xi), &k) in w.xt.m().iter_mut().zip(x.s()).zip(w.k3.s()) {
        *xt = xi + h * k;
    }
    sys.derivative(t + h, w.xt.s(), u, w.k4.m());
    let sixth = h / 6.0;
    let (k1, k2, k3, k4) = (w.k1.s(), w.k2.s(), w.k3.s(), w.k4.s());
    for (i, xi) in x.m().iter_mut().enumerate() {
        *xi += sixth * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
}

/// One classic RK4 step of `ẋ = f(t, x, u)` from `t` to `t + h` with the input `u` held,
/// on a state of compile-time size `N` (stack only, loops unrolled).
///
/// Preconditions: `sys.nx() == N`, `u.len() == sys.nu()`; `h` finite (may be negative).
///
/// ```
/// use pendulab_sim::{rk4_step, FnDynamics};
/// // ẋ = −x: one step of h = 0.1 gives the degree-4 Taylor polynomial of e^{−0.1}.
/// let decay = FnDynamics::new(1, 0, |_t, x: &[f64], _u: &[f64], dx: &mut [f64]| dx[0] = -x[0]);
/// let mut x = [1.0];
/// rk4_step(&decay, 0.0, &mut x, &[], 0.1);
/// let h: f64 = 0.1;
/// // Equal up to the rounding of a dozen operations on numbers ≤ 1.
/// assert!((x[0] - (1.0 - h + h * h / 2.0 - h.powi(3) / 6.0 + h.powi(4) / 24.0)).abs() < 1e-15);
/// ```
#[inline]
pub fn rk4_step<const N: usize, S: Dynamics + ?Sized>(
    sys: &S,
    t: f64,
    x: &mut [f64; N],
    u: &[f64],
    h: f64,
) {
    let mut w = Rk4Scratch::<[f64; N]>::new(N);
    step_generic(sys, t, x, u, h, &mut w, false);
}

/// Reusable scratch for [`rk4_step_slice`] (five state-sized vectors, allocated once).
#[derive(Debug, Clone)]
pub struct Rk4Work {
    k1: Vec<f64>,
    k2: Vec<f64>,
    k3: Vec<f64>,
    k4: Vec<f64>,
    xt: Vec<f64>,
}

impl Rk4Work {
    /// Scratch for `nx` states.
    pub fn new(nx: usize) -> Self {
        Self {
            k1: vec![0.0; nx],
            k2: vec![0.0; nx],
            k3: vec![0.0; nx],
            k4: vec![0.0; nx],
            xt: vec![0.0; nx],
        }
    }
    /// Number of states it serves.
    pub fn nx(&self) -> usize {
        self.k1.len()
    }
}

/// One classic RK4 step on slices (state size known only at run time), allocation-free with a
/// reused [`Rk4Work`].
///
/// Preconditions: `x.len() == sys.nx() == work.nx()`, `u.len() == sys.nu()`.
#[inline]
pub fn rk4_step_slice<S: Dynamics + ?Sized>(
    sys: &S,
    t: f64,
    x: &mut [f64],
    u: &[f64],
    h: f64,
    work: &mut Rk4Work,
) {
    debug_assert_eq!(x.len(), work.nx());
    let half = 0.5 * h;
    let Rk4Work { k1, k2, k3, k4, xt } = work;
    sys.derivative(t, x, u, k1);
    for i in 0..x.len() {
        xt[i] = x[i] + half * k1[i];
    }
    sys.derivative(t + half, xt, u, k2);
    for i in 0..x.len() {
        xt[i] = x[i] + half * k2[i];
    }
    sys.derivative(t + half, xt, u, k3);
    for i in 0..x.len() {
        xt[i] = x[i] + h * k3[i];
    }
    sys.derivative(t + h, xt, u, k4);
    let sixth = h / 6.0;
    for i in 0..x.len() {
        x[i] += sixth * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
}
