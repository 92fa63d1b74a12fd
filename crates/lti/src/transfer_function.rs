//! Single-input single-output transfer functions `G = num/den` and their conversion to and
//! from state space.
//!
//! - [`TransferFunction::new`] (MATLAB `tf`): numerator and denominator [`Polynomial`]s; the
//!   denominator is normalised to be monic, so equal transfer functions written with
//!   different scalings compare equal coefficient by coefficient.
//! - [`TransferFunction::to_state_space`] (`ss(G)`, `tf2ss`): the controllable canonical
//!   realisation (same structure as [`controllable_canonical_form`](crate::analysis::controllable_canonical_form)).
//! - [`TransferFunction::from_state_space`] (`tf(sys)`, `ss2tf`): poles from the eigenvalues
//!   of `A`, zeros from the system pencil ([`StateSpace::zeros`]), gain by matching the
//!   frequency response at well-separated test points. This is MATLAB's route (through
//!   zero-pole-gain) and avoids the Faddeev–Leverrier recursion, which loses all accuracy in
//!   the characteristic polynomial for moderately sized or badly scaled `A`.
//!
//! Nothing is cancelled silently ("minreal-free"): `series`, `feedback` etc. multiply
//! polynomials exactly as written, and a realisation of a non-minimal transfer function is
//! non-minimal.

use crate::analysis::siso_zeros;
use crate::domain::{Continuous, Discrete, TimeDomain};
use crate::error::{LtiError, Result};
use crate::linalg::{Complex64, Mat};
use crate::polynomial::Polynomial;
use crate::state_space::StateSpace;

/// A SISO transfer function `G = num/den` in time domain `D` (`s` or `z`).
///
/// Invariants: the denominator is not the zero polynomial and is monic (leading coefficient
/// 1; the numerator is scaled accordingly); coefficients are finite. Improper transfer
/// functions (numerator degree above the denominator's, e.g. an ideal PID) are allowed for
/// evaluation and Bode plots; a state-space realisation requires a proper one.
#[doc(alias = "tf")]
#[derive(Debug, Clone, PartialEq)]
pub struct TransferFunction<D: TimeDomain> {
    num: Polynomial,
    den: Polynomial,
    domain: D,
}

