//! Interconnections of systems: [`series`], [`parallel`], [`feedback`], [`append`] for
//! state space, and the same for SISO transfer functions ([`series_tf`], [`parallel_tf`],
//! [`feedback_tf`]).
//!
//! Both systems must be in the same time domain (the type enforces continuous/discrete, the
//! functions check equal sample times). Nothing is cancelled: the state of a series
//! connection is `[x₁; x₂]`, the denominator of a transfer-function product is the product
//! of the denominators.

use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::linalg::Mat;
use crate::state_space::StateSpace;
use crate::transfer_function::TransferFunction;

/// The sign with which the feedback path enters the summing junction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FeedbackSign {
    /// `e = r − H y` (MATLAB's default, `feedback(G, H)`).
    #[default]
    Negative,
    /// `e = r + H y` (`feedback(G, H, +1)`).
    Positive,
}

impl FeedbackSign {
    fn sigma(self) -> f64 {
        match self {
            FeedbackSign::Negative => -1.0,
            FeedbackSign::Positive => 1.0,
        }
    }
}

fn block_diag(a1: &Mat, a2: &Mat) -> Mat {
    let (r1, c1) = a1.shape();
    let (r2, c2) = a2.shape();
    let mut out = Mat::zeros(r1 + r2, c1 + c2);
    out.view_mut((0, 0), (r1, c1)).copy_from(a1);
    out.view_mut((r1, c1), (r2, c2)).copy_from(a2);
    out
}

fn stack(top: &Mat, bottom: &Mat) -> Mat {
    let mut out = Mat::zeros(top.nrows() + bottom.nrows(), top.ncols());
    out.view_mut((0, 0), top.shape()).copy_from(top);
    out.view_mut((top.nrows(), 0), bottom.shape())
        .copy_from(bottom);
    out
}

fn side(left: &Mat, right: &Mat) -> Mat {
    let mut out = Mat::zeros(left.nrows(), left.ncols() + right.ncols());
    out.view_mut((0, 0), left.shape()).copy_from(left);
    out.view_mut((0, left.ncols()), right.shape())
        .copy_from(right);
    out
}

/// Series connection `u → sys1 → sys2 → y` (MATLAB `series(sys1, sys2)` = `sys2 * sys1`).
///
/// State `[x₁; x₂]`: `A = [[A₁, 0], [B₂C₁, A₂]]`, `B = [B₁; B₂D₁]`, `C = [D₂C₁, C₂]`,
/// `D = D₂D₁`.
///
/// # Errors
/// [`LtiError::DimensionMismatch`] unless `ny(sys1) = nu(sys2)`;
/// [`LtiError::SampleTimeMismatch`].
pub fn series<D: TimeDomain>(sys1: &StateSpace<D>, sys2: &StateSpace<D>) -> Result<StateSpace<D>> {
    sys1.domain().check_compatible(&sys2.domain())?;
    if sys1.ny() != sys2.nu() {
        return Err(LtiError::DimensionMismatch {
            what: "series: inputs of sys2 (must equal outputs of sys1)".into(),
            expected: (sys1.ny(), 1),
            found: (sys2.nu(), 1),
        });
    }
    let (n1, n2) = (sys1.nx(), sys2.nx());
    let mut a = block_diag(sys1.a(), sys2.a());
    a.view_mut((n1, 0), (n2, n1))
        .copy_from(&(sys2.b() * sys1.c()));
    let b = stack(sys1.b(), &(sys2.b() * sys1.d()));
    let c = side(&(sys2.d() * sys1.c()), sys2.c());
    let d = sys2.d() * sys1.d();
    StateSpace::new(a, b, c, d, sys1.domain())
}

/// Parallel connection `y = sys1 u + sys2 u` (MATLAB `parallel`, `sys1 + sys2`).
///
/// # Errors
/// [`LtiError::DimensionMismatch`] unless both have the same inputs and outputs;
/// [`LtiError::SampleTimeMismatch`].
pub fn parallel<D: TimeDomain>(
    sys1: &StateSpace<D>,
    sys2: &StateSpace<D>,
) -> Result<StateSpace<D>> {
    sys1.domain().check_compatible(&sys2.domain())?;
    if sys1.nu() != sys2.nu() || sys1.ny() != sys2.ny() {
        return Err(LtiError::DimensionMismatch {
            what: "parallel: sys2 outputs x inputs (must equal sys1's)".into(),
            expected: (sys1.ny(), sys1.nu()),
            found: (sys2.ny(), sys2.nu()),
        });
    }
    StateSpace::new(
        block_diag(sys1.a(), sys2.a()),
        stack(sys1.b(), sys2.b()),
        side(sys1.c(), sys2.c()),
        sys1.d() + sys2.d(),
        sys1.domain(),
    )
}

