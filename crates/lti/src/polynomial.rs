//! Real polynomials in one variable, coefficients in **descending** powers (MATLAB's order):
//! `[1, 2, 3]` is `s² + 2 s + 3`.
//!
//! [`Polynomial`] supports the arithmetic transfer functions need (`+`, `−`, `×`, scaling,
//! division with remainder), evaluation at real and complex points (Horner's rule), roots
//! (eigenvalues of the balanced companion matrix, MATLAB `roots`) and construction from roots
//! (MATLAB `poly`).

use crate::error::{LtiError, Result};
use crate::linalg::{Complex64, Mat};

/// A real polynomial `p(s) = c₀ sⁿ + c₁ sⁿ⁻¹ + … + cₙ` stored as `[c₀, …, cₙ]`.
///
/// Invariants: every coefficient is finite; the leading coefficient is non-zero unless the
/// polynomial is the zero polynomial, which is stored as `[0]` (degree 0 by convention, and
/// [`Polynomial::is_zero`] tells it apart).
#[derive(Debug, Clone, PartialEq)]
pub struct Polynomial {
    c: Vec<f64>,
}

impl Polynomial {
    /// Polynomial from coefficients in descending powers. Leading exact zeros are dropped;
    /// an empty slice is the zero polynomial.
    ///
    /// # Errors
    /// [`LtiError::NonFinite`] naming the first NaN or infinite coefficient.
    pub fn new(coefficients: &[f64]) -> Result<Self> {
        if let Some((i, &v)) = coefficients
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_finite())
        {
            return Err(LtiError::NonFinite {
                what: "polynomial coefficients".into(),
                row: 0,
                col: i,
                value: v,
            });
        }
        Ok(Self::from_vec_unchecked(coefficients.to_vec()))
    }

    /// Builds from finite coefficients (internal: callers guarantee finiteness).
    pub(crate) fn from_vec_unchecked(mut c: Vec<f64>) -> Self {
        let first = c.iter().position(|&v| v != 0.0).unwrap_or(c.len());
        c.drain(..first);
        if c.is_empty() {
            c.push(0.0);
        }
        Self { c }
    }

    /// The constant polynomial `k`.
    ///
    /// # Errors
    /// [`LtiError::NonFinite`] if `k` is not finite.
    pub fn constant(k: f64) -> Result<Self> {
        Self::new(&[k])
    }

    /// The zero polynomial.
    pub fn zero() -> Self {
        Self { c: vec![0.0] }
    }

    /// The constant polynomial 1.
    pub fn one() -> Self {
        Self { c: vec![1.0] }
    }

    /// The monic polynomial `Π (s − rᵢ)` with the given roots (MATLAB `poly`).
    ///
    /// Complex roots must come in conjugate pairs for the result to be real; the product is
    /// formed in complex arithmetic and the imaginary parts (rounding residue for conjugate
    /// sets) are discarded.
    ///
    /// # Errors
    /// [`LtiError::NonFinite`] if a root is not finite; [`LtiError::InvalidArgument`] if the
    /// roots are not closed under conjugation (a root's conjugate is missing).
    #[doc(alias = "poly")]
    pub fn from_roots(roots: &[Complex64]) -> Result<Self> {
        for (i, r) in roots.iter().enumerate() {
            if !(r.re.is_finite() && r.im.is_finite()) {
                return Err(LtiError::NonFinite {
                    what: "polynomial roots".into(),
                    row: 0,
                    col: i,
                    value: if r.re.is_finite() { r.im } else { r.re },
                });
            }
        }
        check_conjugate_closed(roots)?;
        Ok(Self::from_vec_unchecked(poly_from_roots(roots)))
    }

    /// Coefficients in descending powers (`[c₀, …, cₙ]`, `c₀ ≠ 0` unless zero).
    pub fn coefficients(&self) -> &[f64] {
        &self.c
    }

    /// Degree (0 for constants, including the zero polynomial).
    pub fn degree(&self) -> usize {
        self.c.len() - 1
    }

    /// `true` for the zero polynomial.
    pub fn is_zero(&self) -> bool {
        self.c.len() == 1 && self.c[0] == 0.0
    }

    /// Leading coefficient `c₀`.
    pub fn leading(&self) -> f64 {
        self.c[0]
    }

    /// Coefficient of `sᵏ` (0 beyond the degree).
    pub fn coefficient_of_power(&self, k: usize) -> f64 {
        let n = self.degree();
        if k > n { 0.0 } else { self.c[n - k] }
    }

    /// Value at a real point (Horner's rule).
    pub fn eval(&self, s: f64) -> f64 {
        self.c.iter().fold(0.0, |acc, &c| acc * s + c)
    }

    /// Value at a complex point (Horner's rule).
    pub fn eval_complex(&self, s: Complex64) -> Complex64 {
        self.c
            .iter()
            .fold(Complex64::new(0.0, 0.0), |acc, &c| acc * s + c)
    }

    /// `k · p`.
    pub fn scale(&self, k: f64) -> Self {
        Self::from_vec_unchecked(self.c.iter().map(|&c| c * k).collect())
    }

    /// `p / c₀` (monic). The zero polynomial is returned unchanged.
    pub fn monic(&self) -> Self {
        if self.is_zero() {
            return self.clone();
        }
        self.scale(1.0 / self.c[0])
    }

    /// Derivative `dp/ds`.
    pub fn derivative(&self) -> Self {
        let n = self.degree();
        if n == 0 {
            return Self::zero();
        }
        Self::from_vec_unchecked(
            self.c[..n]
                .iter()
                .enumerate()
                .map(|(i, &c)| c * (n - i) as f64)
                .collect(),
        )
    }

    /// Sum `p + q` (also available as `&p + &q`).
    pub fn plus(&self, other: &Self) -> Self {
        let n = self.c.len().max(other.c.len());
        let mut out = vec![0.0; n];
        for (i, &v) in self.c.iter().rev().enumerate() {
            out[n - 1 - i] += v;
        }
        for (i, &v) in other.c.iter().rev().enumerate() {
            out[n - 1 - i] += v;
        }
        Self::from_vec_unchecked(out)
    }

    /// Difference `p − q` (also available as `&p - &q`).
    pub fn minus(&self, other: &Self) -> Self {
        self.plus(&other.scale(-1.0))
    }

    /// Product `p · q`, the convolution of the coefficient vectors (MATLAB `conv`; also
    /// available as `&p * &q`).
    #[doc(alias = "conv")]
    pub fn times(&self, other: &Self) -> Self {
        if self.is_zero() || other.is_zero() {
            return Self::zero();
        }
        let mut out = vec![0.0; self.c.len() + other.c.len() - 1];
        for (i, &a) in self.c.iter().enumerate() {
            for (j, &b) in other.c.iter().enumerate() {
                out[i + j] += a * b;
            }
        }
        Self::from_vec_unchecked(out)
    }

    /// Polynomial division `p = q · d + r` with `deg r < deg d` (MATLAB `deconv`).
    ///
    /// # Errors
    /// [`LtiError::InvalidArgument`] if `d` is the zero polynomial.
    #[doc(alias = "deconv")]
    pub fn div_rem(&self, d: &Self) -> Result<(Self, Self)> {
        if d.is_zero() {
            return Err(LtiError::InvalidArgument(
                "polynomial division by the zero polynomial".into(),
            ));
        }
        let (n, m) = (self.degree(), d.degree());
        if n < m || self.is_zero() {
            return Ok((Self::zero(), self.clone()));
        }
        let mut r = self.c.clone();
        let mut q = vec![0.0; n - m + 1];
        for i in 0..=n - m {
            let f = r[i] / d.c[0];
            q[i] = f;
            for (j, &dj) in d.c.iter().enumerate() {
                r[i + j] -= f * dj;
            }
            r[i] = 0.0;
        }
        Ok((
            Self::from_vec_unchecked(q),
            Self::from_vec_unchecked(r[n - m + 1..].to_vec()),
        ))
    }

    /// Roots (MATLAB `roots`): eigenvalues of the companion matrix of the monic polynomial,
    /// after balancing (Parlett–Reinsch diagonal scaling by powers of 2, which is exact and
    /// makes the eigenvalue computation backward stable in a relative sense; the method of
    /// MATLAB's `roots`, Edelman & Murakami 1995). Exact zero trailing coefficients give exact
    /// zero roots. Sorted as [`sort_eigenvalues`](crate::linalg::sort_eigenvalues); conjugate
    /// pairs are exact conjugates.
    ///
    /// # Errors
    /// [`LtiError::NoConvergence`] if the eigenvalue iteration fails. The zero polynomial has
    /// no roots list ([`LtiError::InvalidArgument`]).
    pub fn roots(&self) -> Result<Vec<Complex64>> {
        if self.is_zero() {
            return Err(LtiError::InvalidArgument(
                "the zero polynomial has every number as a root".into(),
            ));
        }
        let c = &self.c;
        let trailing = c.iter().rev().take_while(|&&v| v == 0.0).count();
        let core = &c[..c.len() - trailing];
        let n = core.len() - 1;
        let mut out = vec![Complex64::new(0.0, 0.0); trailing];
        if n > 0 {
            let mut comp = Mat::zeros(n, n);
            for j in 0..n {
                comp[(0, j)] = -core[j + 1] / core[0];
            }
            for i in 1..n {
                comp[(i, i - 1)] = 1.0;
            }
            balance_in_place(&mut comp);
            out.extend(crate::linalg::eigenvalues(&comp)?);
        }
        crate::linalg::sort_eigenvalues(&mut out);
        Ok(out)
    }
}