impl<D: TimeDomain> TransferFunction<D> {
    /// `num/den` in the given time domain; the pair is scaled so that `den` is monic.
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] if `den` is the zero polynomial;
    /// [`LtiError::NonFinite`] if the normalisation overflows (a denominator whose leading
    /// coefficient is tiny compared with the others).
    pub fn new(num: Polynomial, den: Polynomial, domain: D) -> Result<Self> {
        if den.is_zero() {
            return Err(LtiError::InvalidArgument(
                "transfer function denominator is the zero polynomial".into(),
            ));
        }
        let lead = den.leading();
        let (num, den) = (num.scale(1.0 / lead), den.monic());
        for (what, p) in [("numerator", &num), ("denominator", &den)] {
            if let Some((i, &v)) = p
                .coefficients()
                .iter()
                .enumerate()
                .find(|(_, v)| !v.is_finite())
            {
                return Err(LtiError::NonFinite {
                    what: format!("{what} after normalising the denominator to be monic"),
                    row: 0,
                    col: i,
                    value: v,
                });
            }
        }
        Ok(Self { num, den, domain })
    }

    /// `num/den` from coefficient slices in descending powers (MATLAB
    /// `tf([1 2], [1 3 2])`).
    ///
    /// # Errors
    /// [`LtiError::NonFinite`] for NaN/infinite coefficients, and as [`TransferFunction::new`].
    pub fn from_coefficients(num: &[f64], den: &[f64], domain: D) -> Result<Self> {
        Self::new(Polynomial::new(num)?, Polynomial::new(den)?, domain)
    }

    /// The static gain `G = k`.
    ///
    /// # Errors
    /// [`LtiError::NonFinite`] if `k` is not finite.
    pub fn gain(k: f64, domain: D) -> Result<Self> {
        Self::new(Polynomial::constant(k)?, Polynomial::one(), domain)
    }

    /// Numerator polynomial.
    pub fn num(&self) -> &Polynomial {
        &self.num
    }
    /// Denominator polynomial (monic).
    pub fn den(&self) -> &Polynomial {
        &self.den
    }
    /// The time domain.
    pub fn domain(&self) -> D {
        self.domain
    }
    /// `deg den − deg num` (negative for improper transfer functions; the zero transfer
    /// function has relative degree `deg den`).
    pub fn relative_degree(&self) -> i64 {
        if self.num.is_zero() {
            return self.den.degree() as i64;
        }
        self.den.degree() as i64 - self.num.degree() as i64
    }
    /// `true` if `deg num ≤ deg den`.
    pub fn is_proper(&self) -> bool {
        self.relative_degree() >= 0
    }

    /// Poles: roots of the denominator (sorted as
    /// [`sort_eigenvalues`](crate::linalg::sort_eigenvalues)).
    ///
    /// # Errors
    /// [`LtiError::NoConvergence`].
    #[doc(alias = "pole")]
    pub fn poles(&self) -> Result<Vec<Complex64>> {
        self.den.roots()
    }

    /// Zeros: roots of the numerator (empty for the zero transfer function).
    ///
    /// # Errors
    /// [`LtiError::NoConvergence`].
    #[doc(alias = "zero")]
    pub fn zeros(&self) -> Result<Vec<Complex64>> {
        if self.num.is_zero() {
            return Ok(Vec::new());
        }
        self.num.roots()
    }

    /// `G(s₀) = num(s₀)/den(s₀)` (Horner's rule; `±∞`/NaN at a pole).
    pub fn eval(&self, s0: Complex64) -> Complex64 {
        self.num.eval_complex(s0) / self.den.eval_complex(s0)
    }

    /// Steady-state gain `G(0)` (continuous) or `G(1)` (discrete), with common factors
    /// `(s − s₀)` of numerator and denominator cancelled first (a limit, as MATLAB's
    /// `dcgain` of a transfer function).
    ///
    /// # Errors
    /// [`LtiError::PoleAtEvaluationPoint`] if a pole at `s₀` remains (an integrator).
    #[doc(alias = "dcgain")]
    pub fn dc_gain(&self) -> Result<f64> {
        let s0: f64 = match self.domain.sample_time() {
            None => 0.0,
            Some(_) => 1.0,
        };
        let near_zero = |p: &Polynomial| {
            let scale: f64 = p
                .coefficients()
                .iter()
                .rev()
                .enumerate()
                .map(|(k, c)| c.abs() * s0.abs().powi(k as i32))
                .sum();
            p.eval(s0).abs() <= 4.0 * (p.degree() + 1) as f64 * f64::EPSILON * scale
        };
        let root = Polynomial::from_vec_unchecked(vec![1.0, -s0]);
        let (mut num, mut den) = (self.num.clone(), self.den.clone());
        if num.is_zero() {
            return Ok(0.0);
        }
        while near_zero(&den) {
            if !near_zero(&num) || num.degree() == 0 {
                return Err(LtiError::PoleAtEvaluationPoint {
                    what: "DC gain".into(),
                    pole: Complex64::new(s0, 0.0),
                });
            }
            num = num.div_rem(&root)?.0;
            den = den.div_rem(&root)?.0;
        }
        Ok(num.eval(s0) / den.eval(s0))
    }

    /// `true` if every pole is strictly inside the stability region (see
    /// [`StateSpace::is_stable`] for the rounding margin).
    ///
    /// # Errors
    /// [`LtiError::NoConvergence`].
    pub fn is_stable(&self) -> Result<bool> {
        let poles = self.poles()?;
        let scale = poles.iter().map(|p| p.norm()).fold(1.0, f64::max);
        let tol = 100.0 * f64::EPSILON * scale;
        Ok(poles
            .into_iter()
            .all(|p| self.domain.stability_distance(p) < -tol))
    }

    /// Zero-pole-gain form `G = k Π(s − zᵢ)/Π(s − pᵢ)` (MATLAB `zpkdata`): `(zeros, poles, k)`.
    ///
    /// # Errors
    /// [`LtiError::NoConvergence`].
    #[doc(alias = "zpk")]
    pub fn to_zpk(&self) -> Result<(Vec<Complex64>, Vec<Complex64>, f64)> {
        Ok((self.zeros()?, self.poles()?, self.num.leading()))
    }

    /// Builds `G = k Π(s − zᵢ)/Π(s − pᵢ)` (MATLAB `zpk`); complex zeros and poles must come
    /// in conjugate pairs.
    ///
    /// # Errors
    /// As [`Polynomial::from_roots`]; [`LtiError::NonFinite`] for a non-finite `k`.
    pub fn from_zpk(zeros: &[Complex64], poles: &[Complex64], k: f64, domain: D) -> Result<Self> {
        let num = Polynomial::from_roots(zeros)?.scale(k);
        if !k.is_finite() {
            return Err(LtiError::NonFinite {
                what: "zpk gain".into(),
                row: 0,
                col: 0,
                value: k,
            });
        }
        Self::new(num, Polynomial::from_roots(poles)?, domain)
    }

    /// Controllable canonical realisation (MATLAB `ss(G)`, `tf2ss`): with
    /// `den = sⁿ + aₙ₋₁sⁿ⁻¹ + … + a₀` and `num = d·den + r`, `deg r < n`,
    /// `A = [[0, 1, …], …, [−a₀, …, −aₙ₋₁]]`, `B = [0, …, 0, 1]ᵀ`, `C = [r₀, …, rₙ₋₁]`, `D = d`.
    ///
    /// # Errors
    /// [`LtiError::Improper`] if `deg num > deg den`.
    #[doc(alias = "tf2ss")]
    #[doc(alias = "ss")]
    pub fn to_state_space(&self) -> Result<StateSpace<D>> {
        if !self.is_proper() {
            return Err(LtiError::Improper {
                what: "state-space realisation".into(),
                num_degree: self.num.degree(),
                den_degree: self.den.degree(),
            });
        }
        let n = self.den.degree();
        let d = if self.num.degree() == n && !self.num.is_zero() {
            self.num.leading()
        } else {
            0.0
        };
        let r = self.num.minus(&self.den.scale(d));
        let mut a = Mat::zeros(n, n);
        for i in 0..n.saturating_sub(1) {
            a[(i, i + 1)] = 1.0;
        }
        let mut b = Mat::zeros(n, 1);
        let mut c = Mat::zeros(1, n);
        for j in 0..n {
            a[(n - 1, j)] = -self.den.coefficient_of_power(j);
            c[(0, j)] = r.coefficient_of_power(j);
        }
        if n > 0 {
            b[(n - 1, 0)] = 1.0;
        }
        StateSpace::new(a, b, c, Mat::from_element(1, 1, d), self.domain)
    }

    /// The transfer function of a SISO state-space system (MATLAB `tf(sys)`, `ss2tf`):
    /// `den = Π(s − λᵢ(A))`, `num = k Π(s − zᵢ)` with the invariant zeros of
    /// [`StateSpace::zeros`] and `k` fitted (least squares over three test points placed
    /// away from every pole and zero at the geometric-mean magnitude of the poles and zeros)
    /// to `G(s) = D + C(sI − A)⁻¹B` computed by direct solves. Non-minimal realisations give
    /// non-minimal transfer functions (common factors are not cancelled).
    ///
    /// # Errors
    /// [`LtiError::NotSiso`]; [`LtiError::NoConvergence`].
    #[doc(alias = "ss2tf")]
    pub fn from_state_space(sys: &StateSpace<D>) -> Result<Self> {
        if sys.nu() != 1 || sys.ny() != 1 {
            return Err(LtiError::NotSiso {
                what: "transfer function of a state-space system".into(),
                ny: sys.ny(),
                nu: sys.nu(),
            });
        }
        let poles = sys.poles()?;
        let den = Polynomial::from_vec_unchecked(crate::polynomial::poly_from_roots(&poles));
        let zeros = match siso_zeros(sys.a(), sys.b(), sys.c(), sys.d()[(0, 0)])? {
            None => {
                return Self::new(Polynomial::zero(), den, sys.domain());
            }
            Some(z) => z,
        };
        let shape = Polynomial::from_vec_unchecked(crate::polynomial::poly_from_roots(&zeros));
        let k = fit_gain(sys, &poles, &zeros)?;
        Self::new(shape.scale(k), den, sys.domain())
    }
}

