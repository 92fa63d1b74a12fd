//! The central H∞ controller for a plant with `D₁₁ ≠ 0` (Glover & Doyle 1988; the formulas in
//! the parent module's documentation): the plant normalised to `D₁₂ = [0; I]`, `D₂₁ = [0 I]`,
//! the bound `γ` must exceed, and the controller's state-space matrices.

use super::*;

/// The plant normalised to `D₁₂ = [0; I]`, `D₂₁ = [0 I]` (module documentation): `z̃ = Q₁₂ᵀz`,
/// `w = Q₂₁w̃` with orthogonal `Q₁₂`, `Q₂₁`, `u = T_u ũ`, `ỹ = T_y y`; `D₂₂` is ignored
/// (loop-shifted by the caller).
pub(super) struct Normalized {
    b1: Mat,
    b2: Mat,
    c1: Mat,
    c2: Mat,
    d11: Mat,
    tu: Mat,
    ty: Mat,
    /// `max(‖[D₁₁₁₁ D₁₁₁₂]‖₂, ‖[D₁₁₁₁; D₁₁₂₁]‖₂)`.
    pub(super) bound: f64,
}

/// `M^{-1/2}` of a symmetric positive definite `M` (by its eigendecomposition).
fn inverse_sqrt(what: &str, m: &Mat) -> Result<Mat> {
    let eig = symmetrize(m).symmetric_eigen();
    let min = eig
        .eigenvalues
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    if min.is_nan() || min <= 0.0 {
        return Err(LtiError::NotPositiveDefinite {
            what: what.into(),
            min_eigenvalue: min,
        });
    }
    let v = &eig.eigenvectors;
    let s = Mat::from_diagonal(&eig.eigenvalues.map(|l| 1.0 / l.sqrt()));
    Ok(symmetrize(&(v * s * v.transpose())))
}

/// An orthonormal basis of the orthogonal complement of the range of `u` (orthonormal
/// columns): the eigenvectors of the projector `I − UUᵀ` for the eigenvalue 1.
fn complement(u: &Mat) -> Mat {
    let k = u.nrows();
    let p = symmetrize(&(Mat::identity(k, k) - u * u.transpose()));
    let eig = p.symmetric_eigen();
    let cols: Vec<usize> = (0..k).filter(|&i| eig.eigenvalues[i] > 0.5).collect();
    let mut out = Mat::zeros(k, cols.len());
    for (j, &i) in cols.iter().enumerate() {
        out.set_column(j, &eig.eigenvectors.column(i));
    }
    out
}

/// `[M N]` (same rows).
fn hcat(m: &Mat, n: &Mat) -> Mat {
    let mut out = Mat::zeros(m.nrows(), m.ncols() + n.ncols());
    out.view_mut((0, 0), m.shape()).copy_from(m);
    out.view_mut((0, m.ncols()), n.shape()).copy_from(n);
    out
}

/// `[M; N]` (same columns).
fn vcat(m: &Mat, n: &Mat) -> Mat {
    hcat(&m.transpose(), &n.transpose()).transpose()
}

/// The largest singular value (`0` for an empty matrix).
fn norm2(m: &Mat) -> f64 {
    crate::design::standard_plant::singular_values(m)
        .into_iter()
        .fold(0.0, f64::max)
}

impl Normalized {
    pub(super) fn new(plant: &StandardPlant) -> Result<Self> {
        let (d12, d21) = (plant.d12(), plant.d21());
        let tu = inverse_sqrt("D12ᵀD12", &(d12.transpose() * &d12))?;
        let ty = inverse_sqrt("D21D21ᵀ", &(&d21 * d21.transpose()))?;
        let u2 = &d12 * &tu;
        let v2 = (&ty * &d21).transpose();
        let q12 = hcat(&complement(&u2), &u2);
        let q21 = hcat(&complement(&v2), &v2);
        let d11 = q12.transpose() * plant.d11() * &q21;
        let (nd1, nd2) = (plant.nz() - plant.ncon(), plant.nw() - plant.nmeas());
        let bound =
            norm2(&d11.rows(0, nd1).clone_owned()).max(norm2(&d11.columns(0, nd2).clone_owned()));
        Ok(Self {
            b1: plant.b1() * &q21,
            b2: plant.b2() * &tu,
            c1: q12.transpose() * plant.c1(),
            c2: &ty * plant.c2(),
            d11,
            tu,
            ty,
            bound,
        })
    }
}

/// `M⁻¹` of a square matrix or the condition [`HinfCondition::D11Bound`] (`R`, `R̃` are
/// invertible above the bound).
fn inverse_or_bound(m: Mat, gamma: f64, bound: f64) -> Result<Mat> {
    if m.nrows() == 0 {
        return Ok(m);
    }
    m.try_inverse()
        .ok_or_else(|| infeasible(gamma, HinfCondition::D11Bound { bound }))
}

