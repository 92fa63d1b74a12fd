#!/usr/bin/env python3
"""Reference values for pendulab-lapack (the BLAS/LAPACK shim Clarabel's SDP path links).

Runs SciPy's BLAS/LAPACK wrappers (OpenBLAS/reference LAPACK underneath) on deterministic
random inputs covering every argument combination Clarabel 0.11 uses (and the other flag
values of each routine), and writes the inputs and outputs to
crates/lapack/tests/fixtures/lapack_reference.json.

Matrices are stored as lists of rows. Eigen/singular vectors are stored as SciPy returns them;
the Rust test compares them up to the sign of each vector.

Usage: python3 tools/reference/lapack_shim.py  (from the repository root)
"""

import json
import pathlib

import numpy as np
import scipy
from scipy.linalg import blas, lapack

OUT = pathlib.Path("crates/lapack/tests/fixtures/lapack_reference.json")
rng = np.random.default_rng(20240611)


def mat(m, n):
    return rng.standard_normal((m, n))


def spd(n):
    g = mat(n, n)
    return g @ g.T + n * np.eye(n)


def rows(a):
    return np.asarray(a, dtype=float).tolist()


def check(info, what):
    assert info == 0, f"{what}: info = {info}"


cases = {"gemm": [], "gemv": [], "symv": [], "syrk": [], "syr2k": [], "potrf": [],
         "potrs": [], "syevr": [], "gesdd": [], "gesvd": [], "gesv": []}

# gemm: C = alpha op(A) op(B) + beta C, all four transposition pairs, beta != 0 and = 0.
for ta in "NT":
    for tb in "NT":
        for beta in (-0.7, 0.0):
            m, n, k = 5, 4, 3
            a = mat(m, k) if ta == "N" else mat(k, m)
            b = mat(k, n) if tb == "N" else mat(n, k)
            c = mat(m, n)
            out = blas.dgemm(1.3, a, b, beta=beta, c=c, trans_a=int(ta == "T"),
                             trans_b=int(tb == "T"))
            cases["gemm"].append(dict(transa=ta, transb=tb, m=m, n=n, k=k, alpha=1.3, beta=beta,
                                      a=rows(a), b=rows(b), c=rows(c), out=rows(out)))
# a larger product (nalgebra hands sizes > 5 to matrixmultiply)
for ta, tb in (("N", "N"), ("T", "N"), ("N", "T")):
    m, n, k = 9, 8, 7
    a = mat(m, k) if ta == "N" else mat(k, m)
    b = mat(k, n) if tb == "N" else mat(n, k)
    c = mat(m, n)
    out = blas.dgemm(-0.4, a, b, beta=2.0, c=c, trans_a=int(ta == "T"), trans_b=int(tb == "T"))
    cases["gemm"].append(dict(transa=ta, transb=tb, m=m, n=n, k=k, alpha=-0.4, beta=2.0,
                              a=rows(a), b=rows(b), c=rows(c), out=rows(out)))

# gemv: y = alpha op(A) x + beta y.
for t in "NT":
    m, n = 6, 4
    a = mat(m, n)
    x = rng.standard_normal(n if t == "N" else m)
    y = rng.standard_normal(m if t == "N" else n)
    out = blas.dgemv(0.9, a, x, beta=-1.1, y=y, trans=int(t == "T"))
    cases["gemv"].append(dict(trans=t, m=m, n=n, alpha=0.9, beta=-1.1, a=rows(a),
                              x=x.tolist(), y=y.tolist(), out=out.tolist()))

# symv: A is a full non-symmetric array; only the named triangle may be read.
for uplo in "UL":
    n = 5
    a = mat(n, n)
    x = rng.standard_normal(n)
    y = rng.standard_normal(n)
    out = blas.dsymv(1.7, a, x, beta=0.3, y=y, lower=int(uplo == "L"))
    cases["symv"].append(dict(uplo=uplo, n=n, alpha=1.7, beta=0.3, a=rows(a), x=x.tolist(),
                              y=y.tolist(), out=out.tolist()))

# syrk / syr2k: only the named triangle of C is referenced; the other must come back as given.
for uplo in "UL":
    for t in "NT":
        n, k = 5, 3
        a = mat(n, k) if t == "N" else mat(k, n)
        c = mat(n, n)
        out = blas.dsyrk(0.8, a, beta=-0.5, c=c, trans=int(t == "T"), lower=int(uplo == "L"))
        cases["syrk"].append(dict(uplo=uplo, trans=t, n=n, k=k, alpha=0.8, beta=-0.5, a=rows(a),
                                  c=rows(c), out=rows(out)))
        b = mat(n, k) if t == "N" else mat(k, n)
        out2 = blas.dsyr2k(0.6, a, b, beta=1.2, c=c, trans=int(t == "T"), lower=int(uplo == "L"))
        cases["syr2k"].append(dict(uplo=uplo, trans=t, n=n, k=k, alpha=0.6, beta=1.2, a=rows(a),
                                   b=rows(b), c=rows(c), out=rows(out2)))

