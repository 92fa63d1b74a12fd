//! The classic fourth-order Runge–Kutta method (Kutta 1901), fixed step, input held over the
//! step:
//!
//! ```text
//! k₁ = f(t, x, u)            k₂ = f(t + h/2, x + h/2·k₁, u)
//! k₃ = f(t + h/2, x + h/2·k₂, u)   k₄ = f(t + h, x + h·k₃, u)
//! x⁺ = x + h/6 · (k₁ + 2k₂ + 2k₃ + k₄)
//! ```
//!
//! One stepper, `step_with`, written once over the state storage (`[f64; N]` or `Vec<f64>`)
//! and a derivative closure, serves every RK4 of the crate: [`rk4_step`] on `[f64; N]` (state
//! size known at compile time; the loops unroll, everything lives on the stack),
//! [`rk4_step_slice`] on slices with a reusable [`Rk4Work`], the integrator of
//! [`simulate`](crate::simulate), the sampled-data loop, the environment and the fixed-size
//! kernel's provided step ([`rk4_fixed`](crate::fast::rk4_fixed)). None allocates. The lane
//! kernel's [`rk4_lanes`](crate::fast::rk4_lanes) performs the same operations per lane with a
//! step size per lane, and a plant's own step (the cart's anchored step) may share work
//! between the stages; both say how close they stay to this one.

use crate::buffer::Buf;
use crate::dynamics::Dynamics;

/// Scratch of the stepper: the four stages and the stage state, in the storage `B`
/// (`[f64; N]` on the stack or `Vec<f64>`).
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

/// The classic RK4 step, written once for every state storage `B`: `f(t, x, dx)` writes the
/// derivative at `(t, x)` into `dx` (both of the storage type, so a fixed-size right-hand side
/// sees arrays); `x` is advanced from `t` to `t + h` in place. If
/// `k1_known`, `w.k1` already holds `f(t, x)` (e.g. from the previous step's end when the
/// input did not change).
///
/// The operations, in this order, are those every RK4 of the crate performs (so their results
/// agree bit for bit): the stage states `x + (h/2)·k₁`, `x + (h/2)·k₂`, `x + h·k₃` with
/// `h/2 = 0.5·h`, and the update `x + (h/6)·(((k₁ + 2k₂) + 2k₃) + k₄)`. With `B = [f64; N]`
/// every length is a compile-time constant: the loops unroll and nothing is allocated.
#[inline(always)]
pub(crate) fn step_with<B: Buf>(
    mut f: impl FnMut(f64, &B, &mut B),
    t: f64,
    x: &mut B,
    h: f64,
    w: &mut Rk4Scratch<B>,
    k1_known: bool,
) {
    let half = 0.5 * h;
    if !k1_known {
        f(t, x, &mut w.k1);
    }
    for ((xt, &xi), &k) in w.xt.m().iter_mut().zip(x.s()).zip(w.k1.s()) {
        *xt = xi + half * k;
    }
    f(t + half, &w.xt, &mut w.k2);
    for ((xt, &xi), &k) in w.xt.m().iter_mut().zip(x.s()).zip(w.k2.s()) {
        *xt = xi + half * k;
    }
    f(t + half, &w.xt, &mut w.k3);
    for ((xt, &xi), &k) in w.xt.m().iter_mut().zip(x.s()).zip(w.k3.s()) {
        *xt = xi + h * k;
    }
    f(t + h, &w.xt, &mut w.k4);
    let sixth = h / 6.0;
    let (k1, k2, k3, k4) = (w.k1.s(), w.k2.s(), w.k3.s(), w.k4.s());
    for (i, xi) in x.m().iter_mut().enumerate() {
        *xi += sixth * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
}

/// [`step_with`] for a [`Dynamics`] with the input `u` held.
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
    step_with(
        |t, x: &B, dx: &mut B| sys.derivative(t, x.s(), u, dx.m()),
        t,
        x,
        h,
        w,
        k1_known,
    );
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

/// Reusable scratch for [`rk4_step_slice`] (six state-sized vectors, allocated once).
#[derive(Debug, Clone)]
pub struct Rk4Work {
    x: Vec<f64>,
    w: Rk4Scratch<Vec<f64>>,
}

impl Rk4Work {
    /// Scratch for `nx` states.
    pub fn new(nx: usize) -> Self {
        Self {
            x: vec![0.0; nx],
            w: Rk4Scratch::new(nx),
        }
    }
    /// Number of states it serves.
    pub fn nx(&self) -> usize {
        self.x.len()
    }
}

/// One classic RK4 step on slices (state size known only at run time), allocation-free with a
/// reused [`Rk4Work`]; the operations of [`rk4_step`].
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
    // The state is stepped in the work's own vector (copies are exact).
    work.x.copy_from_slice(x);
    step_generic(sys, t, &mut work.x, u, h, &mut work.w, false);
    x.copy_from_slice(&work.x);
}
