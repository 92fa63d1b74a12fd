//! Numerical differentiation of uniformly sampled signals.
//!
//! * [`three_point`] — the book's three-point formulas (eq. 3.47): the central difference
//!   `ẋ[k] = (x[k+1] − x[k−1])/(2 t_s)` inside, and the one-sided second-order formulas
//!   `ẋ[0] = (−3x[0] + 4x[1] − x[2])/(2 t_s)`, `ẋ[n] = (x[n−2] − 4x[n−1] + 3x[n])/(2 t_s)` at the
//!   ends. All three are exact for quadratics. [`three_point_twice`] applies it to its own
//!   output for accelerations, as the book does.
//! * [`savgol_coefficients`] / [`savitzky_golay`] — Savitzky–Golay differentiation (A.
//!   Savitzky, M. J. E. Golay, *Anal. Chem.* 36 (1964) 1627): the derivative at each sample of
//!   the least-squares polynomial of degree `order` through the `window` samples around it;
//!   near the ends, of the polynomial through the first (last) `window` samples (SciPy's
//!   `savgol_filter(mode="interp")`). Exact for polynomials of degree ≤ `order`, and much less
//!   noisy than three-point differences on quantised data.
//!
//! [`Differentiator`] names the choice for the regressions of [`crate::regression`].

use crate::error::{IdentError, Result, UNNAMED};
use nalgebra::DMatrix;

/// How derivatives are computed from sampled positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Differentiator {
    /// The book's three-point formulas (eq. 3.47); accelerations by applying them twice.
    #[default]
    ThreePoint,
    /// Savitzky–Golay: derivative of the local least-squares polynomial of degree `order`
    /// over `window` samples (odd, `window > order ≥ 2` so accelerations exist).
    SavitzkyGolay {
        /// Window length in samples (odd).
        window: usize,
        /// Polynomial degree.
        order: usize,
    },
}

/// First and second derivatives of a signal.
#[derive(Debug, Clone, PartialEq)]
pub struct Derivatives {
    /// First derivative (unit of the signal per second).
    pub first: Vec<f64>,
    /// Second derivative (unit of the signal per second²).
    pub second: Vec<f64>,
}

impl Differentiator {
    /// Smallest number of samples the method works on.
    pub fn min_samples(&self) -> usize {
        match *self {
            Differentiator::ThreePoint => 3,
            Differentiator::SavitzkyGolay { window, .. } => window,
        }
    }

    /// Checks the parameters.
    ///
    /// # Errors
    /// [`IdentError::InvalidParameter`] for an even window, `order < 2` or `window ≤ order`.
    pub fn validate(&self) -> Result<()> {
        if let Differentiator::SavitzkyGolay { window, order } = *self {
            check_savgol(window, order, 2)?;
        }
        Ok(())
    }

    /// First and second derivatives of `x` sampled every `ts` seconds.
    ///
    /// # Errors
    /// [`IdentError::InvalidParameter`] for a bad `ts` or method parameters;
    /// [`IdentError::TooFewSamples`] if `x` is shorter than [`Differentiator::min_samples`].
    pub fn derivatives(&self, x: &[f64], ts: f64) -> Result<Derivatives> {
        self.validate()?;
        match *self {
            Differentiator::ThreePoint => {
                let first = three_point(x, ts)?;
                let second = three_point(&first, ts)?;
                Ok(Derivatives { first, second })
            }
            Differentiator::SavitzkyGolay { window, order } => Ok(Derivatives {
                first: savitzky_golay(x, ts, window, order, 1)?,
                second: savitzky_golay(x, ts, window, order, 2)?,
            }),
        }
    }
}

fn check_ts(ts: f64) -> Result<()> {
    if ts.is_finite() && ts > 0.0 {
        Ok(())
    } else {
        Err(IdentError::InvalidParameter {
            name: "sample time ts".into(),
            value: ts,
            reason: "must be finite and > 0 s".into(),
        })
    }
}

fn too_few(what: &str, needed: usize, found: usize) -> IdentError {
    IdentError::TooFewSamples {
        source_name: UNNAMED.into(),
        what: what.into(),
        needed,
        found,
    }
}

/// Three-point derivative at sample `k` (eq. 3.47): one-sided at the two ends, central inside.
/// `x.len() ≥ 3` is the caller's precondition.
#[inline]
pub(crate) fn three_point_at(x: &[f64], inv_2ts: f64, k: usize) -> f64 {
    let n = x.len();
    if k == 0 {
        (-3.0 * x[0] + 4.0 * x[1] - x[2]) * inv_2ts
    } else if k == n - 1 {
        (x[n - 3] - 4.0 * x[n - 2] + 3.0 * x[n - 1]) * inv_2ts
    } else {
        (x[k + 1] - x[k - 1]) * inv_2ts
    }
}

