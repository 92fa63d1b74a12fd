//! Pole placement: [`place`] (robust, any number of inputs), [`acker`] (Ackermann's formula,
//! single input) and [`place_observer`] (observer gains by duality).
//!
//! All gains follow the library convention `u = −K x`: the closed loop is `A − B K`.

use crate::analysis::controllability_staircase;
use crate::error::{LtiError, Result};
use crate::linalg::{CMat, Complex64, Mat, check_finite, check_shape, check_square};
use crate::polynomial::check_conjugate_closed;

/// Which algorithm produced a pole-placement gain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlacementMethod {
    /// Ackermann's formula `K = e_nᵀ M_c⁻¹ φ(A)` on the original coordinates ([`acker`]).
    Ackermann,
    /// Ackermann's formula in the orthogonal controller-Hessenberg coordinates of the
    /// single-input staircase form, where `M_c` is triangular (used by [`place`] for single
    /// input when poles repeat).
    HessenbergAckermann,
    /// Kautsky–Nichols–Van Dooren robust assignment, method 0 (used by [`place`]).
    KautskyNicholsVanDooren,
    /// Reduction to a single input `B g` after an auxiliary feedback, then Hessenberg
    /// Ackermann (used by [`place`] when a pole's multiplicity exceeds `rank B`, which no
    /// diagonalisable closed loop can achieve).
    SingleInputReduction,
}

/// A pole-placement result with its accuracy.
#[derive(Debug, Clone, PartialEq)]
pub struct PolePlacement {
    /// The gain: `K` (`m × n`, closed loop `A − BK`) from [`place`]/[`acker`], or `L`
    /// (`n × p`, observer `A − LC`) from [`place_observer`].
    pub gain: Mat,
    /// The requested poles, sorted as [`sort_eigenvalues`](crate::linalg::sort_eigenvalues).
    pub requested_poles: Vec<Complex64>,
    /// Eigenvalues of the closed loop (`A − BK` or `A − LC`), sorted likewise.
    pub achieved_poles: Vec<Complex64>,
    /// `max |λ_achieved − λ_requested| / max(1, |λ_requested|)` over a nearest matching of
    /// the two sets.
    pub max_relative_error: f64,
    /// 2-norm condition number of the closed-loop eigenvector matrix (KNV's robustness
    /// measure; `NaN` when the method does not form it).
    pub eigenvector_condition: f64,
    /// The algorithm used.
    pub method: PlacementMethod,
    /// KNV sweeps performed (0 for the other methods).
    pub iterations: usize,
}

fn validate(a: &Mat, b: &Mat, poles: &[Complex64]) -> Result<()> {
    check_square("A", a)?;
    check_shape("B", b, a.nrows(), b.ncols())?;
    check_finite("A", a)?;
    check_finite("B", b)?;
    if poles.len() != a.nrows() {
        // The list shows the conjugates a caller may have added to complex poles.
        let list: Vec<String> = poles
            .iter()
            .map(|p| {
                if p.im == 0.0 {
                    format!("{}", p.re)
                } else {
                    format!("{}{:+}i", p.re, p.im)
                }
            })
            .collect();
        return Err(LtiError::InvalidArgument(format!(
            "pole placement needs {} poles (one per state), got {}: {}",
            a.nrows(),
            poles.len(),
            list.join(", ")
        )));
    }
    for (i, p) in poles.iter().enumerate() {
        if !(p.re.is_finite() && p.im.is_finite()) {
            return Err(LtiError::NonFinite {
                what: "requested poles".into(),
                row: i,
                col: 0,
                value: if p.re.is_finite() { p.im } else { p.re },
            });
        }
    }
    check_conjugate_closed(poles)?;
    Ok(())
}

