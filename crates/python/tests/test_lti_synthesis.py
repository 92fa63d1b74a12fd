"""H∞ and H2 synthesis (``hinfsyn``, ``h2syn``) and ``augw``: closed forms, the defining
properties of the controllers, Slycot's SB10AD/SB10HD through the fixture of
``tools/reference/hinf_reference.py`` (python-control 0.10.2, Slycot 0.7.1), and
python-control's ``augw`` computed in the same run."""

import json
import pathlib

import control as ct
import numpy as np
import pytest

import pendulab as pl

assert ct.__version__ == "0.10.2", ct.__version__

FIXTURE = json.loads(
    (pathlib.Path(__file__).resolve().parents[2] / "lti/tests/data/hinf_reference.json").read_text()
)
CASES = {c["name"]: c for c in FIXTURE["cases"]}


def plant(name):
    c = CASES[name]
    return pl.ss(c["a"], c["b"], c["c"], c["d"]), c["nmeas"], c["ncon"]


def hinf(sys):
    """‖sys‖∞ on a dense grid (a lower bound, enough to check ‖CL‖∞ < γ with a margin)."""
    w = np.logspace(-4, 4, 4000)
    resp = ct.ss(sys.A, sys.B, sys.C, sys.D).frequency_response(w)
    mag = np.asarray(resp.frdata)
    return max(np.linalg.svd(mag[:, :, k], compute_uv=False)[0] for k in range(len(w)))


def test_robust_stabilisation_closed_form():
    # z = u, y = w + u/(s − 1): the optimum is 2 (Glover 1986), SB10AD agrees.
    P, nmeas, ncon = plant("first_order_unstable")
    K, CL, gam = pl.hinfsyn(P, nmeas, ncon, tol=1e-9)
    assert abs(gam - 2.0) < 1e-7
    assert abs(gam - CASES["first_order_unstable"]["gamma_slycot"]) < 1e-6
    res = pl.hinfsyn(P, nmeas, ncon, gamma=2.2)
    assert np.all(np.real(pl.poles(res.CL)) < 0)
    assert hinf(res.CL) < 2.2
    assert res.rho < 2.2**2 and res.gamma_infeasible is None


@pytest.mark.parametrize("name", ["cart_lq", "random6", "random6_d22", "mixsyn"])
def test_optimum_matches_slycot_and_h2_matches_sb10hd(name):
    P, nmeas, ncon = plant(name)
    ref = CASES[name]
    res = pl.hinfsyn(P, nmeas, ncon, tol=1e-9)
    assert abs(res.gam - ref["gamma_slycot"]) <= 1e-6 * ref["gamma_slycot"]
    assert res.gamma_infeasible <= res.gam
    K, CL, norm = pl.h2syn(P, nmeas, ncon)
    assert abs(norm - ref["h2_optimal"]) <= 1e-8 * ref["h2_optimal"]
    assert np.all(np.real(pl.poles(CL)) < 0)


def test_below_the_optimum_is_infeasible_error():
    P, nmeas, ncon = plant("random6")
    with pytest.raises(pl.InfeasibleError) as e:
        pl.hinfsyn(P, nmeas, ncon, gamma=0.9 * CASES["random6"]["gamma_slycot"])
    assert e.value.variant == "HinfInfeasible"


def test_d11_nonzero_matches_slycot():
    # Glover–Doyle formulas for D11 ≠ 0 (the mixed-sensitivity plant with a feedthrough):
    # SB10AD's optimum, and the controller at 1.01 γ keeps the closed loop below it.
    P, nmeas, ncon = plant("mixsyn_d11")
    ref = CASES["mixsyn_d11"]["gamma_slycot"]
    res = pl.hinfsyn(P, nmeas, ncon, tol=1e-9)
    assert abs(res.gam - ref) <= 1e-6 * ref
    above = pl.hinfsyn(P, nmeas, ncon, gamma=1.01 * res.gam)
    assert np.all(np.real(pl.poles(above.CL)) < 0)
    assert hinf(above.CL) < 1.01 * res.gam


def test_violated_assumption_is_named():
    # The cart's LQ plant with D12 = 0: no control reaches z directly, so the synthesis
    # assumption "D12 of full column rank" fails and is named.
    c = CASES["cart_lq"]
    d = np.array(c["d"])
    nz, nw = d.shape[0] - c["nmeas"], d.shape[1] - c["ncon"]
    d[:nz, nw:] = 0.0
    P = pl.ss(c["a"], c["b"], c["c"], d)
    with pytest.raises(pl.InvalidArgumentError) as e:
        pl.hinfsyn(P, c["nmeas"], c["ncon"], gamma=10.0)
    assert e.value.variant == "SynthesisAssumption" and "D12 of full column rank" in str(e.value)


def test_augw_matches_python_control():
    G = ct.tf([2.0, 1.0], [1.0, 3.0, 2.0, 0.5])
    W1 = ct.tf([0.5, 2.0], [1.0, 0.02])
    W2 = ct.tf([0.1, 0.2], [0.01, 1.0])
    W3 = ct.tf([1.0, 0.0], [0.1, 1.0])
    ours = pl.augw(G, W1, W2, W3)
    ref = ct.augw(ct.ss(G), ct.ss(W1), ct.ss(W2), ct.ss(W3))
    assert ours.D.shape == ref.D.shape == (4, 2)
    for w in [0.01, 0.3, 2.0, 50.0]:
        a = ct.ss(ours.A, ours.B, ours.C, ours.D)(1j * w)
        b = ref(1j * w)
        assert np.allclose(a, b, rtol=1e-10, atol=1e-12), w
