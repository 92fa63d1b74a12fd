"""Times pendulab's LTI calls from Python against python-control and SciPy in the same run.

Workloads (issue 17, performance):

- ``lqr``: the linearised cart pendulum of the book (table 3.5, docs/model.md §1, from
  ``pendulab.plants.CartPendulum().linearize()``; n = 4), Q = diag(100, 10, 1, 1), R = 1:
  ``pendulab.lqr`` vs ``control.lqr`` (python-control; slycot is used if installed) vs SciPy's
  ``solve_continuous_are`` + the gain ``R⁻¹BᵀX``.
- ``dcgain``: the trivial call, ``dcgain`` of a 1-state system, pendulab vs python-control.
- ``lsim``: 10⁶ samples of a stable 5-state system with one input (FOH), including the
  NumPy conversions, pendulab vs SciPy's ``signal.lsim`` (SciPy on 10⁵ samples, scaled);
  pendulab with the states (``lsim``) and outputs only (``lsim(..., return_x=False)``).

Each figure is the median of repeated timings (``timeit``); accuracy is checked against the
peers in the same run (printed as the largest relative difference). Usage:
``python crates/python/tools/bench_lti.py`` with the package installed (tools/test's venv).
Tools: python-control and SciPy as installed (versions printed).
"""

import json
import platform
import statistics
import sys
import timeit

import numpy as np
import scipy
import scipy.linalg as sl
import scipy.signal as ss

import control as ct
import pendulab as pl


def per_call(stmt, number, repeat=7):
    """Median seconds per call over ``repeat`` rounds of ``number`` calls."""
    return statistics.median(t / number for t in timeit.repeat(stmt, number=number, repeat=repeat))


def cart_linearisation():
    from pendulab.plants import CartPendulum

    a, b, _c, _d = CartPendulum().linearize()
    return np.asarray(a), np.asarray(b)


def main():
    out = {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "control": ct.__version__,
        "slycot": None,
    }
    try:
        import slycot  # noqa: F401

        out["slycot"] = getattr(slycot, "__version__", "installed")
    except ImportError:
        pass

    a, b = cart_linearisation()
    q, r = np.diag([100.0, 10.0, 1.0, 1.0]), np.array([[1.0]])
    k_pl = pl.lqr(a, b, q, r).K
    k_ct = ct.lqr(a, b, q, r)[0]

    def scipy_lqr():
        x = sl.solve_continuous_are(a, b, q, r)
        return np.linalg.solve(r, b.T @ x)

    k_sp = scipy_lqr()
    out["lqr_us"] = {
        "pendulab": per_call(lambda: pl.lqr(a, b, q, r), 20000) * 1e6,
        "python-control": per_call(lambda: ct.lqr(a, b, q, r), 200) * 1e6,
        "scipy": per_call(scipy_lqr, 200) * 1e6,
    }
    out["lqr_max_rel_diff"] = {
        "vs python-control": float(np.abs(k_pl - k_ct).max() / np.abs(k_ct).max()),
        "vs scipy": float(np.abs(k_pl - k_sp).max() / np.abs(k_sp).max()),
    }

    one = pl.ss([[-2.0]], [[1.0]], [[3.0]], [[0.0]])
    one_ct = ct.ss([[-2.0]], [[1.0]], [[3.0]], [[0.0]])
    out["dcgain_us"] = {
        "pendulab": per_call(lambda: pl.dcgain(one), 200000) * 1e6,
        "python-control": per_call(lambda: ct.dcgain(one_ct), 2000) * 1e6,
    }

    rng = np.random.default_rng(5)
    m5 = rng.standard_normal((5, 5))
    a5 = m5 - (np.linalg.eigvals(m5).real.max() + 0.5) * np.eye(5)
    b5, c5, d5 = rng.standard_normal((5, 1)), rng.standard_normal((1, 5)), np.zeros((1, 1))
    n = 1_000_000
    t = np.arange(n) * 1e-3
    u = np.sin(t)
    sys5 = pl.ss(a5, b5, c5, d5)
    t_pl = per_call(lambda: pl.lsim(sys5, u, t), 1, repeat=5)
    t_pl_y = per_call(lambda: pl.lsim(sys5, u, t, return_x=False), 1, repeat=9)
    assert np.array_equal(pl.lsim(sys5, u, t, return_x=False).y, pl.lsim(sys5, u, t).y)
    n_sp = 100_000
    t_sp = per_call(lambda: ss.lsim((a5, b5, c5, d5), u[:n_sp], t[:n_sp]), 1, repeat=3)
    y_pl = pl.lsim(sys5, u[:n_sp], t[:n_sp]).y
    y_sp = ss.lsim((a5, b5, c5, d5), u[:n_sp], t[:n_sp])[1]
    out["lsim_samples_per_s"] = {
        "pendulab": n / t_pl,
        "pendulab outputs only": n / t_pl_y,
        "scipy": n_sp / t_sp,
    }
    out["lsim_max_rel_diff_vs_scipy"] = float(np.abs(y_pl - y_sp).max() / np.abs(y_sp).max())
    json.dump(out, sys.stdout, indent=2)
    print()


if __name__ == "__main__":
    main()
