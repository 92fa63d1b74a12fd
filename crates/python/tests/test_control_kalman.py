"""pendulab.control's Kalman filters against independent NumPy recursions.

- KalmanFilter: a hand-written Kalman recursion on a random time-varying system (1e-12), and
  the steady state against python-control 0.10.2's ``dlqe`` and SciPy's DARE;
- ExtendedKalmanFilter on a linear callable: the Kalman filter of RK4's exact one-step map
  of a linear system (Φ = Σ_{j≤4} (hA)^j/j!, Γ = h Σ_{j<4} (hA)^j/(j+1)! B) (1e-10);
- UnscentedKalmanFilter: a NumPy unscented transform (Wan & van der Merwe's scaled form) with
  NumPy RK4 on a nonlinear pendulum with a nonlinear measurement (1e-10);
- encoder noise q²/12 against Monte Carlo rounding, nees against NumPy;
- filter_log over the shipped cart log equals the step-by-step loop.
"""

import math
import pathlib

import numpy as np
import pytest

import pendulab as pl
from pendulab import control as pc
from pendulab.plants import CartPendulum

ROOT = pathlib.Path(__file__).resolve().parents[3]
LOG = ROOT / "data" / "rig" / "cdip_least_square_data.csv"


def spd(rng, n, floor=0.1):
    m = rng.standard_normal((n, n))
    return m @ m.T / n + floor * np.eye(n)


def np_update(x, P, C, y, R, Du=0.0):
    S = C @ P @ C.T + R
    K = P @ C.T @ np.linalg.inv(S)
    nu = y - C @ x - Du
    return x + K @ nu, P - K @ S @ K.T, nu, S, K


def test_kalman_filter_matches_numpy_recursion_on_a_random_time_varying_system():
    rng = np.random.default_rng(19)
    n, m, p = 4, 2, 3
    x0, P0 = rng.standard_normal(n), spd(rng, n)
    f = pc.KalmanFilter(x0, P0)
    x, P = x0.copy(), P0.copy()
    for k in range(30):
        A = rng.standard_normal((n, n)) / 2
        B, u, Q = rng.standard_normal((n, m)), rng.standard_normal(m), spd(rng, n, 0.01)
        C, D, R, y = rng.standard_normal((p, n)), rng.standard_normal((p, m)), spd(rng, p), rng.standard_normal(p)
        f.predict(A, B, u, Q)
        x, P = A @ x + B @ u, A @ P @ A.T + Q
        inn = f.update(C, y, R, D, u)
        x, P, nu, S, K = np_update(x, P, C, y, R, D @ u)
        scale = 1 + np.abs(P).max()
        np.testing.assert_allclose(f.x, x, rtol=0, atol=1e-12 * (1 + np.abs(x).max()))
        np.testing.assert_allclose(f.P, P, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(inn.residual, nu, rtol=0, atol=1e-12 * (1 + np.abs(nu).max()))
        np.testing.assert_allclose(inn.S, S, rtol=0, atol=1e-12 * np.abs(S).max())
        np.testing.assert_allclose(inn.K, K, rtol=0, atol=1e-12 * (1 + np.abs(K).max()))
        assert abs(inn.nis - nu @ np.linalg.solve(S, nu)) < 1e-11 * (1 + inn.nis)
    assert f.innovation is inn


def test_kalman_filter_converges_to_dlqe_and_the_dare():
    control = pytest.importorskip("control")
    from scipy.linalg import solve_discrete_are

    rng = np.random.default_rng(7)
    n, p = 4, 2
    A = rng.standard_normal((n, n))
    A *= 0.95 / np.abs(np.linalg.eigvals(A)).max()
    C, Q, R = rng.standard_normal((p, n)), spd(rng, n, 0.05), spd(rng, p)
    f = pc.KalmanFilter(np.zeros(n), np.eye(n))
    for _ in range(400):
        f.predict(A, None, None, Q)
        prior = f.P
        inn = f.update(C, np.zeros(p), R)
    L, P_dlqe, _ = control.dlqe(A, np.eye(n), C, Q, R)
    P_dare = solve_discrete_are(A.T, C.T, Q, R)
    np.testing.assert_allclose(prior, P_dare, rtol=1e-10)
    np.testing.assert_allclose(prior, P_dlqe, rtol=1e-10)
    # dlqe's gain is the predictor's, A times the filter's.
    np.testing.assert_allclose(A @ inn.K, L, rtol=1e-9)


def rk4_linear(A, B, h):
    """RK4's one-step map of ẋ = Ax + Bu with u held: x⁺ = Φx + Γu."""
    n = A.shape[0]
    Phi, Gam, term = np.eye(n), np.zeros_like(B), np.eye(n)
    for j in range(1, 5):
        Gam = Gam + h * term @ B / math.factorial(j)
        term = term @ (h * A)
        Phi = Phi + term / math.factorial(j)
    return Phi, Gam


@pytest.mark.parametrize("measure", ["states", "output"])
def test_ekf_of_a_linear_callable_is_the_kalman_filter(measure):
    rng = np.random.default_rng(3)
    n, m, ts = 3, 1, 0.05
    A, B = rng.standard_normal((n, n)), rng.standard_normal((n, m))
    Cm = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]) if measure == "states" else rng.standard_normal((2, n))
    Q, R, x0, P0 = spd(rng, n, 0.01), spd(rng, 2), rng.standard_normal(n), spd(rng, n)
    f = lambda x, u: A @ x + B @ u  # noqa: E731
    kw = {"measured": [0, 2]} if measure == "states" else {"h": lambda x, u: Cm @ x}
    ekf = pc.ExtendedKalmanFilter(f, ts, x0, P0, Q, R, nu=m, **kw)
    assert (ekf.nx, ekf.nu, ekf.ny) == (n, m, 2)
    Phi, Gam = rk4_linear(A, B, ts)
    x, P = x0.copy(), P0.copy()
    for k in range(25):
        u, y = rng.standard_normal(m), rng.standard_normal(2)
        ekf.predict(u, t=k * ts)
        x, P = Phi @ x + Gam @ u, Phi @ P @ Phi.T + Q
        inn = ekf.update(y, u, t=(k + 1) * ts)
        x, P, nu, S, K = np_update(x, P, Cm, y, R)
        np.testing.assert_allclose(ekf.x, x, rtol=0, atol=1e-10 * (1 + np.abs(x).max()))
        np.testing.assert_allclose(ekf.P, P, rtol=0, atol=1e-10 * (1 + np.abs(P).max()))
        np.testing.assert_allclose(inn.K, K, rtol=0, atol=1e-10 * (1 + np.abs(K).max()))


