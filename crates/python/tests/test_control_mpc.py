"""pendulab.control.LinearMpc and solve_qp against independent references.

- without active constraints the first move is the discrete LQR law of python-control
  0.10.2's ``dlqr`` (1e-9), the terminal weight its Riccati solution;
- with active constraints the condensed QP is rebuilt here in NumPy (ZOH by SciPy's ``expm``,
  the DARE by SciPy's ``solve_discrete_are``, the stacked prediction matrices), and the
  answer is certified by the KKT conditions solved in NumPy on the active rows (multipliers
  ≥ 0, feasibility, stationarity) and compared with SciPy's SLSQP (no cvxpy/Clarabel in the
  venv);
- an infeasible QP raises ``InfeasibleError`` with a Farkas certificate checked in NumPy;
- the closed loop on the nonlinear cart runs through the spec factory (kind ``"mpc"``).
"""

import numpy as np
import pytest
from scipy.linalg import expm, solve_discrete_are
from scipy.optimize import minimize

import pendulab as pl
from pendulab import control as pc
from pendulab.plants import CartPendulum, simulate


def spd(rng, n, floor=0.1):
    m = rng.standard_normal((n, n))
    return m @ m.T / n + floor * np.eye(n)


def kkt_certify(H, g, G, w, x, active_tol=1e-8):
    """Multipliers of the rows active at x from the KKT system in NumPy; returns (λ, the
    equality-constrained optimum on those rows)."""
    slack = G @ x - w
    act = np.flatnonzero(slack > -active_tol * (1 + np.abs(w)))
    n, k = H.shape[0], len(act)
    Ga = G[act]
    K = np.block([[H, Ga.T], [Ga, np.zeros((k, k))]])
    sol = np.linalg.lstsq(K, np.concatenate([-g, w[act]]), rcond=None)[0]
    lam = np.zeros(G.shape[0])
    lam[act] = sol[n:]
    return lam, sol[:n]


def slsqp(H, g, G, w, x0):
    r = minimize(lambda x: 0.5 * x @ H @ x + g @ x, x0, jac=lambda x: H @ x + g, method="SLSQP",
                 constraints=[{"type": "ineq", "fun": lambda x: w - G @ x, "jac": lambda x: -G}],
                 options={"ftol": 1e-13, "maxiter": 1000})
    # SLSQP may stop with "positive directional derivative" at the optimum (status 8): its
    # point is compared, not its flag.
    assert r.success or r.status == 8, r.message
    return r.x


def test_unconstrained_mpc_is_the_discrete_lqr():
    control = pytest.importorskip("control")
    rng = np.random.default_rng(5)
    n, m = 4, 2
    A, B = rng.standard_normal((n, n)), rng.standard_normal((n, m))
    Q, R = spd(rng, n), spd(rng, m)
    K, S, _ = control.dlqr(A, B, Q, R)
    for bounds in [{}, {"u_max": 1e6, "state_bounds": [(0, -1e6, 1e6)]}]:
        mpc = pc.LinearMpc(A, B, 8, Q, R, **bounds)
        np.testing.assert_allclose(mpc.K, K, rtol=1e-9)
        np.testing.assert_allclose(mpc.P, S, rtol=1e-9)
        for _ in range(5):
            x = rng.standard_normal(n)
            u = mpc.step(x)
            np.testing.assert_allclose(u, -K @ x, rtol=1e-9, atol=1e-9 * np.abs(K @ x).max())
            assert mpc.status == "solved" and mpc.active_set == []


