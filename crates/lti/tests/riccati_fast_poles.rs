//! The closed-loop poles reported by the fixed-size CARE path (`RiccatiMethod::Doubling`,
//! `n ≤ 8`), which computes them with its own stack-allocated Hessenberg + Francis QR.
//!
//! Each reported pole `λ` is checked against its defining property for the *reported* gain:
//! `λ` is an eigenvalue of `A_c = A − BK`, i.e. `σ_min(A_c − λI)` (the 2-norm of the
//! smallest perturbation making `λ` an exact eigenvalue) is at the level of a backward-stable
//! eigenvalue computation, `20·n·ε·(‖A‖_F + ‖B‖_F‖K‖_F)` (Householder reductions and QR
//! sweeps are backward stable with errors `c·n·ε‖A_c‖`, Higham, *Accuracy and Stability of
//! Numerical Algorithms*, §19.3; the norm bound also covers the rounding of forming `A − BK`
//! in a different order than the solver). The poles are also compared one to one with the
//! general [`eigenvalues`] of the recomputed `A − BK` (a different implementation: blocked
//! Schur form, Schur vectors, standardised blocks) within `4·κ(λ)·δ` with `δ` that allowance and
//! `κ(λ) = 1/|yᴴx|` the Wilkinson condition number (two backward-stable results, each within
//! `κδ` of the exact eigenvalue to first order, factor 2 for the second-order term).

mod equations_support;
mod riccati_support;

use equations_support::{rand_mat, rng};
use pendulab_lti::Mat;
use pendulab_lti::equations::{RiccatiMethod, RiccatiOptions, RiccatiSolution, care};
use pendulab_lti::linalg::{CMat, Complex64, eigenvalues, sort_eigenvalues};

const EPS: f64 = f64::EPSILON;

/// `A − λI` as a complex matrix.
fn shifted(a: &Mat, lambda: Complex64) -> CMat {
    let n = a.nrows();
    CMat::from_fn(n, n, |i, j| {
        let v = Complex64::new(a[(i, j)], 0.0);
        if i == j { v - lambda } else { v }
    })
}

/// `(σ_min(A − λI), κ(λ))` from one SVD: the singular vectors of the smallest singular value
/// are the unit right and left (near-)null vectors `x`, `y`, and `κ = 1/|yᴴx|`.
fn residual_and_condition(a: &Mat, lambda: Complex64) -> (f64, f64) {
    let svd = shifted(a, lambda).svd(true, true);
    let k = svd.singular_values.imin();
    let (u, vt) = (svd.u.unwrap(), svd.v_t.unwrap());
    let x = vt.row(k).adjoint();
    let y = u.column(k);
    (svd.singular_values[k], 1.0 / y.dotc(&x).norm())
}

fn check_poles(id: &str, a: &Mat, b: &Mat, sol: &RiccatiSolution) {
    assert_eq!(
        sol.method,
        RiccatiMethod::Doubling,
        "{id}: fast path not taken"
    );
    let n = a.nrows();
    let poles = &sol.closed_loop_poles;
    assert_eq!(poles.len(), n, "{id}: pole count");
    let mut sorted = poles.clone();
    sort_eigenvalues(&mut sorted);
    assert_eq!(poles, &sorted, "{id}: poles not in canonical order");
    for p in poles {
        assert!(p.re < 0.0, "{id}: unstable pole {p}");
        if p.im != 0.0 {
            assert!(
                poles.contains(&p.conj()),
                "{id}: {p} without its exact conjugate"
            );
        }
    }
    let acl = a - b * &sol.gain;
    let delta = 20.0 * n as f64 * EPS * (a.norm() + b.norm() * sol.gain.norm());
    for p in poles {
        let (s, _) = residual_and_condition(&acl, *p);
        assert!(
            s <= delta,
            "{id}: sigma_min(A - BK - {p} I) = {s:e} > {delta:e}"
        );
    }
    let general = eigenvalues(&acl).unwrap();
    let mut used = vec![false; n];
    for p in poles {
        let (k, d) = general
            .iter()
            .enumerate()
            .filter(|(k, _)| !used[*k])
            .map(|(k, g)| (k, (p - g).norm()))
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .unwrap();
        used[k] = true;
        let (_, kappa) = residual_and_condition(&acl, general[k]);
        let tol = 4.0 * kappa * delta;
        assert!(
            d <= tol,
            "{id}: pole {p} vs general {}: {d:e} > {tol:e}",
            general[k]
        );
    }
}

/// The `care-n4` workload: the linearised cart pendulum (book table 3.5, `docs/model.md` §1),
/// `Q = diag(100, 10, 1, 1)`, `R = 1`.
#[test]
fn cart_pendulum_poles() {
    let (a, b, q, r) = riccati_support::cart_pendulum();
    let sol = care(&a, &b, &q, &r, None, &RiccatiOptions::default()).unwrap();
    check_poles("cart pendulum", &a, &b, &sol);
}

/// Random LQ problems of every order 1..=8 and input count 1..=n (`A` uniform in `[−1, 1)`
/// times `3/√n`, generically unstable; `Q = FᵀF/n + 0.1 I`, `R = I`).
#[test]
fn random_problem_poles() {
    let mut seed = 9100;
    for n in 1..=8 {
        for m in 1..=n {
            seed += 1;
            let mut g = rng(seed);
            let a = rand_mat(&mut g, n, n) * (3.0 / (n as f64).sqrt());
            let b = rand_mat(&mut g, n, m);
            let f = rand_mat(&mut g, n, n);
            let q = f.transpose() * &f * (1.0 / n as f64) + Mat::identity(n, n) * 0.1;
            let q = (&q + q.transpose()) * 0.5;
            let r = Mat::identity(m, m);
            let sol = care(&a, &b, &q, &r, None, &RiccatiOptions::default())
                .unwrap_or_else(|e| panic!("n={n} m={m}: {e}"));
            check_poles(&format!("n={n} m={m} seed={seed}"), &a, &b, &sol);
        }
    }
}
