//! Lane-batched sampled-data runs: `L` closed loops stepped together in
//! structure-of-arrays form (`x[i][l]` is state `i` of lane `l`), so the compiler turns the
//! per-lane arithmetic into SIMD instructions.
//!
//! The special case served here is the one batch studies need most: a single-input plant
//! under static state feedback `u = −K x` from the exact state, sampled every `ts` with
//! zero-order hold, RK4 substeps, and an optional "stay within `|x_i| ≤ bound`" stop — the
//! [`SampledLoop`](crate::SampledLoop) with [`StaticStateFeedback`](crate::controllers::StaticStateFeedback),
//! the full-state sensor, the ideal actuator and a [`StayWithin`](crate::StayWithin)
//! monitor. A lane whose run ends (bound crossed or all samples run) is refilled at once with
//! the next initial state of its queue, so the lanes stay busy; the plant must therefore be
//! autonomous (its right-hand side may not depend on `t`).
//!
//! Results: per initial state the same [`LaneOutcome`] as the general loop reports (held,
//! RK4 steps integrated, final state). With [`LibmSinCos`] every arithmetic operation is the
//! general loop's, in the same order, so outcomes and final states are **bit-identical** to
//! [`SampledLoop::run_with`](crate::SampledLoop::run_with) of the same configuration (the
//! plant implementation must mirror its scalar right-hand side operation by operation, as
//! `pendulab_plants::CartPendulum` does). With [`PolySinCos`] the sines and cosines come
//! from [`sin_cos_lanes`] (vectorisable; within about 2 ulp of libm, see there), so
//! states differ from the general loop by rounding-level amounts that the closed loop's
//! stable dynamics keep small; runs that end near the bound can in principle end one sample
//! apart.
//!
//! ```
//! use pendulab_sim::lanes::{LaneDynamics, LaneOptions, SinCos, run_feedback_lanes, LibmSinCos};
//! # fn main() -> Result<(), pendulab_sim::SimError> {
//! // ẋ = [x₁, u]: a double integrator under u = −(x₀ + 2x₁), four lanes.
//! struct DoubleIntegrator;
//! impl<const L: usize> LaneDynamics<2, L> for DoubleIntegrator {
//!     fn derivative_lanes<M: SinCos>(&self, x: &[[f64; L]; 2], u: &[f64; L]) -> [[f64; L]; 2] {
//!         [x[1], *u]
//!     }
//! }
//! let o = LaneOptions { ts: 1e-2, t_final: 10.0, substeps: 1, stay_within: None };
//! let out = run_feedback_lanes::<_, LibmSinCos, 2, 4>(
//!     &DoubleIntegrator, &[1.0, 2.0], &o, &[[1.0, 0.0], [0.0, 1.0]])?;
//! assert_eq!(out.len(), 2);
//! assert!(out.iter().all(|o| o.held && o.steps == 1000 && o.final_state[0].abs() < 1e-3));
//! # Ok(()) }
//! ```

use crate::error::{Result, SimError, check_finite};
use crate::fixed::MulAdd;
use rayon::prelude::*;
use std::f64::consts::FRAC_2_PI;

/// How a lane kernel evaluates `sin` and `cos` of `L` angles.
pub trait SinCos {
    /// Whether a plant's own RK4 step ([`LaneDynamics::rk4_step_lanes`]) may take the later
    /// stages' sines from the step's first ones (see [`AnchoredSinCos`]). Default `false`.
    const ANCHORED: bool = false;
    /// `(sin x_l, cos x_l)` for every lane.
    fn sin_cos<const L: usize>(x: &[f64; L]) -> ([f64; L], [f64; L]);
}

/// [`PolySinCos`] for single evaluations, and permission for a plant's RK4 step
/// ([`LaneDynamics::rk4_step_lanes`]) to take the three later stages' sines and cosines from
/// the step's first ones by the addition theorem ([`sin_cos_offset_lanes`], the lane form of
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

/// [`sin_cos_lanes`]: branch-free and vectorisable.
#[derive(Debug, Clone, Copy, Default)]
pub struct PolySinCos;

impl SinCos for PolySinCos {
    #[inline(always)]
    fn sin_cos<const L: usize>(x: &[f64; L]) -> ([f64; L], [f64; L]) {
        sin_cos_lanes(x)
    }
}

/// `π/2` split for Cody–Waite reduction (Cody & Waite 1980, *Software Manual for the
/// Elementary Functions*, ch. 8): `P1` and `P2` carry 33 significant bits each, so `n·P1` and
/// `n·P2` are exact for `|n| < 2²⁰`; `P3` is the rest, `P1 + P2 + P3 = π/2` to ~2⁻¹²⁰.
const PIO2_1: f64 = f64::from_bits(0x3FF9_21FB_5440_0000); // 0x1.921fb544p+0
const PIO2_2: f64 = f64::from_bits(0x3DD0_B461_1A60_0000); // 0x1.0b4611a6p-34
const PIO2_3: f64 = f64::from_bits(0x3BB3_198A_2E03_7073); // 0x1.3198a2e037073p-69
/// `1.5·2⁵²`: adding it rounds a number of magnitude < 2⁵¹ to an integer, which then sits in
/// the low bits of the sum's significand.
const ROUND_SHIFT: f64 = 6_755_399_441_055_744.0;
/// Beyond this `|x|` the reduction is no longer exact and libm takes over.
const POLY_LIMIT: f64 = 1.0e5;