# potrf / potrs on SPD matrices; the factor keeps the other triangle as given (clean=0).
for uplo in "UL":
    n = 6
    a = spd(n)
    garbage = np.triu(mat(n, n), 1) if uplo == "L" else np.tril(mat(n, n), -1)
    a_in = (np.tril(a) if uplo == "L" else np.triu(a)) + garbage
    f, info = lapack.dpotrf(a_in, lower=int(uplo == "L"), clean=0)
    check(info, "dpotrf")
    b = mat(n, 3)
    x, info = lapack.dpotrs(f, b, lower=int(uplo == "L"))
    check(info, "dpotrs")
    cases["potrf"].append(dict(uplo=uplo, n=n, a=rows(a_in), out=rows(f), info=int(info)))
    cases["potrs"].append(dict(uplo=uplo, n=n, nrhs=3, factor=rows(f), b=rows(b), out=rows(x)))
# a symmetric indefinite matrix: the leading minor of order 3 is the first non-positive one
a = spd(5)
a[2, 2] = -50.0
f, info = lapack.dpotrf(a, lower=1, clean=0)
cases["potrf"].append(dict(uplo="L", n=5, a=rows(a), out=None, info=int(info)))

# syevr: all eigenpairs (Clarabel's use), plus index and value ranges.
for uplo in "UL":
    for kind in ("spd", "indefinite"):
        n = 7
        g = mat(n, n)
        a = spd(n) if kind == "spd" else (g + g.T)
        w, z, m, isuppz, info = lapack.dsyevr(a, compute_v=1, range="A", lower=int(uplo == "L"))
        check(info, "dsyevr")
        cases["syevr"].append(dict(uplo=uplo, range="A", n=n, a=rows(a), w=w[:m].tolist(),
                                   z=rows(z[:, :m]), m=int(m), vl=0.0, vu=0.0, il=0, iu=0))
g = mat(6, 6)
a = g + g.T
w, z, m, isuppz, info = lapack.dsyevr(a, compute_v=1, range="I", il=2, iu=4, lower=0)
check(info, "dsyevr I")
cases["syevr"].append(dict(uplo="U", range="I", n=6, a=rows(a), w=w[:m].tolist(),
                           z=rows(z[:, :m]), m=int(m), vl=0.0, vu=0.0, il=2, iu=4))
w, z, m, isuppz, info = lapack.dsyevr(a, compute_v=1, range="V", vl=-1.0, vu=2.5, lower=1)
check(info, "dsyevr V")
cases["syevr"].append(dict(uplo="L", range="V", n=6, a=rows(a), w=w[:m].tolist(),
                           z=rows(z[:, :m]), m=int(m), vl=-1.0, vu=2.5, il=0, iu=0))

# gesdd / gesvd: thin ('S', Clarabel's use) and full ('A') factors, tall, wide and square.
for (m, n) in ((6, 4), (4, 6), (5, 5)):
    a = mat(m, n)
    for full in (0, 1):
        u, s, vt, info = lapack.dgesdd(a, compute_uv=1, full_matrices=full)
        check(info, "dgesdd")
        cases["gesdd"].append(dict(job="A" if full else "S", m=m, n=n, a=rows(a), s=s.tolist(),
                                   u=rows(u), vt=rows(vt)))
        u, s, vt, info = lapack.dgesvd(a, compute_uv=1, full_matrices=full)
        check(info, "dgesvd")
        cases["gesvd"].append(dict(job="A" if full else "S", m=m, n=n, a=rows(a), s=s.tolist(),
                                   u=rows(u), vt=rows(vt)))

# gesv: LU with partial pivoting, two right-hand sides; a singular matrix for INFO.
n = 6
a = mat(n, n)
b = mat(n, 2)
lu, piv, x, info = lapack.dgesv(a, b)
check(info, "dgesv")
cases["gesv"].append(dict(n=n, nrhs=2, a=rows(a), b=rows(b), lu=rows(lu),
                          ipiv=[int(p) + 1 for p in piv], x=rows(x), info=int(info)))
a = mat(n, n)
a[:, 3] = a[:, 0] * 2.0 - a[:, 1]  # column 4 depends on columns 1, 2
a[:, 4] = 0.0                       # and column 5 is zero: U(5,5) == 0 at the latest
lu, piv, x, info = lapack.dgesv(a, b)
cases["gesv"].append(dict(n=n, nrhs=2, a=rows(a), b=rows(b), lu=None, ipiv=None, x=None,
                          info=int(info)))

cfg = scipy.show_config(mode="dicts")["Build Dependencies"]["lapack"]
doc = {
    "generator": "tools/reference/lapack_shim.py",
    "tool": f"SciPy {scipy.__version__} (scipy.linalg.blas / scipy.linalg.lapack), "
            f"NumPy {np.__version__}, {cfg.get('name')} {cfg.get('version')}",
    "layout": "matrices as lists of rows; ipiv 1-based",
    "cases": cases,
}
OUT.write_text(json.dumps(doc, indent=None, separators=(",", ":")) + "\n")
print(f"wrote {OUT} ({OUT.stat().st_size} bytes)")
