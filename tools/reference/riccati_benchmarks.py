"""SciPy reference solutions for the CAREX / DAREX examples that have no closed-form solution.

Writes crates/lti/tests/fixtures/riccati_benchmarks.json: for each example its data (A, B, Q, R
and the cross term N where present) and the stabilising solution X computed by
scipy.linalg.solve_continuous_are / solve_discrete_are (both: ordered QZ on the extended
pencil, with balancing), together with SciPy's own relative residual.

The examples are built here independently of the Rust test-support module
(crates/lti/tests/riccati_benchmarks_support/mod.rs) from the definitions of the collections
(Benner, Laub & Mehrmann, TU Chemnitz SPC 95_22 and 95_23; SLICOT BB01AD/BB02AD), so the Rust
tests also compare their data with the data stored here.

Run: python3 tools/reference/riccati_benchmarks.py   (from the repository root)
Tools: Python 3, NumPy 2.4, SciPy 1.17.
"""

import json
import pathlib

import numpy as np
import scipy
import scipy.linalg as sla

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / "crates/lti/tests/fixtures/riccati_benchmarks"


def fortran_reader(name):
    lines = []
    for line in (DATA / name).read_text().splitlines():
        vals = [float(t.replace("D", "E").replace("d", "E")) for t in line.split()]
        if vals:
            lines.append(vals)
    state = {"next": 0}

    def read(count):
        out = []
        while len(out) < count:
            line = lines[state["next"]]
            state["next"] += 1
            out.extend(line[: count - len(out)])
        return out

    def matrix(r, c):
        return np.array([read(c) for _ in range(r)])

    return matrix


def weight(c, w):
    q = c.T @ w @ c
    return (q + q.T) / 2


