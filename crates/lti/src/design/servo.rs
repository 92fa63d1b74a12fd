//! LQ integral servo (book §6.3), observer-based output feedback and the minimal-order
//! observer (book §7).

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

/// A minimal-order (Gopinath) observer, book §7.
///
/// With `T = [C; R]` (`R` an orthonormal basis of the complement of `C`'s row space) the
/// coordinates `x̄ = T x = [ȳ; w]` split the state into the measured part `ȳ = y − Du` and
/// the `n − p` unmeasured components `w`, `Ā = T A T⁻¹ = [[A₁₁, A₁₂], [A₂₁, A₂₂]]`,
/// `B̄ = T B = [B₁; B₂]`. The observer state `ζ = ŵ − Lȳ` obeys
/// `ζ' = (A₂₂ − LA₁₂) ζ + [(A₂₂ − LA₁₂)L + A₂₁ − LA₁₁] ȳ + (B₂ − LB₁) u`
/// (`ζ'` is `ζ̇` or `ζ[k+1]`), and the estimation error `w − ŵ` evolves with
/// `A₂₂ − LA₁₂`, whose poles `L` places. The estimate is `x̂ = T⁻¹ [ȳ; ζ + Lȳ]`.
#[derive(Debug, Clone, PartialEq)]
pub struct ReducedOrderObserver<D: TimeDomain> {
    /// The observer as a system: inputs `[u; y]`, state `ζ` (`n − p`), output `x̂` (`n`).
    pub system: StateSpace<D>,
    /// The gain `L` (`(n − p) × p`).
    pub gain: Mat,
    /// The transformation `T = [C; R]` (`x̄ = T x`).
    pub transformation: Mat,
    /// The placement of `eig(A₂₂ − LA₁₂)` with its accuracy.
    pub placement: super::PolePlacement,
}

/// Designs a minimal-order observer with error poles `poles` (`n − p` of them).
///
/// # Errors
/// [`LtiError::InvalidArgument`] if `C` does not have full row rank `p < n` or the number of
/// poles is not `n − p`; [`LtiError::NotControllable`] if `(A₁₂, A₂₂)` is unobservable (i.e.
/// `(C, A)` is not observable); as [`place`](super::place).
#[doc(alias = "gopinath")]
pub fn minimal_order_observer<D: TimeDomain>(
    sys: &StateSpace<D>,
    poles: &[crate::linalg::Complex64],
) -> Result<ReducedOrderObserver<D>> {
    let (n, m, p) = (sys.nx(), sys.nu(), sys.ny());
    let rk = crate::analysis::rank(sys.c());
    if p >= n || rk.rank < p {
        return Err(LtiError::InvalidArgument(format!(
            "minimal-order observer needs C with full row rank p < n; C is {p}x{n} with rank {}",
            rk.rank
        )));
    }
    let q = n - p;
    if poles.len() != q {
        return Err(LtiError::InvalidArgument(format!(
            "minimal-order observer needs n − p = {q} poles, got {}",
            poles.len()
        )));
    }
    // Complement of C's row space: the last n − p columns of the full Q of Cᵀ = Q R.
    let (qf, _, _) = crate::analysis::qr_column_pivoting(&sys.c().transpose());
    let mut t = Mat::zeros(n, n);
    t.view_mut((0, 0), (p, n)).copy_from(sys.c());
    t.view_mut((p, 0), (q, n))
        .copy_from(&qf.columns(p, q).transpose());
    let tinv = t.clone().try_inverse().ok_or(LtiError::Singular {
        what: "observer transformation [C; R]".into(),
        rcond: 0.0,
    })?;
    let abar = &t * sys.a() * &tinv;
    let bbar = &t * sys.b();
    let a11 = abar.view((0, 0), (p, p)).clone_owned();
    let a12 = abar.view((0, p), (p, q)).clone_owned();
    let a21 = abar.view((p, 0), (q, p)).clone_owned();
    let a22 = abar.view((p, p), (q, q)).clone_owned();
    let b1 = bbar.rows(0, p).clone_owned();
    let b2 = bbar.rows(p, q).clone_owned();
    let placement = super::place_observer(&a22, &a12, poles)?;
    let l = placement.gain.clone();
    let f = &a22 - &l * &a12;
    let g = &f * &l + &a21 - &l * &a11;
    let h = &b2 - &l * &b1;
    let m1 = tinv.columns(0, p).clone_owned();
    let m2 = tinv.columns(p, q).clone_owned();
    let my = &m1 + &m2 * &l;
    let d = sys.d();
    let mut b_obs = Mat::zeros(q, m + p);
    b_obs.view_mut((0, 0), (q, m)).copy_from(&(&h - &g * d));
    b_obs.view_mut((0, m), (q, p)).copy_from(&g);
    let mut d_obs = Mat::zeros(n, m + p);
    d_obs.view_mut((0, 0), (n, m)).copy_from(&(-(&my * d)));
    d_obs.view_mut((0, m), (n, p)).copy_from(&my);
    Ok(ReducedOrderObserver {
        system: StateSpace::new(f, b_obs, m2, d_obs, sys.domain())?,
        gain: l,
        transformation: t,
        placement,
    })
}