fn require_controllable(a: &Mat, b: &Mat) -> Result<()> {
    let st = controllability_staircase(a, b, None)?;
    if st.controllable_dimension < a.nrows() {
        return Err(LtiError::NotControllable {
            controllable_dimension: st.controllable_dimension,
            nx: a.nrows(),
            mode: st
                .uncontrollable_modes()?
                .first()
                .copied()
                .unwrap_or_default(),
        });
    }
    Ok(())
}

/// Greedy nearest matching of two equally long pole lists; returns the max relative error.
pub(crate) fn match_error(requested: &[Complex64], achieved: &[Complex64]) -> f64 {
    let mut used = vec![false; achieved.len()];
    let mut worst: f64 = 0.0;
    // Match the requested poles in order of decreasing modulus: the large ones dominate.
    let mut order: Vec<usize> = (0..requested.len()).collect();
    order.sort_by(|&i, &j| requested[j].norm().total_cmp(&requested[i].norm()));
    for i in order {
        let r = requested[i];
        let best = (0..achieved.len()).filter(|&j| !used[j]).min_by(|&x, &y| {
            (achieved[x] - r)
                .norm()
                .total_cmp(&(achieved[y] - r).norm())
        });
        if let Some(j) = best {
            used[j] = true;
            worst = worst.max((achieved[j] - r).norm() / r.norm().max(1.0));
        }
    }
    worst
}

fn finish(
    a: &Mat,
    b: &Mat,
    gain: Mat,
    poles: &[Complex64],
    method: PlacementMethod,
    eigenvector_condition: f64,
    iterations: usize,
) -> Result<PolePlacement> {
    check_finite("placement gain", &gain)?;
    let achieved = crate::linalg::eigenvalues(&(a - b * &gain))?;
    let mut requested = poles.to_vec();
    crate::linalg::sort_eigenvalues(&mut requested);
    let max_relative_error = match_error(&requested, &achieved);
    Ok(PolePlacement {
        gain,
        requested_poles: requested,
        achieved_poles: achieved,
        max_relative_error,
        eigenvector_condition,
        method,
        iterations,
    })
}

/// `v ↦ vᵀ Π (A − λᵢ I)` for a real row vector, conjugate pairs applied as the real quadratic
/// `A² − 2 Re λ A + |λ|² I`.
fn row_times_poly(row: &Mat, a: &Mat, poles: &[Complex64]) -> Mat {
    let mut v = row.clone();
    let mut used = vec![false; poles.len()];
    for i in 0..poles.len() {
        if used[i] {
            continue;
        }
        used[i] = true;
        let p = poles[i];
        if p.im == 0.0 {
            v = &v * a - &v * p.re;
        } else {
            if let Some(j) = (0..poles.len()).filter(|&j| !used[j]).min_by(|&x, &y| {
                (poles[x] - p.conj())
                    .norm()
                    .total_cmp(&(poles[y] - p.conj()).norm())
            }) {
                used[j] = true;
            }
            let va = &v * a;
            v = &va * a - &va * (2.0 * p.re) + &v * p.norm_sqr();
        }
    }
    v
}

/// Ackermann's formula for a single input (MATLAB `acker`): `K = e_nᵀ M_c⁻¹ φ(A)` with
/// `M_c = [b, Ab, …, Aⁿ⁻¹b]` and `φ(s) = Π(s − λᵢ)`, closed loop `A − bK`.
///
/// Works for any multiplicities. Numerically it is only as good as `M_c` is conditioned
/// (MATLAB warns beyond `n ≈ 10`); [`place`] is the robust choice, this is the textbook's
/// formula, kept for comparison and teaching.
///
/// # Errors
/// [`LtiError::InvalidArgument`] unless `B` has one column and `n` poles are given, or if a
/// complex pole lacks its conjugate; [`LtiError::NotControllable`]; [`LtiError::NonFinite`].
pub fn acker(a: &Mat, b: &Mat, poles: &[Complex64]) -> Result<PolePlacement> {
    validate(a, b, poles)?;
    if b.ncols() != 1 {
        return Err(LtiError::InvalidArgument(format!(
            "acker needs a single input, B has {} columns",
            b.ncols()
        )));
    }
    require_controllable(a, b)?;
    let n = a.nrows();
    let mc = crate::analysis::ctrb(a, b)?;
    let mut en = Mat::zeros(n, 1);
    en[(n - 1, 0)] = 1.0;
    let w = mc.transpose().lu().solve(&en).ok_or(LtiError::Singular {
        what: "controllability matrix in Ackermann's formula".into(),
        rcond: 0.0,
    })?;
    let k = row_times_poly(&w.transpose(), a, poles);
    finish(a, b, k, poles, PlacementMethod::Ackermann, f64::NAN, 0)
}

