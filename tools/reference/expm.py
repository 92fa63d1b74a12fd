"""Reference values for pendulab-lti's matrix exponential tests.

Writes crates/lti/tests/fixtures/expm.json: for each test matrix A, exp(A) from SciPy
(`scipy.linalg.expm`, Al-Mohy & Higham 2009) and from mpmath at 60 significant digits (the
independent high-precision value the tests compare against), and the relative condition number
kappa_exp(A) in the Frobenius norm (`scipy.linalg.expm_cond`), from which the tests derive their
tolerances: a backward-stable method has relative forward error <~ kappa_exp * u.

Test matrices: classic hard cases for scaling and squaring (Moler & Van Loan 1978/2003; Higham
2005; Al-Mohy & Higham 2009 overscaling examples) and fixed-seed random matrices of large norm.

Run: python3 tools/reference/expm.py   (from the repository root)
"""

import json
import pathlib

import mpmath
import numpy as np
import scipy
import scipy.linalg

mpmath.mp.dps = 60


def mp_expm(a):
    m = mpmath.matrix(a.tolist())
    e = mpmath.expm(m, method="taylor")
    return [[float(e[i, j]) for j in range(a.shape[1])] for i in range(a.shape[0])]


def cases():
    rng = np.random.default_rng(20240611)
    yield "moler_van_loan_2x2", np.array([[-49.0, 24.0], [-64.0, 31.0]])
    # Overscaling example of Al-Mohy & Higham (2009), Sec. 1: [[1, b], [0, -1]], b large.
    yield "overscaling_b1e4", np.array([[1.0, 1e4], [0.0, -1.0]])
    yield "overscaling_b1e8", np.array([[1.0, 1e8], [0.0, -1.0]])
    # Strongly non-normal upper triangular (Higham 2005 test set style).
    yield "triangular_nonnormal", np.array(
        [[-1.0, 100.0, 1e4], [0.0, -2.0, 100.0], [0.0, 0.0, -3.0]]
    )
    # Nearly defective 3x3 with clustered eigenvalues.
    yield "clustered", np.array(
        [[0.5, 1.0, 0.0], [0.0, 0.5 + 1e-8, 1.0], [0.0, 0.0, 0.5 - 1e-8]]
    )
    # Large-norm random matrices (many squarings), fixed seed.
    yield "random_6x6_norm30", 30.0 * rng.standard_normal((6, 6)) / np.sqrt(6)
    yield "random_8x8_small", 1e-3 * rng.standard_normal((8, 8))
    # A stiff negative-definite symmetric matrix (eigenvalues -1 .. -1e3).
    q, _ = np.linalg.qr(rng.standard_normal((5, 5)))
    yield "stiff_symmetric", q @ np.diag([-1.0, -10.0, -100.0, -500.0, -1000.0]) @ q.T
    # Skew-symmetric with large angles (orthogonal exponential).
    s = rng.standard_normal((4, 4))
    yield "skew_large", 20.0 * (s - s.T)


def main():
    out = {
        "tool": f"scipy {scipy.__version__}, mpmath {mpmath.__version__}, numpy {np.__version__}",
        "script": "tools/reference/expm.py",
        "cases": [],
    }
    for name, a in cases():
        out["cases"].append(
            {
                "name": name,
                "a": a.tolist(),
                "expm_scipy": scipy.linalg.expm(a).tolist(),
                "expm_mp60": mp_expm(a),
                "kappa_exp": float(scipy.linalg.expm_cond(a)),
            }
        )
    path = pathlib.Path("crates/lti/tests/fixtures/expm.json")
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