/// Feedback connection (MATLAB `feedback(sys1, sys2, sign)`): `y = sys1 e`,
/// `e = u ± sys2 y` with the sign given explicitly.
///
/// With `σ = −1` (negative) or `+1` (positive) the algebraic loop `e = u + σ(C₂x₂ + D₂y)`,
/// `y = C₁x₁ + D₁e` is solved with `E = (I − σD₂D₁)⁻¹`, giving the closed loop on the state
/// `[x₁; x₂]`.
///
/// # Errors
/// [`LtiError::DimensionMismatch`] unless `nu(sys2) = ny(sys1)` and `ny(sys2) = nu(sys1)`;
/// [`LtiError::Singular`] if the algebraic loop is ill-posed (`I − σD₂D₁` singular);
/// [`LtiError::SampleTimeMismatch`].
pub fn feedback<D: TimeDomain>(
    sys1: &StateSpace<D>,
    sys2: &StateSpace<D>,
    sign: FeedbackSign,
) -> Result<StateSpace<D>> {
    sys1.domain().check_compatible(&sys2.domain())?;
    if sys2.nu() != sys1.ny() || sys2.ny() != sys1.nu() {
        return Err(LtiError::DimensionMismatch {
            what: "feedback: sys2 outputs x inputs (must be sys1's inputs x outputs)".into(),
            expected: (sys1.nu(), sys1.ny()),
            found: (sys2.ny(), sys2.nu()),
        });
    }
    let s = sign.sigma();
    let m = sys1.nu();
    let loop_m = Mat::identity(m, m) - sys2.d() * sys1.d() * s;
    let rcond = 1.0 / crate::analysis::cond2(&loop_m);
    if m > 0 && (rcond.is_nan() || rcond <= m as f64 * f64::EPSILON) {
        return Err(LtiError::Singular {
            what: "feedback algebraic loop I ∓ D2 D1".into(),
            rcond,
        });
    }
    let e = loop_m
        .clone()
        .lu()
        .solve(&Mat::identity(m, m))
        .ok_or(LtiError::Singular {
            what: "feedback algebraic loop I ∓ D2 D1".into(),
            rcond,
        })?;
    let (a1, b1, c1, d1) = (sys1.a(), sys1.b(), sys1.c(), sys1.d());
    let (a2, b2, c2, d2) = (sys2.a(), sys2.b(), sys2.c(), sys2.d());
    // e = E u + E σ D₂ C₁ x₁ + E σ C₂ x₂
    let ex1 = &e * d2 * c1 * s;
    let ex2 = &e * c2 * s;
    // y = C₁x₁ + D₁e
    let yx1 = c1 + d1 * &ex1;
    let yx2 = d1 * &ex2;
    let yu = d1 * &e;
    let a11 = a1 + b1 * &ex1;
    let a12 = b1 * &ex2;
    let a21 = b2 * &yx1;
    let a22 = a2 + b2 * &yx2;
    let a = stack(&side(&a11, &a12), &side(&a21, &a22));
    let b = stack(&(b1 * &e), &(b2 * &yu));
    let c = side(&yx1, &yx2);
    StateSpace::new(a, b, c, yu, sys1.domain())
}

/// Block-diagonal append (MATLAB `append`): inputs and outputs of all systems side by side,
/// no coupling.
///
/// # Errors
/// [`LtiError::InvalidArgument`] for an empty list; [`LtiError::SampleTimeMismatch`].
pub fn append<D: TimeDomain>(systems: &[&StateSpace<D>]) -> Result<StateSpace<D>> {
    let first = systems
        .first()
        .ok_or_else(|| LtiError::InvalidArgument("append: no systems given".into()))?;
    let (mut a, mut b, mut c, mut d) = (
        first.a().clone(),
        first.b().clone(),
        first.c().clone(),
        first.d().clone(),
    );
    for s in &systems[1..] {
        first.domain().check_compatible(&s.domain())?;
        a = block_diag(&a, s.a());
        b = block_diag(&b, s.b());
        c = block_diag(&c, s.c());
        d = block_diag(&d, s.d());
    }
    StateSpace::new(a, b, c, d, first.domain())
}

/// Series connection of transfer functions, `g2 · g1`.
///
/// # Errors
/// [`LtiError::SampleTimeMismatch`].
pub fn series_tf<D: TimeDomain>(
    g1: &TransferFunction<D>,
    g2: &TransferFunction<D>,
) -> Result<TransferFunction<D>> {
    g1.domain().check_compatible(&g2.domain())?;
    TransferFunction::new(g1.num() * g2.num(), g1.den() * g2.den(), g1.domain())
}