/// Single-input placement in staircase (controller-Hessenberg) coordinates:
/// `Ã = ZᵀAZ` upper Hessenberg, `b̃ = Zᵀb = β e₁`, so `M̃_c` is upper triangular with last
/// diagonal entry `β Π h_{i+1,i}` and `K̃ = e_nᵀ φ(Ã) / (β Π h_{i+1,i})`, `K = K̃ Zᵀ`.
fn hessenberg_ackermann(a: &Mat, b: &Mat, poles: &[Complex64]) -> Result<Mat> {
    let n = a.nrows();
    let st = controllability_staircase(a, b, None)?;
    if st.controllable_dimension < n {
        return Err(LtiError::NotControllable {
            controllable_dimension: st.controllable_dimension,
            nx: n,
            mode: st
                .uncontrollable_modes()?
                .first()
                .copied()
                .unwrap_or_default(),
        });
    }
    let mut scale = st.b[(0, 0)];
    for i in 0..n.saturating_sub(1) {
        scale *= st.a[(i + 1, i)];
    }
    let mut en = Mat::zeros(1, n);
    en[(0, n - 1)] = 1.0;
    let kt = row_times_poly(&en, &st.a, poles) / scale;
    Ok(kt * st.z.transpose())
}

/// Robust pole placement (MATLAB `place`): a gain `K` with `eig(A − BK)` equal to `poles`.
///
/// - Multi-input (and single input with distinct poles): Kautsky, Nichols & Van Dooren,
///   "Robust pole assignment in linear state feedback", Int. J. Control 41(5), 1985, method
///   0. With `B = [U₀ U₁][Z; 0]`, each closed-loop eigenvector `xⱼ` is chosen in
///   `Sⱼ = ker U₁ᵀ(A − λⱼI)` (from an SVD), and the vectors are re-chosen one at a time to be
///   as orthogonal as possible to the others (projection of the `j`-th row of `X⁻¹`), which
///   minimises the eigenvalue sensitivity `cond(X)`. Complex pairs use conjugate vectors.
///   Then `A − BK = XΛX⁻¹` gives `K = Z⁻¹U₀ᵀ(A − XΛX⁻¹)`. A rank-deficient `B` is
///   compressed to its range first (minimum-norm gain).
/// - A pole repeated more often than `rank B` admits no diagonalisable closed loop: with one
///   input the gain (unique) comes from Ackermann's formula in controller-Hessenberg
///   coordinates; with several, from a reduction to one input `B g` after an auxiliary
///   feedback that makes the loop cyclic.
///
/// The result reports the achieved poles and their relative error (check it: placing poles
/// is ill-conditioned for large `n` or far-moved poles).
///
/// # Errors
/// [`LtiError::InvalidArgument`] for a wrong number of poles or a complex pole without its
/// conjugate; [`LtiError::NotControllable`] if `(A, B)` is not controllable (then not every
/// pole set can be assigned); [`LtiError::NonFinite`]; [`LtiError::NoConvergence`].
pub fn place(a: &Mat, b: &Mat, poles: &[Complex64]) -> Result<PolePlacement> {
    validate(a, b, poles)?;
    let n = a.nrows();
    if n == 0 {
        return finish(
            a,
            b,
            Mat::zeros(b.ncols(), 0),
            poles,
            PlacementMethod::KautskyNicholsVanDooren,
            1.0,
            0,
        );
    }
    require_controllable(a, b)?;
    // Compress B to its range: B = U_r Σ_r V_rᵀ, place with B' = U_r Σ_r, K = V_r K'.
    let svd = crate::linalg::svd::svd(b);
    let (u, vt) = (&svd.u, &svd.v_t);
    let sv = &svd.singular_values;
    let tol = b.nrows().max(b.ncols()) as f64 * f64::EPSILON * sv.max();
    let r = sv.iter().filter(|&&s| s > tol).count();
    let (bp, vr) = if r == b.ncols() {
        (b.clone(), None)
    } else {
        let mut bp = u.columns(0, r).clone_owned();
        for j in 0..r {
            bp.column_mut(j).scale_mut(sv[j]);
        }
        (bp, Some(vt.rows(0, r).transpose()))
    };
    let lift = |k: Mat| match &vr {
        None => k,
        Some(v) => v * k,
    };
    let max_mult = max_multiplicity(poles);
    if max_mult > r {
        if r == 1 {
            let k = lift(hessenberg_ackermann(a, &bp, poles)?);
            return finish(
                a,
                b,
                k,
                poles,
                PlacementMethod::HessenbergAckermann,
                f64::NAN,
                0,
            );
        }
        let k = lift(single_input_reduction(a, &bp, poles)?);
        return finish(
            a,
            b,
            k,
            poles,
            PlacementMethod::SingleInputReduction,
            f64::NAN,
            0,
        );
    }
    let (k, cond, iters) = knv0(a, &bp, poles)?;
    finish(
        a,
        b,
        lift(k),
        poles,
        PlacementMethod::KautskyNicholsVanDooren,
        cond,
        iters,
    )
}