/// `sin` and `cos` of `L` angles at once, branch-free except for a rare fallback.
///
/// Algorithm: `n = round(x·2/π)` (by the `1.5·2⁵²` shift; its low significand bits give the
/// quadrant `n mod 4`), Cody–Waite reduction `r = x − n·π/2` with a three-part `π/2`, then the
/// Taylor polynomials of `sin r` (to `r¹⁷`) and `cos r` (to `r¹⁸`) on `|r| ≲ π/4` (truncation
/// below 10⁻¹⁹), evaluated by Estrin's scheme, and the quadrant applied by swapping and sign
/// flips on the bit patterns. Error against libm: at most 2 ulp + 4·10⁻¹⁷·max(1, |x|) for
/// `|x| ≤ 10⁵` (the second term is the rounding of the reduced argument, which is the result
/// near the zeros of sin and cos); checked on [−20, 20] in steps of 10⁻⁴, at the quadrant
/// boundaries `kπ/4` and their neighbours, and at points up to 10⁵ (`tests/lanes.rs`).
/// Larger `|x|` (and NaN/∞) fall back to `f64::sin_cos`.
#[inline(always)]
pub fn sin_cos_lanes<const L: usize>(x: &[f64; L]) -> ([f64; L], [f64; L]) {
    const S: [f64; 8] = [
        -1.0 / 6.0,
        1.0 / 120.0,
        -1.0 / 5040.0,
        1.0 / 362_880.0,
        -1.0 / 39_916_800.0,
        1.0 / 6_227_020_800.0,
        -1.0 / 1_307_674_368_000.0,
        1.0 / 355_687_428_096_000.0,
    ];
    const C: [f64; 8] = [
        1.0 / 24.0,
        -1.0 / 720.0,
        1.0 / 40_320.0,
        -1.0 / 3_628_800.0,
        1.0 / 479_001_600.0,
        -1.0 / 87_178_291_200.0,
        1.0 / 20_922_789_888_000.0,
        -1.0 / 6_402_373_705_728_000.0,
    ];
    let mut s = [0.0; L];
    let mut c = [0.0; L];
    let mut wide = false;
    for l in 0..L {
        let xi = x[l];
        let shifted = xi * FRAC_2_PI + ROUND_SHIFT;
        let q = shifted.to_bits();
        let n = shifted - ROUND_SHIFT;
        let r = ((xi - n * PIO2_1) - n * PIO2_2) - n * PIO2_3;
        let r2 = r * r;
        let r4 = r2 * r2;
        let r8 = r4 * r4;
        // Estrin's scheme (Estrin 1960): three levels of independent products instead of
        // Horner's seven, so the latency of one call (what a scalar RK4 stage waits for)
        // roughly halves; the extra rounding stays in `ps`, `pc`, which are scaled by r³, r⁴.
        let ps = ((S[0] + S[1] * r2) + (S[2] + S[3] * r2) * r4)
            + ((S[4] + S[5] * r2) + (S[6] + S[7] * r2) * r4) * r8;
        let pc = ((C[0] + C[1] * r2) + (C[2] + C[3] * r2) * r4)
            + ((C[4] + C[5] * r2) + (C[6] + C[7] * r2) * r4) * r8;
        let sr = r + r * r2 * ps;
        let cr = (1.0 - 0.5 * r2) + r2 * r2 * pc;
        // Quadrant n mod 4: 0 (s, c), 1 (c, −s), 2 (−s, −c), 3 (−c, s).
        let swap = 0u64.wrapping_sub(q & 1);
        let (sb, cb) = (sr.to_bits(), cr.to_bits());
        let sv = (sb & !swap) | (cb & swap);
        let cv = (cb & !swap) | (sb & swap);
        s[l] = f64::from_bits(sv ^ (((q >> 1) & 1) << 63));
        c[l] = f64::from_bits(cv ^ ((q.wrapping_add(1) >> 1) & 1) << 63);
        wide |= xi.abs() > POLY_LIMIT || xi.is_nan();
    }
    if wide {
        for l in 0..L {
            if x[l].abs() > POLY_LIMIT || x[l].is_nan() {
                (s[l], c[l]) = x[l].sin_cos();
            }
        }
    }
    (s, c)
}

