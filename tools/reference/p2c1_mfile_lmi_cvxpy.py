#!/usr/bin/env python3
"""The book's part 2 ch. 1 LMI M-files, transcribed line by line into CVXPY and solved with
two interior-point solvers outside pendulab: CVXOPT and Clarabel (Python build).

M-files followed (line numbers of the book's files):
  p2c122_ex4_adip_oc_servo.m                lines 31-58
  p2c122_ex4_adip_oc_multiobjective_servo.m lines 31-66 (alpha = 3/1.5, beta = 8 alpha, k = tan(pi/4))
  p2c13_ex5_adip_oc_nominal_servo.m         lines 31-65 (alpha = 3/1.5, beta = 20 alpha)
  p2c13_ex5_adip_oc_robust_servo.m          lines 12-86 (mvert(2) vertices, one X and L)
  p2c14_ex6_adip_oc_saturation.m            lines 24-92 (max-trace solve, then the feasibility re-solve
                                            of lines 77-78; K = L inv(X), H = V inv(X) of each)
Every LMI keeps the M-file's margin: `F >= ep*eye` as F - ep*I >> 0, `F <= -ep*eye` as
-F - ep*I >> 0, `F >= 0` as F >> 0; objective maximise trace(X) (obj = -trace(X)).

Writes crates/book/tests/fixtures/p2c1_mfile_lmi.json (gains in the book's sign u = +K x; per solve
also the displayed X = double(X) and L = double(L), and poles = eig(At+Bt*Kt) of the p2c122 servos;
Kt_LQ = -lqr(At,Bt,Q,R) and its poles_LQ by SciPy's CARE solver).
Usage: python3 tools/reference/p2c1_mfile_lmi_cvxpy.py   (from the repository root)
Versions used for the committed fixture: recorded in the JSON ("versions").
"""

import json
import pathlib

import clarabel
import cvxopt
import cvxpy as cp
import numpy as np
import scipy
import scipy.linalg

OUT = pathlib.Path("crates/book/tests/fixtures/p2c1_mfile_lmi.json")
ep = 1e-6

# adip_para: the arm pendulum of book table 3.7 (adip_para.m; docs/model.md)
a1n, b1n, L1, m2, lc2, J2, mu2, g = 6.20, 15.8, 0.227, 0.096, 0.195, 9.06e-4, 1.01e-4, 9.81
alpha2, alpha3, alpha5 = J2 + m2 * lc2**2, m2 * L1 * lc2, m2 * lc2 * g


def plant(a1, b1):
    A21 = np.array([[0, 0], [0, alpha5 / alpha2]])
    A22 = np.array([[-a1, 0], [(a1 * alpha3 + mu2) / alpha2, -mu2 / alpha2]])
    B2 = np.array([[b1], [-b1 * alpha3 / alpha2]])
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [A21, A22]])
    B = np.vstack([np.zeros((2, 1)), B2])
    return A, B


def servo(a1, b1):
    A, B = plant(a1, b1)
    C = np.array([[1, 0, 0, 0]])
    At = np.block([[A, np.zeros((4, 1))], [-C, np.zeros((1, 1))]])
    Bt = np.vstack([B, [[0]]])
    return At, Bt


def mvert(m):
    vmat = np.zeros((0, 1))
    for _ in range(m):
        ls = vmat.shape[1]
        vmat = np.vstack([np.hstack([vmat, vmat]), np.hstack([np.zeros((1, ls)), np.ones((1, ls))])])
    return vmat


def sym(M):
    return (M + M.T) / 2


def lq_lmi(A, B, Q, X, L):
    n = A.shape[0]
    M = A @ X + B @ L
    sq = np.sqrt(Q)
    return cp.bmat([[M.T + M, X @ sq, L.T], [sq @ X, -np.eye(n), np.zeros((n, 1))],
                    [L, np.zeros((1, n)), -np.ones((1, 1))]])


def le(F):  # F <= -ep*eye
    k = F.shape[0]
    return sym(-F) - ep * np.eye(k) >> 0


def ge(F, margin=ep):  # F >= margin*eye
    k = F.shape[0]
    return sym(F) - margin * np.eye(k) >> 0


Qs = np.diag([0.1, 1, 0.001, 0.001, 4])


def servo_problem(models, alpha=None, k=None, beta=None):
    X = cp.Variable((5, 5), symmetric=True)
    L = cp.Variable((1, 5))
    con = [ge(X)]
    for At, Bt in models:
        M = At @ X + Bt @ L
        con.append(le(lq_lmi(At, Bt, Qs, X, L)))
        if alpha is not None:
            con.append(le(M.T + M + 2 * alpha * X))
        if k is not None:
            con.append(le(cp.bmat([[k * (M.T + M), M - M.T], [M.T - M, k * (M.T + M)]])))
        if beta is not None:
            con.append(ge(M.T + M + 2 * beta * X))
    return cp.Problem(cp.Maximize(cp.trace(X)), con), X, L, None


