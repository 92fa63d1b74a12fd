"""pendulab.lmi: each design's certificate is checked here with NumPy (the eigenvalues of the
LMI matrices at the returned values), its optimum against CVXPY 1.9.3 + Clarabel 0.11.1
(``crates/lmi/tests/fixtures/lmi_reference.json``, written by
``tools/reference/lmi_reference.py``; tolerances as in ``crates/lmi/tests/book_lmi.rs``), and
the gain-scheduled design against the CLI's ``pendulab book run p2c15_ex7_adip_oc_gs_servo``
(the same Rust code path). Infeasible and malformed problems raise."""

import json
import pathlib
import subprocess

import numpy as np
import pytest

import pendulab as pl
from pendulab import lmi
from pendulab.plants import ArmPendulum

ROOT = pathlib.Path(__file__).resolve().parents[3]
CLI = ROOT / "target" / "release" / "pendulab"
FIXTURE = json.loads((ROOT / "crates" / "lmi" / "tests" / "fixtures" / "lmi_reference.json").read_text())
#: The servo weights of book Part 2 §1.2.2 (p2c122_ex4_adip_oc_servo.m).
Q_SERVO = np.diag([0.1, 1.0, 0.001, 0.001, 4.0])
R_SERVO = np.eye(1)


def servo(a1=None, b1=None):
    """The arm pendulum's integral-servo model Ã = [[A, 0], [−C, 0]], B̃ = [B; 0], C = θ₁
    (book Part 2 §1.2.2), with the drive's a₁, b₁ optionally replaced."""
    params = {k: v for k, v in (("a1", a1), ("b1", b1)) if v is not None}
    a, b, _, _ = ArmPendulum(params).linearize("upright")
    at = np.zeros((5, 5))
    at[:4, :4] = a
    at[4, 0] = -1.0
    bt = np.vstack([b, [[0.0]]])
    return at, bt


def max_eig(m):
    return np.linalg.eigvalsh((m + m.T) / 2).max()


def test_alpha_stability_certificate_and_infeasibility():
    # Book Part 2 example 1.1: eigenvalues −1.125 ± 0.992j, so α = 1 is feasible, α = 1.2 not.
    a = np.array([[0.0, 1.0], [-2.25, -2.25]])
    res = lmi.alpha_stability(a, 1.0)
    p = res.P
    assert np.linalg.eigvalsh(p).min() > 0
    assert max_eig(a.T @ p + p @ a + 2.0 * p) < 0
    with pytest.raises(pl.InfeasibleError) as err:
        lmi.alpha_stability(a, 1.2)
    assert err.value.status == "infeasible"
    assert err.value.certificate_valid
    # The largest certified decay rate is the spectral abscissa's negative (tolerance 1e-6 of
    # the bisection plus the margin's effect).
    alpha = -np.linalg.eigvals(a).real.max()
    assert abs(lmi.max_decay_rate(a).alpha - alpha) < 1e-5


def test_lq_guaranteed_cost_certificate_and_cvxpy_optimum():
    at, bt = servo()
    res = lmi.lq(at, bt, Q_SERVO, R_SERVO)
    k, x, l = res
    p = np.linalg.inv(x)
    acl = at - bt @ k
    # The certificate: P ≻ 0 and (A − BK)ᵀP + P(A − BK) + Q + KᵀRK ≺ 0 (Schur complement of
    # the LMI), so J ≤ x₀ᵀPx₀.
    assert np.linalg.eigvalsh(x).min() > 0
    assert max_eig(acl.T @ p + p @ acl + Q_SERVO + k.T @ R_SERVO @ k) < 0
    np.testing.assert_allclose(l, -k @ x, rtol=1e-9, atol=1e-9)
    ref = FIXTURE["p2c122_lq"]
    assert abs(np.trace(x) - ref["trace_X"]) < 1e-4 * ref["trace_X"]
    k_lq = np.array(ref["K_riccati"])
    assert np.linalg.norm(k - k_lq) / np.linalg.norm(k_lq) < 1e-3
    x0 = np.array([0.1, 0, 0, 0, 0])
    assert res.cost_bound(x0) == pytest.approx(x0 @ p @ x0, rel=1e-9)
    assert all(np.all(np.real(pp) < 0) for pp in res.poles)


def test_d_stability_poles_and_region_lmi():
    at, bt = servo()
    regions = [("decay_rate", 2.0), ("speed_limit", 16.0), ("sector", np.pi / 4)]
    res = lmi.d_stability(at, bt, Q_SERVO, R_SERVO, regions)
    poles = np.linalg.eigvals(at - bt @ res.K)
    assert np.all(poles.real < -2.0) and np.all(poles.real > -16.0)
    assert np.all(np.abs(poles.imag) < -poles.real)
    assert res.poles_in_regions
    # The decay-rate LMI at the solution: He(A X + B L) + 2αX ≺ 0.
    y = at @ res.X + bt @ res.L
    assert max_eig(y + y.T + 4.0 * res.X) < 0
    ref = FIXTURE["p2c122_multiobjective"]["trace_X"]
    assert abs(res.objective - ref) < 1e-4 * ref


def test_robust_design_holds_at_every_vertex():
    ref = FIXTURE["p2c13_robust"]
    verts = [servo(a1, b1) for a1, b1 in ref["vertices"]]
    res = lmi.robust(verts, Q_SERVO, R_SERVO, [("decay_rate", 2.0), ("speed_limit", 40.0)])
    p = np.linalg.inv(res.X)
    for a, b in verts:
        acl = a - b @ res.K
        poles = np.linalg.eigvals(acl)
        assert np.all(poles.real < -2.0) and np.all(poles.real > -40.0)
        assert max_eig(acl.T @ p + p @ acl + Q_SERVO + res.K.T @ R_SERVO @ res.K) < 0
    assert abs(res.objective - ref["trace_X"]) < 1e-5 * ref["trace_X"]


