"""The LTI API: closed forms, python-control interoperability, unpacking, conversions, and bad
inputs raising pendulab's exceptions with the Rust message (never a crash)."""

import control as ct
import numpy as np
import pytest

import pendulab as pl

# The cart pendulum's upright linearisation in the shape of docs/model.md (x, θ, ẋ, θ̇) with
# round numbers; only its structure matters here.
A4 = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [0, -1.5, -4.0, 0], [0, 30.0, 8.0, 0]])
B4 = np.array([0, 0, 2.0, -4.0])


def test_scalar_closed_forms():
    # ẋ = a x + b u, cost ∫ q x² + r u²: S = r(a + sqrt(a² + b² q / r))/b², K = b S / r.
    a, b, q, r = 1.0, 2.0, 3.0, 0.5
    s = r * (a + np.sqrt(a * a + b * b * q / r)) / (b * b)
    K, S, E = pl.lqr([[a]], [[b]], [[q]], [[r]])
    assert S[0, 0] == pytest.approx(s, rel=1e-14)
    assert K[0, 0] == pytest.approx(b * s / r, rel=1e-14)
    assert E[0] == pytest.approx(a - b * b * s / r, rel=1e-14)
    # lyap: a x + x a + q = 0 → x = −q/(2a).
    assert np.asarray(pl.lyap([[-2.0]], [[3.0]]))[0, 0] == pytest.approx(0.75, rel=1e-15)
    # dlyap: a x a − x + q = 0 → x = q/(1 − a²).
    assert np.asarray(pl.dlyap([[0.5]], [[3.0]]))[0, 0] == pytest.approx(4.0, rel=1e-15)
    # dcgain of b/(s − a) is −b/a; of the discrete b/(z − a) it is b/(1 − a).
    assert pl.dcgain(([[-2.0]], [[1.0]], [[3.0]], [[0.0]])) == pytest.approx(1.5, rel=1e-15)
    assert pl.dcgain(([[0.5]], [[1.0]], [[1.0]], [[0.0]], 0.1)) == pytest.approx(2.0, rel=1e-15)
    # c2d zoh of ẋ = −x + u: e^{−Ts}, 1 − e^{−Ts}.
    d = pl.c2d(pl.ss([[-1.0]], [[1.0]], [[1.0]], 0), 0.1)
    assert d.A[0, 0] == pytest.approx(np.exp(-0.1), rel=1e-15)
    assert d.B[0, 0] == pytest.approx(1 - np.exp(-0.1), rel=1e-14)


def test_step_of_first_order_lag_is_closed_form():
    t = np.linspace(0, 3, 301)
    # The recursion x[k+1] = Φ x[k] + Γ accumulates about one rounding per step.
    tol = len(t) * np.finfo(float).eps * 4
    y, tt = pl.step(pl.tf([2.0], [0.5, 1.0]), t)
    np.testing.assert_allclose(y, 2 * (1 - np.exp(-t / 0.5)), rtol=0, atol=2 * tol)
    y, _ = pl.impulse(pl.tf([2.0], [0.5, 1.0]), t)
    np.testing.assert_allclose(y, 4 * np.exp(-t / 0.5), rtol=0, atol=4 * tol)