def saturation_problem():
    A, B = plant(a1n, b1n)
    Q = np.diag([20, 10, 0.1, 0.1])
    X = cp.Variable((4, 4), symmetric=True)
    L = cp.Variable((1, 4))
    V = cp.Variable((1, 4))
    x0 = np.array([[10 * np.pi / 180], [0], [0], [0]])
    MH = cp.bmat([[X, V.T], [V, 0.1**2 * np.ones((1, 1))]])
    INI = cp.bmat([[X, x0], [x0.T, np.ones((1, 1))]])
    con = [ge(X), le(lq_lmi(A, B, Q, X, L)), le(lq_lmi(A, B, Q, X, V)), sym(MH) >> 0, sym(INI) >> 0]
    return cp.Problem(cp.Maximize(cp.trace(X)), con), X, L, V


alpha = 3 / 1.5
ve = mvert(2)
r1, r2 = a1n * np.array([0.55, 1.45]), b1n * np.array([0.55, 1.45])
vertex = np.vstack([r1[0] + np.diff(r1) * ve[0], r2[0] + np.diff(r2) * ve[1]])

cases = {
    "p2c122_ex4_adip_oc_servo": lambda: servo_problem([servo(a1n, b1n)]),
    "p2c122_ex4_adip_oc_multiobjective_servo": lambda: servo_problem(
        [servo(a1n, b1n)], alpha=alpha, k=np.tan(np.pi / 4), beta=8 * alpha),
    "p2c13_ex5_adip_oc_nominal_servo": lambda: servo_problem([servo(a1n, b1n)], alpha=alpha, beta=20 * alpha),
    "p2c13_ex5_adip_oc_robust_servo": lambda: servo_problem(
        [servo(vertex[0, i], vertex[1, i]) for i in range(4)], alpha=alpha, beta=20 * alpha),
    "p2c14_ex6_adip_oc_saturation": saturation_problem,
}

out = {
    "versions": {"cvxpy": cp.__version__, "cvxopt": cvxopt.__version__, "clarabel": clarabel.__version__,
                 "numpy": np.__version__, "scipy": scipy.__version__},
    "vertex": vertex.tolist(),
}
for name, make in cases.items():
    out[name] = {}
    # Each solver at its default tolerances (CVXOPT 1e-7, Clarabel 1e-8).
    for solver, opts in [("CVXOPT", {"max_iters": 500}), ("CLARABEL", {"max_iter": 500})]:
        prob, X, L, V = make()
        try:
            prob.solve(solver=solver, **opts)
        except Exception as e:  # noqa: BLE001 (CVXOPT can stop with a ZeroDivisionError)
            out[name][solver] = {"status": f"error: {e}"}
            print(name, solver, "error", e)
            continue
        Xv = sym(X.value)
        Xi = np.linalg.inv(Xv)
        # Smallest eigenvalue over the constraints (each stated as G >> 0).
        margin = min(float(np.linalg.eigvalsh(sym(c.args[0].value)).min()) for c in prob.constraints)
        rec = {"status": prob.status, "trace_X": float(np.trace(Xv)), "trace_invX": float(np.trace(Xi)),
               "K": (L.value @ Xi).ravel().tolist(), "min_constraint_eigenvalue": margin,
               "X": Xv.tolist(), "L": L.value.ravel().tolist()}
        if name.startswith("p2c122"):
            # poles = eig(At+Bt*Kt) (p2c122_ex4_adip_oc_servo.m line 60, multiobjective line 75).
            At, Bt = servo(a1n, b1n)
            rec["poles"] = [[z.real, z.imag] for z in np.linalg.eigvals(At + Bt @ (L.value @ Xi))]
        if V is not None:
            rec["H"] = (V.value @ Xi).ravel().tolist()
            # Lines 77-78: CON + [trace(X) <= -double(OBV)], solvesdp(CON) with no objective.
            prob2 = cp.Problem(cp.Minimize(0), prob.constraints + [cp.trace(X) <= rec["trace_X"]])
            try:
                prob2.solve(solver=solver, **opts)
                X2 = sym(X.value)
                rec["second_solve"] = {"status": prob2.status, "trace_X": float(np.trace(X2)),
                                       "K": (L.value @ np.linalg.inv(X2)).ravel().tolist(),
                                       "H": (V.value @ np.linalg.inv(X2)).ravel().tolist()}
            except Exception as e:  # noqa: BLE001
                rec["second_solve"] = {"status": f"error: {e}"}
            print("  second solve:", rec["second_solve"])
        out[name][solver] = rec
        print(name, solver, prob.status, rec["trace_X"], rec["K"], rec.get("H", ""), margin)

# Kt_LQ = -lqr(At,Bt,Q,R), poles_LQ = eig(At+Bt*Kt_LQ) (p2c122_ex4_adip_oc_servo.m lines 89-93),
# by SciPy's CARE solver.
At, Bt = servo(a1n, b1n)
P = scipy.linalg.solve_continuous_are(At, Bt, Qs, np.eye(1))
Kt_LQ = -(Bt.T @ P)
out["Kt_LQ"] = Kt_LQ.ravel().tolist()
out["poles_LQ"] = [[z.real, z.imag] for z in np.linalg.eigvals(At + Bt @ Kt_LQ)]
OUT.write_text(json.dumps(out, indent=1) + "\n")
print("wrote", OUT)