/// Which sine/cosine a scalar right-hand side uses: an opt-in switch for plants (e.g.
/// `pendulab_plants::CartPendulum::with_trig`) whose hot loops are dominated by `sin_cos`.
///
/// - [`Trig::Libm`] (the default): `f64::sin_cos`, results identical to every reference
///   computed with the platform's libm.
/// - [`Trig::Polynomial`]: [`sin_cos_lanes`] on one lane — branch-free, about half the
///   instructions of libm's `sin_cos`; within 2 ulp + 4·10⁻¹⁷·max(1, |x|) of libm for
///   `|x| ≤ 10⁵` (libm beyond, and for NaN/∞). Over one RK4 step this perturbs the state by
///   a few ulp of its derivative times the step, far below the RK4 truncation error of any
///   practical step, but results are no longer bit-identical to libm-based references.
/// - [`Trig::Anchored`]: for a plant's own RK4 step kernel (e.g. the
///   [`crate::fixed::FixedDynamics::rk4_step_fixed_with`] of `pendulab_plants::CartPendulum`),
///   which shares the sines and cosines between the stages: series about zero for the angles
///   fixed by the step's start ([`sin_cos_near_zero`]) and the addition theorem for the small
///   offsets the later stages add ([`sin_cos_offset`], or [`rotate_small`] applied to the
///   stage's acceleration directly), each sine and cosine within 2 ulp + 6·10⁻¹⁷ of libm at
///   its angle, a fraction of libm's instructions and a shorter dependency chain. The cart's
///   step for `h ≤ 2⁻⁸ s` does this with fused multiply–adds where the fixed-size kernel's
///   FMA-compiled loop runs it; for longer steps (the environment's 20 ms) it takes the first
///   angle from one series up to 0.25 rad and the stage offsets up to 1/8 rad, within
///   2 ulp + 1.1·10⁻¹⁶ (`pendulab_plants::CartPendulum::ANCHORED_ANGLE_LIMIT`,
///   `ANCHORED_SHIFT_LIMIT`). A single right-hand side evaluation outside such a step (the
///   general sampled-data loop, linearisation, …) uses libm, as [`Trig::Libm`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Trig {
    /// The platform's `f64::sin_cos`.
    #[default]
    Libm,
    /// [`sin_cos_lanes`] (Cody–Waite reduction and Taylor polynomials), see the type docs.
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

/// Largest `|x − a|` [`sin_cos_shifted`] serves by its series (beyond it: libm).
pub const SHIFT_LIMIT: f64 = 1.0 / 32.0;

/// `(sin x, cos x)` from `(s, c) = (sin a, cos a)` of a nearby anchor `a`: with `d = x − a`
/// (computed in floating point), if `|d| ≤` [`SHIFT_LIMIT`],
///
/// ```text
/// sin x = s + (s·(cos d − 1) + c·sin d),   cos x = c + (c·(cos d − 1) − s·sin d),
/// sin d = d + d³·(−1/3! + d²/5! − d⁴/7!),   cos d − 1 = d²·(−1/2! + d²/4! − d⁴/6!),
/// ```
///
/// (the addition theorem, with the Taylor series truncated: for `|d| ≤ 1/32` the first
/// omitted terms are `d⁹/9! < 3·10⁻¹⁸·|d|` and `d⁸/8! < 3·10⁻¹⁷`); otherwise libm's
/// `x.sin_cos()`. The correction term is at most `|d| ≤ 1/32` in size, so the truncation, its
/// roundings (a few times 2⁻⁵³/32) and the error of `s, c` (libm, < 1 ulp) give a result
/// within 2 ulp + 6·10⁻¹⁷ of libm's `sin x`, `cos x` (`d` itself is exact when `x` and `a`
/// are within a factor 2 of each other — Sterbenz's lemma — and otherwise off by at most half
/// an ulp of `x`); checked over random anchors and shifts in `tests/trig_shift.rs`.
/// About 20 floating-point operations against libm's ~90 instructions.
#[inline(always)]
pub fn sin_cos_shifted(x: f64, a: f64, s: f64, c: f64) -> (f64, f64) {
    let d = x - a;
    // False for NaN (a non-finite x or a), which goes to libm as well.
    let in_range = d.abs() <= SHIFT_LIMIT;
    if !in_range {
        return x.sin_cos();
    }
    let (sd, cm1) = small_angle_series(d);
    (s + (s * cm1 + c * sd), c + (c * cm1 - s * sd))
}

/// Below this `|d|` (`2⁻⁸`) the series drop their `d⁷` and `d⁶` terms ([`short_angle_series`]).
const SHORT_SHIFT_LIMIT: f64 = 1.0 / 256.0;

/// `(sin(a + d), cos(a + d))` from `(s, c) = (sin a, cos a)` and the offset `d` itself
/// (not recovered from a rounded `a + d`): the formulas of [`sin_cos_shifted`] for
/// `|d| ≤` [`SHIFT_LIMIT`] (with shorter series for `|d| ≤ 2⁻⁸`), libm's
/// `(a + d).sin_cos()` otherwise and for NaN.
///
/// This is the sine of the exact sum `a + d`, where [`sin_cos_shifted`] takes the sine of
/// the rounded `x = fl(a + d)`: the two differ by at most half an ulp of `x` times `|cos|`
/// (`|sin|`). The error bound is that of [`sin_cos_shifted`], 2 ulp + 6·10⁻¹⁷, against
/// `sin(a + d)` (checked in `tests/trig_shift.rs` against libm at `fl(a + d)` corrected to
/// first order by the rounding error of the sum). For an RK4 stage angle `θ + c·h·θ̇` this
/// is the stage's exact angle, without the round trip `(θ + δ) − θ` on the step's
/// dependency chain.
#[inline(always)]
pub fn sin_cos_offset(a: f64, d: f64, s: f64, c: f64) -> (f64, f64) {
    let m = d.abs();
    // False for NaN, which goes to libm as well.
    let in_range = m <= SHIFT_LIMIT;
    if !in_range {
        return (a + d).sin_cos();
    }
    let (sd, cm1) = if m <= SHORT_SHIFT_LIMIT {
        short_angle_series(d)
    } else {
        small_angle_series(d)
    };
    (s + (s * cm1 + c * sd), c + (c * cm1 - s * sd))
}