/// Largest number of requested poles within `1e-10·max(1, |λ|)` of one another.
fn max_multiplicity(poles: &[Complex64]) -> usize {
    poles
        .iter()
        .map(|p| {
            poles
                .iter()
                .filter(|q| (*q - p).norm() <= 1e-10 * p.norm().max(1.0))
                .count()
        })
        .max()
        .unwrap_or(0)
}

fn knv0(a: &Mat, b: &Mat, poles: &[Complex64]) -> Result<(Mat, f64, usize)> {
    let n = a.nrows();
    let m = b.ncols();
    // Full QR of B through column-pivot-free Householder: B = Q [Z; 0].
    let (q, rfull, perm) = crate::analysis::qr_column_pivoting(b);
    // Undo the pivoting in Z: B P = Q R  ⇒  B = Q R Pᵀ.
    let mut z = Mat::zeros(m, m);
    for (j, &pj) in perm.iter().enumerate() {
        for i in 0..m {
            z[(i, pj)] = rfull[(i, j)];
        }
    }
    let u0 = q.columns(0, m).clone_owned();
    let u1 = q.columns(m, n - m).clone_owned();
    let ac: CMat = a.map(|v| Complex64::new(v, 0.0));
    let u1h: CMat = u1.transpose().map(|v| Complex64::new(v, 0.0));
    let mut order: Vec<Complex64> = poles.to_vec();
    crate::linalg::sort_eigenvalues(&mut order);
    // Bases S_j (n × m) of ker U₁ᵀ(A − λⱼI).
    let mut bases: Vec<CMat> = Vec::with_capacity(n);
    for &lam in &order {
        let s = if n == m {
            CMat::identity(n, n)
        } else {
            let mut mm = &u1h * &ac;
            let shift = &u1h * lam;
            mm -= shift;
            // Pad to square so the SVD returns a full V; the null space is spanned by the
            // right singular vectors of the m smallest singular values.
            let mut sq = CMat::zeros(n, n);
            sq.view_mut((0, 0), (n - m, n)).copy_from(&mm);
            let vt = crate::linalg::svd::svd(&sq).v_t;
            vt.rows(n - m, m).adjoint()
        };
        bases.push(s);
    }
    // Pairing: partner[j] = index of the conjugate of a complex pole (upper one first).
    let mut partner: Vec<Option<usize>> = vec![None; n];
    {
        let mut used = vec![false; n];
        for j in 0..n {
            if order[j].im > 0.0 && !used[j] {
                let k = (0..n)
                    .filter(|&k| !used[k] && k != j && order[k].im < 0.0)
                    .min_by(|&x, &y| {
                        (order[x] - order[j].conj())
                            .norm()
                            .total_cmp(&(order[y] - order[j].conj()).norm())
                    })
                    .expect("conjugate closure was checked");
                used[j] = true;
                used[k] = true;
                partner[j] = Some(k);
                partner[k] = Some(j);
            }
        }
    }
    // Initial vectors: distinct basis columns for repeated poles.
    let mut x = CMat::zeros(n, n);
    for j in 0..n {
        let repeats = (0..j)
            .filter(|&i| (order[i] - order[j]).norm() <= 1e-10 * order[j].norm().max(1.0))
            .count();
        // Column j mod m (offset by the repeat count) keeps the initial vectors independent
        // for repeated poles (same basis) and when n = m (every basis is the identity).
        let c = (j + repeats) % m;
        let mut col = bases[j].column(c).clone_owned();
        // A complex pole's vector and its conjugate (the partner's) must be independent: a
        // basis column that is a real vector times a phase (every basis is the identity when
        // n = m, and a conjugation-invariant null space may give one) is parallel to its
        // conjugate, |Σ xᵢ²| = Σ |xᵢ|². With two or more inputs, s_c + i·s_{c+1} lies in
        // the subspace and is not.
        if partner[j].is_some() && m >= 2 {
            let square: Complex64 = col.iter().map(|v| v * v).sum();
            if square.norm() >= (1.0 - 1e-8) * col.norm_squared() {
                let other = bases[j].column((c + 1) % m).clone_owned();
                col += other * Complex64::new(0.0, 1.0);
                let nrm = col.norm();
                col.unscale_mut(nrm);
            }
        }
        x.set_column(j, &col);
    }
    for j in 0..n {
        if let Some(k) = partner[j]
            && order[j].im < 0.0
        {
            let c = x.column(k).map(|v| v.conj());
            x.set_column(j, &c);
        }
    }
    let max_sweeps = 100;
    let mut sweeps = 0;
    let mut prev_cond = f64::INFINITY;
    while sweeps < max_sweeps {
        sweeps += 1;
        for j in 0..n {
            if partner[j].is_some() && order[j].im < 0.0 {
                continue; // set with its partner
            }
            let y = orthogonal_to_others(&x, j);
            let s = &bases[j];
            let proj = s * (s.adjoint() * &y);
            let nrm = proj.norm();
            if nrm > 0.0 {
                x.set_column(j, &proj.column(0).unscale(nrm));
            }
            if let Some(k) = partner[j] {
                let c = x.column(j).map(|v| v.conj());
                x.set_column(k, &c);
            }
        }
        let cond = {
            let sv = x.clone().svd(false, false).singular_values;
            sv.max() / sv.min()
        };
        if (prev_cond - cond).abs() <= 1e-6 * cond {
            prev_cond = cond;
            break;
        }
        prev_cond = cond;
    }
    let xinv = x.clone().try_inverse().ok_or(LtiError::Singular {
        what: "closed-loop eigenvector matrix in place (KNV)".into(),
        rcond: 0.0,
    })?;
    let lam = CMat::from_diagonal(&nalgebra::DVector::from_vec(order.clone()));
    let mcl: Mat = (&x * lam * xinv).map(|v| v.re);
    let zinv = z.clone().try_inverse().ok_or(LtiError::Singular {
        what: "R factor of B in place".into(),
        rcond: 0.0,
    })?;
    let k = zinv * u0.transpose() * (a - mcl);
    Ok((k, prev_cond, sweeps))
}

