"""pendulab.lqr/dlqr and the CLI's `pendulab lqr` run the same Rust code path, so for the same
matrices (written to CSV with 17 significant digits, which round-trips every double) their
gains, Riccati solutions and poles are bitwise equal."""

import json
import pathlib
import subprocess

import numpy as np
import pytest

import pendulab as pl

CLI = pathlib.Path(__file__).resolve().parents[3] / "target" / "release" / "pendulab"

pytestmark = pytest.mark.skipif(not CLI.exists(), reason="the CLI is built by tools/test's cargo step")


def write(path, m):
    np.savetxt(path, np.atleast_2d(m), fmt="%.17g", delimiter=",")
    return str(path)


@pytest.mark.parametrize("discrete", [False, True])
@pytest.mark.parametrize("cross", [False, True])
def test_lqr_equals_the_cli(tmp_path, discrete, cross):
    rng = np.random.default_rng(100 + 2 * discrete + cross)
    n, m = 5, 2
    a = rng.standard_normal((n, n)) / 2
    b = rng.standard_normal((n, m))
    w = rng.standard_normal((n + m, n + m))
    w = w @ w.T + 0.1 * np.eye(n + m)
    q, r, nn = w[:n, :n], w[n:, n:], (w[:n, n:] if cross else None)
    args = [str(CLI), "lqr", "--a", write(tmp_path / "A.csv", a), "--b", write(tmp_path / "B.csv", b)]
    args += ["--q", write(tmp_path / "Q.csv", q), "--r", write(tmp_path / "R.csv", r), "--json"]
    if cross:
        args += ["--n", write(tmp_path / "N.csv", nn)]
    if discrete:
        args += ["--discrete", "0.01"]
    out = json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)
    sys = (a, b, np.zeros((0, n)), np.zeros((0, m)), 0.01 if discrete else 0)
    res = pl.lqr(sys, q, r, nn)
    np.testing.assert_array_equal(res.K, np.array(out["gain"]))
    np.testing.assert_array_equal(res.S, np.array(out["riccati"]))
    poles = np.array([complex(re, im) for re, im in out["closed_loop_poles"]])
    np.testing.assert_array_equal(res.E, poles)
    assert res.residual == out["residual"]