/// `(sin x, cos x)` for `|x| ≤` [`SHIFT_LIMIT`] by the series of [`sin_cos_shifted`] about
/// the exact anchor 0 (`sin x = x + x³·(…)`, `cos x = 1 + x²·(…)`; without the `x⁷` and
/// `x⁶` terms for `|x| ≤ 2⁻⁸`, where they are below 5·10⁻¹⁸), within 2 ulp + 6·10⁻¹⁷
/// of libm (checked in `tests/trig_shift.rs`); libm's `x.sin_cos()` for larger `|x|` and NaN.
/// About 15 floating-point operations and a short dependency chain: the step-start angle of
/// [`Trig::Anchored`] near the upright (or any) zero angle.
#[inline(always)]
pub fn sin_cos_small(x: f64) -> (f64, f64) {
    let m = x.abs();
    if m <= SHORT_SHIFT_LIMIT {
        let (sx, cm1) = short_angle_series(x);
        return (sx, 1.0 + cm1);
    }
    let in_range = m <= SHIFT_LIMIT;
    if !in_range {
        return x.sin_cos();
    }
    let (sx, cm1) = small_angle_series(x);
    (sx, 1.0 + cm1)
}

/// `(sin d, cos d − 1)` by their Taylor series to `d⁵` and `d⁴`, for `|d| ≤ 2⁻⁸`, where
/// the omitted terms are below `2⁻⁴⁸·|d|/7! < 7·10⁻¹⁹·|d|` and `2⁻⁴⁸/6! < 5·10⁻¹⁸` (inside
/// the 6·10⁻¹⁷ of the bound of [`sin_cos_shifted`]).
#[inline(always)]
fn short_angle_series(d: f64) -> (f64, f64) {
    const S1: f64 = -1.0 / 6.0;
    const S2: f64 = 1.0 / 120.0;
    const C1: f64 = -0.5;
    const C2: f64 = 1.0 / 24.0;
    let z = d * d;
    (d + (d * z) * (S1 + S2 * z), z * (C1 + C2 * z))
}

/// `(sin d, cos d − 1)` by their Taylor series to `d⁷` and `d⁶` for `|d| ≤ 1/32` (see
/// [`sin_cos_shifted`] for the truncation).
#[inline(always)]
fn small_angle_series(d: f64) -> (f64, f64) {
    const S1: f64 = -1.0 / 6.0;
    const S2: f64 = 1.0 / 120.0;
    const S3: f64 = -1.0 / 5040.0;
    const C1: f64 = -0.5;
    const C2: f64 = 1.0 / 24.0;
    const C3: f64 = -1.0 / 720.0;
    let z = d * d;
    let z2 = z * z;
    let sd = d + (d * z) * ((S1 + S2 * z) + S3 * z2);
    let cm1 = z * ((C1 + C2 * z) + C3 * z2);
    (sd, cm1)
}

/// Largest `|x|` [`sin_cos_near_zero`] serves by a series (beyond it: libm).
pub const NEAR_ZERO_LIMIT: f64 = 0.25;

/// Taylor coefficients of the sine: `sin x = x + x·z·Σ_k SIN_TAYLOR[k]·z^k` with `z = x²`,
/// `SIN_TAYLOR[k] = (−1)^{k+1}/(2k+3)!` (to `x¹¹`).
pub const SIN_TAYLOR: [f64; 5] = [
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5040.0,
    1.0 / 362_880.0,
    -1.0 / 39_916_800.0,
];

/// Taylor coefficients of the cosine: `cos x = 1 + z·Σ_k COS_TAYLOR[k]·z^k` with `z = x²`,
/// `COS_TAYLOR[k] = (−1)^{k+1}/(2k+2)!` (to `x¹²`).
pub const COS_TAYLOR: [f64; 6] = [
    -0.5,
    1.0 / 24.0,
    -1.0 / 720.0,
    1.0 / 40_320.0,
    -1.0 / 3_628_800.0,
    1.0 / 479_001_600.0,
];

