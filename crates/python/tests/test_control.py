"""pendulab.control: each design checked against its defining equations or an independent
solver (SciPy 1.16.3 for the Kalman filter's DARE), each run-time law against its closed
form, and bad input raising."""

import numpy as np
import pytest
import scipy.linalg

import pendulab as pl
from pendulab import control
from pendulab.plants import CartPendulum


def cart():
    a, b, _, _ = CartPendulum().linearize("upright")
    return a, b


def test_sliding_surface_and_law():
    a, b = cart()
    q = np.diag([10.0, 10.0, 1.0, 1.0])
    s = control.sliding_surface(a, b, q)
    sv = s["S"]
    assert s["STb"] == pytest.approx(sv @ b[:, 0], rel=1e-12)
    # On the surface the equivalent control u_eq = −(SᵀB)⁻¹SᵀA x leaves
    # A_eq = (I − B(SᵀB)⁻¹Sᵀ)A, whose eigenvalues are the sliding poles and one zero.
    a_eq = (np.eye(4) - np.outer(b[:, 0], sv) / (sv @ b[:, 0])) @ a
    ev = np.linalg.eigvals(a_eq)
    ev = ev[np.argsort(np.abs(ev))]
    assert abs(ev[0]) < 1e-8 * np.abs(a).max()
    np.testing.assert_allclose(np.sort_complex(ev[1:]), np.sort_complex(s["sliding_poles"]), rtol=1e-8)
    assert np.all(np.real(s["sliding_poles"]) < 0)
    law = control.sliding_mode(sv, a, b, k2=2.0, delta=0.1)
    x = np.array([0.05, 0.1, -0.2, 0.3])
    sigma = sv @ x
    expected = -(sv @ a @ x + 2.0 * sigma / (abs(sigma) + 0.1)) / (sv @ b[:, 0])
    assert law.update(0.0, x)[0] == pytest.approx(expected, rel=1e-12)
    with pytest.raises(pl.ShapeError):
        law.update(0.0, x[:3])
    with pytest.raises(pl.InvalidArgumentError, match="form"):
        control.sliding_surface(a, b, q, form="diagonal")


def test_energy_pumping_is_the_books_law():
    p = CartPendulum().params
    law = control.energy_pumping(0.8)
    x = np.array([0.01, 2.5, 0.3, -1.2])
    # Book Part 2 §3.2.3: z̈* = −K₁ θ̇ cos θ through the drive, v = (a_c ż + z̈*)/b_c.
    expected = (p["a_c"] * x[2] - 0.8 * x[3] * np.cos(x[1])) / p["b_c"]
    assert law.update(0.0, x)[0] == pytest.approx(expected, rel=1e-14)
    with pytest.raises(pl.InvalidArgumentError):
        control.energy_pumping(-1.0)
    with pytest.raises(pl.InvalidArgumentError, match="unknown gain"):
        control.energy_shaping("cart", gains={"k_magic": 1.0})
    u = control.energy_shaping("arm").update(0.0, [0.0, np.pi - 0.1, 0.0, 0.0])
    assert abs(u[0]) <= 5.0


def test_kalman_filter_solves_the_dare():
    rng = np.random.default_rng(7)
    a, b = cart()
    sysd = pl.c2d(pl.ss(a, b, [[1, 0, 0, 0], [0, 1, 0, 0]], 0), 0.01)
    ad, bd, cd = sysd.A, sysd.B, sysd.C
    g = rng.standard_normal((4, 2))
    qn, rn = np.diag([1e-2, 2e-2]), np.diag([1e-4, 1e-4])
    k = control.kalman(ad, bd, cd, 0.01, g, qn, rn)
    p = scipy.linalg.solve_discrete_are(ad.T, cd.T, g @ qn @ g.T, rn)
    np.testing.assert_allclose(k["P"], p, rtol=1e-8, atol=1e-12 * np.abs(p).max())
    m = p @ cd.T @ np.linalg.inv(cd @ p @ cd.T + rn)
    np.testing.assert_allclose(k["M"], m, rtol=1e-7, atol=1e-12)
    np.testing.assert_allclose(k["L"], ad @ m, rtol=1e-7, atol=1e-12)
    assert np.all(np.abs(k["poles"]) < 1)
    with pytest.raises(pl.ShapeError):
        control.kalman(ad, bd, cd, 0.01, g[:3], qn, rn)


def test_optimal_dynamic_quantizer_closed_form():
    # A stable minimum-phase system of relative degree 1: C_f = −M₁⁺ C A (Azuma–Sugie).
    a = np.array([[0.5, 0.1], [0.0, 0.3]])
    b = np.array([[1.0], [0.5]])
    c = np.array([[1.0, 0.0]])
    d = control.odq(a, b, c, 0.01, 2.0)
    m1 = c @ b
    np.testing.assert_allclose(d["C_f"], -np.linalg.pinv(m1) @ c @ a, rtol=1e-12)
    # The closed form reaches E = (d/2)|M₁| (its design cost), no worse than static rounding.
    assert d["design_cost"] == pytest.approx(1.0 * abs(m1[0, 0]), rel=1e-12)
    assert d["cost"] <= d["static_cost"] * (1 + 1e-12)
    lp = control.odq(a, b, c, 0.01, 2.0, method="lp", horizon=50)
    assert lp["design_cost"] <= d["static_cost"] * (1 + 1e-9)
    with pytest.raises(pl.InvalidArgumentError):
        control.odq(a, b, c, 0.01, -1.0)


def test_nmpc_swing_up_respects_the_input_bound_and_is_deterministic():
    ctrl = control.nmpc_arm_swing_up()
    assert (ctrl.ny, ctrl.nu, ctrl.sample_time) == (4, 1, 1e-3)
    x = np.array([0.0, np.pi - 0.05, 0.0, 0.0])
    first = [ctrl.update(k * 1e-3, x)[0] for k in range(20)]
    assert all(np.isfinite(first)) and max(abs(u) for u in first) <= 2.5 + 1e-9
    ctrl.reset()
    again = [ctrl.update(k * 1e-3, x)[0] for k in range(20)]
    assert again == first


def test_build_from_a_spec_is_the_factory():
    k_book = [3.16228, 13.47175, 4.48137, 2.26289]
    c = control.build({"kind": "state-feedback", "k_book": k_book}, "cart", 1e-3)
    y = np.array([0.01, -0.02, 0.1, 0.2])
    # u = +K_book y (the book's sign; docs/model.md §6).
    assert c.update(0.0, y)[0] == pytest.approx(np.dot(k_book, y), rel=1e-14)
    with pytest.raises(pl.InvalidArgumentError):
        control.build({"kind": "state-feedback", "k_book": [1.0, 2.0]}, "cart")
    with pytest.raises(pl.InvalidArgumentError):
        control.build({"kind": "no-such-kind"}, "cart")