def condensed(Ad, Bd, N, Q, R, x0, u_prev, u_max, du_max, track):
    """The MPC's QP built from scratch: H, g and G, w with rows in this function's order."""
    n, m = Bd.shape
    P = solve_discrete_are(Ad, Bd, Q, R)
    Phi = np.vstack([np.linalg.matrix_power(Ad, k) for k in range(1, N + 1)])
    Gam = np.zeros((N * n, N * m))
    for k in range(N):
        for j in range(k + 1):
            Gam[k * n:(k + 1) * n, j * m:(j + 1) * m] = np.linalg.matrix_power(Ad, k - j) @ Bd
    Qb = np.kron(np.eye(N), Q)
    Qb[-n:, -n:] = P
    H = Gam.T @ Qb @ Gam + np.kron(np.eye(N), R)
    g = Gam.T @ Qb @ Phi @ x0
    rows, rhs = [], []
    for s in range(N):
        e = np.zeros(N * m)
        e[s] = 1.0
        rows += [e, -e]
        rhs += [u_max, u_max]
        d = e.copy()
        if s:
            d[s - 1] = -1.0
        rows += [d, -d]
        rhs += [du_max + (u_prev if s == 0 else 0.0), du_max - (u_prev if s == 0 else 0.0)]
        zrow, z0 = Gam[s * n], (Phi @ x0)[s * n]
        rows += [zrow, -zrow]
        rhs += [track - z0, track + z0]
    return H, g, np.array(rows), np.array(rhs)


def test_constrained_mpc_on_the_cart_satisfies_kkt_of_an_independent_condensing():
    A, B, C, D = CartPendulum().linearize()
    sys = pl.ss(A, B, C, D)
    dt, N, u_max, du_max, track = 0.02, 15, 3.0, 1.0, 0.05
    Q, R = np.diag([100.0, 100.0, 1.0, 1.0]), np.array([[0.01]])
    mpc = pc.LinearMpc.sampled(sys, dt, N, Q, R, u_max=u_max, du_max=du_max,
                               state_bounds=[(0, -track, track)])
    M = expm(np.block([[A, B], [np.zeros((1, 5))]]) * dt)
    Ad, Bd = M[:4, :4], M[:4, 4:]
    x0, u_prev = np.array([0.02, 0.12, 0.0, 0.0]), 0.5
    H, g, G, w = condensed(Ad, Bd, N, Q, R, x0, u_prev, u_max, du_max, track)
    np.testing.assert_allclose(mpc.H, H, rtol=1e-9, atol=1e-9 * np.abs(H).max())
    u0 = mpc.step(x0, [u_prev], warm="cold")
    U = mpc.plan
    assert mpc.status == "solved" and len(mpc.active_set) >= 2
    np.testing.assert_array_equal(u0, U[:1])
    # Certified optimal on the independently built QP: feasible, λ ≥ 0, stationary.
    lam, U_eq = kkt_certify(H, g, G, w, U)
    assert (G @ U - w).max() <= 1e-9
    assert lam.min() >= -1e-9 * np.abs(lam).max()
    np.testing.assert_allclose(U, U_eq, rtol=0, atol=1e-9 * np.abs(U).max())
    assert np.abs(H @ U + g + G.T @ lam).max() <= 1e-8 * np.abs(g).max()
    np.testing.assert_allclose(U, slsqp(H, g, G, w, np.zeros_like(U)), rtol=0, atol=1e-5 * np.abs(U).max())
    k = mpc.kkt()
    assert max(k.values()) <= 1e-8 * np.abs(g).max()


def test_solve_qp_matches_kkt_and_slsqp_on_a_random_qp():
    rng = np.random.default_rng(23)
    n, m = 6, 12
    H, A = spd(rng, n), rng.standard_normal((m, n))
    g, w = 5 * rng.standard_normal(n), rng.uniform(0.1, 1.0, m)
    r = pc.solve_qp(H, g, A, w)
    x = r["x"]
    assert r["status"] == "solved" and len(r["active_set"]) >= 1 and r["iterations"] >= 1
    lam, x_eq = kkt_certify(H, g, A, w, x)
    assert lam.min() >= -1e-10 and (A @ x - w).max() <= 1e-10
    np.testing.assert_allclose(x, x_eq, atol=1e-10)
    np.testing.assert_allclose(r["multipliers"], lam, atol=1e-9 * (1 + np.abs(lam).max()))
    np.testing.assert_allclose(x, slsqp(H, g, A, w, np.zeros(n)), atol=1e-6)
    k = pc.kkt_residuals(H, g, A, w, x, r["multipliers"])
    assert k == r["kkt"]
    assert k["stationarity"] == pytest.approx(np.abs(H @ x + g + A.T @ r["multipliers"]).max(), abs=1e-13)
    assert max(k.values()) < 1e-9
    # A warm start from the answer's active set ends at the same point.
    again = pc.solve_qp(H, g, A, w, warm_start=r["active_set"])
    np.testing.assert_allclose(again["x"], x, atol=1e-12)


