//! The LAPACK/BLAS contracts beyond the numbers: argument errors through `INFO` (or a no-op
//! for BLAS), quick returns that touch nothing, `α = 0` / `β = 0` not reading, the other SVD
//! jobs checked by their defining identities, and non-finite input reported, not panicking.

use core::ffi::{c_char, c_int};
use pendulab_lapack::ffi::*;

mod common;

/// A deterministic well-conditioned test matrix (entries in [−1, 1]), column-major.
fn test_matrix(m: usize, n: usize, seed: u64) -> Vec<f64> {
    common::lcg_entries(m * n, seed)
}

fn c(x: u8) -> c_char {
    x as c_char
}

#[test]
fn invalid_lapack_arguments_come_back_as_negative_info() {
    let mut a = vec![4.0, 1.0, 1.0, 3.0];
    let mut info: c_int = 0;
    unsafe { dpotrf_(&c(b'X'), &2, a.as_mut_ptr(), &2, &mut info) };
    assert_eq!(info, -1, "bad UPLO is argument 1");
    unsafe { dpotrf_(&c(b'L'), &-1, a.as_mut_ptr(), &2, &mut info) };
    assert_eq!(info, -2, "negative N is argument 2");
    unsafe { dpotrf_(&c(b'L'), &2, a.as_mut_ptr(), &1, &mut info) };
    assert_eq!(info, -4, "LDA < N is argument 4");
    assert_eq!(a, vec![4.0, 1.0, 1.0, 3.0], "nothing computed on error");

    let mut ipiv = [0 as c_int; 2];
    let mut b = vec![1.0, 1.0];
    unsafe {
        dgesv_(
            &2,
            &1,
            a.as_mut_ptr(),
            &2,
            ipiv.as_mut_ptr(),
            b.as_mut_ptr(),
            &1,
            &mut info,
        )
    };
    assert_eq!(info, -7, "LDB < N is argument 7");

    // dsyevr: a too small workspace outside a query is argument 18.
    let n = 4;
    let mut a = test_matrix(n, n, 1);
    let (mut m, mut w, mut z) = (0 as c_int, vec![0.0; n], vec![0.0; n * n]);
    let mut isuppz = vec![0 as c_int; 2 * n];
    let (mut work, mut iwork) = (vec![0.0; 10], vec![0 as c_int; 40]);
    info = unsafe {
        common::syevr(
            dsyevr_,
            (c(b'V'), c(b'A'), c(b'U')),
            (n as c_int, &mut a, n as c_int),
            (0.0, 0.0, 0, 0, -1.0),
            (&mut m, &mut w, &mut z, n as c_int, &mut isuppz),
            (&mut work, 10, &mut iwork, 40),
        )
    };
    assert_eq!(info, -18);
    // ... and JOBZ = 'V' with LDZ < N is argument 15.
    info = unsafe {
        common::syevr(
            dsyevr_,
            (c(b'V'), c(b'A'), c(b'U')),
            (n as c_int, &mut a, n as c_int),
            (0.0, 0.0, 0, 0, -1.0),
            (&mut m, &mut w, &mut z, 1, &mut isuppz),
            (&mut work, -1, &mut iwork, -1),
        )
    };
    assert_eq!(
        info, -15,
        "argument errors take precedence over the workspace query"
    );

    // dgesdd with JOBZ = 'S' and LDVT < min(M, N) is argument 10.
    let (mm, nn) = (5usize, 3usize);
    let mut a = test_matrix(mm, nn, 2);
    let (mut s, mut u, mut vt) = (vec![0.0; 3], vec![0.0; 15], vec![0.0; 9]);
    let mut work = vec![0.0; 200];
    let mut iwork = vec![0 as c_int; 24];
    unsafe {
        info = common::gesdd(
            dgesdd_,
            c(b'S'),
            (
                (5, 3, &mut a, 5),
                &mut s,
                (&mut u, 5, &mut vt, 2),
                (&mut work, 200),
            ),
            &mut iwork,
        )
    };
    assert_eq!(info, -10);
    // dgesvd with both jobs 'O' is argument 2.
    unsafe {
        info = common::gesvd(
            dgesvd_,
            (c(b'O'), c(b'O')),
            (
                (5, 3, &mut a, 5),
                &mut s,
                (&mut u, 5, &mut vt, 3),
                (&mut work, 200),
            ),
        )
    };
    assert_eq!(info, -2);
}