/// The central controller at `γ` by the general (`D₁₁ ≠ 0`) formulas of the module
/// documentation (assumptions already checked).
pub(super) fn output_feedback_d11(
    plant: &StandardPlant,
    nm: &Normalized,
    gamma: f64,
) -> Result<HinfController> {
    let bound = nm.bound;
    if gamma.is_nan() || gamma <= bound {
        return Err(infeasible(gamma, HinfCondition::D11Bound { bound }));
    }
    let (n, nw, nz, ny, nu) = (
        plant.nx(),
        plant.nw(),
        plant.nz(),
        plant.nmeas(),
        plant.ncon(),
    );
    let (nd1, nd2) = (nz - nu, nw - ny);
    let g2 = gamma * gamma;
    let a = plant.a();
    let (b1, b2, c1, c2, d11) = (&nm.b1, &nm.b2, &nm.c1, &nm.c2, &nm.d11);
    let mut d12 = Mat::zeros(nz, nu);
    d12.view_mut((nd1, 0), (nu, nu)).fill_with_identity();
    let mut d21 = Mat::zeros(ny, nw);
    d21.view_mut((0, nd2), (ny, ny)).fill_with_identity();
    let b = hcat(b1, b2);
    let c = vcat(c1, c2);
    // X∞.
    let d1dot = hcat(d11, &d12);
    let mut r = d1dot.transpose() * &d1dot;
    for i in 0..nw {
        r[(i, i)] -= g2;
    }
    let rinv = inverse_or_bound(r, gamma, bound)?;
    let ax = a - &b * &rinv * d1dot.transpose() * c1;
    let gx = symmetrize(&(&b * &rinv * b.transpose()));
    let qx = symmetrize(
        &(c1.transpose() * c1 - c1.transpose() * &d1dot * &rinv * d1dot.transpose() * c1),
    );
    let x = psd_solution(gamma, HinfRiccati::X, &ax, &gx, &qx)?;
    // Y∞.
    let ddot1 = vcat(d11, &d21);
    let mut rt = &ddot1 * ddot1.transpose();
    for i in 0..nz {
        rt[(i, i)] -= g2;
    }
    let rtinv = inverse_or_bound(rt, gamma, bound)?;
    let ay = a - b1 * ddot1.transpose() * &rtinv * &c;
    let gy = symmetrize(&(c.transpose() * &rtinv * &c));
    let qy = symmetrize(
        &(b1 * b1.transpose() - b1 * ddot1.transpose() * &rtinv * &ddot1 * b1.transpose()),
    );
    let y = psd_solution(gamma, HinfRiccati::Y, &ay.transpose(), &gy, &qy)?;
    let rho = spectral_radius(&(&x * &y))?;
    let coupling = || {
        infeasible(
            gamma,
            HinfCondition::SpectralRadius {
                rho,
                gamma_squared: g2,
            },
        )
    };
    if rho.is_nan() || rho >= g2 {
        return Err(coupling());
    }
    let f = -(&rinv * (d1dot.transpose() * c1 + b.transpose() * &x));
    let l = -((b1 * ddot1.transpose() + &y * c.transpose()) * &rtinv);
    let f12 = f.rows(nd2, ny).clone_owned();
    let f2 = f.rows(nw, nu).clone_owned();
    let l12 = l.columns(nd1, nu).clone_owned();
    let l2 = l.columns(nz, ny).clone_owned();
    let d1111 = d11.view((0, 0), (nd1, nd2)).clone_owned();
    let d1112 = d11.view((0, nd2), (nd1, ny)).clone_owned();
    let d1121 = d11.view((nd1, 0), (nu, nd2)).clone_owned();
    let d1122 = d11.view((nd1, nd2), (nu, ny)).clone_owned();
    let gdum = inverse_or_bound(
        Mat::identity(nd1, nd1) * g2 - &d1111 * d1111.transpose(),
        gamma,
        bound,
    )?;
    let dhat11 = -(&d1121 * d1111.transpose() * gdum * &d1112) - d1122;
    let zinv = (Mat::identity(n, n) - &y * &x / g2).lu();
    let zb2 = zinv.solve(&(b2 + &l12)).ok_or_else(coupling)?;
    let zl2 = zinv.solve(&l2).ok_or_else(coupling)?;
    let bhat1 = &zb2 * &dhat11 - zl2;
    let c2f = c2 + f12;
    let chat1 = f2 - &dhat11 * &c2f;
    let ahat = a + &b * &f - &bhat1 * &c2f;
    let k0 = StateSpace::continuous(
        ahat,
        bhat1 * &nm.ty,
        &nm.tu * chat1,
        &nm.tu * dhat11 * &nm.ty,
    )?;
    let controller = plant.shift_d22(k0)?;
    let closed_loop = plant.close_loop(&controller)?;
    Ok(HinfController {
        controller,
        gamma,
        x,
        y,
        spectral_radius: rho,
        closed_loop,
    })
}