/// `(sin x, cos x)` by Taylor series about the exact anchor 0, in three tiers by `|x|`, with
/// the multiply–adds of `F` (Taylor's series; the tiers as [`sin_cos_small`] plus a wider one):
///
/// ```text
/// |x| ≤ 2⁻⁸:  sin x = x + x·z·(−1/3! + z/5!),                 cos x = 1 + z·(−1/2! + z/4!)
/// |x| ≤ 1/32: sin x = x + x·z·((−1/3! + z/5!) − z²/7!),        cos x = 1 + z·((−1/2! + z/4!) − z²/6!)
/// |x| ≤ 1/4:  sin x = x + x·z·P(z) to x¹¹, cos x = 1 + z·Q(z) to x¹² (Estrin's pairing)
/// ```
///
/// (`z = x²`), libm's `x.sin_cos()` beyond [`NEAR_ZERO_LIMIT`] and for NaN. The first omitted
/// terms are below `7·10⁻¹⁹·|x|` and `5·10⁻¹⁸` (first tier), `3·10⁻¹⁸·|x|` and `2.3·10⁻¹⁷`
/// (second), `2.5·10⁻¹⁸` and `5·10⁻²⁰` (third). The corrections `x·z·P` (at most
/// `|x|³/6 ≤ 2.7·10⁻³`) and `z·Q` (at most `x²/2 ≤ 1/32`) are formed with a relative error
/// of a few roundings (≤ 5·2⁻⁵³: `≤ 1.5·10⁻¹⁸` and `≤ 1.8·10⁻¹⁷`), and the final addition
/// rounds to half an ulp: each result is within ½ ulp + 2.4·10⁻¹⁷ of the exact value, so
/// within **1.5 ulp + 2.5·10⁻¹⁷ of libm's** (itself within 1 ulp), for [`Fused`](crate::fixed::Fused)
/// and [`Separate`](crate::fixed::Separate) alike (checked in `tests/trig_shift.rs`). With
/// [`Separate`](crate::fixed::Separate) the first two tiers perform the operations of
/// [`sin_cos_small`]. About 7 to 15 floating-point operations: the first sine and cosine of
/// the cart's anchored RK4 step for short steps, and those of its fixed stage angles.
#[inline(always)]
pub fn sin_cos_near_zero<F: MulAdd>(x: f64) -> (f64, f64) {
    let m = x.abs();
    if m <= SHORT_SHIFT_LIMIT {
        const S: [f64; 2] = [-1.0 / 6.0, 1.0 / 120.0];
        const C: [f64; 2] = [-0.5, 1.0 / 24.0];
        let z = x * x;
        let s = F::mul_add(x * z, F::mul_add(S[1], z, S[0]), x);
        return (s, F::mul_add(z, F::mul_add(C[1], z, C[0]), 1.0));
    }
    if m <= SHIFT_LIMIT {
        const S: [f64; 3] = [-1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0];
        const C: [f64; 3] = [-0.5, 1.0 / 24.0, -1.0 / 720.0];
        let z = x * x;
        let z2 = z * z;
        let p = F::mul_add(S[2], z2, F::mul_add(S[1], z, S[0]));
        let q = F::mul_add(C[2], z2, F::mul_add(C[1], z, C[0]));
        return (F::mul_add(x * z, p, x), F::mul_add(z, q, 1.0));
    }
    // False for NaN, which goes to libm as well.
    let in_range = m <= NEAR_ZERO_LIMIT;
    if !in_range {
        return x.sin_cos();
    }
    const S: [f64; 5] = SIN_TAYLOR;
    const C: [f64; 6] = COS_TAYLOR;
    let z = x * x;
    let z2 = z * z;
    let p = F::mul_add(
        z2,
        F::mul_add(S[4], z2, F::mul_add(S[3], z, S[2])),
        F::mul_add(S[1], z, S[0]),
    );
    let q = F::mul_add(
        z2,
        F::mul_add(z2, F::mul_add(C[5], z, C[4]), F::mul_add(C[3], z, C[2])),
        F::mul_add(C[1], z, C[0]),
    );
    (F::mul_add(x * z, p, x), F::mul_add(z, q, 1.0))
}

/// Largest `|e|` (`2⁻¹⁴`) [`rotate_small`] is documented for.
pub const ROTATE_LIMIT: f64 = 1.0 / 16384.0;

