"""pendulab.ident: the same library calls as ``pendulab identify`` give the same estimates
(bitwise: one code path) on the shipped rig data, the least-squares methods recover a
simulated drive's known parameters, and bad input raises."""

import json
import pathlib
import subprocess

import numpy as np
import pytest

import pendulab as pl
from pendulab import ident

ROOT = pathlib.Path(__file__).resolve().parents[3]
CLI = ROOT / "target" / "release" / "pendulab"
RIG = ROOT / "data" / "rig"

CASES = [
    ("cart-ls", "cdip_least_square_data.csv", (1.0, 5.0)),
    ("pend-ls", "cdip_least_square_data.csv", (1.0, 5.0)),
    ("cart-step", "cdip_cart_pcont_data_kP_100_ref_02.csv", None),
    ("pend-free", "cdip_pend_data.csv", None),
    ("arm-ls", "adip_least_square_data.csv", None),
    ("arm-pend-ls", "adip_least_square_data.csv", None),
    ("arm-step", "adip_arm_pcont_data_kP_3_ref_1.csv", None),
    ("arm-pend-free", "adip_pend_data.csv", None),
]


@pytest.mark.skipif(not CLI.exists(), reason="the CLI is built by tools/test's cargo step")
@pytest.mark.parametrize("method,file,window", CASES)
def test_identify_equals_the_cli(method, file, window):
    path = RIG / file
    args = [str(CLI), "identify", method, "--data", str(path), "--json"]
    if window is not None:
        args += ["--window", f"{window[0]}:{window[1]}"]
    cli = json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)
    res = ident.identify(method, path, window=window)
    assert res["estimates"] == cli["estimates"]
    assert res["std_errors"] == cli["std_errors"]
    assert res["samples"] == cli["samples"]
    assert res["ts"] == cli["ts"]
    for key in ("condition", "residual_rms"):
        assert res.get(key) == cli.get(key)
    assert res["fit"]["fit_percent"] == cli["fit"]["percent"]
    assert res["warnings"] == cli["warnings"] == []


def test_arrays_and_csv_text_give_the_same_result():
    text = (RIG / "cdip_least_square_data.csv").read_text()
    rec = ident.read_csv(text).window(1.0, 5.0)
    r = ident.drive_ls("cart", rec.uniform_step(), rec.column("z"), rec.column("v"))
    res = ident.identify("cart-ls", text, window=(1.0, 5.0))
    assert (r["a"], r["b"]) == (res["estimates"]["ac"], res["estimates"]["bc"])
    assert r["failed_checks"] == []


def test_drive_least_squares_recovers_a_simulated_drive():
    # z'' = −a ż + b v (book eq. 3.31) driven by two sines (piecewise linear between samples,
    # simulated exactly by FOH) at 1 ms. The three-point derivatives' truncation error is of
    # relative size (ω h)²/6 ≈ 5·10⁻⁵ at the faster sine, so the estimates land within 1e-3.
    a, b, ts = 6.0, 4.5, 1e-3
    t = np.arange(0, 5.0, ts)
    v = np.sin(2 * np.pi * 0.7 * t) + 0.5 * np.sin(2 * np.pi * 1.9 * t)
    sys = pl.ss([[0, 1], [0, -a]], [[0], [b]], [[1, 0]], 0)
    z, _, _ = pl.lsim(sys, v, t, hold="foh")
    for f in ("none", "causal", "zero-phase"):
        r = ident.drive_ls("cart", ts, z, v, filter=f)
        assert r["a"] == pytest.approx(a, rel=1e-3)
        assert r["b"] == pytest.approx(b, rel=1e-3)
        assert r["failed_checks"] == []
        assert r["fit"]["fit_percent"] > 99


def test_bad_inputs_raise():
    path = RIG / "cdip_least_square_data.csv"
    with pytest.raises(pl.InvalidArgumentError, match="unknown method"):
        ident.identify("cart-magic", path)
    with pytest.raises(pl.InvalidArgumentError, match="theta1"):
        ident.identify("arm-step", path)
    with pytest.raises(pl.ShapeError):
        ident.drive_ls("cart", 1e-3, np.zeros(100), np.zeros(99))
    with pytest.raises(pl.NotFiniteError):
        ident.drive_ls("cart", 1e-3, np.r_[np.zeros(999), np.nan], np.zeros(1000))
    with pytest.raises(pl.InvalidArgumentError, match="filter"):
        ident.drive_ls("cart", 1e-3, np.zeros(1000), np.zeros(1000), filter="acausal")
    with pytest.raises(pl.InvalidArgumentError):
        ident.read_csv("t,z\n0,1\n0.001\n")
    with pytest.raises(TypeError):
        ident.identify("cart-ls", np.zeros(3))


def test_a_failed_check_refuses_unless_forced():
    # A 0.2 s window is too short for the prefilter's time constant and the three-point
    # differentiator's band: the library's checks refuse it.
    path = RIG / "cdip_least_square_data.csv"
    with pytest.raises(pl.InvalidArgumentError, match="refused"):
        ident.identify("cart-ls", path, window=(1.0, 1.2))
    res = ident.identify("cart-ls", path, window=(1.0, 1.2), force=True)
    assert res["warnings"]
    # A known constant out of its plausible range (m_p = 1000 kg) is refused as by the CLI.
    with pytest.raises(pl.InvalidArgumentError, match="plausible range"):
        ident.identify("pend-free", RIG / "cdip_pend_data.csv", mp=1000.0)
