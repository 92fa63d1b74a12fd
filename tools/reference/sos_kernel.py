"""Hand-written kernel-form SOS programs in CVXPY for the reference scripts (the gain-scheduled
servo of book part 2 §1.5): polynomials in the scheduling parameters as dicts
{(e_s, e_w, e_s0): coefficient matrix}, their arithmetic, PSD multipliers and the coefficient
matching of M = Zᵀ Q Z. Imported by lmi_reference.py and lmi_perf_cvxpy.py.
"""

import cvxpy as cp
import numpy as np


def mono(es=0, ew=0, es0=0):
    return (es, ew, es0)


def padd(*ps):
    r = {}
    for p in ps:
        for k, v in p.items():
            r[k] = r[k] + v if k in r else v
    return r


def pscale(p, c):
    return {k: c * v for k, v in p.items()}


def pmul(p, q):
    """p * q where, per term, one factor is a numpy array (or scalar)."""
    r = {}
    for k1, v1 in p.items():
        for k2, v2 in q.items():
            k = tuple(a + b for a, b in zip(k1, k2))
            if np.isscalar(v1) or np.isscalar(v2):
                t = v1 * v2
            else:
                t = v1 @ v2
            r[k] = r[k] + t if k in r else t
    return r


def ptrans(p):
    return {k: v.T for k, v in p.items()}


def multiplier(size, var_index, degree):
    """S = (I (x) z)^T R (I (x) z), z = [1, v, ..., v^degree] in parameter var_index; (S, R)."""
    d = degree + 1
    R = cp.Variable((size * d, size * d), PSD=True)
    E = [np.kron(np.eye(size), np.eye(d)[:, [a]]) for a in range(d)]
    S = {}
    for a in range(d):
        for b in range(d):
            e = [0, 0, 0]
            e[var_index] = a + b
            t = E[a].T @ R @ E[b]
            S[tuple(e)] = S[tuple(e)] + t if tuple(e) in S else t
    return S, R


def sos(M, bases):
    """Kernel-form SOS: M = Z^T Q Z, Z = blockdiag(bases), Q PSD; equalities per monomial.
    Returns (constraints, Q)."""
    p = len(bases)
    offs = np.cumsum([0] + [len(b) for b in bases])
    N = offs[-1]
    Q = cp.Variable((N, N), PSD=True)
    prods = {}
    for i in range(p):
        for j in range(p):
            for ia, a in enumerate(bases[i]):
                for jb, b in enumerate(bases[j]):
                    k = tuple(x + y for x, y in zip(a, b))
                    prods.setdefault(k, []).append((i, j, offs[i] + ia, offs[j] + jb))
    cons = []
    for k in set(prods) | set(M):
        rhs = 0
        if k in prods:
            sel = np.zeros((p * p, N * N))
            for (i, j, r, c) in prods[k]:
                sel[i * p + j, r * N + c] += 1.0
            rhs = cp.reshape(sel @ cp.vec(Q, order="C"), (p, p), order="C")
        lhs = M.get(k, np.zeros((p, p)))
        cons.append(lhs == rhs)
    return cons, Q