/// `a + p·cos e + q·sin e` for a small angle `|e| ≤` [`ROTATE_LIMIT`], as
/// `(a + p + e·q) + e²·(−p/2 − e·q/6)` with the multiply–adds of `F`: the rotation of the
/// pair `(p, q)` by `e` (the addition theorem: with `p = sin θ`, `q = cos θ` it is
/// `sin(θ + e)`, with `p = cos θ`, `q = −sin θ` it is `cos(θ + e)`, and with
/// `p = G sin θ − L a cos θ`, `q = G cos θ + L a sin θ` it is `G sin(θ + e) − L a cos(θ + e)`,
/// the form the cart's anchored RK4 step evaluates its later stages' accelerations in). The
/// caller checks the range (no fallback here).
///
/// Error: the omitted terms of `cos e` and `sin e` (Taylor) are below `e⁴/24 ≤ 6·10⁻¹⁹`
/// relative to `|p| + |q|`; the second-order part `e²·(…)` (at most `2⁻²⁹·(|p| + |q|)`)
/// carries a few roundings of its own size (below `10⁻²³·(|p| + |q|)`); the sum `a + p` (one
/// rounding, exact for `a = 0`), the first-order sum `fl(a + p) + e·q` (one rounding with
/// [`Fused`](crate::fixed::Fused), plus one of `e·q ≤ 2⁻¹⁴|q|` with
/// [`Separate`](crate::fixed::Separate)) and the final addition round to half an ulp each.
/// The first-order sum `t` and the result `r` differ by at most `2⁻²⁹·(|p| + |q|)`, so
/// `½ ulp(t) ≤ ulp(r)` (the two differ only where `r` crosses a power of two). Altogether
/// within **1.5 ulp(r) + ½ ulp(fl(a + p)) + 6·10⁻¹⁹·(|p| + |q|)** of the exact value for
/// the given `p`, `q`, `a` (1.5 ulp + 6·10⁻¹⁹·(|p| + |q|) for `a = 0`; checked in
/// `tests/trig_shift.rs` against a double-double reference built on libm's `sin e`).
/// Five multiply–adds and two products; three operations on the chain from `e`.
#[inline(always)]
pub fn rotate_small<F: MulAdd>(p: f64, q: f64, e: f64, a: f64) -> f64 {
    let second = F::mul_add(e, q * (-1.0 / 6.0), -0.5 * p);
    F::mul_add(e * e, second, F::mul_add(e, q, a + p))
}

/// A plant whose right-hand side is evaluated for `L` states at once (structure of arrays),
/// with one input per lane. Autonomous: no time argument.
pub trait LaneDynamics<const N: usize, const L: usize>: Sync {
    /// `ẋ` of every lane; `M` supplies the sines and cosines.
    fn derivative_lanes<M: SinCos>(&self, x: &[[f64; L]; N], u: &[f64; L]) -> [[f64; L]; N];

    /// One classic RK4 step of every lane with the inputs held (provided: [`rk4_lanes`]).
    /// A plant may override it with a step that shares work between the stages when
    /// `M::ANCHORED` (e.g. `pendulab_plants::CartPendulum`); for other `M` the override must
    /// keep [`rk4_lanes`]'s operations.
    #[inline(always)]
    fn rk4_step_lanes<M: SinCos>(&self, x: &mut [[f64; L]; N], u: &[f64; L], h: &[f64; L])
    where
        Self: Sized,
    {
        rk4_lanes::<Self, M, N, L>(self, x, u, h);
    }
}

/// `(sin(a_l + d_l), cos(a_l + d_l))` of every lane from `(s, c) = (sin a, cos a)` and the
/// offsets `d` by the formulas of [`sin_cos_offset`] with the series to `d⁷`/`d⁶` in every
/// lane (no branch per lane, so the lanes stay vectorised); `None` if any `|d_l|` exceeds
/// [`SHIFT_LIMIT`] or is NaN (the caller then evaluates the step another way). Each result
/// within 2 ulp + 6·10⁻¹⁷ of the sine and cosine of the exact sum, as [`sin_cos_offset`].
#[inline(always)]
pub fn sin_cos_offset_lanes<const L: usize>(
    d: &[f64; L],
    s: &[f64; L],
    c: &[f64; L],
) -> Option<([f64; L], [f64; L])> {
    let mut in_range = true;
    let (mut so, mut co) = ([0.0; L], [0.0; L]);
    for l in 0..L {
        in_range &= d[l].abs() <= SHIFT_LIMIT;
        let (sd, cm1) = small_angle_series(d[l]);
        so[l] = s[l] + (s[l] * cm1 + c[l] * sd);
        co[l] = c[l] + (c[l] * cm1 - s[l] * sd);
    }
    in_range.then_some((so, co))
}

/// Options of [`run_feedback_lanes`] (the general loop's [`SampledOptions`](crate::SampledOptions)
/// with `t₀ = 0`, RK4 and no delay, plus the stop rule).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaneOptions {
    /// Sample time (s), finite and > 0.
    pub ts: f64,
    /// End time (s); `⌊t_final/ts⌋` sample intervals are run, at least one.
    pub t_final: f64,
    /// RK4 substeps per sample (≥ 1).
    pub substeps: usize,
    /// Stop a run at the first sample with `|x_i| > bound` or `x_i` NaN: `Some((i, bound))`.
    pub stay_within: Option<(usize, f64)>,
}

/// The outcome of one run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaneOutcome<const N: usize> {
    /// `true` if no sample crossed the bound (always `true` without a bound).
    pub held: bool,
    /// RK4 steps integrated (substeps × sample intervals run).
    pub steps: usize,
    /// The state at the last sample seen (the first one past the bound for a stopped run).
    pub final_state: [f64; N],
}

