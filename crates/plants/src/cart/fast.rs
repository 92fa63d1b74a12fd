//! The cart pendulum on `pendulab_sim`'s fast paths ([`pendulab_sim::fast`]): its fixed-size
//! and lane kernels' right-hand sides and RK4 steps, and [`FastCart`], the kernel type that
//! carries a sine/cosine strategy ([`Trig`]) beside the physics.
//!
//! [`CartPendulum`] itself is physics: it evaluates `sin θ, cos θ` by libm everywhere, and on
//! the fast paths it takes the provided steps, which reproduce the general loop bit for bit
//! (`SampledLoop::fixed`, `FixedEnv`, the lane kernel with `LibmSinCos`). A faster sine and
//! cosine is chosen by a switch passed to the fast loop, never stored in the plant:
//!
//! - the lane kernel's strategy type ([`pendulab_sim::fast::SinCos`]): with
//!   [`AnchoredSinCos`](pendulab_sim::fast::AnchoredSinCos) the plant's lane step takes the
//!   later stages' sines from the step's first ones (`lanes.rs`);
//! - a [`FastCart`] (the plant and a [`Trig`]) in place of the plant, for the fixed-size loop
//!   ([`FixedLoop`](pendulab_sim::fast::FixedLoop)), the fixed-size environment
//!   ([`FixedEnv`](pendulab_sim::env::FixedEnv)) or any general loop: [`Trig::Polynomial`]
//!   changes its right-hand side, [`Trig::Anchored`] its RK4 step on the fast paths
//!   (`anchored.rs`).
//!
//! Neighbours: `anchored.rs` holds the anchored-trig RK4 step for one state, `lanes.rs` the
//! same for several states at once, `tests.rs` checks both against libm.

use super::CartPendulum;
use pendulab_sim::Dynamics;
pub use pendulab_sim::fast::Trig;
use pendulab_sim::fast::{FixedDynamics, FixedStep, MulAdd, StepVisitor};

mod anchored;
mod lanes;
#[cfg(test)]
mod tests;

/// The cart pendulum with a sine/cosine strategy for its hot loops: a kernel type to pass to
/// a loop in place of the [`CartPendulum`].
///
/// - [`Trig::Libm`]: the plant's own arithmetic, bit for bit.
/// - [`Trig::Polynomial`]: the right-hand side ([`FastCart::derivative_array`], the
///   [`Dynamics`] implementation and the fixed-size kernel's) evaluates `sin θ, cos θ` by
///   [`pendulab_sim::fast::sin_cos_lanes`] on one lane: every sine and cosine within
///   2 ulp + 4·10⁻¹⁷·max(1, |θ|) of libm for `|θ| ≤ 10⁵` (libm beyond), so `θ̈` differs from
///   the libm plant's by a few ulp of its terms; simulations are then not bit-identical to
///   libm-based references.
/// - [`Trig::Anchored`]: only the RK4 step of the fixed-size closed-loop kernel
///   ([`FixedLoop`](pendulab_sim::fast::FixedLoop), e.g. from `SampledLoop::fixed`) and of
///   [`FixedEnv`](pendulab_sim::env::FixedEnv) changes: the stages share their sines and
///   cosines — series near upright (within [`FastCart::ANCHORED_ANGLE_LIMIT`]) for the angles
///   fixed by the step's start, the addition theorem for what the later stages add — each
///   within 2 ulp + 6·10⁻¹⁷ of libm for steps of at most 2⁻⁸ s (whose step uses fused
///   multiply–adds where the kernel's FMA-compiled loop runs it), 2 ulp + 1.1·10⁻¹⁶ for
///   longer ones, with the pendulum's constants divided by `J` beforehand. Every other
///   evaluation (a single right-hand side, the general loop) uses libm.
///
/// Jacobians, linearisations, energy and geometry are the plant's ([`FastCart::plant`]),
/// always with libm.
///
/// ```
/// use pendulab_plants::CartPendulum;
/// use pendulab_plants::cart::fast::{FastCart, Trig};
/// use pendulab_sim::env::FixedEnv;
/// use pendulab_sim::EnvConfig;
/// # fn main() -> Result<(), pendulab_sim::SimError> {
/// let plant = CartPendulum::book();
/// // The same environment twice: libm at every stage, and the anchored step.
/// let config = EnvConfig::cart_pole(0.4)?;
/// let mut exact = FixedEnv::<_, 4>::new(plant, config.clone())?;
/// let mut fast = FixedEnv::<_, 4>::new(FastCart::new(plant, Trig::Anchored), config)?;
/// assert_eq!(exact.reset(Some(7)), fast.reset(Some(7)));
/// let (a, b) = (exact.step(2.0)?, fast.step(2.0)?);
/// assert!((0..4).all(|i| (a.obs[i] - b.obs[i]).abs() < 1e-14));
/// # Ok(()) }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FastCart {
    plant: CartPendulum,
    trig: Trig,
}

impl FastCart {
    /// [`Trig::Anchored`]: the largest `|θ|` \[rad\] at the start of an RK4 step whose sine and
    /// cosine come from a series (beyond it: libm). The CartPole-v1 environment's angles,
    /// |θ| ≤ 12° = 0.21 rad, lie within it.
    pub const ANCHORED_ANGLE_LIMIT: f64 = 0.25;

    /// [`Trig::Anchored`]: the largest stage offset `|d|` \[rad\] (`(h/2)·θ̇` or `h·θ̇`) whose
    /// sine and cosine come from the step's first ones by the addition theorem (beyond it:
    /// libm at the stage angle). A step of `h = 20 ms` stays within it up to |θ̇| = 6.25 rad/s.
    pub const ANCHORED_SHIFT_LIMIT: f64 = 0.125;