def test_saturated_design_bounds_the_input_on_the_ellipsoid():
    ref = FIXTURE["p2c14_saturation"]
    a, b, _, _ = ArmPendulum().linearize("upright")
    q, r = np.diag([20.0, 10.0, 0.1, 0.1]), np.eye(1)
    x0 = np.array(ref["x0"])
    res = lmi.saturated(a, b, q, r, [ref["u_max"]], [x0])
    # x₀ in E = {xᵀX⁻¹x ≤ 1} and max over E of |K x| = √(K X Kᵀ) ≤ u_max.
    assert x0 @ np.linalg.solve(res.X, x0) <= 1.0 + 1e-9
    assert np.sqrt(res.K @ res.X @ res.K.T)[0, 0] <= ref["u_max"] * (1 + 1e-9)
    assert abs(res.objective - ref["trace_X_max"]) < 1e-4 * ref["trace_X_max"]


def arm_lpv_servo():
    a0, a1, b0, b1 = ArmPendulum().lpv()
    at0, bt0 = np.zeros((5, 5)), np.zeros((5, 1))
    at0[:4, :4], at0[4, 0], bt0[:4] = a0, -1.0, b0
    at1, bt1 = np.zeros((5, 5)), np.zeros((5, 1))
    at1[:4, :4], bt1[:4] = a1, b1
    return at0, at1, bt0, bt1


@pytest.mark.skipif(not CLI.exists(), reason="the CLI is built by tools/test's cargo step")
def test_gain_schedule_equals_the_cli_and_its_certificate_holds():
    rho_bar = 1.0 - np.cos(np.radians(65.0))
    a0, a1, b0, b1 = arm_lpv_servo()
    sched = lmi.gain_scheduled(a0, a1, b0, b1, Q_SERVO, R_SERVO, (0.0, rho_bar), rho_dot_bound=0.75)
    out = subprocess.run(
        [str(CLI), "book", "run", "p2c15_ex7_adip_oc_gs_servo", "--json"], check=True, capture_output=True, text=True
    )
    values = json.loads(out.stdout)["values"]
    # The book's sign: K_book = −K.
    np.testing.assert_allclose(-sched(0.0)[0], values["K_at_rho0"], rtol=1e-9)
    np.testing.assert_allclose(-sched(rho_bar)[0], values["K_at_rho_max"], rtol=1e-9)
    assert sched.gamma_star == pytest.approx(values["gamma"], rel=1e-9)
    assert sched.gamma == pytest.approx(values["gamma_design"], rel=1e-9)
    # CVXPY's γ* of the same SOS program (both at reduced accuracy: relative 1e-3).
    assert abs(sched.gamma_star - FIXTURE["p2c15_gain_schedule"]["gamma_star"]) < 1e-3 * sched.gamma_star
    # The certificate on a grid: X(ρ) ≻ 0 and, for ρ̇ = ±ν,
    # Ẋ − He(A(ρ)X + B(ρ)L) − XQX − LᵀRL ⪰ 0 (the Schur complement of M₃; book (1.62)).
    x0, x1, x2 = sched.x_coefficients
    for rho in np.linspace(0.0, rho_bar, 21):
        x, l = sched.X(rho), sched.L(rho)
        assert np.linalg.eigvalsh(x).min() > 0
        a, b = a0 + rho * a1, b0 + rho * b1
        y = a @ x + b @ l
        for rho_dot in (-0.75, 0.75):
            xdot = rho_dot * (x1 + 2 * rho * x2)
            m3 = xdot - y - y.T - x @ Q_SERVO @ x - l.T @ R_SERVO @ l
            assert np.linalg.eigvalsh((m3 + m3.T) / 2).min() > -1e-9 * np.abs(m3).max()
        np.testing.assert_allclose(sched(rho), -l @ np.linalg.inv(x), rtol=1e-9, atol=1e-12)


def test_infeasible_and_malformed_designs_raise():
    # An unstable mode the input cannot reach: no stabilising gain, so no LQ certificate.
    a = np.array([[1.0, 0.0], [0.0, -1.0]])
    b = np.array([[0.0], [1.0]])
    with pytest.raises(pl.InfeasibleError):
        lmi.lq(a, b, np.eye(2), np.eye(1))
    with pytest.raises(pl.ShapeError):
        lmi.lq(np.eye(3), np.ones((2, 1)), np.eye(3), np.eye(1))
    with pytest.raises(pl.NotFiniteError):
        lmi.lq([[np.nan, 0], [0, 1]], b, np.eye(2), np.eye(1))
    with pytest.raises(pl.InvalidArgumentError, match="unknown region"):
        lmi.d_stability(a, b, np.eye(2), np.eye(1), [("circle", 1.0)])
    with pytest.raises(pl.InvalidArgumentError, match="theta"):
        lmi.d_stability(a, b, np.eye(2), np.eye(1), [("sector", 2.0)])
    with pytest.raises(pl.InvalidArgumentError, match="rho_range"):
        lmi.gain_scheduled(a, a, b, b, np.eye(2), np.eye(1), (1.0, 0.0))
    with pytest.raises(pl.InvalidArgumentError, match="together"):
        lmi.state_feedback([(a, b)], Q=np.eye(2))