#[test]
fn invalid_blas_arguments_are_a_no_op() {
    let a = [1.0, 2.0, 3.0, 4.0];
    let mut cm = [9.0; 4];
    unsafe {
        dgemm_(
            &c(b'X'),
            &c(b'N'),
            &2,
            &2,
            &2,
            &1.0,
            a.as_ptr(),
            &2,
            a.as_ptr(),
            &2,
            &0.0,
            cm.as_mut_ptr(),
            &2,
        )
    };
    assert_eq!(cm, [9.0; 4]);
    let mut y = [9.0; 2];
    unsafe {
        dgemv_(
            &c(b'N'),
            &2,
            &2,
            &1.0,
            a.as_ptr(),
            &2,
            a.as_ptr(),
            &0,
            &0.0,
            y.as_mut_ptr(),
            &1,
        )
    };
    assert_eq!(y, [9.0; 2], "a zero increment is invalid");
}

#[test]
fn alpha_zero_reads_no_inputs_and_lower_case_flags_work() {
    let nan = [f64::NAN; 4];
    let mut cm = [1.0, 2.0, 3.0, 4.0];
    unsafe {
        dgemm_(
            &c(b'n'),
            &c(b't'),
            &2,
            &2,
            &2,
            &0.0,
            nan.as_ptr(),
            &2,
            nan.as_ptr(),
            &2,
            &2.0,
            cm.as_mut_ptr(),
            &2,
        )
    };
    assert_eq!(cm, [2.0, 4.0, 6.0, 8.0]);
    let mut cs = [1.0, 7.0, 2.0, 3.0];
    unsafe {
        dsyrk_(
            &c(b'u'),
            &c(b'n'),
            &2,
            &2,
            &0.0,
            nan.as_ptr(),
            &2,
            &-1.0,
            cs.as_mut_ptr(),
            &2,
        )
    };
    assert_eq!(
        cs,
        [-1.0, 7.0, -2.0, -3.0],
        "only the upper triangle scaled"
    );
}

#[test]
fn zero_dimensions_touch_nothing() {
    let mut info: c_int = 99;
    let mut a = [f64::NAN; 1];
    unsafe { dpotrf_(&c(b'L'), &0, a.as_mut_ptr(), &1, &mut info) };
    assert_eq!(info, 0);
    let mut s = [5.0; 1];
    let mut work = [0.0; 1];
    let mut iwork = [0 as c_int; 1];
    unsafe {
        // A, U and VT are one buffer: nothing may be touched.
        let a = a.as_mut_ptr();
        let (s, work, iwork) = (s.as_mut_ptr(), work.as_mut_ptr(), iwork.as_mut_ptr());
        dgesdd_(
            &c(b'N'),
            &0,
            &3,
            a,
            &1,
            s,
            a,
            &1,
            a,
            &1,
            work,
            &-1,
            iwork,
            &mut info,
        )
    };
    assert_eq!(info, 0);
    assert_eq!(s, [5.0]);
    assert!(work[0] >= 1.0, "the query still reports a size");
}

#[test]
fn non_finite_input_is_reported_through_info() {
    let n = 4;
    let mut a = test_matrix(n, n, 3);
    a[5] = f64::NAN; // (1, 1), on the diagonal: in both triangles
    let (mut m, mut w, mut z) = (0 as c_int, vec![0.0; n], vec![0.0; 1]);
    let mut isuppz = vec![0 as c_int; 2 * n];
    let (mut work, mut iwork) = (vec![0.0; 26 * n], vec![0 as c_int; 10 * n]);
    let mut info = unsafe {
        common::syevr(
            dsyevr_,
            (c(b'N'), c(b'A'), c(b'L')),
            (n as c_int, &mut a, n as c_int),
            (0.0, 0.0, 0, 0, -1.0),
            (&mut m, &mut w, &mut z, 1, &mut isuppz),
            (&mut work, 26 * n as c_int, &mut iwork, 10 * n as c_int),
        )
    };
    assert!(info > 0, "info = {info}");
    let mut spd = vec![2.0, 0.0, 0.0, f64::NAN];
    unsafe { dpotrf_(&c(b'L'), &2, spd.as_mut_ptr(), &2, &mut info) };
    assert_eq!(info, 2, "a NaN pivot is not positive");
}

