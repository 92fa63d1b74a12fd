#!/usr/bin/env python3
"""Timing reference for `pendulab bench lmi-servo` and `pendulab bench sos-gain-schedule`:
the same two problems written in CVXPY and solved by Clarabel (Python), timed repeatedly.

The problems are those of tools/reference/lmi_reference.py (written from their mathematical
statements, not from pendulab's modelling layer):

- lmi-servo: the LMI LQ cost bound of p2c122_ex4 (5-state arm servo, maximise trace X);
- sos-gain-schedule: the kernel-form SOS program of p2c15_ex7 (minimise gamma), one solve
  (gain_schedule_sos.py, the program lmi_reference.py solves).

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

from book_plants import arm, augment
from gain_schedule_sos import gain_schedule_program

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
    return gain_schedule_program(At, Bt, Qs, EPS)[0]


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