/// Writes the three-point derivative of `x` into `out` (same length, at least 3).
pub(crate) fn three_point_into(x: &[f64], ts: f64, out: &mut [f64]) {
    let n = x.len();
    debug_assert!(n >= 3 && out.len() == n);
    let h = 0.5 / ts;
    out[0] = three_point_at(x, h, 0);
    // The interior loop on windows vectorises.
    for (o, w) in out[1..n - 1].iter_mut().zip(x.windows(3)) {
        *o = (w[2] - w[0]) * h;
    }
    out[n - 1] = three_point_at(x, h, n - 1);
}

/// The book's three-point derivative (eq. 3.47) of `x` sampled every `ts` seconds.
///
/// Second-order accurate everywhere; exact for polynomials of degree ≤ 2 (interior and ends).
///
/// # Errors
/// [`IdentError::InvalidParameter`] unless `ts` is finite and positive;
/// [`IdentError::TooFewSamples`] for fewer than 3 samples.
pub fn three_point(x: &[f64], ts: f64) -> Result<Vec<f64>> {
    check_ts(ts)?;
    if x.len() < 3 {
        return Err(too_few("three-point differentiation", 3, x.len()));
    }
    let mut out = vec![0.0; x.len()];
    three_point_into(x, ts, &mut out);
    Ok(out)
}

/// The three-point derivative applied twice (the book's accelerations): `D(D(x))`.
///
/// Inside, `ẍ[k] = (x[k+2] − 2x[k] + x[k−2])/(4 t_s²)`; exact for quadratics (including
/// the ends, since each pass is).
///
/// # Errors
/// As [`three_point`].
pub fn three_point_twice(x: &[f64], ts: f64) -> Result<Vec<f64>> {
    let d = three_point(x, ts)?;
    three_point(&d, ts)
}

fn check_savgol(window: usize, order: usize, deriv: usize) -> Result<()> {
    let bad = |name: &str, value: usize, reason: String| IdentError::InvalidParameter {
        name: name.into(),
        value: value as f64,
        reason,
    };
    if window.is_multiple_of(2) || window < 3 {
        return Err(bad(
            "Savitzky-Golay window",
            window,
            "must be odd and at least 3".into(),
        ));
    }
    if order >= window {
        return Err(bad(
            "Savitzky-Golay order",
            order,
            format!("must be less than the window length {window}"),
        ));
    }
    if deriv > order {
        return Err(bad(
            "Savitzky-Golay derivative order",
            deriv,
            format!("must not exceed the polynomial order {order}"),
        ));
    }
    Ok(())
}

/// Savitzky–Golay coefficients `c` such that `Σ_i c_i x[i]` (over a window of `window`
/// samples spaced `delta`) is the `deriv`-th derivative, at sample position `pos` of the
/// window, of the degree-`order` least-squares polynomial through the window.
///
/// `pos = (window − 1)/2` is the centre (the usual smoother/differentiator). The order of the
/// coefficients is that of the samples (SciPy's `savgol_coeffs(..., pos=pos, use="dot")`).
/// Computed from a Householder QR of the scaled Vandermonde matrix `V[i, j] = ((i −
/// pos)/s)^j` (s = half the window, for conditioning): `c = deriv! · row_deriv(V⁺) / (s·delta)^deriv`.
///
/// # Errors
/// [`IdentError::InvalidParameter`] for an even window, `order ≥ window`, `deriv > order`,
/// `pos ≥ window` or a non-positive `delta`.
pub fn savgol_coefficients(
    window: usize,
    order: usize,
    deriv: usize,
    delta: f64,
    pos: usize,
) -> Result<Vec<f64>> {
    check_savgol(window, order, deriv)?;
    check_ts(delta)?;
    if pos >= window {
        return Err(IdentError::InvalidParameter {
            name: "Savitzky-Golay evaluation position".into(),
            value: pos as f64,
            reason: format!("must be less than the window length {window}"),
        });
    }
    let s = ((window - 1) / 2) as f64;
    let p = order + 1;
    let v = DMatrix::from_fn(window, p, |i, j| {
        ((i as f64 - pos as f64) / s).powi(j as i32)
    });
    // V⁺ = R⁻¹ Qᵀ; we need row `deriv` of it, i.e. e_derivᵀ R⁻¹ Qᵀ = (Q (R⁻ᵀ e_deriv))ᵀ.
    let qr = v.qr();
    let r = qr.r();
    let q = qr.q();
    // Solve Rᵀ w = e_deriv (forward substitution on the lower-triangular Rᵀ).
    let mut w = vec![0.0; p];
    for i in 0..p {
        let mut acc = if i == deriv { 1.0 } else { 0.0 };
        for k in 0..i {
            acc -= r[(k, i)] * w[k];
        }
        w[i] = acc / r[(i, i)];
    }
    let fact: f64 = (1..=deriv).map(|k| k as f64).product();
    let scale = fact / (s * delta).powi(deriv as i32);
    Ok((0..window)
        .map(|i| scale * (0..p).map(|k| q[(i, k)] * w[k]).sum::<f64>())
        .collect())
}