def test_infeasible_qp_and_mpc_raise_infeasible_error_with_a_valid_certificate():
    A, w = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0]]), np.array([-1.0, -1.0, 3.0])
    with pytest.raises(pl.InfeasibleError) as e:
        pc.solve_qp(np.eye(2), [0.0, 0.0], A, w)
    y = e.value.certificate
    assert e.value.status == "infeasible" and e.value.certificate_valid
    assert y.min() >= 0 and np.abs(y @ A).max() <= 1e-12 and y @ w < 0
    # The cart far outside a track bound it cannot regain in one step.
    Ad, Bd = np.array([[1.0, 0.1], [0.0, 1.0]]), np.array([[0.005], [0.1]])
    mpc = pc.LinearMpc(Ad, Bd, 5, np.eye(2), [[1.0]], u_max=1.0, state_bounds=[(0, -0.1, 0.1)])
    with pytest.raises(pl.InfeasibleError) as e:
        mpc.step([1.0, 0.0])
    assert e.value.certificate_valid and mpc.status == "infeasible"


def test_bad_inputs_raise_typed_errors():
    A, B = np.eye(2), np.array([[0.0], [1.0]])
    with pytest.raises(pl.ShapeError):
        pc.LinearMpc(A, B, 5, np.eye(3), [[1.0]])
    with pytest.raises(pl.NotFiniteError):
        pc.LinearMpc([[1.0, float("nan")], [0.0, 1.0]], B, 5, np.eye(2), [[1.0]])
    with pytest.raises(pl.InvalidArgumentError, match="horizon"):
        pc.LinearMpc(A, B, 0, np.eye(2), [[1.0]])
    with pytest.raises(pl.LinAlgError):
        pc.LinearMpc(A, B, 5, np.eye(2), [[-1.0]])
    with pytest.raises(pl.InvalidArgumentError, match="state_bounds"):
        pc.LinearMpc(A, B, 5, np.eye(2), [[1.0]], state_bounds=[(4, -1.0, 1.0)])
    mpc = pc.LinearMpc(A * 0.9, B, 5, np.eye(2), [[1.0]], u_max=1.0)
    with pytest.raises(pl.ShapeError):
        mpc.step([1.0, 2.0, 3.0])
    with pytest.raises(pl.InvalidArgumentError, match="warm"):
        mpc.step([1.0, 2.0], warm="hot")
    with pytest.raises(pl.LinAlgError) as e:
        pc.solve_qp(-np.eye(2), [0.0, 0.0], np.eye(2), [1.0, 1.0])
    assert e.value.variant == "Singular"
    with pytest.raises(pl.ShapeError):
        pc.solve_qp(np.eye(2), [0.0, 0.0, 0.0], np.eye(2), [1.0, 1.0])


def test_mpc_spec_balances_the_nonlinear_cart_within_its_voltage_limit():
    u_max = 1.5
    run = simulate("cart", {"kind": "mpc", "u_max": u_max, "travel_limit": 0.3}, [0.0, 0.1, 0.0, 0.0], 4.0)
    assert np.abs(run.command).max() <= u_max + 1e-9
    assert np.abs(run.command).max() >= 0.99 * u_max  # the limit is active at the start
    assert np.abs(run.x[-1]).max() < 1e-3
