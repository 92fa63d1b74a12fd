//! Eigenvalues of small dense real matrices on the stack (`N ≤ 8` in practice).
//!
//! [`eigenvalues_small`] runs the same two stages as [`eigenvalues`](super::eigenvalues) —
//! Householder reduction to upper Hessenberg form, then Francis' implicit double-shift QR
//! iteration — but on a fixed-size `[[f64; N]; N]` array, for eigenvalues only, so a call
//! performs no heap allocation and the compiler sees every loop bound. The QR stage follows
//! LAPACK `dlahqr` (no Schur vectors, `WANTZ = .FALSE.`):
//!
//! - the active block is the unreduced trailing part `l..=i`; the reflectors act on its rows
//!   and columns, applied to whole rows and columns of the array as in `dlahqr`'s full Schur
//!   form mode (`WANTT = .TRUE.`), which keeps every loop bound a compile-time constant;
//! - deflation uses the conservative small-subdiagonal criterion of Ahues & Tisseur ("A new
//!   deflation criterion for the QR algorithm", LAPACK Working Note 122, 1997);
//! - the double shift is the eigenvalue pair of the trailing 2×2 block (two equal real
//!   shifts — the one closer to `h_ii` — when they are real), with the exceptional shifts
//!   `¾s + h`, `−0.4375 s` of `dlahqr` after every 10 iterations without deflation;
//! - a sweep starts at the lowest row `m` above which two consecutive subdiagonal entries are
//!   negligible, and chases the bulge with 3×3 (last step 2×2) Householder reflectors;
//! - a deflated 2×2 block is standardised by [`lanv2`] (LAPACK `dlanv2`), which gives its
//!   eigenvalues, a complex pair as exact conjugates `a ± bj`.
//!
//! Failure (a non-finite entry, or no convergence within `30·max(N, 10)` iterations as in
//! `dlahqr`) is reported as an error so that a caller can fall back to the general routine.

use super::dense::{EPS, SAFMIN, lanv2, larfg};
use super::{Complex64, sort_eigenvalues};
use crate::error::LtiError;

/// Householder reflector of `[alpha; x]` (LAPACK `dlarfg` semantics): returns `(beta, tau)`
/// and overwrites `x` with `v`, so that `(I − τ[1; v][1; v]ᵀ)[alpha; x] = [beta; 0]`; `τ = 0`
/// when `x = 0`.
///
/// With every magnitude in `[1e-150, 1e150]` no square over- or underflows harmfully and
/// `|beta| ≥ 1e-150` needs no rescaling, so one square root suffices; otherwise the general
/// [`larfg`] (with `dlarfg`'s rescaling) takes over.
#[inline(always)]
fn reflector(alpha: f64, x: &mut [f64]) -> (f64, f64) {
    let xmax = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if xmax == 0.0 {
        return (alpha, 0.0);
    }
    let big = xmax.max(alpha.abs());
    if (1e-150..=1e150).contains(&big) {
        let ss = x.iter().fold(alpha * alpha, |s, v| s + v * v);
        let beta = -ss.sqrt().copysign(alpha);
        let tau = (beta - alpha) / beta;
        let scal = 1.0 / (alpha - beta);
        x.iter_mut().for_each(|v| *v *= scal);
        (beta, tau)
    } else {
        larfg(alpha, x)
    }
}

