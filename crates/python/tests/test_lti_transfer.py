"""pendulab.pade / thiran / TransferMatrix / c2d('matched', 'impulse') against python-control
0.10.2 and SciPy 1.16.3 run in the same process."""

import numpy as np
import pytest

import pendulab as pl

control = pytest.importorskip("control")
signal = pytest.importorskip("scipy.signal")

G_NUM = [[[1.0], [2.0, 1.0]], [[1.0, 3.0], [0.5]]]
G_DEN = [[[1.0, 1.0], [1.0, 2.0, 5.0]], [[1.0, 4.0], [1.0, 0.5]]]
H_NUM = [[[3.0, 0.0], [1.0]], [[-1.0], [2.0, 1.0, 1.0]]]
H_DEN = [[[1.0, 2.0], [1.0, 3.0]], [[1.0, 1.0, 4.0], [1.0, 6.0, 2.0]]]
POINTS = [0.3j, 2.0j, 0.4 + 1.1j]


def as_matrix(v, shape):
    return np.asarray(v, dtype=complex).reshape(shape)


def test_pade_matches_python_control():
    for T, n in [(0.1, 1), (0.5, 3), (1.5, 6)]:
        num, den = pl.pade(T, n)
        cnum, cden = control.pade(T, n)
        np.testing.assert_allclose(num, cnum, rtol=1e-13)
        np.testing.assert_allclose(den, cden, rtol=1e-13)
    with pytest.raises(pl.InvalidArgumentError):
        pl.pade(-1.0, 2)
    with pytest.raises(pl.InvalidArgumentError):
        pl.pade(1.0, 0)


def test_thiran_group_delay_at_dc():
    g = pl.thiran(0.0057, 0.002)
    b, a = g.num, g.den
    pad = len(a) - len(b)
    kb = np.arange(pad, pad + len(b))
    ka = np.arange(len(a))
    delay = (kb @ b) / b.sum() - (ka @ a) / a.sum()
    assert abs(delay - 2.85) < 1e-10
    assert g.dt == 0.002


def test_transfer_matrix_arithmetic_matches_python_control():
    g, h = pl.tf(G_NUM, G_DEN), pl.tf(H_NUM, H_DEN)
    assert isinstance(g, pl.TransferMatrix) and g.shape == (2, 2)
    cg, ch = control.tf(G_NUM, G_DEN), control.tf(H_NUM, H_DEN)
    for ours, theirs in [(g + h, cg + ch), (g - h, cg - ch), (g * h, cg * ch), (-g, -cg), (2.0 * g, 2.0 * cg)]:
        for s in POINTS:
            np.testing.assert_allclose(ours(s), as_matrix(theirs(s), (2, 2)), rtol=1e-10, atol=1e-12)
    with pytest.raises(pl.ShapeError):
        g * pl.TransferMatrix([[[1.0], [1.0], [1.0]]], [[[1.0], [1.0], [1.0]]])


def test_feedback_and_minimal_realisation():
    rng = np.random.default_rng(7)
    a = rng.standard_normal((4, 4))
    a -= (max(np.linalg.eigvals(a).real) + 1.0) * np.eye(4)
    b, c = rng.standard_normal((4, 2)), rng.standard_normal((2, 4))
    k = np.array([[0.5, 0.1], [-0.2, 0.8]])
    p = pl.tf(pl.ss(a, b, c, np.zeros((2, 2))))
    assert isinstance(p, pl.TransferMatrix)
    cl = p.feedback(pl.TransferMatrix([[[0.5], [0.1]], [[-0.2], [0.8]]], [[[1.0], [1.0]], [[1.0], [1.0]]]))
    theirs = control.feedback(control.ss(a, b, c, 0), control.ss([], [], [], k))
    for s in POINTS:
        np.testing.assert_allclose(cl(s), as_matrix(theirs(s), (2, 2)), rtol=1e-9)
    assert p.to_ss().nstates == 4
    # McMillan degree of [[1/(s+1), 2/(s+1)], [3/(s+1), 6/(s+1)]] is 1 (rank-one residue).
    one = pl.tf([[[1.0], [2.0]], [[3.0], [6.0]]], [[[1.0, 1.0]] * 2] * 2)
    assert one.to_ss().nstates == 1
    # pendulab functions accept a TransferMatrix as a system.
    assert len(pl.poles(one)) == 1


def test_c2d_matched_and_impulse():
    g = pl.tf([1.0, 2.0], [1.0, 3.0])
    gd = pl.c2d(g, 0.1, "matched")
    cd = control.sample_system(control.tf([1.0, 2.0], [1.0, 3.0]), 0.1, method="matched")
    np.testing.assert_allclose(gd.num, cd.num[0][0], rtol=1e-12)
    np.testing.assert_allclose(gd.den, cd.den[0][0], rtol=1e-12)
    a = np.array([[0.0, 1.0], [-2.0, -3.0]])
    b = np.array([[0.0], [1.0]])
    c = np.array([[1.0, 0.5]])
    sd = pl.c2d(pl.ss(a, b, c, 0.0), 0.05, "impulse")
    ad, bd, cdm, dd, _ = signal.cont2discrete((a, b, c, np.zeros((1, 1))), 0.05, method="impulse")
    for ours, theirs in [(sd.A, ad), (sd.B, bd), (sd.C, cdm), (sd.D, dd)]:
        np.testing.assert_allclose(ours, theirs, rtol=1e-12, atol=1e-15)
    with pytest.raises(pl.InvalidArgumentError):
        pl.c2d(pl.ss(a, b, c, 1.0), 0.05, "impulse")


def test_a_negative_count_is_an_invalid_argument_naming_it():
    """Count arguments (orders, horizons, numbers of envs or threads) refuse a negative integer
    with pendulab.InvalidArgumentError, the argument named in the error's note, instead of
    the OverflowError of an unsigned conversion; a float stays a TypeError; NumPy integers and
    None (where allowed) are accepted."""
    import pendulab.gym
    import pendulab.ident

    P = pl.ss(np.zeros((1, 1)), np.ones((1, 2)), np.ones((2, 1)), np.zeros((2, 2)))
    u = np.sin(np.arange(50.0))
    y = np.cos(np.arange(50.0))
    cases = [
        (lambda: pl.pade(0.1, -1), "n"),
        (lambda: pl.pade(0.1, np.int64(-3)), "n"),
        (lambda: pl.thiran(0.1, 0.05, -2), "order"),
        (lambda: pl.hinfsyn(P, -1, 1), "nmeas"),
        (lambda: pl.h2syn(P, 1, -1), "ncon"),
        (lambda: pendulab.ident.arx(u, y, 0.1, na=-1, nb=1), "na"),
        (lambda: pendulab.ident.moesp(u, y, 0.1, horizon=-4), "horizon"),
        (lambda: pendulab.gym.CartPoleVectorEnv(num_envs=-2), None),
    ]
    for call, name in cases:
        with pytest.raises(pl.InvalidArgumentError, match=r"expected an integer ≥ 0, got -\d") as e:
            call()
        if name is not None:
            assert f"while processing '{name}'" in getattr(e.value, "__notes__", []), e.value
    with pytest.raises(TypeError):
        pl.pade(0.1, 1.5)
    num, den = pl.pade(0.1, np.int64(2))
    assert np.allclose(num, [1.0, -60.0, 1200.0]) and np.allclose(den, [1.0, 60.0, 1200.0])
    # thiran with order None chooses the order: a 2-sample delay is z⁻².
    assert np.allclose(pl.thiran(0.1, 0.05, None).den, [1.0, 0.0, 0.0])
