"""Reference values for pendulab-control's optimal dynamic quantizer (Azuma–Sugie LP design).

Independent of pendulab: the cart-pendulum model of docs/model.md §1, the LQR gain from SciPy's
CARE solver, the ZOH discretisation from SciPy's matrix exponential, and the quantizer LP
(Azuma & Sugie, IEEE TAC 53(9), 2008) written out as an explicit linear program for SciPy's
HiGHS solver. Writes crates/control/tests/fixtures/odq_reference.json.

Run: python3 tools/reference/odq_reference.py   (from the repository root)
"""

import json
import pathlib

import numpy as np
import scipy
from scipy.linalg import expm, solve_continuous_are
from scipy.optimize import linprog
from scipy.sparse import lil_matrix

from book_plants import cdip


def c2d_zoh(A, B, ts):
    n, m = B.shape
    M = np.zeros((n + m, n + m))
    M[:n, :n] = A
    M[:n, n:] = B
    E = expm(M * ts)
    return E[:n, :n], E[:n, n:]


def markov(A, B, C, count):
    out = []
    AkB = B.copy()
    for _ in range(count):
        out.append(C @ AkB)
        AkB = A @ AkB
    return out


def odq_lp(A, B, C, T, gamma_wv=None):
    """min γ over taps H_0..H_{T-2} (SISO input: m = 1), outputs p."""
    p, m = C.shape[0], B.shape[1]
    assert m == 1
    L = T - 1
    Mk = markov(A, B, C, T)  # M_1 .. M_T
    # variables: h (L), e (p*L), gamma (1), [hbar (L)]
    nh, ne = L, p * L
    nv = nh + ne + 1 + (L if gamma_wv is not None else 0)
    ig = nh + ne
    rows = []
    rhs = []
    Aub = lil_matrix((2 * p * L + p + (2 * L + 1 if gamma_wv is not None else 0), nv))
    r = 0
    for row in range(L):
        k = row + 2
        for i in range(p):
            # g = M_k[i] + sum_{col<=row} M_{k-1-col}[i] h_col ; g - e <= 0 ; -g - e <= 0
            for col in range(row + 1):
                coef = Mk[k - 2 - col][i, 0]
                Aub[r, col] = coef
                Aub[r + 1, col] = -coef
            Aub[r, nh + row * p + i] = -1.0
            Aub[r + 1, nh + row * p + i] = -1.0
            rhs += [-Mk[k - 1][i, 0], Mk[k - 1][i, 0]]
            r += 2
    for i in range(p):
        for row in range(L):
            Aub[r, nh + row * p + i] = 1.0
        Aub[r, ig] = -1.0
        rhs.append(-abs(Mk[0][i, 0]))
        r += 1
    if gamma_wv is not None:
        ib = ig + 1
        for col in range(L):
            Aub[r, col] = 1.0
            Aub[r, ib + col] = -1.0
            Aub[r + 1, col] = -1.0
            Aub[r + 1, ib + col] = -1.0
            rhs += [0.0, 0.0]
            r += 2
        for col in range(L):
            Aub[r, ib + col] = 1.0
        rhs.append(gamma_wv - 1.0)
        r += 1
    c = np.zeros(nv)
    c[ig] = 1.0
    bounds = [(None, None)] * nv
    res = linprog(c, A_ub=Aub.tocsr(), b_ub=np.array(rhs), bounds=bounds, method="highs")
    assert res.status == 0, res.message
    return res.fun, res.x[:nh]


def l1_static(A, B, C, samples=200000):
    sums = np.zeros(C.shape[0])
    z = B.copy()
    for _ in range(samples):
        sums += np.abs(C @ z).sum(axis=1)
        z = A @ z
        if np.linalg.norm(z) < 1e-16:
            break
    return sums


def main():
    A, B = cdip()
    Q = np.diag([10.0, 10.0, 0.0, 0.0])
    R = np.array([[1.0]])
    X = solve_continuous_are(A, B, Q, R)
    K = np.linalg.solve(R, B.T @ X)  # u = -K x
    ts = 0.01
    Ad, Bd = c2d_zoh(A, B, ts)
    Acl = Ad - Bd @ K
    C = np.hstack([np.eye(2), np.zeros((2, 2))])
    d = 2.0
    T = 300
    opt_free, taps_free = odq_lp(Acl, Bd, C, T)
    opt_wv, taps_wv = odq_lp(Acl, Bd, C, T, gamma_wv=3.35)
    static = l1_static(Acl, Bd, C)
    out = {
        "tool": f"scipy {scipy.__version__} (solve_continuous_are, expm, linprog/HiGHS), numpy {np.__version__}",
        "K": K.tolist(),
        "ts": ts,
        "step": d,
        "horizon": T,
        "lp_optimum_unconstrained": opt_free,
        "lp_optimum_gamma_wv_3_35": opt_wv,
        "gamma_wv": 3.35,
        "static_cost_per_output": (static * d / 2).tolist(),
        "first_markov_parameter": markov(Acl, Bd, C, 1)[0].ravel().tolist(),
    }
    path = pathlib.Path("crates/control/tests/fixtures/odq_reference.json")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