def np_ukf_step(f_step, h, x, P, Q, R, y, alpha, beta, kappa):
    """One prediction and update of the scaled unscented Kalman filter, in NumPy."""
    n = len(x)
    c = alpha**2 * (n + kappa)
    lam = c - n
    wm = np.full(2 * n + 1, 0.5 / c)
    wc = wm.copy()
    wm[0] = lam / c
    wc[0] = lam / c + 1 - alpha**2 + beta

    def sigma(m, P):
        Lc = np.linalg.cholesky(c * P)
        return np.array([m, *(m + Lc[:, i] for i in range(n)), *(m - Lc[:, i] for i in range(n))])

    X = sigma(x, P)
    Y = np.array([f_step(p) for p in X])
    xm = wm @ Y
    Pp = sum(wc[i] * np.outer(Y[i] - xm, Y[i] - xm) for i in range(2 * n + 1)) + Q
    X = sigma(xm, Pp)
    Z = np.array([h(p) for p in X])
    zm = wm @ Z
    S = sum(wc[i] * np.outer(Z[i] - zm, Z[i] - zm) for i in range(2 * n + 1)) + R
    Pxz = sum(wc[i] * np.outer(X[i] - xm, Z[i] - zm) for i in range(2 * n + 1))
    K = Pxz @ np.linalg.inv(S)
    return xm + K @ (y - zm), Pp - K @ S @ K.T


def test_ukf_matches_a_numpy_unscented_transform_on_a_nonlinear_pendulum():
    rng = np.random.default_rng(11)
    ts, sub = 0.02, 2

    def f(x, u):
        return np.array([x[1], -9.81 * np.sin(x[0]) - 0.1 * x[1] + u[0]])

    def h(x, u=None):
        return np.array([np.sin(x[0]), x[0] * x[1]])

    def rk4(x, u):
        hh = ts / sub
        for _ in range(sub):
            k1 = f(x, u)
            k2 = f(x + hh / 2 * k1, u)
            k3 = f(x + hh / 2 * k2, u)
            k4 = f(x + hh * k3, u)
            x = x + hh / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        return x

    Q, R = np.diag([1e-4, 1e-3]), np.diag([1e-2, 2e-2])
    x0, P0 = np.array([0.8, -0.2]), np.diag([0.1, 0.3])
    for alpha, beta, kappa in [(1.0, 2.0, 0.0), (0.5, 2.0, 1.0)]:
        ukf = pc.UnscentedKalmanFilter(f, ts, x0, P0, Q, R, h=h, nu=1, substeps=sub,
                                       alpha=alpha, beta=beta, kappa=kappa)
        x, P = x0.copy(), P0.copy()
        for k in range(20):
            u, y = rng.standard_normal(1), rng.standard_normal(2) * 0.3
            ukf.predict(u)
            ukf.update(y, u)
            x, P = np_ukf_step(lambda p: rk4(p, u), h, x, P, Q, R, y, alpha, beta, kappa)
            np.testing.assert_allclose(ukf.x, x, rtol=0, atol=1e-10)
            np.testing.assert_allclose(ukf.P, P, rtol=0, atol=1e-10)


