//! The fast paths' strategy types: how a kernel evaluates `a·b + c` ([`MulAdd`]: [`Fused`],
//! [`Separate`]) and sines and cosines ([`SinCos`] for the lane kernel: [`LibmSinCos`],
//! [`PolySinCos`], [`AnchoredSinCos`]; [`Trig`] for a scalar kernel's right-hand side). Each
//! is a switch the caller passes to a fast loop (a type parameter or a value of the kernel
//! type), never a field of a physics type.

use super::trig::sin_cos_lanes;
/// How a plant's RK4 step evaluates `a·b + c` ([`FixedDynamics::rk4_step_fixed_with`](crate::fast::FixedDynamics::rk4_step_fixed_with)).
///
/// Rust never contracts `a * b + c` into a fused multiply–add, and the baseline x86-64
/// target has no FMA instruction, so a step written once and generic over this strategy is
/// compiled twice by [`FixedLoop`](crate::fast::FixedLoop): with [`Fused`] inside a function compiled for FMA and
/// chosen at run time when the processor has it, with [`Separate`] otherwise.
pub trait MulAdd {
    /// Which strategy this is.
    const PATH: MulAddPath;
    /// `a·b + c`.
    fn mul_add(a: f64, b: f64, c: f64) -> f64;
}

/// `a·b + c` rounded once ([`f64::mul_add`]): one instruction, with the latency of one
/// operation instead of two, where FMA is enabled; in code compiled without it a call to the
/// library's `fma` — correct but slow, so [`FixedLoop`](crate::fast::FixedLoop) selects it only inside its
/// FMA-compiled loop.
#[derive(Debug, Clone, Copy, Default)]
pub struct Fused;