impl std::ops::Add for &Polynomial {
    type Output = Polynomial;
    fn add(self, rhs: Self) -> Polynomial {
        self.plus(rhs)
    }
}

impl std::ops::Sub for &Polynomial {
    type Output = Polynomial;
    fn sub(self, rhs: Self) -> Polynomial {
        self.minus(rhs)
    }
}

impl std::ops::Mul for &Polynomial {
    type Output = Polynomial;
    fn mul(self, rhs: Self) -> Polynomial {
        self.times(rhs)
    }
}

impl std::ops::Neg for &Polynomial {
    type Output = Polynomial;
    fn neg(self) -> Polynomial {
        self.scale(-1.0)
    }
}

impl std::fmt::Display for Polynomial {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let n = self.degree();
        let mut first = true;
        for (i, &c) in self.c.iter().enumerate() {
            if c == 0.0 && !(first && i == n) {
                continue;
            }
            let p = n - i;
            let sign = if c < 0.0 { "-" } else { "+" };
            if first {
                if c < 0.0 {
                    write!(f, "-")?;
                }
            } else {
                write!(f, " {sign} ")?;
            }
            let a = c.abs();
            match p {
                0 => write!(f, "{a}")?,
                _ if a == 1.0 => {}
                _ => write!(f, "{a} ")?,
            }
            match p {
                0 => {}
                1 => write!(f, "s")?,
                _ => write!(f, "s^{p}")?,
            }
            first = false;
        }
        Ok(())
    }
}