/// Least-squares gain `k` with `G(sᵢ) ≈ k Π(sᵢ − z)/Π(sᵢ − p)` at three test points.
fn fit_gain<D: TimeDomain>(
    sys: &StateSpace<D>,
    poles: &[Complex64],
    zeros: &[Complex64],
) -> Result<f64> {
    if sys.nx() == 0 {
        return Ok(sys.d()[(0, 0)]);
    }
    let mags: Vec<f64> = poles
        .iter()
        .chain(zeros)
        .map(|z| z.norm())
        .filter(|&m| m > 0.0)
        .collect();
    let rho = if mags.is_empty() {
        1.0
    } else {
        (mags.iter().map(|m| m.ln()).sum::<f64>() / mags.len() as f64).exp()
    };
    // Candidate points: several radii and angles; keep the three farthest (relative to their
    // modulus) from every pole and zero.
    let mut cands: Vec<(f64, Complex64)> = Vec::new();
    for &r in &[1.0, 0.6, 1.7, 0.35, 2.9] {
        for &th in &[1.3, 1.9, 0.8, 2.6, 0.35, 1.57] {
            let s = Complex64::from_polar(rho * r, th);
            let dist = poles
                .iter()
                .chain(zeros)
                .map(|p| (s - p).norm() / s.norm())
                .fold(f64::INFINITY, f64::min);
            cands.push((dist, s));
        }
    }
    cands.sort_by(|a, b| b.0.total_cmp(&a.0));
    let (mut num, mut den) = (Complex64::new(0.0, 0.0), 0.0);
    for &(_, s) in cands.iter().take(3) {
        let g = crate::analysis::evaluate_at(sys.a(), sys.b(), sys.c(), sys.d(), s, "gain fit")?
            [(0, 0)];
        let shape = zeros
            .iter()
            .fold(Complex64::new(1.0, 0.0), |acc, z| acc * (s - z))
            / poles
                .iter()
                .fold(Complex64::new(1.0, 0.0), |acc, p| acc * (s - p));
        num += shape.conj() * g;
        den += shape.norm_sqr();
    }
    Ok(num.re / den)
}

