"""Reference values for pendulab-lti's delays, MIMO transfer matrices and matched /
impulse-invariant c2d.

Tools: python-control 0.10.2 and SciPy 1.16.3 (NumPy underneath; no Slycot, so MIMO
transfer functions are never converted to state space here: MIMO feedback is formed on
state-space systems, MIMO tf products and sums polynomially).

Writes crates/lti/tests/data/tf_reference.json:
  - pade: control.pade(T, n) numerator and denominator (descending powers);
  - tm_arith: two 2x2 continuous transfer matrices G, H and a 2x1 column C (lists of lists
    of coefficients) and the frequency responses of G + H, G - H, G * H, G * C at s = j w
    and at one complex point (python-control's MIMO tf arithmetic, evaluated by __call__);
  - tm_feedback: random stable 2-input 2-output state-space plants P (fixed seed) and a
    static or dynamic 2x2 controller K given as state space; control.feedback(P, K, sign)
    evaluated at s = j w; plus control.ss2tf(P) per entry (numerators/denominators);
  - impulse: scipy.signal.cont2discrete((A, B, C, D), ts, method='impulse') matrices;
  - matched: control.sample_system(G, ts, method='matched') numerator and denominator for
    SISO G (python-control matches the DC gain and leaves zeros at infinity there).

Run from the repository root:
    python3 -m venv /tmp/venv && /tmp/venv/bin/pip install control==0.10.2 scipy==1.16.3
    /tmp/venv/bin/python tools/reference/tf_python.py
"""

import json
import pathlib

import control
import numpy as np
import scipy.signal

OUT = pathlib.Path("crates/lti/tests/data/tf_reference.json")
W = [0.05, 0.4, 1.3, 4.0, 17.0]
POINT = complex(0.3, 0.8)


def cplx(m):
    """A complex matrix as [re, im] lists of rows."""
    m = np.atleast_2d(np.asarray(m, dtype=complex))
    return {"re": m.real.tolist(), "im": m.imag.tolist()}


def response(sys, points):
    """sys(s) as a list of complex matrices, one per point."""
    out = []
    for s in points:
        v = np.asarray(sys(s), dtype=complex)
        out.append(cplx(v.reshape(sys.noutputs, sys.ninputs)))
    return out


def coeffs(tf):
    """Numerators and denominators of a tf as lists of lists of lists."""
    num = [[np.atleast_1d(tf.num[i][j]).tolist() for j in range(tf.ninputs)] for i in range(tf.noutputs)]
    den = [[np.atleast_1d(tf.den[i][j]).tolist() for j in range(tf.ninputs)] for i in range(tf.noutputs)]
    return num, den


def random_stable(rng, n, m, p):
    """A random stable state-space system with shifted eigenvalues (fixed seed)."""
    a = rng.standard_normal((n, n))
    a -= (max(np.linalg.eigvals(a).real) + 0.5 + rng.random()) * np.eye(n)
    b = rng.standard_normal((n, m))
    c = rng.standard_normal((p, n))
    d = np.zeros((p, m))
    return a, b, c, d


def main():
    rng = np.random.default_rng(20261206)
    out = {"tools": {"python-control": control.__version__, "scipy": scipy.__version__},
           "w": W, "point": [POINT.real, POINT.imag]}
    points = [1j * w for w in W] + [POINT]

    out["pade"] = []
    for t, n in [(0.1, 1), (0.5, 2), (1.0, 3), (0.2, 5), (2.0, 6), (0.05, 9)]:
        num, den = control.pade(t, n)
        out["pade"].append({"T": t, "n": n, "num": list(num), "den": list(den)})

    g_num = [[[1.0], [2.0, 1.0]], [[1.0, 3.0], [0.5]]]
    g_den = [[[1.0, 1.0], [1.0, 2.0, 5.0]], [[1.0, 4.0], [1.0, 0.5]]]
    h_num = [[[3.0, 0.0], [1.0]], [[-1.0], [2.0, 1.0, 1.0]]]
    h_den = [[[1.0, 2.0], [1.0, 3.0]], [[1.0, 1.0, 4.0], [1.0, 6.0, 2.0]]]
    c_num = [[[1.0, 0.5]], [[2.0]]]
    c_den = [[[1.0, 0.0]], [[1.0, 10.0]]]
    g = control.tf(g_num, g_den)
    h = control.tf(h_num, h_den)
    c = control.tf(c_num, c_den)
    out["tm_arith"] = {
        "G": {"num": g_num, "den": g_den},
        "H": {"num": h_num, "den": h_den},
        "C": {"num": c_num, "den": c_den},
        "sum": response(g + h, points),
        "difference": response(g - h, points),
        "product": response(g * h, points),
        "product_column": response(g * c, points),
    }

    out["tm_feedback"] = []
    for case in range(3):
        a, b, cm, d = random_stable(rng, 3 + case, 2, 2)
        p = control.ss(a, b, cm, d)
        if case == 0:
            k = control.ss([], [], [], [[0.5, 0.1], [-0.2, 0.8]])
        else:
            ka, kb, kc, _ = random_stable(rng, 2, 2, 2)
            k = control.ss(ka, kb, kc, [[0.3, 0.0], [0.1, -0.2]])
        entry = {"P": {"A": a.tolist(), "B": b.tolist(), "C": cm.tolist(), "D": d.tolist()},
                 "K": {"A": np.asarray(k.A).tolist(), "B": np.asarray(k.B).tolist(),
                       "C": np.asarray(k.C).tolist(), "D": np.asarray(k.D).tolist()}}
        for sign, name in [(-1, "negative"), (1, "positive")]:
            entry[name] = response(control.feedback(p, k, sign=sign), points)
        num, den = coeffs(control.tf(p))
        entry["ss2tf"] = {"num": num, "den": den}
        out["tm_feedback"].append(entry)

    out["impulse"] = []
    for case, ts in enumerate([0.1, 0.05, 0.3]):
        a, b, cm, d = random_stable(rng, 2 + case, 1 + case % 2, 1 + (case + 1) % 2)
        ad, bd, cd, dd, _ = scipy.signal.cont2discrete((a, b, cm, d), ts, method="impulse")
        out["impulse"].append({"ts": ts, "A": a.tolist(), "B": b.tolist(), "C": cm.tolist(),
                               "Ad": ad.tolist(), "Bd": bd.tolist(), "Cd": cd.tolist(),
                               "Dd": dd.tolist()})

    out["matched"] = []
    for num, den, ts in [([1.0, 2.0], [1.0, 3.0], 0.1),
                         ([2.0], [1.0, 1.5], 0.2),
                         ([1.0, 0.5, 4.0], [1.0, 1.0, 9.0], 0.05),
                         ([3.0, 1.0], [1.0, 2.0, 2.0], 0.1),
                         ([5.0], [1.0, 3.0, 2.0], 0.1),
                         ([1.0, -1.0], [1.0, 6.0, 11.0, 6.0], 0.25)]:
        gd = control.sample_system(control.tf(num, den), ts, method="matched")
        out["matched"].append({"num": num, "den": den, "ts": ts,
                               "numd": np.atleast_1d(gd.num[0][0]).tolist(),
                               "dend": np.atleast_1d(gd.den[0][0]).tolist()})

    OUT.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