/// Monic polynomial coefficients (descending) of `Π (s − rᵢ)`, formed in complex arithmetic,
/// real parts kept.
pub(crate) fn poly_from_roots(roots: &[Complex64]) -> Vec<f64> {
    let mut c = vec![Complex64::new(1.0, 0.0)];
    for &r in roots {
        let mut next = vec![Complex64::new(0.0, 0.0); c.len() + 1];
        for (i, &ci) in c.iter().enumerate() {
            next[i] += ci;
            next[i + 1] -= ci * r;
        }
        c = next;
    }
    c.into_iter().map(|z| z.re).collect()
}

/// Checks that every non-real root has its conjugate in the list (to a relative tolerance of
/// 1e-8 of its modulus, loose enough for computed eigenvalues, tight enough to catch a
/// genuinely missing partner).
pub(crate) fn check_conjugate_closed(roots: &[Complex64]) -> Result<()> {
    let mut used = vec![false; roots.len()];
    for i in 0..roots.len() {
        let r = roots[i];
        if r.im == 0.0 || used[i] {
            continue;
        }
        let tol = 1e-8 * r.norm().max(1e-300);
        let partner = (0..roots.len())
            .filter(|&j| j != i && !used[j])
            .map(|j| (j, (roots[j] - r.conj()).norm()))
            .filter(|&(_, d)| d <= tol)
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match partner {
            Some((j, _)) => {
                used[i] = true;
                used[j] = true;
            }
            None => {
                return Err(LtiError::InvalidArgument(format!(
                    "root {}{:+}j has no complex-conjugate partner; a real polynomial needs one",
                    r.re, r.im
                )));
            }
        }
    }
    Ok(())
}