def carex(group, number, eps=None, size=None):
    if (group, number) in [(1, 3), (1, 4)]:
        name, n = ("BB01103.dat", 4) if number == 3 else ("BB01104.dat", 8)
        m = fortran_reader(name)
        a, b, q = m(n, n), m(n, 2), m(n, n)
        return a, b, q, np.eye(2)
    if (group, number) == (1, 5):
        m = fortran_reader("BB01105.dat")
        a, b = m(9, 9), m(9, 3)
        return a, b, np.eye(9), np.eye(3)
    if (group, number) == (1, 6):
        m = fortran_reader("BB01106.dat")
        a, b, c = m(30, 30), m(30, 3), m(5, 30)
        return a, b, weight(c, np.eye(5)), np.eye(3)
    if (group, number) == (2, 2):
        a = np.diag([-0.1, -0.02])
        b = np.array([[0.1, 0.0], [0.001, 0.01]])
        c = np.array([[10.0, 100.0]])
        r = np.array([[1.0 + eps, 1.0], [1.0, 1.0]])
        return a, b, weight(c, np.eye(1)), r
    if (group, number) == (2, 7):
        a = np.zeros((4, 4))
        a[0, 1] = 0.4
        a[1, 2] = 0.345
        a[2, 1] = -0.524 / eps
        a[2, 2] = -0.465 / eps
        a[2, 3] = 0.262 / eps
        a[3, 3] = -1.0 / eps
        b = np.zeros((4, 1))
        b[3, 0] = 1.0 / eps
        c = np.zeros((2, 4))
        c[0, 0] = 1.0
        c[1, 2] = 1.0
        return a, b, weight(c, np.eye(2)), np.eye(1)
    if (group, number) == (2, 8):
        a = np.array(
            [[-eps, 1, 0, 0], [-1, -eps, 0, 0], [0, 0, eps, 1], [0, 0, -1, eps]], dtype=float
        )
        c = np.ones((1, 4))
        return a, np.ones((4, 1)), weight(c, np.eye(1)), np.eye(1)
    if (group, number) == (3, 1):
        l = size
        n = 2 * l - 1
        a = np.zeros((n, n))
        b = np.zeros((n, l))
        c = np.zeros((l - 1, n))
        for i in range(1, n + 1):
            if i % 2 == 1:
                a[i - 1, i - 1] = -1.0
                b[i - 1, (i + 1) // 2 - 1] = 1.0
            else:
                a[i - 1, i - 2] = 1.0
                a[i - 1, i] = -1.0
                c[i // 2 - 1, i - 1] = 1.0
        return a, b, weight(c, 10.0 * np.eye(l - 1)), np.eye(l)
    if (group, number) == (4, 1):
        n = size
        a = np.diag(np.ones(n - 1), 1)
        b = np.zeros((n, 1))
        b[-1, 0] = 1.0
        c = np.zeros((1, n))
        c[0, 0] = 1.0
        return a, b, weight(c, eps * np.eye(1)), np.eye(1)
    if (group, number) == (4, 2):
        n = size
        h1 = n + 1.0
        k = np.diag(-2.0 * eps * h1 * np.ones(n)) + np.diag(eps * h1 * np.ones(n - 1), 1)
        k += np.diag(eps * h1 * np.ones(n - 1), -1)
        mm = np.diag(4.0 / (6 * h1) * np.ones(n)) + np.diag(np.ones(n - 1) / (6 * h1), 1)
        mm += np.diag(np.ones(n - 1) / (6 * h1), -1)

        def hat(i, lo, hi):
            # Integral of the i-th hat function (node i/(n+1), 1-based) over [lo, hi],
            # by exact integration of the piecewise-linear function.
            left, mid, right = (i - 1) / h1, i / h1, (i + 1) / h1
            s = 0.0
            for x0, x1, f in [
                (left, mid, lambda x: (x - left) * h1),
                (mid, right, lambda x: (right - x) * h1),
            ]:
                u0, u1 = max(x0, lo), min(x1, hi)
                if u0 < u1:
                    s += (f(u0) + f(u1)) / 2 * (u1 - u0)
            return s

        bv = np.array([[hat(i, 0.2, 0.3)] for i in range(1, n + 1)])
        cv = np.array([[hat(i, 0.2, 0.3) for i in range(1, n + 1)]])
        a = np.linalg.solve(mm, k)
        b = np.linalg.solve(mm, bv)
        return a, b, weight(cv, np.eye(1)), np.eye(1)
    if (group, number) == (4, 3):
        l = size
        n = 2 * l
        mu, delta, kappa = eps, 4.0, 1.0
        a = np.zeros((n, n))
        a[:l, l:] = np.eye(l)
        a[l:, l:] = -delta / mu * np.eye(l)
        t = kappa / mu
        a[l, 0] = -t
        a[l, 1] = t
        a[n - 1, l - 2] = t
        a[n - 1, l - 1] = -t
        for i in range(2, l):
            a[l + i - 1, i - 1] = -2 * t
            a[l + i - 1, i] = t
            a[l + i - 1, i - 2] = t
        b = np.zeros((n, 2))
        b[l, 0] = 1 / mu
        b[n - 1, 1] = -1 / mu
        return a, b, np.eye(n), np.eye(2)
    raise ValueError((group, number))


def darex(group, number, eps=None):
    """Returns a, b, q, r, s (s may be None)."""
    if (group, number) == (1, 2):
        a = np.array([[0.0, 1.0], [0.0, -1.0]])
        b = np.array([[1.0, 0.0], [2.0, 1.0]])
        q = np.array([[-4.0, -4.0], [-4.0, 7.0]]) / 11.0
        r = np.array([[9.0, 3.0], [3.0, 1.0]])
        s = np.array([[3.0, 1.0], [-1.0, 7.0]])
        return a, b, q, r, s
    if (group, number) == (1, 5):
        m = fortran_reader("BB02105.dat")
        a, b = m(4, 4), m(4, 2)
        q = np.zeros((4, 4))
        for i, j, v in [(0, 0, 1.87), (3, 0, -0.244), (1, 1, 0.744), (2, 1, 0.205),
                        (2, 2, 0.589), (3, 3, 1.048)]:
            q[i, j] = q[j, i] = v
        return a, b, q, np.eye(2), None
    if (group, number) == (1, 6):
        m = fortran_reader("BB02106.dat")
        return m(4, 4), m(4, 2), 0.01 * np.eye(4), np.eye(2), None
    if (group, number) == (1, 7):
        m = fortran_reader("BB02107.dat")
        a, b = m(4, 4), m(4, 4)
        c = np.array([[1, 1, 2, 4], [0, 1, 1, 2], [0, 0, 1, 1], [0, 0, 0, 1]], dtype=float)
        q0 = np.array([[2, -1, 0, 0], [-1, 2, -1, 0], [0, -1, 2, 0], [0, 0, 0, 0]], dtype=float)
        return a, b, weight(c, q0), np.eye(4), None
    if (group, number) == (1, 8):
        m = fortran_reader("BB02108.dat")
        return m(5, 5), m(5, 2), np.eye(5), np.eye(2), None
    if (group, number) == (1, 9):
        a = np.zeros((6, 6))
        for i, j in [(0, 1), (1, 2), (3, 4), (4, 5)]:
            a[i, j] = 1.0
        b = np.zeros((6, 2))
        b[2, 0] = 1.0
        b[5, 1] = 1.0
        c = np.array([[1, 1, 0, 0, 0, 0], [0, 0, 0, 1, -1, 0]], dtype=float)
        s = np.zeros((6, 2))
        s[[0, 1, 3, 4], 0] = [1, 1, 1, -1]
        return a, b, weight(c, np.eye(2)), np.diag([3.0, 1.0]), s
    if (group, number) == (1, 10):
        m = fortran_reader("BB02110.dat")
        a, b = m(9, 9), m(9, 3)
        c = np.zeros((2, 9))
        c[0, 0] = 1.0
        c[1, 4] = 1.0
        return a, b, weight(c, 50 * np.eye(2)), np.eye(3), None
    if (group, number) == (1, 11):
        m = fortran_reader("BB02111.dat")
        a, b = m(11, 11), m(11, 2)
        a[9, 9] = a[10, 10] = 1.0
        c = np.zeros((4, 11))
        c[0, 5] = 15.0
        c[1, 6] = 7.0
        c[1, 7] = -5.357
        c[1, 8] = -3.943
        c[2, 9] = 1.0
        c[3, 10] = 1.0
        return a, b, weight(c, np.diag([0.5, 5, 0.5, 5])), np.diag([400.0, 700.0]), None
    if (group, number) == (1, 12):
        a = np.zeros((13, 13))
        for i in range(10):
            a[i, i + 1] = 1.0
        a[5, 6] = a[7, 8] = 0.0
        a[11, 11] = a[12, 12] = 1.0
        for (i, j), v in {(11, 0): -3.318, (12, 0): -1.5484, (5, 5): 0.7788, (7, 6): -0.4724,
                          (12, 6): 0.3981, (7, 7): 1.3746, (12, 7): 0.5113, (12, 8): 5.7865,
                          (10, 10): 0.8071}.items():
            a[i, j] = v
        b = np.zeros((13, 2))
        b[5, 0] = b[7, 1] = 1.0
        c = np.zeros((4, 13))
        for (i, j), v in {(0, 0): 3.318, (1, 0): 1.5484, (1, 6): -0.3981, (1, 7): -0.5113,
                          (1, 8): -5.7865, (2, 11): 1.0, (3, 12): 1.0}.items():
            c[i, j] = v
        return a, b, weight(c, np.diag([0.5, 5, 0.5, 5])), np.diag([400.0, 700.0]), None
    if (group, number) == (2, 2):
        a = np.diag([0.9512, 0.9048])
        b = np.array([[4.877, 4.877], [-1.1895, 3.569]])
        return a, b, np.diag([0.005, 0.02]), np.diag([1 / (3 * eps), 3 * eps]), None
    raise ValueError((group, number))


def rel_residual_care(a, b, q, r, x):
    xb = x @ b
    g = xb @ np.linalg.solve(r, xb.T)
    res = a.T @ x + x @ a - g + q
    den = 2 * np.linalg.norm(a.T @ x) + np.linalg.norm(g) + np.linalg.norm(q)
    return float(np.linalg.norm(res) / den)


def rel_residual_dare(a, b, q, r, s, x):
    s = np.zeros_like(b) if s is None else s
    atxb = a.T @ x @ b + s
    g = atxb @ np.linalg.solve(b.T @ x @ b + r, atxb.T)
    res = a.T @ x @ a - x - g + q
    den = (np.linalg.norm(a.T @ x @ a) + np.linalg.norm(x) + np.linalg.norm(g)
           + np.linalg.norm(q))
    return float(np.linalg.norm(res) / den)


CAREX = [
    ("CAREX 1.3", (1, 3, None, None)),
    ("CAREX 1.4", (1, 4, None, None)),
    ("CAREX 1.5", (1, 5, None, None)),
    ("CAREX 1.6", (1, 6, None, None)),
    ("CAREX 2.2 (eps = 1e0)", (2, 2, 1.0, None)),
    ("CAREX 2.2 (eps = 1e-4)", (2, 2, 1e-4, None)),
    ("CAREX 2.2 (eps = 1e-8)", (2, 2, 1e-8, None)),
    ("CAREX 2.7 (eps = 1e-2)", (2, 7, 1e-2, None)),
    ("CAREX 2.7 (eps = 1e-6)", (2, 7, 1e-6, None)),
    ("CAREX 2.8 (eps = 1e0)", (2, 8, 1.0, None)),
    ("CAREX 2.8 (eps = 1e-3)", (2, 8, 1e-3, None)),
    ("CAREX 2.8 (eps = 1e-6)", (2, 8, 1e-6, None)),
    ("CAREX 3.1 (l = 20)", (3, 1, None, 20)),
    ("CAREX 4.1 (n = 21, q = 1e0)", (4, 1, 1.0, 21)),
    ("CAREX 4.2 (n = 100, a = 1e-2)", (4, 2, 1e-2, 100)),
    ("CAREX 4.3 (l = 30, mu = 4e0)", (4, 3, 4.0, 30)),
]

DAREX = [
    ("DAREX 1.2", (1, 2, None)),
    ("DAREX 1.5", (1, 5, None)),
    ("DAREX 1.6", (1, 6, None)),
    ("DAREX 1.7", (1, 7, None)),
    ("DAREX 1.8", (1, 8, None)),
    ("DAREX 1.9", (1, 9, None)),
    ("DAREX 1.10", (1, 10, None)),
    ("DAREX 1.11", (1, 11, None)),
    ("DAREX 1.12", (1, 12, None)),
    ("DAREX 2.2 (eps = 1e0)", (2, 2, 1.0)),
    ("DAREX 2.2 (eps = 1e3)", (2, 2, 1e3)),
    ("DAREX 2.2 (eps = 1e6)", (2, 2, 1e6)),
]


def main():
    out = {
        "generator": "tools/reference/riccati_benchmarks.py",
        "tools": f"NumPy {np.__version__}, SciPy {scipy.__version__}",
        "care": {},
        "dare": {},
    }
    for key, (g, k, eps, size) in CAREX:
        a, b, q, r = carex(g, k, eps, size)
        x = sla.solve_continuous_are(a, b, q, r)
        x = (x + x.T) / 2
        out["care"][key] = {
            "a": a.tolist(), "b": b.tolist(), "q": q.tolist(), "r": r.tolist(),
            "x": x.tolist(), "scipy_residual": rel_residual_care(a, b, q, r, x),
        }
        print(f"{key}: n = {a.shape[0]}, residual {out['care'][key]['scipy_residual']:.2e}")
    for key, (g, k, eps) in DAREX:
        a, b, q, r, s = darex(g, k, eps)
        x = sla.solve_discrete_are(a, b, q, r, s=s)
        x = (x + x.T) / 2
        out["dare"][key] = {
            "a": a.tolist(), "b": b.tolist(), "q": q.tolist(), "r": r.tolist(),
            "n": None if s is None else s.tolist(),
            "x": x.tolist(), "scipy_residual": rel_residual_dare(a, b, q, r, s, x),
        }
        print(f"{key}: n = {a.shape[0]}, residual {out['dare'][key]['scipy_residual']:.2e}")
    path = ROOT / "crates/lti/tests/fixtures/riccati_benchmarks.json"
    path.write_text(json.dumps(out, indent=None, separators=(",", ":")) + "\n")
    print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