/// Parallel connection of transfer functions, `g1 + g2 = (n₁d₂ + n₂d₁)/(d₁d₂)`.
///
/// # Errors
/// [`LtiError::SampleTimeMismatch`].
pub fn parallel_tf<D: TimeDomain>(
    g1: &TransferFunction<D>,
    g2: &TransferFunction<D>,
) -> Result<TransferFunction<D>> {
    g1.domain().check_compatible(&g2.domain())?;
    let num = &(g1.num() * g2.den()) + &(g2.num() * g1.den());
    TransferFunction::new(num, g1.den() * g2.den(), g1.domain())
}

/// Feedback of transfer functions: `g/(1 ∓ g h) = n_g d_h / (d_g d_h ∓ n_g n_h)` for
/// `e = r ∓ h y`.
///
/// # Errors
/// [`LtiError::Singular`] if the closed-loop denominator vanishes identically (an ill-posed
/// loop, e.g. `g h = 1` with positive feedback); [`LtiError::SampleTimeMismatch`].
pub fn feedback_tf<D: TimeDomain>(
    g: &TransferFunction<D>,
    h: &TransferFunction<D>,
    sign: FeedbackSign,
) -> Result<TransferFunction<D>> {
    g.domain().check_compatible(&h.domain())?;
    let loop_term = (g.num() * h.num()).scale(-sign.sigma());
    let den = &(g.den() * h.den()) + &loop_term;
    if den.is_zero() {
        return Err(LtiError::Singular {
            what: "feedback: closed-loop denominator 1 ∓ g h is identically zero".into(),
            rcond: 0.0,
        });
    }
    TransferFunction::new(g.num() * h.den(), den, g.domain())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Continuous;
    use crate::linalg::Complex64;

    #[test]
    fn state_space_and_transfer_function_loops_agree_pointwise() {
        // G = 1/(s + 1), H = (s + 3)/(s + 5) with D ≠ 0 in H: compare both routes at points.
        let g = TransferFunction::continuous(&[2.0], &[1.0, 1.0]).unwrap();
        let h = TransferFunction::continuous(&[1.0, 3.0], &[1.0, 5.0]).unwrap();
        let (gs, hs) = (g.to_state_space().unwrap(), h.to_state_space().unwrap());
        for sign in [FeedbackSign::Negative, FeedbackSign::Positive] {
            let t = feedback_tf(&g, &h, sign).unwrap();
            let s = feedback(&gs, &hs, sign).unwrap();
            for w in [0.1, 1.0, 7.0] {
                let p = Complex64::new(0.0, w);
                // Closed form at p: G/(1 ∓ GH).
                let gp = g.eval(p);
                let hp = h.eval(p);
                let sgn = if sign == FeedbackSign::Negative {
                    1.0
                } else {
                    -1.0
                };
                let exact = gp / (1.0 + sgn * gp * hp);
                assert!((t.eval(p) - exact).norm() < 1e-13);
                assert!((s.evaluate(p).unwrap()[(0, 0)] - exact).norm() < 1e-13);
            }
        }
        let ser = series(&gs, &hs).unwrap();
        let par = parallel(&gs, &hs).unwrap();
        let p = Complex64::new(0.3, 2.0);
        assert!((ser.evaluate(p).unwrap()[(0, 0)] - g.eval(p) * h.eval(p)).norm() < 1e-13);
        assert!((par.evaluate(p).unwrap()[(0, 0)] - (g.eval(p) + h.eval(p))).norm() < 1e-13);
        assert!((series_tf(&g, &h).unwrap().eval(p) - g.eval(p) * h.eval(p)).norm() < 1e-13);
        assert!((parallel_tf(&g, &h).unwrap().eval(p) - (g.eval(p) + h.eval(p))).norm() < 1e-13);
        let ap = append(&[&gs, &hs]).unwrap();
        assert_eq!((ap.nu(), ap.ny(), ap.nx()), (2, 2, 2));
    }

    #[test]
    fn ill_posed_loop_is_an_error() {
        let one = StateSpace::static_gain(Mat::from_element(1, 1, 1.0), Continuous).unwrap();
        assert!(matches!(
            feedback(&one, &one, FeedbackSign::Positive),
            Err(LtiError::Singular { .. })
        ));
        let g = TransferFunction::gain(1.0, Continuous).unwrap();
        assert!(feedback_tf(&g, &g, FeedbackSign::Positive).is_err());
    }
}
