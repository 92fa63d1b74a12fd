"""SciPy's verdict on the LQ problems of crates/lti/tests/lq_checks.rs (issue 21, item 4).

Writes crates/lti/tests/fixtures/lq_checks_scipy.json: for each case its data, which SciPy
routine was called (scipy.linalg.solve_continuous_are / solve_discrete_are: ordered QZ on the
extended pencil with balancing) and its verdict: "LinAlgError" with SciPy's message, or the X it
returned with the closed-loop poles of that X, their smallest stability margin (−Re λ, resp.
1 − |λ|) and SciPy's relative residual, classified as
- "stabilising": every margin above 1e-6 and residual below 1e-8;
- "not stabilising": a margin ≤ 1e-6 (on, beyond or at rounding distance from the boundary)
  or a residual above 1e-8 — SciPy returned a matrix but not a stabilising solution.
SciPy 1.17.1 raises LinAlgError on none of the boundary cases: it returns X = 0 (poles ±j) for
the oscillator with Q = 0, and for the hidden oscillator X with closed-loop poles 1e-9 left of
the axis — the behaviour the issue reports for pendulab. The Rust tests require pendulab to
refuse every case SciPy does not solve to a stabilising X, and to agree with X where it does.

Cases (their closed forms are derived in the Rust test file):
- oscillator_q0: A = [[0, 1], [-1, 0]], B = [0; 1], Q = 0, R = 1. The Hamiltonian is block
  triangular, eigenvalues ±j twice: on the imaginary axis.
- hidden_oscillator: the same oscillator plus a stable state, rotated by an orthogonal T, with
  Q = T diag(0, 0, 1) Tᵀ (Q does not see the oscillator): ±j twice again.
- carex_2_5_eps0: CAREX 2.5 at eps = 0 (indefinite Q): Hamiltonian eigenvalues ±j twice.
- rotation_q0 (discrete): A = [[0, 1], [-1, 0]] (eigenvalues ±j on the unit circle), B = [0; 1],
  Q = 0, R = 1: symplectic pencil eigenvalues ±j twice.
- oscillator_q1e-6, rotation_q1e-6: Q = diag(1e-6, 0): a genuine stabilising solution near
  the boundary (closed-loop poles the stable roots of (s² + 1)² + q = 0, resp.
  z² ∓ j√q z + 1 = 0).
- oscillator_q1e-30: Q = diag(1e-30, 0): observable only at 1e-30, Hamiltonian eigenvalues at
  distance ≈ √q/2 = 5e-16 from the axis — numerically on it.

Run: python3 tools/reference/lq_checks_scipy.py   (from the repository root)
Tools: Python 3, NumPy 2.4.6, SciPy 1.17.1 (the versions are also written to the fixture).
"""

import json
import pathlib

import numpy as np
import scipy
import scipy.linalg as sla

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = ROOT / "crates/lti/tests/fixtures/lq_checks_scipy.json"

OSC = np.array([[0.0, 1.0], [-1.0, 0.0]])
B2 = np.array([[0.0], [1.0]])
T = np.array([[0.36, 0.48, 0.8], [0.48, 0.64, -0.6], [-0.8, 0.6, 0.0]])


def hidden_oscillator():
    a0 = np.zeros((3, 3))
    a0[:2, :2] = OSC
    a0[2, 2] = -1.0
    a = T @ a0 @ T.T
    b = T @ np.array([[0.0], [1.0], [1.0]])
    q = T @ np.diag([0.0, 0.0, 1.0]) @ T.T
    q = 0.5 * (q + q.T)
    return a, b, q, np.eye(1)


def carex_2_5(eps):
    a = np.array([[3.0 - eps, 1.0], [4.0, 2.0 - eps]])
    b = np.array([[1.0], [1.0]])
    q = np.array([[4 * eps - 11.0, 2 * eps - 5.0], [2 * eps - 5.0, 2 * eps - 2.0]])
    return a, b, q, np.eye(1)


CASES = [
    ("oscillator_q0", "continuous", (OSC, B2, np.zeros((2, 2)), np.eye(1))),
    ("hidden_oscillator", "continuous", hidden_oscillator()),
    ("carex_2_5_eps0", "continuous", carex_2_5(0.0)),
    ("oscillator_q1e-30", "continuous", (OSC, B2, np.diag([1e-30, 0.0]), np.eye(1))),
    ("oscillator_q1e-6", "continuous", (OSC, B2, np.diag([1e-6, 0.0]), np.eye(1))),
    ("rotation_q0", "discrete", (OSC, B2, np.zeros((2, 2)), np.eye(1))),
    ("rotation_q1e-6", "discrete", (OSC, B2, np.diag([1e-6, 0.0]), np.eye(1))),
]


def relative_residual(kind, a, b, q, r, x):
    if kind == "continuous":
        g = x @ b @ np.linalg.solve(r, b.T @ x)
        terms = [a.T @ x, x @ a, g, q]
        res = a.T @ x + x @ a - g + q
    else:
        s = b.T @ x @ b + r
        g = a.T @ x @ b @ np.linalg.solve(s, b.T @ x @ a)
        terms = [a.T @ x @ a, x, g, q]
        res = a.T @ x @ a - x - g + q
    scale = sum(np.linalg.norm(t) for t in terms)
    return float(np.linalg.norm(res) / scale) if scale > 0 else float(np.linalg.norm(res))


def main():
    out = {
        "tool": f"scipy {scipy.__version__}, numpy {np.__version__}",
        "cases": {},
    }
    for name, kind, (a, b, q, r) in CASES:
        entry = {
            "kind": kind,
            "a": a.tolist(),
            "b": b.tolist(),
            "q": q.tolist(),
            "r": r.tolist(),
        }
        solver = sla.solve_continuous_are if kind == "continuous" else sla.solve_discrete_are
        entry["routine"] = solver.__name__
        try:
            x = solver(a, b, q, r)
            if kind == "continuous":
                k = np.linalg.solve(r, b.T @ x)
            else:
                k = np.linalg.solve(b.T @ x @ b + r, b.T @ x @ a)
            poles = np.linalg.eigvals(a - b @ k)
            margin = min(-p.real if kind == "continuous" else 1.0 - abs(p) for p in poles)
            res = relative_residual(kind, a, b, q, r, x)
            ok = margin > 1e-6 and np.isfinite(res) and res < 1e-8
            entry["verdict"] = "stabilising" if ok else "not stabilising"
            entry["x"] = x.tolist()
            entry["poles"] = [[float(p.real), float(p.imag)] for p in poles]
            entry["min_margin"] = float(margin)
            entry["scipy_residual"] = res if np.isfinite(res) else None
        except (np.linalg.LinAlgError, ValueError) as e:
            entry["verdict"] = "LinAlgError"
            entry["message"] = str(e)
        out["cases"][name] = entry
        print(
            f"{name:22} {entry['verdict']:16} margin {entry.get('min_margin')} "
            f"residual {entry.get('scipy_residual')} {entry.get('message', '')}"
        )
    OUT.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
