#!/usr/bin/env python3
"""Independent references for pendulab-lmi: the book's part 2 ch. 1 LMIs solved with CVXPY
(Clarabel backend) and the Riccati LQ gains from SciPy.

Every problem is written here from its mathematical statement, without pendulab's modelling
layer: the arm-type pendulum of docs/model.md §2 (table 3.7 parameters, book_plants.py), the
LMIs of the book part 2 ch. 1, and for p2c15_ex7 a hand-written kernel-form SOS program (Gram matrices as PSD
variables, coefficient matching as equalities; gain_schedule_sos.py, shared with the timing script).

Writes crates/lmi/tests/fixtures/lmi_reference.json.
Usage: python3 tools/reference/lmi_reference.py   (from the repository root)
Gains are in the library convention u = -K x.
"""

import json
import pathlib
import time

import clarabel
import cvxpy as cp
import numpy as np
import scipy
from scipy.linalg import solve_continuous_are

from book_plants import arm, augment
from gain_schedule_sos import RHO_DOT_BOUND, RHO_MAX, gain_schedule_program

OUT = pathlib.Path("crates/lmi/tests/fixtures/lmi_reference.json")
EPS = 1e-6

Qs = np.diag([0.1, 1, 0.001, 0.001, 4.0])
Rs = np.array([[1.0]])


def lqr(A, B, Q, R):
    P = solve_continuous_are(A, B, Q, R)
    return np.linalg.solve(R, B.T @ P), P


def solve(prob):
    t0 = time.perf_counter()
    prob.solve(solver=cp.CLARABEL)
    total = time.perf_counter() - t0
    return total, prob.solver_stats.solve_time


out = {"generator": "tools/reference/lmi_reference.py",
       "tool": f"CVXPY {cp.__version__} with Clarabel {clarabel.__version__}, SciPy {scipy.__version__}, NumPy {np.__version__}",
       "convention": "u = -K x", "margin": EPS}

# ---- p2c121_ex3: min xi1 + xi2, P = [[xi1, xi2], [xi2, 1]] ----------------------------------
A = np.array([[0.0, 1.0], [-2.25, -2.25]])
xi = cp.Variable(2)
P = cp.bmat([[xi[0], xi[1]], [xi[1], 1.0]])
prob = cp.Problem(cp.Minimize(xi[0] + xi[1]),
                  [P >> EPS * np.eye(2), A.T @ P + P @ A + 2 * P << -EPS * np.eye(2)])
solve(prob)
out["p2c121"] = {"optimum": prob.value, "xi": xi.value.tolist()}

# ---- p2c122_ex4: LMI LQ servo vs Riccati -----------------------------------------------------
A, B = arm()
At, Bt = augment(A, B)


def lq_lmi(vertices, Q, R, regions=(), umax=None, x0s=(), maximize=True, extra=None):
    n, m = vertices[0][1].shape
    X = cp.Variable((n, n), symmetric=True)
    L = cp.Variable((m, n))
    Qh = np.sqrt(np.diag(Q)) * np.eye(n) if np.allclose(Q, np.diag(np.diag(Q))) else scipy.linalg.sqrtm(Q).real
    Rh = scipy.linalg.sqrtm(R).real
    cons = [X >> EPS * np.eye(n)]
    for (Av, Bv) in vertices:
        Y = Av @ X + Bv @ L
        cons.append(cp.bmat([[Y + Y.T, X @ Qh, L.T @ Rh],
                             [Qh @ X, -np.eye(n), np.zeros((n, m))],
                             [Rh @ L, np.zeros((m, n)), -np.eye(m)]]) << -EPS * np.eye(2 * n + m))
        for reg in regions:
            kind = reg[0]
            if kind == "decay":
                cons.append(Y + Y.T + 2 * reg[1] * X << -EPS * np.eye(n))
            elif kind == "speed":
                cons.append(-(Y + Y.T) - 2 * reg[1] * X << -EPS * np.eye(n))
            elif kind == "sector":
                s, c = np.sin(reg[1]), np.cos(reg[1])
                cons.append(cp.bmat([[s * (Y + Y.T), c * (Y - Y.T)],
                                     [c * (Y.T - Y), s * (Y + Y.T)]]) << -EPS * np.eye(2 * n))
    if umax is not None:
        for i in range(m):
            cons.append(cp.bmat([[X, L[i:i + 1, :].T], [L[i:i + 1, :], np.array([[umax**2]])]]) >> 0)
        for x0 in x0s:
            x0 = np.asarray(x0).reshape(-1, 1)
            cons.append(cp.bmat([[np.eye(1), x0.T], [x0, X]]) >> 0)
    if extra is not None:
        cons += extra(X, L)
    prob = cp.Problem(cp.Maximize(cp.trace(X)) if maximize else cp.Minimize(0), cons)
    tt, ts = solve(prob)
    K = -L.value @ np.linalg.inv(X.value)
    return K, X.value, prob, tt, ts