/// Runs `u = −K x` (`gain` = the row `K`) with zero-order hold from every initial state in
/// `x0s`, `L` runs at a time per thread (rayon), and returns the outcomes in input order.
///
/// # Errors
/// [`SimError::InvalidSampleTime`], [`SimError::InvalidTimeSpan`],
/// [`SimError::InvalidParameter`] for bad options or a non-finite gain;
/// [`SimError::InvalidArgument`] for a bound on a state that does not exist;
/// [`SimError::NonFiniteInitialState`] for a bad initial state; [`SimError::NonFiniteCommand`]
/// / [`SimError::NonFiniteState`] (of the lowest-index failing run) if a run blows up.
pub fn run_feedback_lanes<P, M, const N: usize, const L: usize>(
    plant: &P,
    gain: &[f64; N],
    options: &LaneOptions,
    x0s: &[[f64; N]],
) -> Result<Vec<LaneOutcome<N>>>
where
    P: LaneDynamics<N, L>,
    M: SinCos,
{
    let ts = options.ts;
    if !(ts.is_finite() && ts > 0.0) {
        return Err(SimError::InvalidSampleTime(ts));
    }
    crate::integrate::check_span(0.0, options.t_final)?;
    let samples = (options.t_final / ts + 1e-9).floor();
    if !(1.0..=1e12).contains(&samples) {
        return Err(SimError::InvalidTimeSpan {
            what: "the run must span 1 to 1e12 samples",
            t0: 0.0,
            t_final: options.t_final,
        });
    }
    if options.substeps == 0 {
        return Err(SimError::InvalidParameter {
            what: "RK4 substeps per sample".into(),
            value: 0.0,
            requirement: "must be at least 1",
        });
    }
    if let Some((i, b)) = options.stay_within {
        if i >= N {
            return Err(SimError::InvalidArgument(format!(
                "stay-within bound on state {i}, but there are {N} states"
            )));
        }
        if b.is_nan() || b < 0.0 {
            return Err(SimError::InvalidParameter {
                what: format!("bound on state {i}"),
                value: b,
                requirement: "must be ≥ 0",
            });
        }
    }
    for (j, &g) in gain.iter().enumerate() {
        check_finite(&format!("gain entry {j}"), g)?;
    }
    for x0 in x0s {
        crate::error::check_initial_state(x0, N)?;
    }
    let n_samples = samples as usize;
    let cfg = Config {
        steps: (0..n_samples)
            .map(|k| {
                let span = (k + 1) as f64 * ts - k as f64 * ts;
                if options.substeps == 1 {
                    span
                } else {
                    span / options.substeps as f64
                }
            })
            .collect(),
        substeps: options.substeps,
        samples: n_samples,
        ts,
        stay: options.stay_within,
    };
    // Queues of a few hundred runs per task: enough to amortise the lane start-up and to
    // balance the threads.
    let per_task = (64 * L).max(1);
    let parts: Vec<Result<Vec<LaneOutcome<N>>>> = x0s
        .par_chunks(per_task)
        .map(|chunk| run_queue_dispatch::<P, M, N, L>(plant, gain, &cfg, chunk))
        .collect();
    let mut out = Vec::with_capacity(x0s.len());
    for p in parts {
        out.extend(p?);
    }
    Ok(out)
}

struct Config {
    /// RK4 step of each sample interval: `((k + 1)·ts − k·ts) / substeps`.
    steps: Vec<f64>,
    substeps: usize,
    samples: usize,
    ts: f64,
    stay: Option<(usize, f64)>,
}

/// [`run_queue`] compiled for AVX2 when the processor has it (detected at run time), else for
/// the baseline target. AVX2 only widens the vectors: there is no fused multiply–add (Rust
/// never contracts `a·b + c`, and FMA is not enabled), so every operation rounds as in the
/// baseline code and the results are bit-identical.
fn run_queue_dispatch<P, M, const N: usize, const L: usize>(
    plant: &P,
    gain: &[f64; N],
    cfg: &Config,
    queue: &[[f64; N]],
) -> Result<Vec<LaneOutcome<N>>>
where
    P: LaneDynamics<N, L>,
    M: SinCos,
{
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor supports AVX2 (checked just above), the only requirement of
        // calling a function compiled with `target_feature(enable = "avx2")`.
        return unsafe { run_queue_avx2::<P, M, N, L>(plant, gain, cfg, queue) };
    }
    run_queue::<P, M, N, L>(plant, gain, cfg, queue)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_queue_avx2<P, M, const N: usize, const L: usize>(
    plant: &P,
    gain: &[f64; N],
    cfg: &Config,
    queue: &[[f64; N]],
) -> Result<Vec<LaneOutcome<N>>>
where
    P: LaneDynamics<N, L>,
    M: SinCos,
{
    run_queue::<P, M, N, L>(plant, gain, cfg, queue)
}