/// Reduces `h` (row-major, `h[i][j]` = row `i`, column `j`) to upper Hessenberg form by the
/// similarity `Qᵀ h Q` with Householder reflectors `Q = H₁⋯H_{N−2}` (Golub & Van Loan,
/// "Matrix Computations", 4th ed., Algorithm 7.4.2); entries below the subdiagonal are set
/// to exact zeros.
#[inline(always)]
fn hessenberg<const N: usize>(h: &mut [[f64; N]; N]) {
    for k in 0..N.saturating_sub(2) {
        // Reflector for column k, rows k+1..N; v = [1; x] with x in `v[k+2..N]`.
        let mut v = [0.0f64; N];
        for r in k + 2..N {
            v[r] = h[r][k];
        }
        let (beta, tau) = reflector(h[k + 1][k], &mut v[k + 2..N]);
        h[k + 1][k] = beta;
        for row in h.iter_mut().skip(k + 2) {
            row[k] = 0.0;
        }
        if tau == 0.0 {
            continue;
        }
        v[k + 1] = 1.0;
        // Left: rows k+1..N, columns k+1..N.
        for j in k + 1..N {
            let mut s = 0.0;
            for r in k + 1..N {
                s += v[r] * h[r][j];
            }
            let s = s * tau;
            for r in k + 1..N {
                h[r][j] -= s * v[r];
            }
        }
        // Right: all rows, columns k+1..N.
        for row in h.iter_mut() {
            let mut s = 0.0;
            for c in k + 1..N {
                s += row[c] * v[c];
            }
            let s = s * tau;
            for c in k + 1..N {
                row[c] -= s * v[c];
            }
        }
    }
}

/// Eigenvalues of the 2×2 block `[[a, b], [c, d]]` through its standardisation by
/// [`lanv2`]; a complex pair is returned as exact conjugates, positive imaginary part first.
#[inline(always)]
fn block_eigenvalues(a: f64, b: f64, c: f64, d: f64) -> (Complex64, Complex64) {
    let r = lanv2(a, b, c, d);
    if r.rt1.1 == 0.0 {
        (Complex64::new(r.rt1.0, 0.0), Complex64::new(r.rt2.0, 0.0))
    } else {
        let im = r.rt1.1.abs();
        (Complex64::new(r.rt1.0, im), Complex64::new(r.rt1.0, -im))
    }
}