impl MulAdd for Fused {
    const PATH: MulAddPath = MulAddPath::Fused;
    #[inline(always)]
    fn mul_add(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
}

/// `a·b + c` as a product and a sum, each rounded (what Rust evaluates for `a * b + c`).
#[derive(Debug, Clone, Copy, Default)]
pub struct Separate;

impl MulAdd for Separate {
    const PATH: MulAddPath = MulAddPath::Separate;
    #[inline(always)]
    fn mul_add(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
}

/// Which multiply–add a [`FixedLoop`](crate::fast::FixedLoop) run offers the plant's step ([`MulAdd`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MulAddPath {
    /// [`Fused`]: the loop compiled for FMA (x86-64 processors with FMA, detected at run
    /// time).
    Fused,
    /// [`Separate`]: the loop compiled for the baseline target.
    Separate,
}

/// How a lane kernel evaluates `sin` and `cos` of `L` angles.
pub trait SinCos {
    /// Whether a plant's own RK4 step ([`LaneDynamics::rk4_step_lanes`](crate::fast::LaneDynamics::rk4_step_lanes)) may take the later
    /// stages' sines from the step's first ones (see [`AnchoredSinCos`]). Default `false`.
    const ANCHORED: bool = false;
    /// `(sin x_l, cos x_l)` for every lane.
    fn sin_cos<const L: usize>(x: &[f64; L]) -> ([f64; L], [f64; L]);
}

/// [`PolySinCos`] for single evaluations, and permission for a plant's RK4 step
/// ([`LaneDynamics::rk4_step_lanes`](crate::fast::LaneDynamics::rk4_step_lanes)) to take the three later stages' sines and cosines from
/// the step's first ones by the addition theorem ([`sin_cos_offset_lanes`](crate::fast::sin_cos_offset_lanes), the lane form of
/// [`Trig::Anchored`]). Plants that do not override the step run it as [`PolySinCos`].
#[derive(Debug, Clone, Copy, Default)]
pub struct AnchoredSinCos;

impl SinCos for AnchoredSinCos {
    const ANCHORED: bool = true;
    #[inline(always)]
    fn sin_cos<const L: usize>(x: &[f64; L]) -> ([f64; L], [f64; L]) {
        sin_cos_lanes(x)
    }
}

/// The platform's `f64::sin_cos` per lane: bit-identical to scalar code, not vectorised.
#[derive(Debug, Clone, Copy, Default)]
pub struct LibmSinCos;

impl SinCos for LibmSinCos {
    #[inline(always)]
    fn sin_cos<const L: usize>(x: &[f64; L]) -> ([f64; L], [f64; L]) {
        let mut s = [0.0; L];
        let mut c = [0.0; L];
        for l in 0..L {
            (s[l], c[l]) = x[l].sin_cos();
        }
        (s, c)
    }
}

/// [`sin_cos_lanes`](crate::fast::sin_cos_lanes): branch-free and vectorisable.
#[derive(Debug, Clone, Copy, Default)]
pub struct PolySinCos;

impl SinCos for PolySinCos {
    #[inline(always)]
    fn sin_cos<const L: usize>(x: &[f64; L]) -> ([f64; L], [f64; L]) {
        sin_cos_lanes(x)
    }
}

/// Which sine/cosine a scalar right-hand side uses: an opt-in switch for plants (e.g.
/// `pendulab_plants::cart::fast::FastCart`) whose hot loops are dominated by `sin_cos`.
///
/// - [`Trig::Libm`] (the default): `f64::sin_cos`, results identical to every reference
///   computed with the platform's libm.
/// - [`Trig::Polynomial`]: [`sin_cos_lanes`](crate::fast::sin_cos_lanes) on one lane — branch-free, about half the
///   instructions of libm's `sin_cos`; within 2 ulp + 4·10⁻¹⁷·max(1, |x|) of libm for
///   `|x| ≤ 10⁵` (libm beyond, and for NaN/∞). Over one RK4 step this perturbs the state by
///   a few ulp of its derivative times the step, far below the RK4 truncation error of any
///   practical step, but results are no longer bit-identical to libm-based references.
/// - [`Trig::Anchored`]: for a plant's own RK4 step kernel (e.g. the
///   [`crate::fast::FixedDynamics::rk4_step_fixed_with`] of `pendulab_plants::cart::fast::FastCart`),
///   which shares the sines and cosines between the stages: series about zero for the angles
///   fixed by the step's start ([`sin_cos_near_zero`](crate::fast::sin_cos_near_zero)) and the addition theorem for the small
///   offsets the later stages add ([`sin_cos_offset`](crate::fast::sin_cos_offset), or [`rotate_small`](crate::fast::rotate_small) applied to the
///   stage's acceleration directly), each sine and cosine within 2 ulp + 6·10⁻¹⁷ of libm at
///   its angle, a fraction of libm's instructions and a shorter dependency chain. The cart's
///   step for `h ≤ 2⁻⁸ s` does this with fused multiply–adds where the fixed-size kernel's
///   FMA-compiled loop runs it; for longer steps (the environment's 20 ms) it takes the first
///   angle from one series up to 0.25 rad and the stage offsets up to 1/8 rad, within
///   2 ulp + 1.1·10⁻¹⁶ (`pendulab_plants::cart::fast::FastCart::ANCHORED_ANGLE_LIMIT`,
///   `ANCHORED_SHIFT_LIMIT`). A single right-hand side evaluation outside such a step (the
///   general sampled-data loop, linearisation, …) uses libm, as [`Trig::Libm`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Trig {
    /// The platform's `f64::sin_cos`.
    #[default]
    Libm,
    /// [`sin_cos_lanes`](crate::fast::sin_cos_lanes) (Cody–Waite reduction and Taylor polynomials), see the type docs.
    Polynomial,
    /// Stage angles of an RK4 step from the step's first angle, see the type docs.
    Anchored,
}

impl Trig {
    /// `(sin x, cos x)` by the selected method ([`Trig::Anchored`]: libm, as there is no
    /// anchor here).
    #[inline(always)]
    pub fn sin_cos(self, x: f64) -> (f64, f64) {
        match self {
            Trig::Libm | Trig::Anchored => x.sin_cos(),
            Trig::Polynomial => {
                let (s, c) = sin_cos_lanes(&[x]);
                (s[0], c[0])
            }
        }
    }
}