def test_a_number_T_is_the_final_time_and_none_chooses_one():
    # MATLAB's step(sys, tFinal) and python-control's T given as a number: a final time, not
    # a one-sample time vector. G = 2/(0.5 s + 1): y = 2(1 − e^{−2t}).
    g = pl.tf([2.0], [0.5, 1.0])
    tol = 1001 * np.finfo(float).eps * 8
    for T in (3.0, 3, np.float64(3.0), np.array(3.0)):
        y, t = pl.step(g, T)
        assert len(t) == 1001 and t[0] == 0.0 and t[-1] == pytest.approx(3.0, rel=1e-15)
        np.testing.assert_allclose(y, 2 * (1 - np.exp(-2 * t)), rtol=0, atol=tol)
    # python-control 0.10 ends its grid at the same final time.
    assert ct.step_response(ct.tf([2.0], [0.5, 1.0]), 3.0).time[-1] == pytest.approx(3.0)
    y, t = pl.impulse(g, 3.0)
    np.testing.assert_allclose(y, 4 * np.exp(-2 * t), rtol=0, atol=2 * tol)
    r = pl.initial(pl.ss([[-2.0]], [[1.0]], [[1.0]], 0), 3.0, [1.5])
    np.testing.assert_allclose(r.y, 1.5 * np.exp(-2 * r.t), rtol=0, atol=tol)
    # None: 7 time constants of the slowest pole (−2 → 3.5 s), within 0.1 % of the end.
    y, t = pl.step(g)
    assert t[-1] == pytest.approx(3.5, rel=1e-12) and abs(y[-1] - 2) <= 2e-3
    # A discrete system steps at its dt: y[k] = 1 − 0.5^k from x[k+1] = 0.5 x[k] + 0.5 u.
    y, t = pl.step(pl.ss([[0.5]], [[0.5]], [[1.0]], 0, 0.1), 1.0)
    np.testing.assert_allclose(t, 0.1 * np.arange(11), rtol=0, atol=1e-15)
    np.testing.assert_allclose(y, 1 - 0.5 ** np.arange(11), rtol=0, atol=1e-15)
    for bad in (0.0, -1.0, np.inf, np.nan):
        with pytest.raises(pl.InvalidArgumentError, match="final time"):
            pl.step(g, bad)


def test_lsim_split_superposes():
    # Linearity (book Part 1 §4, eq. 4.24): y = y_zi + y_zs; the three runs round on their
    # own, about one rounding per step of the recursion.
    t = np.linspace(0, 2, 201)
    u = np.sin(3 * t)
    sys = pl.ss(A4 - np.outer(B4, pl.lqr(A4, B4, np.eye(4), 1.0).K), B4, np.eye(4)[:2], 0)
    zi, zs, total = pl.lsim_split(sys, u, t, [0.1, 0.2, 0.0, -0.1])
    scale = np.abs(total.y).max()
    assert np.abs(zi.y + zs.y - total.y).max() <= 8 * len(t) * np.finfo(float).eps * scale
    np.testing.assert_array_equal(total.y, pl.lsim(sys, u, t, [0.1, 0.2, 0.0, -0.1]).y)
    assert not np.any(zi.u) and np.array_equal(zs.u.ravel(), u)


def test_results_unpack_and_carry_diagnostics():
    Q, R = np.diag([100.0, 10, 1, 1]), 1.0
    res = pl.lqr(A4, B4, Q, R)
    K, S, E = res
    assert len(res) == 3 and res[0] is not None
    assert np.array_equal(K, res.K) and np.array_equal(S, res.S) and np.array_equal(E, res.E)
    assert res.residual < 1e-12
    assert (E.real < 0).all()
    with pytest.raises(TypeError, match="holds several values"):
        np.asarray(res)
    X, L, G = pl.care(A4, B4.reshape(4, 1), Q, np.eye(1))
    np.testing.assert_array_equal(G, K)
    np.testing.assert_array_equal(X, S)
    w = pl.place(A4, B4, [-1, -2, -3, -4])
    assert np.asarray(w).shape == (1, 4) and w.max_relative_error < 1e-10
    servo = pl.lqi(pl.ss(A4, B4, [[1, 0, 0, 0]], 0), np.diag([100.0, 10, 1, 1, 50]), 1.0)
    assert servo.K.shape == (1, 5)
    np.testing.assert_array_equal(servo.K[:, :4], servo.state_gain)
    np.testing.assert_array_equal(servo.K[:, 4:], servo.integral_gain)


