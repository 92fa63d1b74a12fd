"""Reference values for pendulab-control's LQ-optimal sliding surface (book p2c323).

Independent of pendulab: the linearised cart pendulum of docs/model.md §1, the book's regular-form
transformation T = [[I, -B1/B2], [0, 1]] and SciPy's CARE solver on the reduced system, for
Q = diag(10, 100, 1, 1):
  - "book": care(A11 - A12 Q12'/Q22, A12, Q11, Q22) as the book's script writes it,
  - "exact": care(A11 - A12 Q12'/Q22, A12, Q11 - Q12 Q12'/Q22, Q22), the completed square,
with S = ([A12' P + Q12', Q22] T)'. Also the poles of the reduced closed loop.
Writes crates/control/tests/fixtures/sliding_mode_reference.json.

Run: python3 tools/reference/sliding_mode_reference.py   (from the repository root)
"""

import json
import pathlib

import numpy as np
import scipy
from scipy.linalg import solve_continuous_are

from book_plants import cdip


def surface(A, B, Q, exact):
    n = A.shape[0]
    B1 = B[: n - 1, :]
    B2 = B[n - 1, 0]
    T = np.eye(n)
    T[: n - 1, n - 1] = (-B1 / B2).ravel()
    Ti = np.linalg.inv(T)
    Ab = T @ A @ Ti
    Qb = Ti.T @ Q @ Ti
    A11, A12 = Ab[: n - 1, : n - 1], Ab[: n - 1, n - 1 :]
    Q11, Q12, Q22 = Qb[: n - 1, : n - 1], Qb[: n - 1, n - 1 :], Qb[n - 1 :, n - 1 :]
    At11 = A11 - A12 @ Q12.T / Q22
    Qr = Q11 - Q12 @ Q12.T / Q22 if exact else Q11
    P = solve_continuous_are(At11, A12, Qr, Q22)
    S = (np.hstack([A12.T @ P + Q12.T, Q22]) @ T).T
    K = (A12.T @ P + Q12.T) / Q22
    poles = np.linalg.eigvals(A11 - A12 @ K)
    return S.ravel(), sorted(poles, key=lambda z: (z.real, z.imag))


def main():
    A, B = cdip()
    Q = np.diag([10.0, 100.0, 1.0, 1.0])
    out = {"tool": f"scipy {scipy.__version__} (solve_continuous_are), numpy {np.__version__}"}
    for name, exact in [("book", False), ("exact", True)]:
        S, poles = surface(A, B, Q, exact)
        out[f"S_{name}"] = S.tolist()
        out[f"poles_{name}_re"] = [p.real for p in poles]
        out[f"poles_{name}_im"] = [p.imag for p in poles]
    path = pathlib.Path("crates/control/tests/fixtures/sliding_mode_reference.json")
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
