"""Shared fixtures of the Python tests: seeded random systems for the reference comparisons.

The LTI tests compare pendulab with SciPy 1.16.3 and python-control 0.10.2 (pinned in
``requirements-test.txt``), computed in the same test run. Tolerances are relative to each
problem's conditioning; ``EPS`` is the double-precision unit roundoff.
"""

import numpy as np

EPS = np.finfo(float).eps

#: Number of random systems per reference comparison, and their sizes: every size 1–60
#: once, the other 140 drawn uniformly from 1–12 (the references' O(n³) cost at n = 60
#: dominates the suite's time).
N_SYSTEMS = 200


def sizes(seed, largest=60):
    rng = np.random.default_rng(seed)
    return [*range(1, largest + 1), *rng.integers(1, 13, N_SYSTEMS - largest).tolist()]


def stable_matrix(rng, n, margin=0.5, discrete=False):
    """A random n x n matrix shifted (continuous) or scaled (discrete) to be stable with
    the given margin (a negative margin: its most unstable pole at -margin, or 1 - margin/2)."""
    m = rng.standard_normal((n, n)) / np.sqrt(n)
    ev = np.linalg.eigvals(m)
    if discrete:
        return m * ((1.0 - margin / 2) / max(np.abs(ev).max(), 1e-3))
    return m - (ev.real.max() + margin) * np.eye(n)


def psd_weights(rng, n, m, cross):
    """Q (n x n), R (m x m) and N (n x m, or None) with [[Q, N], [N^T, R]] positive definite."""
    w = rng.standard_normal((n + m, n + m))
    w = w @ w.T / (n + m) + 0.1 * np.eye(n + m)
    q, r, nn = w[:n, :n], w[n:, n:], w[:n, n:]
    if not cross:
        return q, r, None
    return q, r, nn