def test_python_control_systems_and_tuples_are_accepted():
    sys_ct = ct.ss(A4, B4.reshape(4, 1), [[1, 0, 0, 0]], 0)
    sys_pl = pl.StateSpace(sys_ct)
    assert sys_pl.nstates == 4 and sys_pl.dt == 0
    np.testing.assert_array_equal(sys_pl.A, A4)
    for s in (sys_ct, sys_pl, (A4, B4, [[1, 0, 0, 0]], 0)):
        np.testing.assert_array_equal(pl.poles(s), pl.poles(sys_pl))
    d = ct.c2d(sys_ct, 0.01)
    assert pl.StateSpace(d).dt == 0.01
    # A SISO python-control transfer function: 2/(0.5 s + 1) has DC gain 2 and a pole at −2.
    g_ct = ct.tf([2.0], [0.5, 1.0])
    assert pl.dcgain(g_ct) == pytest.approx(2.0, rel=1e-15)
    np.testing.assert_allclose(pl.poles(g_ct), [-2.0], rtol=1e-15)
    with pytest.raises(pl.ShapeError, match="single-input single-output"):
        pl.poles(ct.tf([[[1.0], [1.0]]], [[[1.0, 1.0], [1.0, 2.0]]]))
    K1, _, _ = pl.lqr(sys_ct, np.eye(4), 1.0)
    K2, _, _ = pl.lqr(A4, B4, np.eye(4), 1.0)
    np.testing.assert_array_equal(K1, K2)


def test_any_real_dtype_and_order_is_read_as_float64():
    ref = np.asarray(pl.lyap(-np.eye(3) * 2 + np.triu(np.ones((3, 3)), 1), np.eye(3)))
    a = -np.eye(3) * 2 + np.triu(np.ones((3, 3)), 1)
    for variant in (a.astype(np.float32), np.asfortranarray(a), a.astype(np.int64), a.tolist()):
        np.testing.assert_array_equal(np.asarray(pl.lyap(variant, np.eye(3, dtype=np.float32))), ref)
    big = np.zeros((6, 6))
    big[::2, ::2] = a
    np.testing.assert_array_equal(np.asarray(pl.lyap(big[::2, ::2], np.eye(3))), ref)


def test_sign_convention_u_minus_kx():
    K, _, E = pl.lqr(A4, B4, np.eye(4), 1.0)
    ev = np.linalg.eigvals(A4 - np.outer(B4, K))
    np.testing.assert_allclose(np.sort_complex(ev), np.sort_complex(E), rtol=1e-9)