def test_encoder_noise_and_nees():
    q = 2 * math.pi / 14400
    assert pc.quantization_variance(q) == pytest.approx(q * q / 12, rel=1e-15)
    # Monte Carlo: the rounding error of a signal spread over many counts has variance q²/12.
    s = np.random.default_rng(1).uniform(-1000 * q, 1000 * q, 400_000)
    err = q * np.round(s / q) - s
    assert abs(err.var() / pc.quantization_variance(q) - 1) < 0.02
    np.testing.assert_allclose(pc.encoder_covariance([1e-3, q]), np.diag([1e-6 / 12, q * q / 12]), rtol=1e-15)
    rng = np.random.default_rng(2)
    P, x, xh = spd(rng, 3), rng.standard_normal(3), rng.standard_normal(3)
    assert pc.nees(x, xh, P) == pytest.approx((x - xh) @ np.linalg.solve(P, x - xh), rel=1e-12)
    with pytest.raises(pl.InvalidArgumentError):
        pc.quantization_variance(0.0)
    with pytest.raises(pl.LinAlgError):
        pc.nees(x, xh, -P)


def cart_filter(kind, ts):
    r = pc.encoder_covariance([4.8414e-5, 2 * math.pi / 14400])
    q = np.diag([1e-14, 1e-14, (0.5 * ts) ** 2, (5.0 * ts) ** 2])
    cls = pc.ExtendedKalmanFilter if kind == "ekf" else pc.UnscentedKalmanFilter
    return lambda y0: cls(CartPendulum(), ts, [y0[0], y0[1], 0, 0], np.diag([r[0, 0], r[1, 1], 1e-2, 1e-2]), q, r)


@pytest.mark.skipif(not LOG.exists(), reason="the shipped rig log is not in this checkout")
@pytest.mark.parametrize("kind", ["ekf", "ukf"])
def test_filter_log_over_the_shipped_cart_log_is_the_step_by_step_loop(kind):
    t, u, y = pc.read_cart_log(LOG)
    n = 600
    t, u, y = t[:n], u[:n], y[:n]
    make = cart_filter(kind, t[1] - t[0])
    run = pc.filter_log(make(y[0]), t, u, y)
    f = make(y[0])
    for k in range(n):
        if k:
            f.predict(u[k - 1], t[k - 1])
        inn = f.update(y[k], u[k], t[k])
        np.testing.assert_array_equal(run["states"][k], f.x)
        assert run["nis"][k] == inn.nis
    np.testing.assert_array_equal(run["variances"][-1], np.diag(f.P))
    # The estimates follow the encoders to a few counts.
    assert np.abs(run["states"][:, :2] - y).max() < 20 * 2 * math.pi / 14400
    whole = pc.filter_log(make(y[0]), log=LOG)
    np.testing.assert_array_equal(whole["states"][:n], run["states"])


def test_filter_errors():
    f = pc.KalmanFilter([0.0, 0.0], np.eye(2))
    with pytest.raises(pl.ShapeError):
        f.predict(np.eye(3), None, None, np.eye(3))
    with pytest.raises(pl.NotFiniteError):
        f.update(np.eye(2), [float("nan"), 0.0], np.eye(2))
    with pytest.raises(pl.LinAlgError):
        pc.KalmanFilter([0.0, 0.0], -np.eye(2))
    with pytest.raises(pl.InvalidArgumentError, match="measured state 5"):
        pc.ExtendedKalmanFilter("cart", 1e-3, np.zeros(4), np.eye(4), np.eye(4), np.eye(1), measured=[5])
    with pytest.raises(pl.InvalidArgumentError, match="measured"):
        pc.ExtendedKalmanFilter(lambda x, u: -x, 1e-3, [1.0], [[1.0]], [[1.0]], [[1.0]])
    calls = []

    def flaky(x, u):
        calls.append(1)
        if len(calls) > 5:
            return [1.0, 2.0]
        return -x

    ekf = pc.ExtendedKalmanFilter(flaky, 0.01, [1.0], [[1.0]], [[0.1]], [[0.1]], measured=[0])
    with pytest.raises(pl.ShapeError, match=r"f\(x, u\) returned 2 values"):
        ekf.predict()
    ukf = pc.UnscentedKalmanFilter(lambda x, u: -x, 0.01, [1.0], [[1.0]], [[0.1]], [[0.1]],
                                   h=lambda x, u: 1 / 0 if x[0] < 0.5 else [x[0]])
    with pytest.raises(ZeroDivisionError):
        ukf.update([0.9])
    ekf = pc.ExtendedKalmanFilter("cart", 1e-3, np.zeros(4), np.eye(4), np.eye(4) * 1e-6, np.eye(2) * 1e-6)
    with pytest.raises(pl.ShapeError, match="one row of 2 per sample"):
        pc.filter_log(ekf, [0.0, 1e-3], [0.0, 0.0], [[0.0, 0.0]])