    /// `plant` with its hot loops' sines and cosines by `trig` (see the type docs).
    pub fn new(plant: CartPendulum, trig: Trig) -> Self {
        Self { plant, trig }
    }

    /// The plant (physics, libm).
    pub fn plant(&self) -> &CartPendulum {
        &self.plant
    }

    /// The sine/cosine strategy.
    pub fn trig(&self) -> Trig {
        self.trig
    }

    /// `ẋ = f(x, v)` as [`CartPendulum::derivative_array`], with `sin θ, cos θ` by
    /// [`Trig::sin_cos`] ([`Trig::Anchored`]: libm, as there is no anchor here).
    #[inline(always)]
    pub fn derivative_array(&self, x: &[f64; 4], v: f64) -> [f64; 4] {
        self.plant.derivative_with(x, v, self.trig.sin_cos(x[1]))
    }
}

impl Dynamics for FastCart {
    fn nx(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    // Forced inline, as the plant's (the RK4 stages then see the arithmetic).
    #[inline(always)]
    fn derivative(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        debug_assert!(x.len() == 4 && u.len() == 1 && dx.len() == 4);
        let f = self.derivative_array(&[x[0], x[1], x[2], x[3]], u[0]);
        dx[..4].copy_from_slice(&f);
    }
}

/// The fixed-size kernel's right-hand side: the operations of
/// [`CartPendulum::derivative_array`] (which the [`Dynamics`] implementation also evaluates),
/// with the provided RK4 step, so the kernel reproduces the general loop bit for bit.
impl FixedDynamics<4> for CartPendulum {
    #[inline(always)]
    fn derivative_fixed(&self, x: &[f64; 4], u: f64) -> [f64; 4] {
        self.derivative_array(x, u)
    }
}

/// The fixed-size kernel's right-hand side with the strategy's sines and cosines
/// ([`FastCart::derivative_array`]), and, with [`Trig::Anchored`], the anchored RK4 step
/// (`anchored.rs`): for steps of at most 2⁻⁸ s (the 1 ms loops) the narrow step, written once
/// for both multiply–adds of [`FixedDynamics::rk4_step_fixed_with`] (the kernel's
/// FMA-compiled loop takes it with fused multiply–adds); for longer steps (the 20 ms of the
/// CartPole-v1 environment) the wide step with separate multiplications and additions.
impl FixedDynamics<4> for FastCart {
    #[inline(always)]
    fn derivative_fixed(&self, x: &[f64; 4], u: f64) -> [f64; 4] {
        self.derivative_array(x, u)
    }

    /// The operations of [`pendulab_sim::fast::rk4_fixed`], the sines and cosines aside;
    /// with [`Trig::Anchored`] the anchored step with separate multiplications and additions.
    #[inline(always)]
    fn rk4_step_fixed(&self, x: &mut [f64; 4], u: f64, h: f64) {
        self.rk4_step_fixed_with::<pendulab_sim::fast::Separate>(x, u, h);
    }

    /// As [`FixedDynamics::rk4_step_fixed`]; with [`Trig::Anchored`] and steps of at most
    /// 2⁻⁸ s, the multiply–adds of the anchored step by `F`.
    #[inline(always)]
    fn rk4_step_fixed_with<F: MulAdd>(&self, x: &mut [f64; 4], u: f64, h: f64) {
        if self.trig != Trig::Anchored {
            return self.plain_step(x, u, h);
        }
        anchored::step::<F>(&self.plant, x, u, h);
    }

    /// The step chosen once for a whole run: with [`Trig::Anchored`] a stepper that takes
    /// only the anchored step, otherwise one that takes only the provided step
    /// ([`pendulab_sim::fast::rk4_fixed`] on [`FastCart::derivative_array`]); each the steps
    /// of [`FixedDynamics::rk4_step_fixed_with`] for that strategy, without its branch.
    #[inline(always)]
    fn visit_stepper<V: StepVisitor<4>>(&self, visitor: V) -> V::Output {
        match self.trig {
            Trig::Anchored => visitor.visit(&AnchoredStep(self.plant)),
            Trig::Libm | Trig::Polynomial => visitor.visit(&PlainStep(self)),
        }
    }
}

/// [`FastCart`]'s stepper for [`Trig::Anchored`]: the anchored RK4 step (`anchored.rs`).
struct AnchoredStep(CartPendulum);

impl FixedStep<4> for AnchoredStep {
    #[inline(always)]
    fn step<F: MulAdd>(&self, x: &mut [f64; 4], u: f64, h: f64) {
        anchored::step::<F>(&self.0, x, u, h);
    }
}

/// [`FastCart`]'s stepper for [`Trig::Libm`] and [`Trig::Polynomial`]: the provided RK4 step
/// ([`pendulab_sim::fast::rk4_fixed`]) on the kernel's right-hand side.
struct PlainStep<'a>(&'a FastCart);

impl FixedStep<4> for PlainStep<'_> {
    #[inline(always)]
    fn step<F: MulAdd>(&self, x: &mut [f64; 4], u: f64, h: f64) {
        pendulab_sim::fast::rk4_fixed(self.0, x, u, h);
    }
}

impl FastCart {
    /// The provided step ([`pendulab_sim::fast::rk4_fixed`]) for [`Trig::Libm`] and
    /// [`Trig::Polynomial`], kept out of line so that the loop around the anchored step
    /// stays as compact as with a plant that has only that step.
    #[cold]
    #[inline(never)]
    fn plain_step(&self, x: &mut [f64; 4], u: f64, h: f64) {
        pendulab_sim::fast::rk4_fixed(self, x, u, h);
    }
}