/// Francis double-shift QR on the upper Hessenberg `h` (row-major), eigenvalues only, after
/// LAPACK `dlahqr` (module documentation). Writes the eigenvalues into `ev` in the order in
/// which they deflate; `Err(iterations)` if the iteration limit is reached.
#[inline(always)]
fn francis<const N: usize>(h: &mut [[f64; N]; N], ev: &mut [Complex64; N]) -> Result<(), usize> {
    let ulp = EPS;
    let smlnum = SAFMIN * (N as f64 / ulp);
    let itmax = 30 * N.max(10);
    // Iterations since the last deflation (dlahqr's KDEFL), which schedules exceptional
    // shifts.
    let mut kdefl = 0usize;
    let mut total = 0usize;
    // `i`: last row of the active block; rows i+1..N have deflated.
    let mut i_opt = N.checked_sub(1);
    while let Some(i) = i_opt {
        let mut l = 0usize;
        let mut converged = false;
        for _ in 0..=itmax {
            // Look for a single small subdiagonal entry, from the bottom up.
            let mut k = i;
            while k > l {
                let hkk1 = h[k][k - 1].abs();
                if hkk1 <= smlnum {
                    break;
                }
                let mut tst = h[k - 1][k - 1].abs() + h[k][k].abs();
                if tst == 0.0 {
                    if k >= 2 {
                        tst += h[k - 1][k - 2].abs();
                    }
                    if k + 1 < N {
                        tst += h[k + 1][k].abs();
                    }
                }
                // Ahues & Tisseur: the entry is negligible relative to the 2×2 block it
                // couples, measured by the products that matter for the eigenvalues.
                if hkk1 <= ulp * tst {
                    let hk1k = h[k - 1][k].abs();
                    let ab = hkk1.max(hk1k);
                    let ba = hkk1.min(hk1k);
                    let dd = (h[k - 1][k - 1] - h[k][k]).abs();
                    let hk = h[k][k].abs();
                    let aa = hk.max(dd);
                    let bb = hk.min(dd);
                    let s = aa + ab;
                    if ba * (ab / s) <= smlnum.max(ulp * (bb * (aa / s))) {
                        break;
                    }
                }
                k -= 1;
            }
            l = k;
            if l > 0 {
                h[l][l - 1] = 0.0;
            }
            if l + 1 >= i {
                converged = true;
                break;
            }
            kdefl += 1;
            total += 1;
            // Shifts: exceptional ones every 10 iterations without deflation (alternately
            // built from the bottom and from the top of the active block), otherwise the
            // eigenvalues of the trailing 2×2 block.
            let (h11, h12, h21, h22) = if kdefl.is_multiple_of(20) {
                let s = h[i][i - 1].abs() + h[i - 1][i - 2].abs();
                let h11 = 0.75 * s + h[i][i];
                (h11, -0.4375 * s, s, h11)
            } else if kdefl.is_multiple_of(10) {
                let s = h[l + 1][l].abs() + h[l + 2][l + 1].abs();
                let h11 = 0.75 * s + h[l][l];
                (h11, -0.4375 * s, s, h11)
            } else {
                (h[i - 1][i - 1], h[i - 1][i], h[i][i - 1], h[i][i])
            };
            let s = h11.abs() + h12.abs() + h21.abs() + h22.abs();
            let (rt1r, rt1i, rt2r, rt2i) = if s == 0.0 {
                (0.0, 0.0, 0.0, 0.0)
            } else {
                let rs = 1.0 / s;
                let (h11, h12, h21, h22) = (h11 * rs, h12 * rs, h21 * rs, h22 * rs);
                let tr = (h11 + h22) / 2.0;
                let det = (h11 - tr) * (h22 - tr) - h12 * h21;
                let rtdisc = det.abs().sqrt();
                if det >= 0.0 {
                    // Complex conjugate shifts.
                    (tr * s, rtdisc * s, tr * s, -rtdisc * s)
                } else {
                    // Real shifts: the one closer to h22, used twice.
                    let (a, b) = (tr + rtdisc, tr - rtdisc);
                    let r = if (a - h22).abs() <= (b - h22).abs() {
                        a * s
                    } else {
                        b * s
                    };
                    (r, 0.0, r, 0.0)
                }
            };
            // Look for two consecutive small subdiagonal entries; `v` is the first column
            // of (H − σ₁I)(H − σ₂I) restricted to rows m..m+2, scaled against overflow.
            let mut m = i - 2;
            let mut v = [0.0f64; 3];
            loop {
                let h21s0 = h[m + 1][m];
                let rs = 1.0 / ((h[m][m] - rt2r).abs() + rt2i.abs() + h21s0.abs());
                let h21s = h21s0 * rs;
                v[0] = h21s * h[m][m + 1] + (h[m][m] - rt1r) * ((h[m][m] - rt2r) * rs)
                    - rt1i * (rt2i * rs);
                v[1] = h21s * (h[m][m] + h[m + 1][m + 1] - rt1r - rt2r);
                v[2] = h21s * h[m + 2][m + 1];
                // Scaling only guards against over- and underflow; its rounding is
                // immaterial (the reflector built from v is normalised).
                let rs = 1.0 / (v[0].abs() + v[1].abs() + v[2].abs());
                v.iter_mut().for_each(|x| *x *= rs);
                if m == l {
                    break;
                }
                let h00 = h[m][m - 1].abs() * (v[1].abs() + v[2].abs());
                let h01 = ulp
                    * v[0].abs()
                    * (h[m - 1][m - 1].abs() + h[m][m].abs() + h[m + 1][m + 1].abs());
                if h00 <= h01 {
                    break;
                }
                m -= 1;
            }
            // Double-shift sweep: chase the bulge from row m down to row i. The reflectors
            // act on rows and columns of the active block l..=i only, but each update runs over
            // whole rows (columns 0..N) and whole columns (rows 0..N): outside the active
            // block's rows and columns this is dlahqr's full-Schur-form update (WANTT), the
            // same similarity, which leaves every deflated block and every zero below the
            // subdiagonal unchanged (a reflector combines entries that are exact zeros there
            // into exact zeros). Constant loop bounds let the compiler unroll and vectorise.
            for k in m..i {
                let three = k + 2 <= i;
                if k > m {
                    v[0] = h[k][k - 1];
                    v[1] = h[k + 1][k - 1];
                    v[2] = if three { h[k + 2][k - 1] } else { 0.0 };
                }
                let (beta, t1, v2, v3) = if three {
                    let mut x = [v[1], v[2]];
                    let (beta, t1) = reflector(v[0], &mut x[..]);
                    (beta, t1, x[0], x[1])
                } else {
                    let mut x = [v[1]];
                    let (beta, t1) = reflector(v[0], &mut x[..]);
                    (beta, t1, x[0], 0.0)
                };
                // Column k − 1 of the rows k..k+2 is set explicitly after the row update.
                let below = if k > m {
                    beta
                } else if m > l {
                    // dlahqr: equivalent to negating h[k][k-1], and robust when v2, v3
                    // underflow (the entries this would create below it are negligible by
                    // the choice of m and are dropped).
                    h[k][k - 1] * (1.0 - t1)
                } else {
                    // k = m = l: h[l][l-1] is zero (deflated, or l = 0).
                    0.0
                };
                let t2 = t1 * v2;
                let t3 = t1 * v3;
                if three {
                    let (top, rest) = h.split_at_mut(k + 1);
                    let (r0, (r1, r2)) = (&mut top[k], rest.split_at_mut(1));
                    let (r1, r2) = (&mut r1[0], &mut r2[0]);
                    for j in 0..N {
                        let sum = r0[j] + v2 * r1[j] + v3 * r2[j];
                        r0[j] -= sum * t1;
                        r1[j] -= sum * t2;
                        r2[j] -= sum * t3;
                    }
                    if k > 0 {
                        r0[k - 1] = below;
                        r1[k - 1] = 0.0;
                        r2[k - 1] = 0.0;
                    }
                    for row in h.iter_mut() {
                        let sum = row[k] + v2 * row[k + 1] + v3 * row[k + 2];
                        row[k] -= sum * t1;
                        row[k + 1] -= sum * t2;
                        row[k + 2] -= sum * t3;
                    }
                } else {
                    let (top, rest) = h.split_at_mut(k + 1);
                    let (r0, r1) = (&mut top[k], &mut rest[0]);
                    for j in 0..N {
                        let sum = r0[j] + v2 * r1[j];
                        r0[j] -= sum * t1;
                        r1[j] -= sum * t2;
                    }
                    if k > 0 {
                        r0[k - 1] = below;
                        r1[k - 1] = 0.0;
                    }
                    for row in h.iter_mut() {
                        let sum = row[k] + v2 * row[k + 1];
                        row[k] -= sum * t1;
                        row[k + 1] -= sum * t2;
                    }
                }
            }
        }
        if !converged {
            return Err(total);
        }
        if l == i {
            ev[i] = Complex64::new(h[i][i], 0.0);
        } else {
            // l == i − 1: a 2×2 block.
            let (e1, e2) = block_eigenvalues(h[i - 1][i - 1], h[i - 1][i], h[i][i - 1], h[i][i]);
            ev[i - 1] = e1;
            ev[i] = e2;
        }
        kdefl = 0;
        i_opt = l.checked_sub(1);
    }
    Ok(())
}

