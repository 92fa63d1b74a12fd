"""``mu_diag_complex`` and ``disk_margin_mimo`` against brute-force NumPy/SciPy computations in
the same run: for 2 × 2 matrices ``μ`` for diagonal complex ``Δ`` equals both
``min_d σ̄(diag(1, d) M diag(1, 1/d))`` (the D-scaled bound is exact for two blocks; Doyle
1982) and ``max_θ ρ(diag(1, e^{jθ}) M)`` (the lower bound's maximum is ``μ``), each computed
here by a fine grid refined with ``scipy.optimize.minimize_scalar``. Disk margins: a 1 × 1 loop
is the SISO ``disk_margin``, a diagonal loop's multi-loop margin the smaller SISO one, and the
spinning satellite (Doyle's ``a = 10`` example, as in lti's Rust tests) against a frequency
sweep of the brute-force ``μ`` of ``S + (σ − 1)/2·I``.
"""

import numpy as np
import pytest
import scipy
from scipy import optimize

import pendulab as pl

assert scipy.__version__ == "1.16.3", scipy.__version__


def mu_upper_brute(m, grid=np.linspace(-12.0, 12.0, 481)):
    """``min_x σ̄(diag(1, eˣ) M diag(1, e⁻ˣ))``: a grid over x, refined (convex in x)."""

    def f(x):
        s = np.array([[m[0, 0], m[0, 1] * np.exp(-x)], [m[1, 0] * np.exp(x), m[1, 1]]])
        return np.linalg.norm(s, 2)

    vals = [f(x) for x in grid]
    k = int(np.argmin(vals))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    r = optimize.minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": 1e-12})
    return min(r.fun, vals[k])


def mu_lower_brute(m, grid=np.linspace(0.0, 2 * np.pi, 721)):
    """``max_θ ρ(diag(1, e^{jθ}) M)``: a grid over θ, refined."""

    def f(t):
        q = np.diag([1.0, np.exp(1j * t)])
        return np.max(np.abs(np.linalg.eigvals(q @ m)))

    vals = [f(t) for t in grid]
    k = int(np.argmax(vals))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    r = optimize.minimize_scalar(lambda t: -f(t), bounds=(lo, hi), method="bounded", options={"xatol": 1e-12})
    return max(-r.fun, vals[k])


def test_mu_of_a_scalar_is_its_modulus():
    r = pl.mu_diag_complex([[3.0 - 4.0j]])
    upper, lower = r
    assert upper == lower == 5.0
    assert list(r.d_scaling) == [1.0]


@pytest.mark.parametrize("seed", range(8))
def test_mu_2x2_equals_the_brute_force_value(seed):
    rng = np.random.default_rng(seed)
    m = rng.standard_normal((2, 2)) + 1j * rng.standard_normal((2, 2))
    m[0, 1] *= 10.0 ** rng.uniform(-2, 2)
    r = pl.mu_diag_complex(m)
    up, lo = mu_upper_brute(m), mu_lower_brute(m)
    assert abs(up - lo) <= 1e-6 * up  # the two brute-force values agree: both are μ
    assert r.lower <= r.upper
    assert r.upper == pytest.approx(up, rel=1e-7)
    assert r.lower == pytest.approx(lo, rel=1e-6)
    # The reported scaling attains the reported upper bound.
    d = r.d_scaling
    assert np.linalg.norm(np.diag(d) @ m @ np.diag(1 / d), 2) == pytest.approx(r.upper, rel=1e-12)


def test_mu_of_a_diagonal_matrix_and_a_real_input():
    r = pl.mu_diag_complex(np.diag([2.0, -7.0, 0.5]))
    assert r.upper == pytest.approx(7.0, rel=1e-12)
    assert r.lower == pytest.approx(7.0, rel=1e-12)


def test_mu_bad_input_raises_typed_errors():
    with pytest.raises(pl.ShapeError, match="M"):
        pl.mu_diag_complex(np.ones((2, 3)))
    with pytest.raises(pl.ShapeError, match="2-d"):
        pl.mu_diag_complex(np.ones((2, 2, 2)))
    with pytest.raises(pl.NotFiniteError, match="M"):
        pl.mu_diag_complex([[1.0, np.nan], [0.0, 1.0]])
    with pytest.raises(pl.InvalidArgumentError, match="M"):
        pl.mu_diag_complex([["a", "b"], ["c", "d"]])


def siso_loops():
    return [
        pl.tf([2.0], [1.0, 1.0]),
        pl.tf([1.0, 0.2], [1.0, 1.0, 1.0]),
        pl.tf([5.0, 10.0], [1.0, 2.0, -3.0]),  # open-loop unstable, stable closed loop
        pl.tf([0.5], [1.0, -0.5], dt=0.1),
    ]


@pytest.mark.parametrize("k", range(4))
@pytest.mark.parametrize("skew", [0.0, 0.5, -0.5])
def test_a_1x1_loop_is_the_siso_disk_margin(k, skew):
    l = siso_loops()[k]
    siso = pl.disk_margin(l, skew)
    dm, mm = pl.disk_margin_mimo(l, skew)
    assert len(dm) == 1
    assert dm[0].alpha == pytest.approx(siso.alpha, rel=1e-12)
    assert dm[0].frequency == pytest.approx(siso.frequency, rel=1e-9)
    # The multi-loop margin of one channel is the same disk, located on a grid and refined.
    assert mm.alpha == pytest.approx(siso.alpha, rel=1e-6)
    lo, hi = pl.disk_margin_mimo(l, skew).alpha_bounds
    assert lo <= siso.alpha * (1 + 1e-6) and hi >= siso.alpha * (1 - 1e-6)


