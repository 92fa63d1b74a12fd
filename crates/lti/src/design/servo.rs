//! LQ integral servo (book §6.3) and observer-based output feedback.

use super::lqr::{Lqr, check_gain, lqr};
use crate::domain::TimeDomain;
use crate::error::{LtiError, Result};
use crate::linalg::{Mat, check_finite, check_shape};
use crate::state_space::StateSpace;

/// The plant augmented with the integral of the tracking error, `(Ã, B̃)`.
///
/// Continuous time (book eq. 6.40): `w = ∫(r − y) dt`, so with `r = 0`
/// `Ã = [[A, 0], [−C, 0]]`, `B̃ = [B; −D]` on the state `[x; w]` (`B̃ = [B; 0]` when `D = 0`,
/// as in the book). Discrete time: `w_{k+1} = w_k + (r_k − y_k)`, `Ã = [[A, 0], [−C, I]]`,
/// `B̃ = [B; −D]`.
///
/// # Errors
/// None beyond construction; returns `Result` for a uniform design API.
pub fn integral_augmentation<D: TimeDomain>(sys: &StateSpace<D>) -> Result<(Mat, Mat)> {
    let (n, m, p) = (sys.nx(), sys.nu(), sys.ny());
    let mut a = Mat::zeros(n + p, n + p);
    a.view_mut((0, 0), (n, n)).copy_from(sys.a());
    a.view_mut((n, 0), (p, n)).copy_from(&(-sys.c()));
    if sys.domain().sample_time().is_some() {
        for i in 0..p {
            a[(n + i, n + i)] = 1.0;
        }
    }
    let mut b = Mat::zeros(n + p, m);
    b.view_mut((0, 0), (n, m)).copy_from(sys.b());
    b.view_mut((n, 0), (p, m)).copy_from(&(-sys.d()));
    Ok((a, b))
}

/// An LQ integral servo `u = −K₁ x − K₂ w`, `w = ∫(r − y)`.
#[derive(Debug, Clone, PartialEq)]
pub struct LqServo {
    /// State gain `K₁` (`m × n`).
    pub state_gain: Mat,
    /// Integral gain `K₂` (`m × p`).
    pub integral_gain: Mat,
    /// The LQR on the augmented system (gain `[K₁, K₂]`).
    pub lqr: Lqr,
}

/// LQ integral servo (book §6.3): [`lqr`] on [`integral_augmentation`] with weight `Q`
/// (`(n + p) × (n + p)`, on `[x; w]`), `R` (`m × m`), giving `u = −K₁ x − K₂ w` with
/// `w = ∫(r − y) dt`. The book's gains are `K₁_book = −K₁`, `K₂_book = −K₂`.
///
/// The augmented pair is stabilisable iff `(A, B)` is and the plant has no transmission zero
/// at `s = 0` (`z = 1`) — otherwise the Riccati solver reports it.
///
/// # Errors
/// As [`lqr`]; shape errors naming `Q`.
pub fn lq_servo<D: TimeDomain>(sys: &StateSpace<D>, q: &Mat, r: &Mat) -> Result<LqServo> {
    let (n, p) = (sys.nx(), sys.ny());
    check_shape("Q (augmented [x; w])", q, n + p, n + p)?;
    let (a, b) = integral_augmentation(sys)?;
    let aug = StateSpace::new(
        a,
        b,
        Mat::zeros(0, n + p),
        Mat::zeros(0, sys.nu()),
        sys.domain(),
    )?;
    let l = lqr(&aug, q, r, None)?;
    Ok(LqServo {
        state_gain: l.gain.columns(0, n).clone_owned(),
        integral_gain: l.gain.columns(n, p).clone_owned(),
        lqr: l,
    })
}

/// Observer-based output-feedback controller (MATLAB `reg(sys, K, L)`): from `y` to `u`,
/// `x̂' = (A − BK − LC + LDK) x̂ + L y`, `u = −K x̂`, for state feedback `u = −Kx` and a
/// full-order observer with gain `L` (`A − LC`). Its poles together with the plant's give
/// `eig(A − BK) ∪ eig(A − LC)` (separation principle). In the book's signs
/// (`K_book = −K`, `L_book = −L`) this is `(A + BK_book + L_book C, −L_book, K_book)`.
///
/// # Errors
/// [`LtiError::DimensionMismatch`] for `K` not `nu × nx` or `L` not `nx × ny`;
/// [`LtiError::NonFinite`].
#[doc(alias = "reg")]
pub fn observer_controller<D: TimeDomain>(
    sys: &StateSpace<D>,
    k: &Mat,
    l: &Mat,
) -> Result<StateSpace<D>> {
    check_gain(sys, k, "K")?;
    check_shape("L", l, sys.nx(), sys.ny())?;
    check_finite("L", l)?;
    let a = sys.a() - sys.b() * k - l * sys.c() + l * sys.d() * k;
    let c = -k;
    let d = Mat::zeros(sys.nu(), sys.ny());
    StateSpace::new(a, l.clone(), c, d, sys.domain()).map_err(|e| match e {
        LtiError::NonFinite { .. } => e,
        other => other,
    })
}
