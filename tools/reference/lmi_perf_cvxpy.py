#!/usr/bin/env python3
"""Timing reference for `pendulab bench lmi-servo` and `pendulab bench sos-gain-schedule`:
the same two problems written in CVXPY and solved by Clarabel (Python), timed repeatedly.

The problems are those of tools/reference/lmi_reference.py (written from their mathematical
statements, not from pendulab's modelling layer):

- lmi-servo: the LMI LQ cost bound of p2c122_ex4 (5-state arm servo, maximise trace X);
- sos-gain-schedule: the kernel-form SOS program of p2c15_ex7 (minimise gamma), one solve.

For each: wall-clock total of `prob.solve` (CVXPY canonicalisation + Clarabel), Clarabel's own
`solve_time`, process CPU time, iteration count, and the conic dimensions Clarabel sees; with
Clarabel's default linear solver choice ("auto": faer's supernodal LDL on dense-fill KKT
systems, QDLDL otherwise) and with "qdldl" forced.

Usage: python3 tools/reference/lmi_perf_cvxpy.py [repeats]   (from the repository root)
Prints one JSON document; nothing is written. Tool versions are printed with the figures.
"""

import json
import statistics
import sys
import time

import clarabel
import cvxpy as cp
import numpy as np
import scipy

from book_plants import a1n, al2, al3, arm, augment, b1n
from sos_kernel import mono, multiplier, padd, pmul, pscale, ptrans, sos

EPS = 1e-6
At, Bt = augment(*arm())
Qs = np.diag([0.1, 1, 0.001, 0.001, 4.0])
Rs = np.array([[1.0]])
n, m = 5, 1


def servo_problem():
    X = cp.Variable((n, n), symmetric=True)
    L = cp.Variable((m, n))
    Qh = np.sqrt(np.diag(Qs)) * np.eye(n)
    Y = At @ X + Bt @ L
    cons = [X >> EPS * np.eye(n),
            cp.bmat([[Y + Y.T, X @ Qh, L.T],
                     [Qh @ X, -np.eye(n), np.zeros((n, m))],
                     [L, np.zeros((m, n)), -np.eye(m)]]) << -EPS * np.eye(2 * n + m)]
    return cp.Problem(cp.Maximize(cp.trace(X)), cons)


def gain_schedule_problem():
    rb = 1.0 - np.cos(np.deg2rad(65.0))
    nu = 0.75
    A1t = np.zeros((5, 5)); A1t[3, 2] = -a1n * al3 / al2
    B1t = np.zeros((5, 1)); B1t[3, 0] = b1n * al3 / al2
    X = [cp.Variable((n, n), symmetric=True) for _ in range(3)]
    Lv = [cp.Variable((m, n)) for _ in range(3)]
    gam = cp.Variable()
    I5 = np.eye(n)
    Xs = {mono(0): X[0], mono(1): rb * X[1], mono(2): rb**2 * X[2]}
    Ls = {mono(0): Lv[0], mono(1): rb * Lv[1], mono(2): rb**2 * Lv[2]}
    Xs0 = {mono(es0=0): X[0], mono(es0=1): rb * X[1], mono(es0=2): rb**2 * X[2]}
    g1 = {mono(1): 1.0, mono(2): -1.0}
    g2 = {mono(es0=1): 1.0, mono(es0=2): -1.0}
    ga = {mono(): 1.0, mono(ew=1): -1.0}
    gb = {mono(): 1.0, mono(ew=1): 1.0}
    S11, _ = multiplier(n, 0, 1)
    S22, _ = multiplier(n, 2, 1)
    S31, _ = multiplier(n, 0, 3)
    Sa, _ = multiplier(n, 0, 3)
    Sb, _ = multiplier(n, 0, 3)
    epsI = {mono(): EPS * I5}
    M1 = padd(Xs, pscale(pmul(g1, S11), -1.0), pscale(epsI, -1.0))
    M211 = padd(Xs0, pscale(pmul(g2, S22), -1.0), pscale(epsI, -1.0))
    As = {mono(): At, mono(1): rb * A1t}
    Bs = {mono(): Bt, mono(1): rb * B1t}
    Y = padd(pmul(As, Xs), pmul(Bs, Ls))
    Xdot = {mono(0, 1): nu * X[1], mono(1, 1): 2 * nu * rb * X[2]}
    M311 = padd(Xdot, pscale(Y, -1.0), pscale(ptrans(Y), -1.0), pscale(pmul(g1, S31), -1.0),
                pscale(pmul(ga, Sa), -1.0), pscale(pmul(gb, Sb), -1.0), pscale(epsI, -1.0))
    Qh = np.sqrt(np.diag(Qs)) * np.eye(n)
    XQ = pmul(Xs, {mono(): Qh})
    LR = pmul(ptrans(Ls), {mono(): np.eye(1)})

    def block(rows):
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

    M2 = block([[(M211, (n, n)), (I5, (n, n))], [(I5, (n, n)), ({mono(): gam * I5}, (n, n))]])
    M3 = block([[(M311, (n, n)), (XQ, (n, n)), (LR, (n, m))],
                [(ptrans(XQ), (n, n)), (np.eye(n), (n, n)), (np.zeros((n, m)), (n, m))],
                [(ptrans(LR), (m, n)), (np.zeros((m, n)), (m, n)), (np.eye(m), (m, m))]])
    bs = lambda k: [mono(e) for e in range(k + 1)]
    bs0 = lambda k: [mono(es0=e) for e in range(k + 1)]
    cons = sos(M1, [bs(2)] * n)[0] + sos(M2, [bs0(2)] * n + [[mono()]] * n)[0] \
        + sos(M3, [bs(4)] * n + [[mono()]] * (n + m))[0]
    return cp.Problem(cp.Minimize(gam), cons)


def dims(prob):
    data, _, _ = prob.get_problem_data(cp.CLARABEL)
    cones = data["dims"]
    return {"variables": int(data["A"].shape[1]), "rows": int(data["A"].shape[0]),
            "nonzeros": int(data["A"].nnz), "equalities": int(cones.zero),
            "psd_sizes": [int(s) for s in cones.psd]}


def measure(build, repeats, method):
    """Rebuilds the CVXPY problem every time (a 'design' = build + solve, as in the bench)."""
    totals, cpus, solves, iters, value = [], [], [], [], None
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        prob = build()
        prob.solve(solver=cp.CLARABEL, direct_solve_method=method)
        totals.append(time.perf_counter() - w0)
        cpus.append(time.process_time() - c0)
        solves.append(prob.solver_stats.solve_time)
        iters.append(prob.solver_stats.num_iters)
        value = prob.value
    return {"direct_solve_method": method,
            "total_ms_median": 1e3 * statistics.median(totals),
            "total_ms_min": 1e3 * min(totals),
            "process_cpu_ms_median": 1e3 * statistics.median(cpus),
            "clarabel_solve_ms_median": 1e3 * statistics.median(solves),
            "clarabel_solve_ms_min": 1e3 * min(solves),
            "iterations": iters[-1], "objective": value, "status": prob.status}


if __name__ == "__main__":
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 10
    out = {"tool": f"CVXPY {cp.__version__} with Clarabel {clarabel.__version__}, "
                   f"SciPy {scipy.__version__}, NumPy {np.__version__}",
           "repeats": repeats}
    for name, build in [("lmi-servo", servo_problem), ("sos-gain-schedule", gain_schedule_problem)]:
        out[name] = {"dims": dims(build()),
                     "auto": measure(build, repeats, "auto"),
                     "qdldl": measure(build, max(1, repeats // 3), "qdldl")}
    print(json.dumps(out, indent=1))