/// The runs of `queue` through `L` lanes, refilling a lane as soon as its run ends.
#[inline(always)]
fn run_queue<P, M, const N: usize, const L: usize>(
    plant: &P,
    gain: &[f64; N],
    cfg: &Config,
    queue: &[[f64; N]],
) -> Result<Vec<LaneOutcome<N>>>
where
    P: LaneDynamics<N, L>,
    M: SinCos,
{
    let mut out = vec![
        LaneOutcome {
            held: true,
            steps: 0,
            final_state: [0.0; N],
        };
        queue.len()
    ];
    let mut x = [[0.0; L]; N];
    // Per lane: which run it carries (usize::MAX: idle) and the sample index reached.
    let mut run = [usize::MAX; L];
    let mut k = [0usize; L];
    let mut next = 0usize;
    let mut busy = 0usize;
    let load = |l: usize, x: &mut [[f64; L]; N], i: usize| {
        for (j, xj) in x.iter_mut().enumerate() {
            xj[l] = queue[i][j];
        }
    };
    for l in 0..L {
        if next < queue.len() {
            load(l, &mut x, next);
            run[l] = next;
            next += 1;
            busy += 1;
        }
    }
    let ts = cfg.ts;
    let mut u = [0.0; L];
    let mut h = [0.0; L];
    while busy > 0 {
        // Sample instant of every lane: the monitor and the end of a run, first tested for all
        // lanes at once (vectorised), then handled lane by lane where needed.
        let mut any_end = false;
        for l in 0..L {
            let stop = match cfg.stay {
                Some((i, b)) => {
                    let v = x[i][l];
                    v.abs() > b || v.is_nan()
                }
                None => false,
            };
            any_end |= stop | (k[l] >= cfg.samples);
        }
        if any_end {
            for l in 0..L {
                // A lane may need several refills in a row (a run that starts past the bound).
                while run[l] != usize::MAX {
                    let stop = match cfg.stay {
                        Some((i, b)) => {
                            let v = x[i][l];
                            v.abs() > b || v.is_nan()
                        }
                        None => false,
                    };
                    if !stop && k[l] < cfg.samples {
                        break;
                    }
                    let o = &mut out[run[l]];
                    o.held = !stop;
                    o.steps = k[l] * cfg.substeps;
                    for j in 0..N {
                        o.final_state[j] = x[j][l];
                    }
                    k[l] = 0;
                    if next < queue.len() {
                        load(l, &mut x, next);
                        run[l] = next;
                        next += 1;
                    } else {
                        // Idle from now on: park the lane at the origin (its work is
                        // discarded) and keep it out of the monitor.
                        for xj in x.iter_mut() {
                            xj[l] = 0.0;
                        }
                        run[l] = usize::MAX;
                        k[l] = 0;
                        busy -= 1;
                    }
                }
            }
            if busy == 0 {
                break;
            }
        }
        // The controller: u = −(Σ_j K_j x_j), accumulated as StaticStateFeedback does; and the
        // step of the general loop, t_{k+1} − t_k with t_k = k·ts (not exactly ts), per
        // substep.
        let mut bad = false;
        for l in 0..L {
            let mut acc = 0.0;
            for j in 0..N {
                acc += gain[j] * (x[j][l] - 0.0);
            }
            u[l] = -acc;
            bad |= !u[l].is_finite();
            h[l] = cfg.steps[k[l].min(cfg.samples - 1)];
        }
        if bad && let Some(l) = (0..L).find(|&l| run[l] != usize::MAX && !u[l].is_finite()) {
            return Err(SimError::NonFiniteCommand {
                t: k[l] as f64 * ts,
                index: 0,
                value: u[l],
            });
        }
        for _ in 0..cfg.substeps {
            plant.rk4_step_lanes::<M>(&mut x, &u, &h);
        }
        let mut bad = false;
        for l in 0..L {
            k[l] += 1;
            for xj in x.iter() {
                bad |= !xj[l].is_finite();
            }
        }
        if bad {
            for l in 0..L {
                if run[l] == usize::MAX {
                    continue;
                }
                if let Some(j) = (0..N).find(|&j| !x[j][l].is_finite()) {
                    return Err(SimError::NonFiniteState {
                        t: k[l] as f64 * ts,
                        index: j,
                        value: x[j][l],
                    });
                }
            }
        }
    }
    Ok(out)
}

/// One classic RK4 step of every lane with the inputs held, in the operation order of the
/// general kernel (`crate::integrate::rk4`).
#[inline(always)]
pub fn rk4_lanes<P, M, const N: usize, const L: usize>(
    plant: &P,
    x: &mut [[f64; L]; N],
    u: &[f64; L],
    h: &[f64; L],
) where
    P: LaneDynamics<N, L>,
    M: SinCos,
{
    let mut half = [0.0; L];
    let mut sixth = [0.0; L];
    for l in 0..L {
        half[l] = 0.5 * h[l];
        sixth[l] = h[l] / 6.0;
    }
    let stage = |k: &[[f64; L]; N], s: &[f64; L]| {
        let mut xt = [[0.0; L]; N];
        for j in 0..N {
            for l in 0..L {
                xt[j][l] = x[j][l] + s[l] * k[j][l];
            }
        }
        xt
    };
    let k1 = plant.derivative_lanes::<M>(x, u);
    let k2 = plant.derivative_lanes::<M>(&stage(&k1, &half), u);
    let k3 = plant.derivative_lanes::<M>(&stage(&k2, &half), u);
    let k4 = plant.derivative_lanes::<M>(&stage(&k3, h), u);
    for j in 0..N {
        for l in 0..L {
            x[j][l] += sixth[l] * (k1[j][l] + 2.0 * k2[j][l] + 2.0 * k3[j][l] + k4[j][l]);
        }
    }
}