K_lq, P_lq = lqr(At, Bt, Qs, Rs)
K_lmi, X_lmi, prob, tt, ts = lq_lmi([(At, Bt)], Qs, Rs)
out["p2c122_lq"] = {"K_riccati": K_lq.tolist(), "P_riccati": P_lq.tolist(),
                    "K_lmi_cvxpy": K_lmi.tolist(), "trace_X": float(np.trace(X_lmi)),
                    "cvxpy_total_s": tt, "clarabel_solve_s": ts}

# ---- p2c122_ex4 multiobjective: Re < -2, Re > -16, sector pi/4 -----------------------------
regions = [("decay", 2.0), ("speed", 16.0), ("sector", np.pi / 4)]
K_mo, X_mo, prob, _, _ = lq_lmi([(At, Bt)], Qs, Rs, regions=regions)
out["p2c122_multiobjective"] = {"K": K_mo.tolist(), "trace_X": float(np.trace(X_mo)),
                                "poles": [[z.real, z.imag] for z in np.linalg.eigvals(At - Bt @ K_mo)]}

# ---- p2c13_ex5 robust: 4 vertices, alpha = 2, beta = 40 -------------------------------------
verts = []
for a1 in (3.41, 8.99):
    for b1 in (8.69, 22.91):
        Av, Bv = arm(a1, b1)
        verts.append(augment(Av, Bv))
K_rob, X_rob, prob, _, _ = lq_lmi(verts, Qs, Rs, regions=[("decay", 2.0), ("speed", 40.0)])
out["p2c13_robust"] = {
    "vertices": [[3.41, 8.69], [3.41, 22.91], [8.99, 8.69], [8.99, 22.91]],
    "K": K_rob.tolist(), "trace_X": float(np.trace(X_rob)),
    "max_real_pole_per_vertex_robust": [float(max(np.linalg.eigvals(Av - Bv @ K_rob).real)) for (Av, Bv) in verts],
    "max_real_pole_per_vertex_nominal_lq": [float(max(np.linalg.eigvals(Av - Bv @ K_lq).real)) for (Av, Bv) in verts],
}

# ---- p2c14_ex6 saturation: |u| <= 0.1, x0 = [10 deg, 0, 0, 0] ------------------------------
Qsat = np.diag([20.0, 10.0, 0.1, 0.1])
x0 = [np.deg2rad(10.0), 0, 0, 0]
K_sat, X_sat, prob, _, _ = lq_lmi([(A, B)], Qsat, Rs, umax=0.1, x0s=[x0])
out["p2c14_saturation"] = {"trace_X_max": float(np.trace(X_sat)), "K_at_max": K_sat.tolist(),
                           "x0": x0, "u_max": 0.1}

# ---- p2c15_ex7: gain-scheduled servo, kernel-form SOS by hand (gain_schedule_sos.py) -------
rb, nu = RHO_MAX, RHO_DOT_BOUND
prob, X, Lv = gain_schedule_program(At, Bt, Qs, EPS)
tt, ts = solve(prob)
gamma_star = float(prob.value)
K_rhobar = None
if prob.status in ("optimal", "optimal_inaccurate"):
    Xv = [x.value for x in X]
    Lvv = [l.value for l in Lv]
    Xrb = Xv[0] + rb * Xv[1] + rb**2 * Xv[2]
    Lrb = Lvv[0] + rb * Lvv[1] + rb**2 * Lvv[2]
    K_rhobar = (-Lrb @ np.linalg.inv(Xrb)).tolist()
out["p2c15_gain_schedule"] = {
    "status": prob.status, "gamma_star": gamma_star, "K_at_rho_max_at_optimum": K_rhobar,
    "rho_max": rb, "rho_dot_bound": nu,
    "cvxpy_total_s": tt, "clarabel_solve_s": ts,
    "note": "X(rho) = X0 + rho X1 + rho^2 X2 with rho = rb*s; cvxpy variables hold X0, X1, X2 in the rho basis",
}

OUT.parent.mkdir(parents=True, exist_ok=True)
OUT.write_text(json.dumps(out, indent=1) + "\n")
print(json.dumps({k: (v if not isinstance(v, dict) else {kk: vv for kk, vv in v.items() if "P_" not in kk}) for k, v in out.items()}, indent=1)[:4000])