/// A unit vector orthogonal to every column of `X` except column `j`: the conjugated `j`-th
/// row of `X⁻¹` when `X` is invertible, otherwise (or when it is nearly singular) the right
/// singular vector of `[x₁ … x̂ⱼ … xₙ]ᴴ` for its smallest singular value.
fn orthogonal_to_others(x: &CMat, j: usize) -> nalgebra::DVector<Complex64> {
    let n = x.nrows();
    let sv = x.clone().svd(false, false).singular_values;
    if sv.min() > 1e-10 * sv.max()
        && let Some(xinv) = x.clone().try_inverse()
    {
        let y: nalgebra::DVector<Complex64> = xinv.row(j).adjoint();
        let nrm = y.norm();
        return y / Complex64::new(nrm, 0.0);
    }
    let mut others = CMat::zeros(n, n);
    let mut r = 0;
    for k in 0..n {
        if k != j {
            others.set_row(r, &x.column(k).adjoint());
            r += 1;
        }
    }
    let vt = crate::linalg::svd::svd(&others).v_t;
    vt.row(n - 1).adjoint()
}

/// Multi-input placement with repeated poles beyond `rank B`: pick `g` (a column of `B`, or a
/// fixed mix of them) such that `(A − BK₀, Bg)` is controllable, where `K₀` is zero or a
/// fixed pseudo-random auxiliary gain that makes the loop cyclic; then
/// `K = K₀ + g k` with `k` from Hessenberg Ackermann on `(A − BK₀, Bg)`.
fn single_input_reduction(a: &Mat, b: &Mat, poles: &[Complex64]) -> Result<Mat> {
    let (n, m) = (a.nrows(), b.ncols());
    let mut gs: Vec<Mat> = (0..m)
        .map(|j| {
            let mut g = Mat::zeros(m, 1);
            g[(j, 0)] = 1.0;
            g
        })
        .collect();
    gs.push(Mat::from_fn(m, 1, |i, _| 1.0 / (i + 1) as f64));
    // Deterministic pseudo-random auxiliary gains (linear congruential sequence).
    let mut seed: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let scale = a.norm().max(1.0) / b.norm().max(f64::MIN_POSITIVE);
    for attempt in 0..6 {
        let k0 = if attempt == 0 {
            Mat::zeros(m, n)
        } else {
            Mat::from_fn(m, n, |_, _| next() * scale)
        };
        let ak = a - b * &k0;
        for g in &gs {
            let bg = b * g;
            let st = controllability_staircase(&ak, &bg, None)?;
            if st.controllable_dimension == n {
                let k1 = hessenberg_ackermann(&ak, &bg, poles)?;
                return Ok(k0 + g * k1);
            }
        }
    }
    Err(LtiError::NoConvergence {
        algorithm: "pole placement: reduction to a single input".into(),
        iterations: 6,
    })
}

/// Observer gain by duality (MATLAB `place(A', C', p)'`): `L` (`n × p`) with
/// `eig(A − LC) = poles`, from [`place`] on `(Aᵀ, Cᵀ)`.
///
/// The returned [`PolePlacement`] holds `L` in `gain` and `eig(A − LC)` in `achieved_poles`.
///
/// # Errors
/// As [`place`] (with [`LtiError::NotControllable`] meaning `(C, A)` is not observable).
pub fn place_observer(a: &Mat, c: &Mat, poles: &[Complex64]) -> Result<PolePlacement> {
    check_square("A", a)?;
    check_shape("C", c, c.nrows(), a.nrows())?;
    let mut p = place(&a.transpose(), &c.transpose(), poles)?;
    p.gain = p.gain.transpose();
    Ok(p)
}
