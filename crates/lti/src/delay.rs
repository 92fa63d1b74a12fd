//! Rational approximations of a time delay: the Padé approximant of `e^{−sT}` (continuous,
//! MATLAB / python-control `pade`) and the Thiran all-pass fractional-delay filter (discrete,
//! MATLAB `thiran`).
//!
//! # Padé
//!
//! The diagonal `(n, n)` Padé approximant of `e^{−sT}` is `P(−sT)/P(sT)` with
//! `P(x) = Σ_{k=0}^{n} c_k x^k`, `c_k = (2n − k)! n! / ((2n)! k! (n − k)!)`
//! (Golub & Van Loan, *Matrix Computations*, §9.3.1, the Padé approximant of `e^x`). It is
//! all-pass (`|P(−jωT)/P(jωT)| = 1`), its phase `−2 arg P(jωT)` agrees with the delay's `−ωT`
//! up to `O((ωT)^{2n+1})`, and for `n = 1` it is `(1 − sT/2)/(1 + sT/2)`. The coefficients
//! are formed by the recurrence `c_k = c_{k−1} (n − k + 1)/((2n − k + 1) k)`, as
//! python-control's `pade` does.
//!
//! # Thiran
//!
//! A delay of `D = τ/ts` samples is approximated by `z^{−m}` times the order-`N` all-pass
//! filter `H(z) = z^{−N} A(z^{−1}) / A(z)`, `A(z) = 1 + Σ_{k=1}^{N} a_k z^{−k}`,
//! `a_k = (−1)^k C(N, k) Π_{i=0}^{N} (d − N + i)/(d − N + k + i)` with `d = D − m` (Thiran,
//! "Recursive digital filters with maximally flat group delay", IEEE Trans. Circuit Theory
//! 18(6), 1971; Laakso, Välimäki, Karjalainen & Laine, "Splitting the unit delay", IEEE
//! Signal Processing Magazine 13(1), 1996). Its group delay is maximally flat at `ω = 0` and
//! equals `d` there; its poles are inside the unit circle for `d > N − 1`. [`thiran`] follows
//! MATLAB (`N = ⌈D⌉`, `m = 0`; an integer `D` gives the pure delay `z^{−D}`), and
//! [`thiran_with_order`] keeps a chosen order `N` and puts the integer part
//! `m = ⌈D⌉ − N` of the delay into `z^{−m}`, so that `d ∈ (N − 1, N]`.

use crate::domain::{Continuous, Discrete};
use crate::error::{LtiError, Result};
use crate::polynomial::Polynomial;
use crate::transfer_function::TransferFunction;

/// The `(n, n)` Padé approximant of the delay `e^{−sT}` (`T` seconds, order `n ≥ 1`), as a
/// continuous transfer function with monic denominator (module documentation). `T = 0`
/// gives the unit gain.
///
/// # Errors
/// [`LtiError::InvalidArgument`] for `T < 0`, a non-finite `T` or `n = 0`;
/// [`LtiError::NonFinite`] if the normalised coefficients overflow (`T` tiny and `n` large).
pub fn pade(t: f64, n: usize) -> Result<TransferFunction<Continuous>> {
    if !(t.is_finite() && t >= 0.0) {
        return Err(LtiError::InvalidArgument(format!(
            "pade: the delay must be finite and ≥ 0 s, got {t}"
        )));
    }
    if n == 0 {
        return Err(LtiError::InvalidArgument(
            "pade: the order must be at least 1".into(),
        ));
    }
    if t == 0.0 {
        return TransferFunction::gain(1.0, Continuous);
    }
    // c_k T^k, k = 0..n (ascending powers of s).
    let mut ascending = vec![1.0; n + 1];
    let mut c = 1.0;
    for (k, slot) in ascending.iter_mut().enumerate().skip(1) {
        c *= t * (n - k + 1) as f64 / (((2 * n - k + 1) * k) as f64);
        *slot = c;
    }
    let den: Vec<f64> = ascending.iter().rev().copied().collect();
    let num: Vec<f64> = ascending
        .iter()
        .enumerate()
        .rev()
        .map(|(k, &v)| if k % 2 == 1 { -v } else { v })
        .collect();
    TransferFunction::new(Polynomial::new(&num)?, Polynomial::new(&den)?, Continuous)
}

/// The Thiran all-pass approximation of a delay of `tau` seconds at sample time `ts`, MATLAB's
/// `thiran(tau, ts)`: order `N = ⌈tau/ts⌉`, no separate integer delay; a delay that is an
/// integer number of samples is the pure delay `z^{−N}` (module documentation).
///
/// # Errors
/// As [`thiran_with_order`].
pub fn thiran(tau: f64, ts: f64) -> Result<TransferFunction<Discrete>> {
    let d = samples(tau, ts)?;
    thiran_with_order(tau, ts, d.ceil() as usize)
}

/// `z^{−m}` times the order-`order` Thiran all-pass filter for a delay of `tau` seconds at
/// sample time `ts` (module documentation): with `D = tau/ts`, `m = ⌈D⌉ − order` whole
/// samples and the fractional remainder `d = D − m ∈ (order − 1, order]` in the all-pass part.
/// `tau = 0` with `order = 0` gives the unit gain.
///
/// # Errors
/// [`LtiError::InvalidSampleTime`]; [`LtiError::InvalidArgument`] for a negative or
/// non-finite `tau`, or an order above `⌈tau/ts⌉` (the filter would be unstable), or `order =
/// 0` for a positive delay.
pub fn thiran_with_order(tau: f64, ts: f64, order: usize) -> Result<TransferFunction<Discrete>> {
    let domain = Discrete::new(ts)?;
    let big_d = samples(tau, ts)?;
    let whole = big_d.ceil();
    if order as f64 > whole || (order == 0 && big_d > 0.0) {
        return Err(LtiError::InvalidArgument(format!(
            "thiran: order {order} is not in 1..=⌈tau/ts⌉ = {whole} for a delay of {big_d} samples"
        )));
    }
    let m = (whole as usize) - order;
    let d = big_d - m as f64;
    let n = order;
    // a_k = (−1)^k C(N, k) Π_{i=0}^{N} (d − N + i)/(d − N + k + i), a_0 = 1.
    let mut a = vec![1.0; n + 1];
    let mut binom = 1.0;
    for (k, slot) in a.iter_mut().enumerate().skip(1) {
        binom *= (n - k + 1) as f64 / k as f64;
        let prod: f64 = (0..=n)
            .map(|i| (d - n as f64 + i as f64) / (d - n as f64 + (k + i) as f64))
            .product();
        *slot = if k % 2 == 1 { -binom } else { binom } * prod;
    }
    // H(z) = (a_N z⁰ … + a_1 z^{N−1} + z^N)·… over zᵐ (z^N + a_1 z^{N−1} + … + a_N).
    let num: Vec<f64> = a.iter().rev().copied().collect();
    let mut den = a;
    den.extend(std::iter::repeat_n(0.0, m));
    TransferFunction::new(Polynomial::new(&num)?, Polynomial::new(&den)?, domain)
}

/// `tau/ts` after checking both.
fn samples(tau: f64, ts: f64) -> Result<f64> {
    Discrete::new(ts)?;
    if !(tau.is_finite() && tau >= 0.0) {
        return Err(LtiError::InvalidArgument(format!(
            "thiran: the delay must be finite and ≥ 0 s, got {tau}"
        )));
    }
    let d = tau / ts;
    // A delay within rounding of a whole number of samples is that number.
    let r = d.round();
    Ok(if (d - r).abs() <= 8.0 * f64::EPSILON * r.max(1.0) {
        r
    } else {
        d
    })
}
