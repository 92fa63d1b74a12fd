//! Sines and cosines for the fast paths: the branch-free polynomial of the lane kernel
//! ([`sin_cos_lanes`]) and the series and addition-theorem forms that the anchored RK4 steps
//! take their stage angles from ([`sin_cos_near_zero`], [`sin_cos_offset`], [`rotate_small`],
//! [`sin_cos_offset_lanes`]), each with its error bound against libm (checked in
//! `tests/trig_shift.rs` and `tests/lanes.rs`).

use super::strategy::MulAdd;
use std::f64::consts::FRAC_2_PI;
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
/// [`Trig::Anchored`](crate::fast::Trig::Anchored) near the upright (or any) zero angle.
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
/// within **1.5 ulp + 2.5·10⁻¹⁷ of libm's** (itself within 1 ulp), for [`Fused`](crate::fast::Fused)
/// and [`Separate`](crate::fast::Separate) alike (checked in `tests/trig_shift.rs`). With
/// [`Separate`](crate::fast::Separate) the first two tiers perform the operations of
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
/// [`Fused`](crate::fast::Fused), plus one of `e·q ≤ 2⁻¹⁴|q|` with
/// [`Separate`](crate::fast::Separate)) and the final addition round to half an ulp each.
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
