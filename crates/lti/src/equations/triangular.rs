//! Kernels on quasi-triangular (real Schur) coefficients: the reduced Sylvester and Stein
//! equations of the Bartels–Stewart method.
//!
//! Bartels & Stewart, "Solution of the matrix equation AX + XB = C", Comm. ACM 15 (1972);
//! the block recursions follow LAPACK `dtrsyl` (continuous) and Barraud's / Kitagawa's
//! column recursion for the Stein equation (A. Y. Barraud, "A numerical algorithm to solve
//! AᵀXA − X = Q", IEEE TAC 22 (1977); SLICOT `SB03MX`), re-derived here for the forms used.
//! 1×1 and 2×2 diagonal blocks give linear systems of order ≤ 4, solved by Gaussian
//! elimination with complete pivoting.

use crate::linalg::Mat;
use crate::linalg::dense::{EPS, SAFMIN, axpy, solve_small_complete_pivoting};

/// Diagonal blocks `(start, size)` of a quasi-upper-triangular matrix.
pub(crate) fn diag_blocks(s: &Mat) -> Vec<(usize, usize)> {
    let n = s.nrows();
    let mut out = Vec::with_capacity(n);
    let mut k = 0;
    while k < n {
        let size = if k + 1 < n && s[(k + 1, k)] != 0.0 {
            2
        } else {
            1
        };
        out.push((k, size));
        k += size;
    }
    out
}

/// How the right coefficient of [`solve_quasi_sylvester`] is given.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RightCoef {
    /// `T` is upper quasi-triangular as stored.
    Upper,
    /// The coefficient is `Tᵀ`, with the stored `T` upper quasi-triangular.
    TransposeOfUpper,
}

/// Solves `S Y + Y T' = F` in place (`F` is overwritten by `Y`), where `S` (`m × m`) is upper
/// quasi-triangular and `T'` is `T` or `Tᵀ` with `T` (`n × n`) upper quasi-triangular.
///
/// Returns `true` if a near-singular 1×1/2×2 subsystem had to be perturbed (an eigenvalue
/// collision `λ(S) + λ(T) ≈ 0`); callers check collisions beforehand.
pub(crate) fn solve_quasi_sylvester(s: &Mat, t: &Mat, which: RightCoef, f: &mut Mat) -> bool {
    let m = s.nrows();
    let n = t.nrows();
    debug_assert_eq!(f.shape(), (m, n));
    let sblocks = diag_blocks(s);
    let tblocks = diag_blocks(t);
    let smin = (EPS * (s.amax() + t.amax())).max(SAFMIN / EPS);
    let mut perturbed = false;
    // T' entry (k, l) with T' = T or Tᵀ.
    let tp = |k: usize, l: usize| match which {
        RightCoef::Upper => t[(k, l)],
        RightCoef::TransposeOfUpper => t[(l, k)],
    };
    // Order of the column blocks: T' upper → left to right (column l couples to k < l);
    // T' lower → right to left.
    let order: Vec<(usize, usize)> = match which {
        RightCoef::Upper => tblocks.clone(),
        RightCoef::TransposeOfUpper => tblocks.iter().rev().copied().collect(),
    };
    for &(l, ls) in &order {
        // Solve S Y_L + Y_L T'_LL = F_L by back substitution over the row blocks of S.
        let mut tll = [[0.0; 2]; 2];
        for p in 0..ls {
            for q in 0..ls {
                tll[p][q] = tp(l + p, l + q);
            }
        }
        for &(k, ks) in sblocks.iter().rev() {
            // Small system S_KK Y + Y T'_LL = F_KL, Kronecker (I ⊗ S_KK + T'_LLᵀ ⊗ I).
            let dim = ks * ls;
            let mut mm = [0.0; 16];
            let mut rhs = [0.0; 4];
            for q in 0..ls {
                for p in 0..ks {
                    let row = p + q * ks;
                    rhs[row] = f[(k + p, l + q)];
                    for sidx in 0..ls {
                        for r in 0..ks {
                            let col = r + sidx * ks;
                            let mut v = 0.0;
                            if sidx == q {
                                v += s[(k + p, k + r)];
                            }
                            if r == p {
                                v += tll[sidx][q];
                            }
                            mm[row + col * dim] = v;
                        }
                    }
                }
            }
            perturbed |= solve_small_complete_pivoting(dim, &mut mm[..dim * dim], &mut rhs, smin);
            for q in 0..ls {
                for p in 0..ks {
                    f[(k + p, l + q)] = rhs[p + q * ks];
                }
            }
            // F[0..k, L] −= S[0..k, K] Y_KL.
            if k > 0 {
                for q in 0..ls {
                    for p in 0..ks {
                        let y = f[(k + p, l + q)];
                        if y != 0.0 {
                            let scol = s.column(k + p);
                            let sc = &scol.as_slice()[..k];
                            let start = (l + q) * m;
                            axpy(-y, sc, &mut f.as_mut_slice()[start..start + k]);
                        }
                    }
                }
            }
        }
        // Update the columns still to be solved: F_J −= Y_L T'_LJ.
        let targets: Vec<usize> = match which {
            RightCoef::Upper => (l + ls..n).collect(),
            RightCoef::TransposeOfUpper => (0..l).collect(),
        };
        for j in targets {
            for q in 0..ls {
                let c = tp(l + q, j);
                if c != 0.0 {
                    let (ycol, fcol) = two_columns(f, l + q, j);
                    axpy(-c, ycol, fcol);
                }
            }
        }
    }
    perturbed
}