def block_diag_ss(a, b):
    sa, sb = pl.ss(a), pl.ss(b)
    na, nb = sa.nstates, sb.nstates
    z = lambda r, c: np.zeros((r, c))
    A = np.block([[sa.A, z(na, nb)], [z(nb, na), sb.A]])
    B = np.block([[sa.B, z(na, 1)], [z(nb, 1), sb.B]])
    C = np.block([[sa.C, z(1, nb)], [z(1, na), sb.C]])
    D = np.diag([sa.D[0, 0], sb.D[0, 0]])
    return (A, B, C, D, sa.dt)


@pytest.mark.parametrize("pair", [(0, 1), (1, 2), (0, 2)])
def test_a_diagonal_loops_multi_loop_margin_is_the_smaller_siso_one(pair):
    loops = siso_loops()
    l1, l2 = loops[pair[0]], loops[pair[1]]
    a1, a2 = pl.disk_margin(l1).alpha, pl.disk_margin(l2).alpha
    r = pl.disk_margin_mimo(block_diag_ss(l1, l2))
    assert r.closed_loop_stable
    assert [m.alpha for m in r.loop_at_a_time] == pytest.approx([a1, a2], rel=1e-9)
    assert r.multi_loop.alpha == pytest.approx(min(a1, a2), rel=1e-6)


A_SAT = 10.0


def satellite():
    """P = 1/(s² + a²) [[s − a², a(s + 1)], [−a(s + 1), s − a²]] with K = I."""
    a = A_SAT
    return (np.array([[0.0, a], [-a, 0.0]]), np.eye(2), np.array([[1.0, a], [-a, 1.0]]), np.zeros((2, 2)))


def satellite_s_sigma(w, skew):
    """``S + (σ − 1)/2·I`` at jω from the transfer-function entries, ``L = N/den``:
    ``S = den (den I + N)⁻¹``."""
    a, s = A_SAT, 1j * w
    den = s * s + a * a
    n = np.array([[s - a * a, a * (s + 1)], [-a * (s + 1), s - a * a]])
    return den * np.linalg.inv(den * np.eye(2) + n) + 0.5 * (skew - 1.0) * np.eye(2)


@pytest.mark.parametrize("skew", [0.0, 0.5])
def test_spinning_satellite_against_a_brute_force_mu_sweep(skew):
    r = pl.disk_margin_mimo(satellite(), skew)
    assert r.closed_loop_stable
    # sup_ω μ(S_σ(jω)) by a log sweep, refined around its largest value.
    logw = np.linspace(-3.0, 3.0, 1200)  # misses ω = a, where S is 0/0 (a cancelled pole)
    mus = [mu_upper_brute(satellite_s_sigma(10**x, skew), np.linspace(-6, 6, 97)) for x in logw]
    k = int(np.argmax(mus))
    ref = optimize.minimize_scalar(
        lambda x: -mu_upper_brute(satellite_s_sigma(10**x, skew)),
        bounds=(logw[max(k - 1, 0)], logw[min(k + 1, len(logw) - 1)]),
        method="bounded",
        options={"xatol": 1e-10},
    )
    mu_peak, w_peak = -ref.fun, 10**ref.x
    assert r.multi_loop.alpha == pytest.approx(1.0 / mu_peak, rel=1e-6)
    assert r.peak_frequency == pytest.approx(w_peak, rel=1e-3)
    lo, hi = r.alpha_bounds
    assert lo <= 1.0 / mu_peak * (1 + 1e-6) and hi >= 1.0 / mu_peak * (1 - 1e-6)
    assert r.mu_peak.upper == pytest.approx(mu_peak, rel=1e-6)
    # Loop at a time: 1/max_ω |S_ii + (σ − 1)/2| over a dense sweep (up to ω = ∞: S → I).
    w = np.logspace(-3, 4, 20001)
    for i in range(2):
        peak = max(max(abs(satellite_s_sigma(x, skew)[i, i]) for x in w), abs(1 + 0.5 * (skew - 1)))
        assert r.loop_at_a_time[i].alpha == pytest.approx(1.0 / peak, rel=1e-6)
    # The coupled loop is far less robust than each channel alone.
    assert r.multi_loop.alpha < 0.1 * min(m.alpha for m in r.loop_at_a_time)


def test_an_unstable_closed_loop_has_zero_margins():
    # L = −2 I/(s + 1): 1 + L has a zero at s = 1.
    l = (-np.eye(2), np.eye(2), -2.0 * np.eye(2), np.zeros((2, 2)))
    r = pl.disk_margin_mimo(l)
    assert not r.closed_loop_stable
    assert r.multi_loop.alpha == 0.0
    assert [m.alpha for m in r.loop_at_a_time] == [0.0, 0.0]
    assert np.isnan(r.peak_frequency)


def test_disk_margin_mimo_bad_input_raises_typed_errors():
    with pytest.raises(pl.ShapeError, match="disk_margin_mimo"):
        pl.disk_margin_mimo((-np.eye(2), np.ones((2, 1)), np.eye(2), np.zeros((2, 1))))
    with pytest.raises(pl.InvalidArgumentError, match="skew"):
        pl.disk_margin_mimo(satellite(), float("nan"))
    a = satellite()[0].copy()
    a[0, 1] = np.inf
    with pytest.raises(pl.NotFiniteError, match="A"):
        pl.disk_margin_mimo((a, *satellite()[1:]))
    # I + D singular: the loop is ill-posed.
    with pytest.raises(pl.LinAlgError):
        pl.disk_margin_mimo((-np.eye(2), np.eye(2), np.eye(2), -np.eye(2)))