/// ‖A − U diag(s) Vᵀ‖_F / ‖A‖_F for column-major `a` (`m × n`), `u` (`m × k`, ld `ldu`),
/// `vt` (`k × n`, ld `ldvt`).
fn reconstruction_error(
    a: &[f64],
    (m, n): (usize, usize),
    s: &[f64],
    (u, ldu): (&[f64], usize),
    (vt, ldvt): (&[f64], usize),
) -> f64 {
    let k = s.len();
    let mut num = 0.0;
    let mut den = 0.0;
    for j in 0..n {
        for i in 0..m {
            let r: f64 = (0..k)
                .map(|p| u[i + p * ldu] * s[p] * vt[p + j * ldvt])
                .sum();
            num += (a[i + j * m] - r).powi(2);
            den += a[i + j * m].powi(2);
        }
    }
    (num / den).sqrt()
}

/// The jobs Clarabel does not use ('O' overwriting A, 'N' values only) by their defining
/// identity A = U Σ Vᵀ, against the 'S' job's singular values. Tolerance 1e-13: a backward
/// stable SVD reconstructs to a small multiple of machine precision times ‖A‖.
#[test]
fn overwrite_and_values_only_svd_jobs() {
    for (m, n) in [(6usize, 4usize), (4, 6)] {
        let a0 = test_matrix(m, n, (m * 10 + n) as u64);
        let mn = m.min(n);
        let mut work = vec![0.0; 1000];
        let mut iwork = vec![0 as c_int; 8 * mn];
        let mut info: c_int = -1;
        // Reference values: 'N'.
        let mut a = a0.clone();
        let mut s_ref = vec![0.0; mn];
        let mut dummy = vec![0.0; 1];
        unsafe {
            // U and VT are one unused buffer.
            let (mi, ni, d) = (m as c_int, n as c_int, dummy.as_mut_ptr());
            let (a, s) = (a.as_mut_ptr(), s_ref.as_mut_ptr());
            let (w, iw) = (work.as_mut_ptr(), iwork.as_mut_ptr());
            dgesdd_(
                &c(b'N'),
                &mi,
                &ni,
                a,
                &mi,
                s,
                d,
                &1,
                d,
                &1,
                w,
                &1000,
                iw,
                &mut info,
            )
        };
        assert_eq!(info, 0);
        assert_eq!(a, a0, "JOBZ = 'N' leaves A alone");
        // 'O': U over A when m ≥ n (Vᵀ is n × n in VT), Vᵀ over A otherwise (U is m × m).
        let mut a = a0.clone();
        let mut s = vec![0.0; mn];
        let mut u = vec![0.0; m * m];
        let mut vt = vec![0.0; n * n];
        unsafe {
            info = common::gesdd(
                dgesdd_,
                c(b'O'),
                (
                    (m as c_int, n as c_int, &mut a, m as c_int),
                    &mut s,
                    (&mut u, m as c_int, &mut vt, n as c_int),
                    (&mut work, 1000),
                ),
                &mut iwork,
            )
        };
        assert_eq!(info, 0);
        let err = if m >= n {
            reconstruction_error(&a0, (m, n), &s, (&a, m), (&vt, n))
        } else {
            reconstruction_error(&a0, (m, n), &s, (&u, m), (&a, m))
        };
        assert!(err <= 1e-13, "gesdd 'O' {m}x{n}: {err:e}");
        let ds: f64 = s
            .iter()
            .zip(&s_ref)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(ds <= 1e-13 * s_ref[0], "values agree across jobs");
        // dgesvd: JOBU = 'O' (U over A), JOBVT = 'S'.
        let mut a = a0.clone();
        let mut s = vec![0.0; mn];
        let mut vt = vec![0.0; mn * n];
        unsafe {
            info = common::gesvd(
                dgesvd_,
                (c(b'O'), c(b'S')),
                (
                    (m as c_int, n as c_int, &mut a, m as c_int),
                    &mut s,
                    (&mut dummy, 1, &mut vt, mn as c_int),
                    (&mut work, 1000),
                ),
            )
        };
        assert_eq!(info, 0);
        let err = reconstruction_error(&a0, (m, n), &s, (&a, m), (&vt, mn));
        assert!(err <= 1e-13, "gesvd 'O','S' {m}x{n}: {err:e}");
    }
}