/// Borrows column `a` immutably and column `b` mutably (`a ≠ b`).
fn two_columns(f: &mut Mat, a: usize, b: usize) -> (&[f64], &mut [f64]) {
    let m = f.nrows();
    let data = f.as_mut_slice();
    if a < b {
        let (lo, hi) = data.split_at_mut(b * m);
        (&lo[a * m..a * m + m], &mut hi[..m])
    } else {
        let (lo, hi) = data.split_at_mut(a * m);
        (&hi[..m], &mut lo[b * m..b * m + m])
    }
}

/// Solves the reduced Stein equation `S Y Sᵀ − Y = F` in place (`F` overwritten by `Y`), `S`
/// (`n × n`) upper quasi-triangular. Column blocks are computed from the last to the first:
/// for block column `L`,
/// `S Y_L S_LLᵀ − Y_L = F_L − S (Σ_{K>L} Y_K S_LKᵀ)`,
/// solved by back substitution over the row blocks of `S`.
///
/// Returns `true` if a near-singular subsystem had to be perturbed (`λ_i λ_j ≈ 1`).
pub(crate) fn solve_quasi_stein(s: &Mat, f: &mut Mat) -> bool {
    let n = s.nrows();
    let blocks = diag_blocks(s);
    let smin = (EPS * (s.amax() * s.amax()).max(1.0)).max(SAFMIN / EPS);
    let mut perturbed = false;
    let mut w = vec![0.0; n * 2];
    let mut sw = vec![0.0; n * 2];
    let mut acc = vec![0.0; n * 2];
    for &(l, ls) in blocks.iter().rev() {
        // W = Σ_{K>L} Y_K S_LKᵀ  (n × ls): column q of W = Σ_{j ≥ l+ls} Y[:, j] S[l+q, j].
        w.iter_mut().for_each(|x| *x = 0.0);
        for q in 0..ls {
            for j in l + ls..n {
                let c = s[(l + q, j)];
                if c != 0.0 {
                    let yc = f.column(j);
                    axpy(c, yc.as_slice(), &mut w[q * n..q * n + n]);
                }
            }
        }
        // SW = S W (quasi-triangular matrix times vector).
        sw.iter_mut().for_each(|x| *x = 0.0);
        for q in 0..ls {
            for j in 0..n {
                let c = w[q * n + j];
                if c != 0.0 {
                    let rows = (j + 2).min(n);
                    let sc = s.column(j);
                    axpy(c, &sc.as_slice()[..rows], &mut sw[q * n..q * n + rows]);
                }
            }
        }
        for q in 0..ls {
            for i in 0..n {
                f[(i, l + q)] -= sw[q * n + i];
            }
        }
        // Now S Y_L S_LLᵀ − Y_L = F_L. Back substitution over row blocks I of S:
        // S_II Y_IL S_LLᵀ − Y_IL = F_IL − (Σ_{J>I} S_IJ Y_JL) S_LLᵀ.
        // acc holds Σ_{J>I} S[:, J] Y_JL for the rows above.
        acc.iter_mut().for_each(|x| *x = 0.0);
        let mut sll = [[0.0; 2]; 2];
        for p in 0..ls {
            for q in 0..ls {
                sll[p][q] = s[(l + p, l + q)];
            }
        }
        for &(i, is) in blocks.iter().rev() {
            // rhs = F_IL − acc_I S_LLᵀ
            let dim = is * ls;
            let mut rhs = [0.0; 4];
            for q in 0..ls {
                for p in 0..is {
                    let mut v = f[(i + p, l + q)];
                    for r in 0..ls {
                        v -= acc[r * n + i + p] * sll[q][r];
                    }
                    rhs[p + q * is] = v;
                }
            }
            // Kronecker: (S_LL ⊗ S_II − I) vec(Y).
            let mut mm = [0.0; 16];
            for q in 0..ls {
                for p in 0..is {
                    let row = p + q * is;
                    for r in 0..ls {
                        for t in 0..is {
                            let col = t + r * is;
                            let mut v = sll[q][r] * s[(i + p, i + t)];
                            if row == col {
                                v -= 1.0;
                            }
                            mm[row + col * dim] = v;
                        }
                    }
                }
            }
            perturbed |= solve_small_complete_pivoting(dim, &mut mm[..dim * dim], &mut rhs, smin);
            for q in 0..ls {
                for p in 0..is {
                    f[(i + p, l + q)] = rhs[p + q * is];
                }
            }
            // acc[0..i] += S[0..i, I] Y_IL
            if i > 0 {
                for q in 0..ls {
                    for p in 0..is {
                        let y = rhs[p + q * is];
                        if y != 0.0 {
                            let sc = s.column(i + p);
                            axpy(y, &sc.as_slice()[..i], &mut acc[q * n..q * n + i]);
                        }
                    }
                }
            }
        }
    }
    perturbed
}