/// Eigenvalues of the real `N × N` matrix `a` (row-major: `a[i][j]` is row `i`, column `j`),
/// in the order of [`sort_eigenvalues`] (real part descending, then imaginary part
/// descending; conjugate pairs are exact conjugates).
///
/// Same mathematics as [`eigenvalues`](super::eigenvalues) (Hessenberg reduction, Francis
/// QR after LAPACK `dlahqr`), on the stack and without the Schur vectors; see the module
/// documentation. Backward stable: the results are the exact eigenvalues of `a + E` with
/// `‖E‖ = O(N ε ‖a‖)`.
///
/// # Errors
/// [`LtiError::NonFinite`] naming the first non-finite entry; [`LtiError::NoConvergence`] if
/// the QR iteration does not deflate within `30·max(N, 10)` iterations per eigenvalue
/// block. Either way a caller can fall back to the general routine.
pub(crate) fn eigenvalues_small<const N: usize>(
    a: &[[f64; N]; N],
) -> Result<[Complex64; N], LtiError> {
    for (i, row) in a.iter().enumerate() {
        for (j, &v) in row.iter().enumerate() {
            if !v.is_finite() {
                return Err(LtiError::NonFinite {
                    what: "matrix".to_string(),
                    row: i,
                    col: j,
                    value: v,
                });
            }
        }
    }
    let mut ev = [Complex64::new(0.0, 0.0); N];
    let mut h = *a;
    hessenberg(&mut h);
    francis(&mut h, &mut ev).map_err(|iterations| LtiError::NoConvergence {
        algorithm: "Francis double-shift QR (fixed-size eigenvalues)".to_string(),
        iterations,
    })?;
    sort_eigenvalues(&mut ev);
    Ok(ev)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::{CMat, Mat, eigenvalues};

    /// Row-major array of a `Mat`.
    fn rows<const N: usize>(a: &Mat) -> [[f64; N]; N] {
        std::array::from_fn(|i| std::array::from_fn(|j| a[(i, j)]))
    }

    /// `Mat` of a row-major array.
    fn mat<const N: usize>(a: &[[f64; N]; N]) -> Mat {
        Mat::from_fn(N, N, |i, j| a[i][j])
    }

    /// Backward-error allowance `‖E‖_F ≤ 20·N·ε·‖A‖_F` of Hessenberg reduction followed by
    /// Francis QR: both are sequences of Householder similarities, backward stable with errors
    /// of order `c·N·ε‖A‖` (Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed.,
    /// §19.3; Golub & Van Loan §7.5.6 quote `‖E‖ ≈ ε‖A‖` for the QR stage) with a modest
    /// constant; 20 allows for it and for the 2×2 standardisation.
    fn backward_tol(a: &Mat) -> f64 {
        20.0 * a.nrows() as f64 * EPS * a.norm().max(f64::MIN_POSITIVE)
    }

    /// `A − λI` as a complex matrix.
    fn shifted(a: &Mat, lambda: Complex64) -> CMat {
        let n = a.nrows();
        CMat::from_fn(n, n, |i, j| {
            let v = Complex64::new(a[(i, j)], 0.0);
            if i == j { v - lambda } else { v }
        })
    }

    /// `σ_min(A − λI)`: the 2-norm of the smallest perturbation `E` for which `λ` is an exact
    /// eigenvalue of `A + E` (the defining residual of a computed eigenvalue).
    fn sigma_min(a: &Mat, lambda: Complex64) -> f64 {
        shifted(a, lambda).svd(false, false).singular_values.min()
    }

    /// Condition number `κ(λ) = ‖x‖‖y‖/|yᴴx|` of a simple eigenvalue (Wilkinson), with `x`, `y`
    /// the right and left singular vectors of `A − λI` for its smallest singular value (unit
    /// null vectors of `A − λI` and `(A − λI)ᴴ` up to rounding).
    fn kappa(a: &Mat, lambda: Complex64) -> f64 {
        let svd = shifted(a, lambda).svd(true, true);
        let (u, vt) = (svd.u.unwrap(), svd.v_t.unwrap());
        let k = svd.singular_values.imin();
        let x = vt.row(k).adjoint();
        let y = u.column(k);
        1.0 / y.dotc(&x).norm()
    }

    /// Pairs every computed eigenvalue with the nearest unused reference value and asserts
    /// `|λ̂ − λ| ≤ tol(λ)`.
    fn assert_match(got: &[Complex64], want: &[Complex64], tol: impl Fn(Complex64) -> f64) {
        assert_eq!(got.len(), want.len());
        let mut used = vec![false; want.len()];
        for g in got {
            let (k, d) = want
                .iter()
                .enumerate()
                .filter(|(k, _)| !used[*k])
                .map(|(k, w)| (k, (g - w).norm()))
                .min_by(|x, y| x.1.total_cmp(&y.1))
                .unwrap();
            used[k] = true;
            let t = tol(want[k]);
            assert!(
                d <= t,
                "{g} vs {}: |diff| {d:e} > tol {t:e} (all: {got:?} vs {want:?})",
                want[k]
            );
        }
    }

    /// Checks the properties every result must have: canonical order, exact conjugate pairs
    /// and, for each eigenvalue, a defining residual `σ_min(A − λI)` within the backward-error
    /// allowance.
    fn check_basic<const N: usize>(a: &[[f64; N]; N]) -> [Complex64; N] {
        let ev = eigenvalues_small(a).expect("converges");
        let mut sorted = ev;
        sort_eigenvalues(&mut sorted);
        assert_eq!(ev, sorted, "not in canonical order");
        for e in &ev {
            if e.im != 0.0 {
                assert!(
                    ev.contains(&e.conj()),
                    "{e} without its exact conjugate in {ev:?}"
                );
            }
        }
        let am = mat(a);
        let tol = backward_tol(&am);
        for e in &ev {
            let s = sigma_min(&am, *e);
            assert!(s <= tol, "sigma_min(A - {e} I) = {s:e} > {tol:e} for {am}");
        }
        ev
    }

    /// Companion matrix of the monic polynomial with the given roots (conjugate pairs listed
    /// both): first row `−c_{N−1}, …, −c_0`, ones on the subdiagonal. The coefficients are
    /// expanded in complex arithmetic; with the small dyadic roots used here they are exact.
    fn companion<const N: usize>(roots: &[Complex64; N]) -> [[f64; N]; N] {
        // p(x) = Σ c[k] x^k, c[N] = 1.
        let mut c = vec![Complex64::new(0.0, 0.0); N + 1];
        c[0] = Complex64::new(1.0, 0.0);
        for (deg, r) in roots.iter().enumerate() {
            for k in (0..=deg + 1).rev() {
                let lower = if k > 0 {
                    c[k - 1]
                } else {
                    Complex64::new(0.0, 0.0)
                };
                c[k] = lower - r * c[k];
            }
        }
        for ck in &c {
            assert_eq!(ck.im, 0.0, "roots not closed under conjugation");
        }
        let mut a = [[0.0; N]; N];
        for j in 0..N {
            a[0][j] = -c[N - 1 - j].re;
        }
        for i in 1..N {
            a[i][i - 1] = 1.0;
        }
        a
    }

    fn cx(re: f64, im: f64) -> Complex64 {
        Complex64::new(re, im)
    }

    /// Simple roots: `|λ̂ − λ| ≤ κ(λ)·‖E‖` to first order (Wilkinson), with `‖E‖` the
    /// backward-error allowance and a factor 2 for the second-order term.
    fn simple_root_tol(a: &Mat) -> impl Fn(Complex64) -> f64 + '_ {
        let e = backward_tol(a);
        move |l| 2.0 * kappa(a, l) * e
    }

    /// Checks the eigenvalues of the companion matrix of `roots` ([`check_basic`]) and that
    /// they match the roots within the simple-root bound; returns them.
    fn check_simple_roots<const N: usize>(roots: &[Complex64; N]) -> [Complex64; N] {
        let a = companion(roots);
        let ev = check_basic(&a);
        assert_match(&ev, roots, simple_root_tol(&mat(&a)));
        ev
    }

    #[test]
    fn companion_real_and_complex_roots() {
        let roots = [cx(1.0, 0.0), cx(-2.0, 0.0), cx(3.0, 0.0), cx(-4.0, 0.0)];
        check_simple_roots(&roots);

        let roots = [
            cx(-1.0, 2.0),
            cx(-1.0, -2.0),
            cx(0.5, 1.5),
            cx(0.5, -1.5),
            cx(-3.0, 0.0),
            cx(2.0, 0.25),
            cx(2.0, -0.25),
        ];
        let ev = check_simple_roots(&roots);
        assert_eq!(ev.iter().filter(|e| e.im != 0.0).count(), 6);

        // Purely imaginary pairs (an undamped oscillator's poles) and a zero root.
        let roots = [
            cx(0.0, 1.0),
            cx(0.0, -1.0),
            cx(0.0, 3.0),
            cx(0.0, -3.0),
            cx(0.0, 0.0),
        ];
        check_simple_roots(&roots);
    }

    #[test]
    fn companion_clustered_roots() {
        // Three roots 1e-4 apart: still simple, κ large; the κ-based bound covers it.
        let roots = [
            cx(1.0, 0.0),
            cx(1.0001, 0.0),
            cx(1.0002, 0.0),
            cx(-2.0, 1.0),
            cx(-2.0, -1.0),
            cx(0.5, 0.0),
        ];
        check_simple_roots(&roots);
    }

    #[test]
    fn companion_repeated_roots() {
        // A root of multiplicity k of a companion matrix is a single k×k Jordan block, so a
        // perturbation of size δ moves it by O(δ^{1/k}) (Puiseux expansion; Moro, Burke &
        // Overton, SIAM J. Matrix Anal. Appl. 18, 1997). With δ the backward-error allowance
        // the cluster lies within C·δ^{1/k} of the root; C = 10·(1 + |λ|) bounds the
        // expansion's leading coefficient for these small-coefficient polynomials.
        let roots = [
            cx(2.0, 0.0),
            cx(2.0, 0.0),
            cx(2.0, 0.0),
            cx(-1.0, 0.0),
            cx(-1.0, 0.0),
        ];
        let a = companion(&roots);
        let ev = check_basic(&a);
        let delta = backward_tol(&mat(&a));
        assert_match(&ev, &roots, |l| {
            let k = roots.iter().filter(|r| **r == l).count() as f64;
            10.0 * (1.0 + l.norm()) * delta.powf(1.0 / k)
        });
        // A double complex pair.
        let roots = [cx(-1.0, 1.0), cx(-1.0, -1.0), cx(-1.0, 1.0), cx(-1.0, -1.0)];
        let a = companion(&roots);
        let ev = check_basic(&a);
        let delta = backward_tol(&mat(&a));
        assert_match(&ev, &roots, |l| 10.0 * (1.0 + l.norm()) * delta.sqrt());
    }

    #[test]
    fn cyclic_shift_needs_exceptional_shifts() {
        // The cyclic permutation matrix (companion of x^N − 1) is a classic stall of the
        // standard shift strategy (every Wilkinson shift is 0, so an unshifted sweep just
        // permutes the matrix); only the exceptional shifts make QR converge. Its eigenvalues
        // are the N-th roots of unity, all with κ = 1 (the matrix is normal).
        fn run<const N: usize>() {
            let mut a = [[0.0; N]; N];
            a[0][N - 1] = 1.0;
            for i in 1..N {
                a[i][i - 1] = 1.0;
            }
            let ev = check_basic(&a);
            let roots: Vec<Complex64> = (0..N)
                .map(|k| {
                    Complex64::from_polar(1.0, 2.0 * std::f64::consts::PI * k as f64 / N as f64)
                })
                .collect();
            let tol = 2.0 * backward_tol(&mat(&a));
            assert_match(&ev, &roots, |_| tol);
        }
        run::<3>();
        run::<4>();
        run::<5>();
        run::<6>();
        run::<7>();
        run::<8>();
    }

    /// Random matrices from [`splitmix_matrix`](crate::linalg::testing::splitmix_matrix),
    /// optionally graded (column `j` scaled by `grade^j`), against the general
    /// [`eigenvalues`]. Both routines are backward stable, so each differs from the exact
    /// spectrum by at most `κ(λ)·‖E‖` (first order), and from each other by twice that; a
    /// further factor 2 covers the second-order term.
    fn random_vs_general<const N: usize>(seed: u64, grade: f64) {
        let mut am = crate::linalg::testing::splitmix_matrix(N, N, seed);
        for (j, mut col) in am.column_iter_mut().enumerate() {
            col *= grade.powi(j as i32);
        }
        let a = rows::<N>(&am);
        let ev = check_basic(&a);
        let reference = eigenvalues(&am).unwrap();
        let e = backward_tol(&am);
        assert_match(&ev, &reference, |l| 4.0 * kappa(&am, l) * e);
    }

    #[test]
    fn random_matrices_agree_with_general_routine() {
        for seed in 0..40 {
            random_vs_general::<1>(seed, 1.0);
            random_vs_general::<2>(seed, 1.0);
            random_vs_general::<3>(seed, 1.0);
            random_vs_general::<4>(seed, 1.0);
            random_vs_general::<5>(seed, 1.0);
            random_vs_general::<6>(seed, 1.0);
            random_vs_general::<7>(seed, 1.0);
            random_vs_general::<8>(seed, 1.0);
        }
    }

    #[test]
    fn graded_matrices_agree_with_general_routine() {
        for seed in 100..120 {
            random_vs_general::<4>(seed, 1e-3);
            random_vs_general::<6>(seed, 1e-2);
            random_vs_general::<8>(seed, 1e-2);
            random_vs_general::<8>(seed, 1e2);
        }
    }

    #[test]
    fn zero_and_triangular_matrices_are_exact() {
        // Zero matrix: every eigenvalue is exactly 0.
        let ev = eigenvalues_small(&[[0.0; 5]; 5]).unwrap();
        assert!(ev.iter().all(|e| *e == cx(0.0, 0.0)), "{ev:?}");
        // Upper triangular: no reflector or QR step touches it (all subdiagonals are already
        // zero), so the eigenvalues are the diagonal entries exactly.
        let mut a = [[0.0; 6]; 6];
        let diag = [3.5, -1.25, 0.0, 7.0, -1.25, 1e-3];
        for i in 0..6 {
            a[i][i] = diag[i];
            for j in i + 1..6 {
                a[i][j] = (i + 2 * j) as f64 - 4.5;
            }
        }
        let ev = eigenvalues_small(&a).unwrap();
        let mut want: Vec<Complex64> = diag.iter().map(|d| cx(*d, 0.0)).collect();
        sort_eigenvalues(&mut want);
        assert_eq!(ev.to_vec(), want);
        // Block upper triangular with the standardised 2×2 block [[1, −2], [2, 1]]: the QR
        // iteration deflates at once and lanv2 returns 1 ± j·sqrt(2)·sqrt(2) — the real
        // eigenvalues exactly, the imaginary part 2 within the rounding of two square roots
        // and a product (3 ε relative).
        let mut a = [[0.0; 4]; 4];
        a[0] = [1.0, -2.0, 5.0, 1.0];
        a[1] = [2.0, 1.0, -3.0, 2.0];
        a[2][2] = -4.0;
        a[2][3] = 6.0;
        a[3][3] = 0.5;
        let ev = eigenvalues_small(&a).unwrap();
        assert_eq!((ev[0].re, ev[1].re), (1.0, 1.0));
        assert!((ev[0].im - 2.0).abs() <= 3.0 * EPS * 2.0, "{ev:?}");
        assert_eq!(ev[1], ev[0].conj());
        assert_eq!((ev[2], ev[3]), (cx(0.5, 0.0), cx(-4.0, 0.0)));
    }

    #[test]
    fn tiny_and_huge_scales() {
        // Scaling A by s scales every eigenvalue by s; the entries here leave the fast range of
        // the reflectors ([1e-150, 1e150]), exercising dlarfg's rescaling branch.
        let base = crate::linalg::testing::splitmix_matrix(5, 5, 7);
        let want = eigenvalues(&base).unwrap();
        let e = backward_tol(&base);
        for s in [1e-200, 1e200] {
            let ev = eigenvalues_small(&rows::<5>(&(&base * s))).unwrap();
            let scaled: Vec<Complex64> = ev.iter().map(|l| l / s).collect();
            assert_match(&scaled, &want, |l| 4.0 * kappa(&base, l) * e);
        }
    }

    #[test]
    fn non_finite_input_is_an_error() {
        let mut a = [[1.0; 4]; 4];
        a[2][1] = f64::NAN;
        match eigenvalues_small(&a) {
            Err(LtiError::NonFinite { row, col, .. }) => assert_eq!((row, col), (2, 1)),
            other => panic!("expected NonFinite, got {other:?}"),
        }
        a[2][1] = 1.0;
        a[0][3] = f64::NEG_INFINITY;
        assert!(matches!(
            eigenvalues_small(&a),
            Err(LtiError::NonFinite { row: 0, col: 3, .. })
        ));
        // Finite entries whose products overflow must not panic either.
        let big = [[f64::MAX, f64::MAX], [-f64::MAX, f64::MAX]];
        let _ = eigenvalues_small(&big);
        let empty: [[f64; 0]; 0] = [];
        assert!(eigenvalues_small(&empty).unwrap().is_empty());
    }
}
