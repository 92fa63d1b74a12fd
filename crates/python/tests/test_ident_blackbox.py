"""pendulab.ident.arx / moesp: the same library calls as ``pendulab identify arx|moesp`` give
the same models and fits (two routes, compared to the last bit), a simulated first-order
system is recovered (closed form), and bad input raises."""

import json
import pathlib
import subprocess

import numpy as np
import pytest

import pendulab as pl
from pendulab import ident

ROOT = pathlib.Path(__file__).resolve().parents[3]
CLI = ROOT / "target" / "release" / "pendulab"
CART = ROOT / "data" / "rig" / "cdip_least_square_data.csv"


def cli(*args):
    out = subprocess.run([str(CLI), "identify", *args, "--json"], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def cart(t0, t1, q=1):
    rec = ident.read_csv(CART).window(t0, t1)
    return rec.column("v")[::q], rec.column("z")[::q]


needs_cli = pytest.mark.skipif(not CLI.exists(), reason="the CLI is built by tools/test's cargo step")


@needs_cli
def test_arx_equals_the_cli():
    c = cli("arx", "--data", str(CART), "--decimate", "10", "--window", "0.5:5", "--validate", "0.5:9")
    r = ident.arx(*cart(0.5, 5.0, 10), 0.01, na=2, nb=2, nk=1, validate=cart(0.5, 9.0, 10))
    assert list(r.a) == c["model"]["a"]
    assert list(r.b) == c["model"]["b"]
    assert r.fit == c["fit"]["percent"]
    assert r.aic is None and c["order_selection"] is None
    assert isinstance(r.model, pl.StateSpace)
    assert r.model.dt == 0.01


@needs_cli
def test_arx_order_selection_equals_the_cli():
    c = cli("arx", "--data", str(CART), "--decimate", "10", "--window", "0.5:5", "--max-order", "3")
    r = ident.arx(*cart(0.5, 5.0, 10), 0.01, max_order=3)
    assert [row["aic"] for row in r.aic] == [row["aic"] for row in c["order_selection"]]
    assert (r.na, r.nb, r.nk) == (c["model"]["na"], c["model"]["nb"], c["model"]["nk"])
    assert r.fit == c["fit"]["percent"]


@needs_cli
def test_moesp_equals_the_cli():
    c = cli("moesp", "--data", str(CART), "--horizon", "20", "--order", "2", "--window", "0.5:5",
            "--validate", "0.5:9")
    r = ident.moesp(*cart(0.5, 5.0), 0.001, order=2, horizon=20, validate=cart(0.5, 9.0))
    assert r.A.tolist() == c["model"]["a"]
    assert r.B.tolist() == c["model"]["b"]
    assert r.C.tolist() == c["model"]["c"]
    assert r.D.tolist() == c["model"]["d"]
    assert list(r.singular_values) == c["model"]["singular_values"]
    assert r.fit == c["fit"]["percent"]


def first_order(a, b, n):
    rng = np.random.default_rng(7)
    u = np.sign(rng.standard_normal(n))
    y = np.zeros(n)
    for k in range(n - 1):
        y[k + 1] = a * y[k] + b * u[k]
    return u, y


def test_a_simulated_first_order_system_is_recovered():
    a, b = 0.8, -0.3
    u, y = first_order(a, b, 500)
    r = ident.arx(u, y, 0.01, na=1, nb=1)
    assert r.a[1] == pytest.approx(-a, abs=1e-10)
    assert r.b[0] == pytest.approx(b, abs=1e-10)
    assert r.fit == pytest.approx(100.0, abs=1e-6)
    m = ident.moesp(u, y, 0.01, horizon=8)
    assert m.order == 1
    assert m.A[0, 0] == pytest.approx(a, abs=1e-8)
    # The pole is invariant; the Markov parameter C B is too.
    assert (m.C @ m.B)[0, 0] == pytest.approx(b, abs=1e-8)


def test_bad_input_raises():
    u, y = first_order(0.8, -0.3, 100)
    with pytest.raises(pl.InvalidArgumentError):
        ident.arx(u, y, 0.01, na=0, nb=1)
    with pytest.raises(pl.InvalidArgumentError):
        ident.arx(u, y, 0.01, na=1, nb=1, max_order=2)
    with pytest.raises(pl.ShapeError):
        ident.arx(u, y, 0.01, na=40, nb=40)
    with pytest.raises(pl.ShapeError):
        ident.arx(u[:-1], y, 0.01, na=1, nb=1)
    bad = y.copy()
    bad[5] = np.nan
    with pytest.raises(pl.NotFiniteError):
        ident.arx(u, bad, 0.01, na=1, nb=1)
    with pytest.raises(pl.NotFiniteError):
        ident.moesp(u, bad, 0.01)
    with pytest.raises(pl.InvalidArgumentError):
        ident.moesp(u, y, 0.01, order=20, horizon=5)
    with pytest.raises(pl.ShapeError):
        ident.moesp(u, y, 0.01, horizon=40)


def third_order(n=400):
    """A noise-free third-order system with a weak third mode: the largest singular-value gap
    below 3 is σ₂/σ₃, so ``max_order=2`` gives 2 (the same record as the CLI's test)."""
    st, u = 12345, []
    for _ in range(n):
        st = (st * 6364136223846793005 + 1442695040888963407) % 2**64
        u.append(1.0 if st >> 63 else -1.0)
    u = np.array(u)
    p, b = np.array([0.9, 0.7, -0.6]), np.array([0.5, -0.8, 0.05])
    x, y = np.zeros(3), np.zeros(n)
    for k in range(n):
        y[k] = x.sum() + 0.2 * u[k]
        x = p * x + b * u[k]
    return u, y


def test_moesp_max_order_caps_the_selection():
    u, y = third_order()
    full = ident.moesp(u, y, 0.01, horizon=8)
    assert full.order == 3 and full.max_order is None
    capped = ident.moesp(u, y, 0.01, horizon=8, max_order=2)
    sv = capped.singular_values
    assert capped.order == (1 if sv[0] / sv[1] >= sv[1] / sv[2] else 2) == 2
    assert capped.max_order == 2
    fixed = ident.moesp(u, y, 0.01, horizon=8, order=2)
    assert np.array_equal(capped.A, fixed.A) and np.array_equal(capped.B, fixed.B)
    assert capped.fit == fixed.fit
    with pytest.raises(pl.InvalidArgumentError, match="max_order"):
        ident.moesp(u, y, 0.01, horizon=8, max_order=0)
    with pytest.raises(pl.InvalidArgumentError, match="max_order"):
        ident.moesp(u, y, 0.01, horizon=8, order=2, max_order=2)


@needs_cli
def test_moesp_max_order_equals_the_cli(tmp_path):
    u, y = third_order()
    f = tmp_path / "third.csv"
    f.write_text("t,u,y\n" + "".join(f"{k * 0.01!r},{a!r},{b!r}\n" for k, (a, b) in enumerate(zip(u.tolist(), y.tolist()))))
    c = cli("moesp", "--data", str(f), "--input", "u", "--output", "y", "--horizon", "8", "--max-order", "2")
    r = ident.moesp(u, y, 0.01, horizon=8, max_order=2)
    assert c["model"]["order"] == r.order == 2
    assert r.A.tolist() == c["model"]["a"]
    assert list(r.singular_values) == c["model"]["singular_values"]
    assert r.fit == c["fit"]["percent"]