/// Parlett–Reinsch balancing (LAPACK `gebal`, scaling only): diagonal similarity by powers of
/// two so that row and column norms are comparable. Exact in floating point.
pub(crate) fn balance_in_place(a: &mut Mat) {
    let n = a.nrows();
    let radix = 2.0f64;
    let mut converged = false;
    let mut sweeps = 0;
    while !converged && sweeps < 100 {
        converged = true;
        sweeps += 1;
        for i in 0..n {
            let mut c = 0.0;
            let mut r = 0.0;
            for j in 0..n {
                if j != i {
                    c += a[(j, i)].abs();
                    r += a[(i, j)].abs();
                }
            }
            if c == 0.0 || r == 0.0 {
                continue;
            }
            let s = c + r;
            let mut f = 1.0;
            let mut cc = c;
            let mut rr = r;
            while cc < rr / radix {
                cc *= radix;
                rr /= radix;
                f *= radix;
            }
            while cc >= rr * radix {
                cc /= radix;
                rr *= radix;
                f /= radix;
            }
            if (cc + rr) < 0.95 * s {
                converged = false;
                for j in 0..n {
                    a[(i, j)] /= f;
                }
                for j in 0..n {
                    a[(j, i)] *= f;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arithmetic_matches_hand_expansion() {
        // (s + 1)(s + 2) = s² + 3s + 2, by hand.
        let p = Polynomial::new(&[1.0, 1.0]).unwrap();
        let q = Polynomial::new(&[1.0, 2.0]).unwrap();
        assert_eq!((&p * &q).coefficients(), &[1.0, 3.0, 2.0]);
        assert_eq!((&p + &q).coefficients(), &[2.0, 3.0]);
        assert_eq!((&p - &p).coefficients(), &[0.0]);
        assert!((&p - &p).is_zero());
        let (quo, rem) = (&(&p * &q) + &Polynomial::one()).div_rem(&p).unwrap();
        assert_eq!(quo.coefficients(), &[1.0, 2.0]);
        assert_eq!(rem.coefficients(), &[1.0]);
        assert_eq!(
            Polynomial::new(&[3.0, 2.0, 1.0])
                .unwrap()
                .derivative()
                .coefficients(),
            &[6.0, 2.0]
        );
        assert_eq!(Polynomial::new(&[0.0, 0.0, 2.0]).unwrap().degree(), 0);
        assert!(Polynomial::new(&[1.0, f64::NAN]).is_err());
    }

    #[test]
    fn roots_of_known_polynomials() {
        // s² + 1 has roots ±j; s³ − 6s² + 11s − 6 = (s−1)(s−2)(s−3); s²·(s+1) has a double 0.
        let r = Polynomial::new(&[1.0, 0.0, 1.0]).unwrap().roots().unwrap();
        assert!((r[0] - Complex64::new(0.0, 1.0)).norm() < 1e-15);
        assert_eq!(r[1], r[0].conj());
        let r = Polynomial::new(&[1.0, -6.0, 11.0, -6.0])
            .unwrap()
            .roots()
            .unwrap();
        for (x, e) in r.iter().zip([3.0, 2.0, 1.0]) {
            assert!((x.re - e).abs() < 1e-13 && x.im == 0.0);
        }
        let r = Polynomial::new(&[1.0, 1.0, 0.0, 0.0])
            .unwrap()
            .roots()
            .unwrap();
        assert_eq!(r[0], Complex64::new(0.0, 0.0));
        assert_eq!(r[1], Complex64::new(0.0, 0.0));
        assert!((r[2].re + 1.0).abs() < 1e-15);
    }

    #[test]
    fn from_roots_round_trip_and_conjugate_check() {
        let roots = [
            Complex64::new(-1.0, 2.0),
            Complex64::new(-1.0, -2.0),
            Complex64::new(-3.0, 0.0),
        ];
        // (s² + 2s + 5)(s + 3) = s³ + 5s² + 11s + 15.
        let p = Polynomial::from_roots(&roots).unwrap();
        assert_eq!(p.coefficients(), &[1.0, 5.0, 11.0, 15.0]);
        assert!(Polynomial::from_roots(&roots[..1]).is_err());
        let s = Complex64::new(0.3, -0.7);
        let direct = (s - roots[0]) * (s - roots[1]) * (s - roots[2]);
        assert!((p.eval_complex(s) - direct).norm() < 1e-14);
    }
}