/// Savitzky–Golay derivative of order `deriv` (0 smooths) of `x` sampled every `ts` seconds,
/// with a window of `window` samples and polynomials of degree `order`.
///
/// Interior samples use the centred coefficients; the first and last `(window − 1)/2` samples
/// use the polynomial fitted to the first (last) `window` samples, evaluated at their own
/// positions (SciPy's `savgol_filter(x, window, order, deriv, delta=ts, mode="interp")`).
///
/// # Errors
/// As [`savgol_coefficients`]; [`IdentError::TooFewSamples`] if `x` is shorter than the window.
pub fn savitzky_golay(
    x: &[f64],
    ts: f64,
    window: usize,
    order: usize,
    deriv: usize,
) -> Result<Vec<f64>> {
    check_savgol(window, order, deriv)?;
    check_ts(ts)?;
    let n = x.len();
    if n < window {
        return Err(too_few("Savitzky-Golay differentiation", window, n));
    }
    let half = (window - 1) / 2;
    let centre = savgol_coefficients(window, order, deriv, ts, half)?;
    let mut out = vec![0.0; n];
    for (o, w) in out[half..n - half].iter_mut().zip(x.windows(window)) {
        *o = centre.iter().zip(w).map(|(c, v)| c * v).sum();
    }
    for pos in 0..half {
        let c = savgol_coefficients(window, order, deriv, ts, pos)?;
        out[pos] = c.iter().zip(&x[..window]).map(|(c, v)| c * v).sum();
        let c = savgol_coefficients(window, order, deriv, ts, window - 1 - pos)?;
        out[n - 1 - pos] = c.iter().zip(&x[n - window..]).map(|(c, v)| c * v).sum();
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn three_point_exact_on_quadratics() {
        // x(t) = 2 − 3t + 5t², ẋ = −3 + 10t, ẍ = 10: exact at every sample, ends included.
        let ts = 0.01;
        let t: Vec<f64> = (0..50).map(|k| 0.3 + k as f64 * ts).collect();
        let x: Vec<f64> = t.iter().map(|t| 2.0 - 3.0 * t + 5.0 * t * t).collect();
        let d = three_point(&x, ts).unwrap();
        let dd = three_point_twice(&x, ts).unwrap();
        for (k, t) in t.iter().enumerate() {
            // Rounding: |x| ≈ 2, divided by 2ts = 0.02 → ~1e-13; again for ẍ → ~1e-11.
            assert!((d[k] - (-3.0 + 10.0 * t)).abs() < 1e-11, "k={k}");
            assert!((dd[k] - 10.0).abs() < 1e-8, "k={k}: {}", dd[k]);
        }
    }

    #[test]
    fn three_point_errors() {
        assert!(matches!(
            three_point(&[1.0, 2.0], 0.1),
            Err(IdentError::TooFewSamples { .. })
        ));
        assert!(matches!(
            three_point(&[1.0, 2.0, 3.0], 0.0),
            Err(IdentError::InvalidParameter { .. })
        ));
    }

    #[test]
    fn savgol_exact_on_polynomials() {
        // Cubic, window 11, order 3: every derivative exact, ends included.
        let ts = 0.002;
        let x: Vec<f64> = (0..40)
            .map(|k| {
                let t = k as f64 * ts;
                1.0 + t - 4.0 * t * t + 30.0 * t * t * t
            })
            .collect();
        let d1 = savitzky_golay(&x, ts, 11, 3, 1).unwrap();
        let d2 = savitzky_golay(&x, ts, 11, 3, 2).unwrap();
        for k in 0..40 {
            let t = k as f64 * ts;
            assert!(
                (d1[k] - (1.0 - 8.0 * t + 90.0 * t * t)).abs() < 1e-9,
                "k={k}"
            );
            assert!((d2[k] - (-8.0 + 180.0 * t)).abs() < 1e-5, "k={k}");
        }
        assert!(savgol_coefficients(10, 2, 1, 1.0, 4).is_err());
        assert!(savgol_coefficients(5, 5, 1, 1.0, 2).is_err());
        assert!(savgol_coefficients(5, 2, 3, 1.0, 2).is_err());
    }
}
