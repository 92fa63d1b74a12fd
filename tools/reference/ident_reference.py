"""Reference values from NumPy and SciPy for pendulab-ident's unit tests.

Writes crates/ident/tests/fixtures/ident_reference.json with
  - least-squares problems (tall, noisy; one with badly scaled columns) and NumPy's
    `numpy.linalg.lstsq` solution, residual sum of squares, the 2-norm condition number
    (`numpy.linalg.cond`) and standard errors sigma * sqrt(diag((A^T A)^-1)) computed from the
    SVD of A (sigma^2 = RSS / (n - p)), an algorithm independent of a QR factorisation;
  - Savitzky-Golay coefficients from `scipy.signal.savgol_coeffs(..., use="dot")` for several
    windows, orders, derivatives, sample spacings and evaluation positions, and a whole
    `scipy.signal.savgol_filter(..., mode="interp")` derivative of a test signal;
  - the ZOH and FOH discretisations of 1/(Tf s + 1)^3 by `scipy.signal.cont2discrete`, applied
    by `scipy.signal.lfilter` (zero initial state) to a test input.

Run: python3 tools/reference/ident_reference.py   (from the repository root)
Versions used for the committed fixture are recorded in it.
"""

import json
import pathlib

import numpy as np
import scipy
import scipy.signal as ss


def lstsq_case(rng, n, scales, p_true, noise):
    a = rng.standard_normal((n, len(scales))) * np.array(scales)
    # A correlated column pair, as filtered regressors are.
    a[:, 1] += 0.3 * a[:, 0] * scales[1] / scales[0]
    b = a @ np.array(p_true) + noise * rng.standard_normal(n)
    x, rss, rank, sv = np.linalg.lstsq(a, b, rcond=None)
    u, s, vt = np.linalg.svd(a, full_matrices=False)
    sigma2 = float(rss[0]) / (n - len(scales))
    cov = (vt.T / s**2) @ vt * sigma2
    return {
        "a_columns": [a[:, j].tolist() for j in range(a.shape[1])],
        "b": b.tolist(),
        "estimate": x.tolist(),
        "rss": float(rss[0]),
        "rank": int(rank),
        "condition": float(np.linalg.cond(a)),
        "std_error": np.sqrt(np.diag(cov)).tolist(),
    }


def main():
    rng = np.random.default_rng(20240611)
    cases = [
        lstsq_case(rng, 400, [1.0, 2.0], [6.25, 4.36], 0.5),
        lstsq_case(rng, 300, [1.0, 1e-3, 50.0], [1.5, -2000.0, 0.01], 1e-2),
    ]

    savgol = []
    for window, order, deriv, delta, pos in [
        (5, 2, 0, 1.0, 2),
        (5, 2, 1, 0.001, 2),
        (11, 3, 1, 0.001, 5),
        (11, 3, 2, 0.001, 5),
        (21, 2, 2, 0.001, 10),
        (11, 3, 1, 0.001, 0),
        (11, 3, 2, 0.001, 3),
        (9, 4, 1, 0.5, 8),
    ]:
        c = ss.savgol_coeffs(window, order, deriv=deriv, delta=delta, pos=pos, use="dot")
        savgol.append(
            {"window": window, "order": order, "deriv": deriv, "delta": delta, "pos": pos,
             "coefficients": c.tolist()}
        )
    ts = 0.001
    t = np.arange(200) * ts
    x = np.sin(7 * t) + 0.3 * t**2 + 0.01 * rng.standard_normal(t.size)
    sg_signal = {
        "ts": ts, "window": 15, "order": 3, "deriv": 1, "x": x.tolist(),
        "result": ss.savgol_filter(x, 15, 3, deriv=1, delta=ts, mode="interp").tolist(),
    }

    tf = 0.075
    den = np.polymul(np.polymul([tf, 1.0], [tf, 1.0]), [tf, 1.0])
    u = np.concatenate([np.zeros(5), np.ones(100), -0.5 * np.ones(100), rng.standard_normal(95)])
    filt = {"tf": tf, "ts": ts, "u": u.tolist()}
    for method in ["zoh", "foh"]:
        num_d, den_d, _ = ss.cont2discrete(([1.0], den), ts, method=method)
        filt[method] = ss.lfilter(num_d.ravel(), den_d, u).tolist()

    out = {
        "generator": "tools/reference/ident_reference.py",
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "lstsq": cases,
        "savgol_coeffs": savgol,
        "savgol_filter": sg_signal,
        "lowpass3": filt,
    }
    path = pathlib.Path("crates/ident/tests/fixtures/ident_reference.json")
    path.write_text(json.dumps(out, indent=1) + "\n")
    print("wrote", path)


if __name__ == "__main__":
    main()
