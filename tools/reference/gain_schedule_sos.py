"""The kernel-form SOS program of the gain-scheduled arm servo (book part 2 §1.5, p2c15_ex7) in
CVXPY, stated once for the two scripts beside it: lmi_reference.py solves it for the fixture
and lmi_perf_cvxpy.py times it, so the timed program is the one solved.

Parameters (normalised): rho = rb * s, s in [0, 1]; rho0 = rb * s0; rho_dot = 0.75 w,
w in [-1, 1]. Polynomials are dicts {(e_s, e_w, e_s0): coefficient matrix} (sos_kernel.py);
the Gram matrices are PSD variables, the coefficient matching equalities, the monomial bases
written out below. Written from the mathematical statement, not from pendulab's modelling
layer; the arm pendulum's parameters come from book_plants.py (docs/model.md §2).
"""

import cvxpy as cp
import numpy as np

from book_plants import a1n, al2, al3, b1n
from sos_kernel import mono, multiplier, padd, pmul, pscale, ptrans, sos

RHO_MAX = 1.0 - np.cos(np.deg2rad(65.0))  # rb: rho = 1 - cos(theta1) for |theta1| <= 65 deg
RHO_DOT_BOUND = 0.75  # nu: |rho_dot| <= nu


def block(rows):
    """A block matrix of polynomials: rows of (block, shape), a block a polynomial (dict), a
    constant matrix or a CVXPY expression; returns the polynomial of its coefficients."""
    keys = set()
    for r in rows:
        for (b, _shape) in r:
            if isinstance(b, dict):
                keys |= set(b)
    out_ = {}
    for k in keys:
        out_[k] = cp.bmat([[(b[k] if k in b else np.zeros(shape)) if isinstance(b, dict)
                            else (b if k == mono() else np.zeros(shape))
                            for (b, shape) in r] for r in rows])
    return out_


def gain_schedule_program(At, Bt, Qs, eps):
    """The SOS program of p2c15_ex7 for the augmented arm servo (At, Bt) with state weight Qs
    (diagonal) and margin eps: minimise gamma. Returns (problem, X, L) with X = [X0, X1, X2],
    L = [L0, L1, L2] the CVXPY variables of X(rho), L(rho) in the rho basis."""
    rb, nu = RHO_MAX, RHO_DOT_BOUND
    n, m = Bt.shape
    A1t = np.zeros((n, n)); A1t[3, 2] = -a1n * al3 / al2
    B1t = np.zeros((n, m)); B1t[3, 0] = b1n * al3 / al2
    X = [cp.Variable((n, n), symmetric=True) for _ in range(3)]
    Lv = [cp.Variable((m, n)) for _ in range(3)]
    gam = cp.Variable()
    In = np.eye(n)
    Xs = {mono(0): X[0], mono(1): rb * X[1], mono(2): rb**2 * X[2]}
    Ls = {mono(0): Lv[0], mono(1): rb * Lv[1], mono(2): rb**2 * Lv[2]}
    Xs0 = {mono(es0=0): X[0], mono(es0=1): rb * X[1], mono(es0=2): rb**2 * X[2]}
    g1 = {mono(1): 1.0, mono(2): -1.0}                      # s (1 - s)
    g2 = {mono(es0=1): 1.0, mono(es0=2): -1.0}              # s0 (1 - s0)
    ga = {mono(): 1.0, mono(ew=1): -1.0}                    # 1 - w
    gb = {mono(): 1.0, mono(ew=1): 1.0}                     # 1 + w
    S11, _ = multiplier(n, 0, 1)
    S22, _ = multiplier(n, 2, 1)
    S31, _ = multiplier(n, 0, 3)
    Sa, _ = multiplier(n, 0, 3)
    Sb, _ = multiplier(n, 0, 3)
    epsI = {mono(): eps * In}
    M1 = padd(Xs, pscale(pmul(g1, S11), -1.0), pscale(epsI, -1.0))
    M211 = padd(Xs0, pscale(pmul(g2, S22), -1.0), pscale(epsI, -1.0))
    As = {mono(): At, mono(1): rb * A1t}
    Bs = {mono(): Bt, mono(1): rb * B1t}
    Y = padd(pmul(As, Xs), pmul(Bs, Ls))
    # Xdot = rho_dot (X1 + 2 rho X2) = nu w (X1 + 2 rb s X2)
    Xdot = {mono(0, 1): nu * X[1], mono(1, 1): 2 * nu * rb * X[2]}
    M311 = padd(Xdot, pscale(Y, -1.0), pscale(ptrans(Y), -1.0), pscale(pmul(g1, S31), -1.0),
                pscale(pmul(ga, Sa), -1.0), pscale(pmul(gb, Sb), -1.0), pscale(epsI, -1.0))
    Qh = np.sqrt(np.diag(Qs)) * np.eye(n)
    XQ = pmul(Xs, {mono(): Qh})
    LR = pmul(ptrans(Ls), {mono(): np.eye(m)})
    M2 = block([[(M211, (n, n)), (In, (n, n))], [(In, (n, n)), ({mono(): gam * In}, (n, n))]])
    M3 = block([[(M311, (n, n)), (XQ, (n, n)), (LR, (n, m))],
                [(ptrans(XQ), (n, n)), (np.eye(n), (n, n)), (np.zeros((n, m)), (n, m))],
                [(ptrans(LR), (m, n)), (np.zeros((m, n)), (m, n)), (np.eye(m), (m, m))]])
    bs = lambda k: [mono(e) for e in range(k + 1)]
    bs0 = lambda k: [mono(es0=e) for e in range(k + 1)]
    c1, _ = sos(M1, [bs(2)] * n)
    c2, _ = sos(M2, [bs0(2)] * n + [[mono()]] * n)
    c3, _ = sos(M3, [bs(4)] * n + [[mono()]] * (n + m))
    return cp.Problem(cp.Minimize(gam), c1 + c2 + c3), X, Lv