impl TransferFunction<Continuous> {
    /// A continuous-time transfer function from coefficients (descending powers of `s`).
    ///
    /// # Errors
    /// As [`TransferFunction::from_coefficients`].
    pub fn continuous(num: &[f64], den: &[f64]) -> Result<Self> {
        Self::from_coefficients(num, den, Continuous)
    }
}

impl TransferFunction<Discrete> {
    /// A discrete-time transfer function from coefficients (descending powers of `z`) with
    /// sample time `ts` seconds.
    ///
    /// # Errors
    /// As [`TransferFunction::from_coefficients`], [`LtiError::InvalidSampleTime`].
    pub fn discrete(num: &[f64], den: &[f64], ts: f64) -> Result<Self> {
        Self::from_coefficients(num, den, Discrete::new(ts)?)
    }

    /// Sample time in seconds.
    pub fn ts(&self) -> f64 {
        self.domain.ts()
    }
}

impl<D: TimeDomain> std::fmt::Display for TransferFunction<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let var = if self.domain.sample_time().is_some() {
            "z"
        } else {
            "s"
        };
        let n = self.num.to_string().replace('s', var);
        let d = self.den.to_string().replace('s', var);
        write!(f, "({n}) / ({d})")
    }
}

impl<D: TimeDomain> TryFrom<&StateSpace<D>> for TransferFunction<D> {
    type Error = LtiError;
    fn try_from(sys: &StateSpace<D>) -> Result<Self> {
        Self::from_state_space(sys)
    }
}

impl<D: TimeDomain> TryFrom<&TransferFunction<D>> for StateSpace<D> {
    type Error = LtiError;
    fn try_from(g: &TransferFunction<D>) -> Result<Self> {
        g.to_state_space()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn realisation_round_trip_keeps_coefficients() {
        // (2s² + 3s + 1)/(s³ + 4s² + 5s + 2) = (2s + 1)(s + 1)/((s + 1)²(s + 2)).
        let g = TransferFunction::continuous(&[2.0, 3.0, 1.0], &[1.0, 4.0, 5.0, 2.0]).unwrap();
        let sys = g.to_state_space().unwrap();
        let back = TransferFunction::from_state_space(&sys).unwrap();
        for (x, y) in back.num().coefficients().iter().zip(g.num().coefficients()) {
            assert!((x - y).abs() < 1e-12, "{back}");
        }
        for (x, y) in back.den().coefficients().iter().zip(g.den().coefficients()) {
            assert!((x - y).abs() < 1e-12, "{back}");
        }
    }

    #[test]
    fn dc_gain_cancels_common_factor_and_rejects_integrator() {
        // s/(s(s + 2)) → 1/2 as s → 0; 1/(s(s + 2)) has an integrator.
        let g = TransferFunction::continuous(&[1.0, 0.0], &[1.0, 2.0, 0.0]).unwrap();
        assert!((g.dc_gain().unwrap() - 0.5).abs() < 1e-15);
        let g = TransferFunction::continuous(&[1.0], &[1.0, 2.0, 0.0]).unwrap();
        assert!(matches!(
            g.dc_gain(),
            Err(LtiError::PoleAtEvaluationPoint { .. })
        ));
        // Discrete: 0.5/(z − 0.5) at z = 1 is 1.
        let g = TransferFunction::discrete(&[0.5], &[1.0, -0.5], 0.1).unwrap();
        assert!((g.dc_gain().unwrap() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn normalisation_overflow_is_an_error() {
        // Leading denominator coefficient 1e-300: dividing by it overflows the others.
        assert!(matches!(
            TransferFunction::continuous(&[1.0], &[1e-300, 1e10]),
            Err(LtiError::NonFinite { .. })
        ));
    }

    #[test]
    fn improper_is_rejected_for_realisation_only() {
        let pid = TransferFunction::continuous(&[0.8, 10.0, 5.0], &[1.0, 0.0]).unwrap();
        assert!(matches!(
            pid.to_state_space(),
            Err(LtiError::Improper { .. })
        ));
        let v = pid.eval(Complex64::new(0.0, 2.0));
        // 0.8 s + 10 + 5/s at s = 2j: 10 + j(1.6 − 2.5).
        assert!((v - Complex64::new(10.0, -0.9)).norm() < 1e-14);
    }
}
