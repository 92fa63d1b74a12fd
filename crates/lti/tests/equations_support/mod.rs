//! Helpers shared by the matrix-equation and Riccati tests: seeded random matrices and
//! structural checks. Nothing here computes an expected answer.
#![allow(dead_code)]

use pendulab_lti::Mat;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Deterministic generator for a test.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// `r × c` matrix with entries uniform in [−1, 1).
pub fn rand_mat(rng: &mut ChaCha8Rng, r: usize, c: usize) -> Mat {
    Mat::from_fn(r, c, |_, _| rng.random_range(-1.0..1.0))
}

/// Random orthogonal matrix (Q factor of a random matrix).
pub fn rand_orthogonal(rng: &mut ChaCha8Rng, n: usize) -> Mat {
    rand_mat(rng, n, n).qr().q()
}

/// `‖ZᵀZ − I‖_F`.
pub fn orthogonality_error(z: &Mat) -> f64 {
    (z.transpose() * z - Mat::identity(z.ncols(), z.ncols())).norm()
}

/// Checks that `t` is quasi-upper-triangular in standard form; returns a description of the
/// first violation.
pub fn check_standard_form(t: &Mat) -> Result<(), String> {
    let n = t.nrows();
    for j in 0..n {
        for i in j + 2..n {
            if t[(i, j)] != 0.0 {
                return Err(format!("T[{i},{j}] = {} below the subdiagonal", t[(i, j)]));
            }
        }
    }
    let mut k = 0;
    while k < n {
        if k + 1 < n && t[(k + 1, k)] != 0.0 {
            if k + 2 < n && t[(k + 2, k + 1)] != 0.0 {
                return Err(format!("consecutive nonzero subdiagonals at {k}"));
            }
            if t[(k, k)] != t[(k + 1, k + 1)] {
                return Err(format!("2x2 block at {k} has unequal diagonal"));
            }
            if t[(k, k + 1)] * t[(k + 1, k)] >= 0.0 {
                return Err(format!("2x2 block at {k} has b*c >= 0"));
            }
            k += 2;
        } else {
            k += 1;
        }
    }
    Ok(())
}

/// A stable matrix with well-separated, well-conditioned spectrum: `−(s I + M)` with `M` random
/// of norm ≲ √n / 2, shifted so that all eigenvalues have real part ≤ −0.5 (Gershgorin-free
/// argument: the field of values of a matrix lies within `‖M‖₂` of its centre).
pub fn rand_stable(rng: &mut ChaCha8Rng, n: usize) -> Mat {
    let m = rand_mat(rng, n, n) * (0.5 / (n as f64).sqrt());
    let norm2 = m.clone().svd(false, false).singular_values.max();
    -(m + Mat::identity(n, n) * (norm2 + 0.5))
}

/// Largest distance between two eigenvalue lists after pairing each expected value with the
/// nearest unused computed one (order-independent comparison).
pub fn eig_distance(
    computed: &[pendulab_lti::Complex64],
    expected: &[pendulab_lti::Complex64],
) -> f64 {
    assert_eq!(computed.len(), expected.len(), "eigenvalue counts differ");
    let mut used = vec![false; computed.len()];
    let mut worst = 0.0_f64;
    for e in expected {
        let (mut best, mut bi) = (f64::INFINITY, 0);
        for (i, c) in computed.iter().enumerate() {
            if !used[i] && (c - e).norm() < best {
                best = (c - e).norm();
                bi = i;
            }
        }
        used[bi] = true;
        worst = worst.max(best);
    }
    worst
}

/// Random LQ data of order `n` with `m` inputs: `A` uniform in `[−1, 1)` times `3/√n`
/// (generically unstable, about half the eigenvalues in the right half-plane), `B` random
/// (generically controllable), `[[Q, N], [Nᵀ, R]] = MᵀM/(n+m) + 0.1 I ≻ 0` so the data are a
/// genuine LQ problem; the cross term `N` only when `cross`.
pub fn lq_data(seed: u64, n: usize, m: usize, cross: bool) -> (Mat, Mat, Mat, Mat, Option<Mat>) {
    let mut r = rng(seed);
    let a = rand_mat(&mut r, n, n) * (3.0 / (n as f64).sqrt());
    let b = rand_mat(&mut r, n, m);
    let f = rand_mat(&mut r, n + m, n + m);
    let w = f.transpose() * f * (1.0 / (n + m) as f64) + Mat::identity(n + m, n + m) * 0.1;
    let q = w.view((0, 0), (n, n)).into_owned();
    let rr = w.view((n, n), (m, m)).into_owned();
    let nn = w.view((0, n), (n, m)).into_owned();
    (a, b, q, rr, cross.then_some(nn))
}