@pytest.mark.parametrize(
    "call, exc, words",
    [
        (lambda: pl.lqr(np.ones((2, 3)), np.ones((2, 1)), np.eye(2), 1.0), pl.ShapeError, "A must be square"),
        (lambda: pl.lqr(A4, B4, np.eye(3), 1.0), pl.ShapeError, "Q"),
        (lambda: pl.lqr(A4, B4, np.eye(4), np.nan), pl.NotFiniteError, "R has a non-finite entry"),
        (lambda: pl.lyap([[np.inf]], [[1.0]]), pl.NotFiniteError, "A has a non-finite entry inf"),
        (lambda: pl.lqr(np.zeros((2, 2)), [[0.0], [1.0]], np.eye(2), 1.0), pl.NotStabilizableError, "not stabilisable"),
        (lambda: pl.lqr(A4, B4, -np.eye(4), 1.0), pl.InvalidArgumentError, "positive semidefinite"),
        (lambda: pl.lqr(A4, B4, np.eye(4), np.array([[1.0 + 1j]])), pl.InvalidArgumentError, "R must be real"),
        (lambda: pl.lqr(A4, B4, np.eye(4), [[1.0 + 1j]]), pl.InvalidArgumentError, "R cannot be read as a real array"),
        (lambda: pl.lqr(A4, B4, np.ones((4, 4, 1)), 1.0), pl.ShapeError, "at most 2 dimensions"),
        (lambda: pl.lyap([[1.0, 0], [0, -1]], np.eye(2)), pl.LinAlgError, "no unique solution"),
        (lambda: pl.dcgain(([[0.0]], [[1.0]], [[1.0]], [[0.0]])), pl.LinAlgError, "pole at"),
        (lambda: pl.place(np.zeros((2, 2)), [[1.0], [0.0]], [-1, -2]), pl.NotControllableError, "not controllable"),
        (lambda: pl.c2d(pl.ss([[-1.0]], [[1.0]], [[1.0]], 0), 0.1, "magic"), pl.InvalidArgumentError, "unknown discretisation"),
        (lambda: pl.lsim(pl.ss([[-1.0]], [[1.0]], [[1.0]], 0), [1.0, 1.0, 1.0], [0, 0.1, 0.3]), pl.InvalidArgumentError, "not uniformly spaced"),
        (lambda: pl.ss(np.eye(2), np.ones((3, 1)), np.ones((1, 2)), 0), pl.ShapeError, "B"),
        (lambda: pl.ss([[1.0]], [[1.0]], [[1.0]], 0, dt=-1.0), pl.InvalidArgumentError, "sample time"),
        (lambda: pl.lqr([[1.0]], [["x"]], [[1.0]], 1.0), pl.InvalidArgumentError, "B cannot be read"),
    ],
)
def test_bad_input_raises_with_the_rust_message(call, exc, words):
    with pytest.raises(exc) as info:
        call()
    assert words in str(info.value)
    assert isinstance(info.value, pl.Error) and isinstance(info.value, ValueError)


def test_numerical_failures_are_numpy_linalg_errors():
    with pytest.raises(np.linalg.LinAlgError) as info:
        pl.lqr(np.zeros((2, 2)), [[0.0], [1.0]], np.eye(2), 1.0)
    assert info.value.variant == "NotStabilizable"


def test_wrong_argument_counts_are_type_errors():
    with pytest.raises(TypeError):
        pl.lqr(A4, B4)
    with pytest.raises(TypeError):
        pl.poles("not a system")


def test_lsim_outputs_only_equals_the_full_run():
    rng = np.random.default_rng(11)
    t = np.arange(2001) * 1e-3
    for n, m, p in [(5, 1, 1), (9, 2, 2), (3, 2, 1)]:
        a = rng.standard_normal((n, n)) - 3 * np.eye(n)
        sys = pl.ss(a, rng.standard_normal((n, m)), rng.standard_normal((p, n)), rng.standard_normal((p, m)))
        u = np.sin(np.outer(t, np.arange(1, m + 1)))
        u = u[:, 0] if m == 1 else u
        x0 = rng.standard_normal(n)
        for hold in ("foh", "zoh"):
            full = pl.lsim(sys, u, t, x0, hold=hold)
            y, t_out, x = pl.lsim(sys, u, t, x0, hold=hold, return_x=False)
            assert x is None
            np.testing.assert_array_equal(y, full.y)
            np.testing.assert_array_equal(t_out, t)
    # Non-contiguous and integer inputs take the converting path, with the same result.
    sys = pl.ss([[-1.0]], [[1.0]], [[1.0]], 0)
    u = np.ones(4002)[::2]
    np.testing.assert_array_equal(pl.lsim(sys, u, t, return_x=False).y, pl.lsim(sys, u, t).y)
    np.testing.assert_array_equal(pl.lsim(sys, np.ones(2001, dtype=int), t, return_x=False).y, pl.lsim(sys, u, t).y)
    with pytest.raises(pl.NotFiniteError):
        pl.lsim(sys, np.r_[np.ones(2000), np.nan], t, return_x=False)
    with pytest.raises(pl.ShapeError):
        pl.lsim(sys, np.ones(2000), t, return_x=False)
    with pytest.raises(pl.InvalidArgumentError):
        pl.lsim(sys, np.ones(3), [0.0, 0.1, 0.3], return_x=False)
