"""Model reduction (``stabsep``, ``hsvd``, ``balreal``, ``balred``) and ``hinfnorm`` against
NumPy and SciPy 1.16.3 computed in the same run, on systems built with a known modal split.

Each test system is ``G = G_s + G_u`` assembled from a stable part ``(A_s, B_s, C_s, D)`` and
an unstable part ``(A_u, B_u, C_u, 0)`` and then hidden by a random similarity, so the
stable part's Hankel singular values are computed by SciPy's Lyapunov solvers from
``(A_s, B_s, C_s)`` alone, independently of pendulab's Schur-based split. Frequency
responses are evaluated here by ``C (sI − A)⁻¹ B + D`` with ``numpy.linalg.solve``.
"""

import numpy as np
import pytest
import scipy
from scipy import linalg as sla

import pendulab as pl

assert scipy.__version__ == "1.16.3", scipy.__version__


def modal_system(seed, ns, nu, m=2, p=2, discrete=False):
    """``(A, B, C, D, dt)`` of ``G_s + G_u`` behind a random similarity, and the stable part
    ``(A_s, B_s, C_s, D)``, the unstable poles."""
    rng = np.random.default_rng(seed)
    if discrete:
        es = rng.uniform(-0.9, 0.9, ns)
        eu = rng.uniform(1.2, 2.0, nu) * rng.choice([-1.0, 1.0], nu)
    else:
        es = -rng.uniform(0.2, 5.0, ns)
        eu = rng.uniform(0.3, 3.0, nu)
    qs = rng.standard_normal((ns, ns)) + 3 * np.eye(ns)
    qu = rng.standard_normal((nu, nu)) + 3 * np.eye(nu)
    As = qs @ np.diag(es) @ np.linalg.inv(qs)
    Au = qu @ np.diag(eu) @ np.linalg.inv(qu)
    Bs, Bu = rng.standard_normal((ns, m)), rng.standard_normal((nu, m))
    Cs, Cu = rng.standard_normal((p, ns)), rng.standard_normal((p, nu))
    D = rng.standard_normal((p, m))
    A = sla.block_diag(As, Au)
    B = np.vstack([Bs, Bu])
    C = np.hstack([Cs, Cu])
    T = rng.standard_normal((ns + nu, ns + nu)) + 3 * np.eye(ns + nu)
    Ti = np.linalg.inv(T)
    dt = 0.1 if discrete else 0.0
    return (T @ A @ Ti, T @ B, C @ Ti, D, dt), (As, Bs, Cs, D), eu


def response(A, B, C, D, points):
    """``G(s)`` at each point (complex s or z), shape ``(len(points), p, m)``."""
    n = A.shape[0]
    return np.array([C @ np.linalg.solve(s * np.eye(n) - A, B) + D for s in points])


def grid(dt, n=4000):
    w = np.logspace(-3, 3, n)
    if dt:
        w = w[w < np.pi / dt]
        return w, np.exp(1j * w * dt)
    return w, 1j * w


def ss_tuple(s):
    return (s.A, s.B, s.C, s.D, s.dt)


def gramians(A, B, C, discrete):
    """``W_c``, ``W_o`` by SciPy's Lyapunov (Stein) solvers."""
    if discrete:
        return sla.solve_discrete_lyapunov(A, B @ B.T), sla.solve_discrete_lyapunov(A.T, C.T @ C)
    return sla.solve_continuous_lyapunov(A, -B @ B.T), sla.solve_continuous_lyapunov(A.T, -C.T @ C)


def hankel_sv(A, B, C, discrete):
    """``√λ(W_c W_o)``, descending."""
    wc, wo = gramians(A, B, C, discrete)
    ev = np.linalg.eigvals(wc @ wo).real
    return np.sort(np.sqrt(np.clip(ev, 0.0, None)))[::-1]


def sorted_eigs(a):
    return np.sort_complex(np.asarray(a, dtype=complex))


CASES = [
    (11, 5, 2, False),
    (12, 6, 1, True),
    (13, 4, 0, False),
    (14, 3, 3, False),
    (15, 5, 2, True),
]


@pytest.mark.parametrize("seed,ns,nu,discrete", CASES)
def test_stabsep_parts_sum_to_g_with_the_right_poles(seed, ns, nu, discrete):
    sys, _, eu = modal_system(seed, ns, nu, discrete=discrete)
    A, B, C, D, dt = sys
    gs, gu = pl.stabsep(sys)
    assert gs.nstates == ns and gu.nstates == nu
    assert gs.dt == dt and gu.dt == dt
    assert np.array_equal(gu.D, np.zeros_like(D))
    _, pts = grid(dt, 300)
    g = response(A, B, C, D, pts)
    parts = response(gs.A, gs.B, gs.C, gs.D, pts) + response(gu.A, gu.B, gu.C, gu.D, pts)
    assert np.max(np.abs(parts - g)) < 1e-9 * np.max(np.abs(g))
    ev = np.linalg.eigvals(A)
    stable = (np.abs(ev) < 1) if discrete else (ev.real < 0)
    assert np.allclose(sorted_eigs(np.linalg.eigvals(gs.A)), sorted_eigs(ev[stable]), rtol=1e-9, atol=1e-9)
    assert np.allclose(sorted_eigs(np.linalg.eigvals(gu.A)) if nu else [], sorted_eigs(eu), rtol=1e-9)


@pytest.mark.parametrize("seed,ns,nu,discrete", CASES)
def test_hsvd_is_inf_per_unstable_state_then_the_stable_parts(seed, ns, nu, discrete):
    sys, (As, Bs, Cs, _), _ = modal_system(seed, ns, nu, discrete=discrete)
    hsv = pl.hsvd(sys)
    assert hsv.shape == (ns + nu,)
    assert np.all(np.isinf(hsv[:nu]))
    ref = hankel_sv(As, Bs, Cs, discrete)
    # √λ(W_c W_o) resolves σᵢ only to about ε‖W_c W_o‖/σᵢ: an absolute tolerance on σ₁'s scale.
    assert np.allclose(hsv[nu:], ref, rtol=1e-8, atol=1e-9 * ref[0])


@pytest.mark.parametrize("seed,ns,nu,discrete", CASES)
def test_balreal_balances_the_stable_part(seed, ns, nu, discrete):
    sys, (As, Bs, Cs, _), eu = modal_system(seed, ns, nu, discrete=discrete)
    A, B, C, D, dt = sys
    sysb, g, T, Ti = pl.balreal(sys)
    n = ns + nu
    assert np.allclose(T @ Ti, np.eye(n), atol=1e-9)
    assert np.allclose(sysb.A, T @ A @ Ti, atol=1e-8 * np.abs(A).max())
    assert np.allclose(sysb.B, T @ B, atol=1e-9 * np.abs(B).max())
    assert np.allclose(sysb.C, C @ Ti, atol=1e-9 * np.abs(C).max())
    assert np.array_equal(sysb.D, D)
    assert np.all(np.isinf(g[:nu]))
    # The unstable block is decoupled and holds the unstable poles.
    assert np.allclose(sysb.A[nu:, :nu], 0.0) and np.allclose(sysb.A[:nu, nu:], 0.0)
    assert np.allclose(sorted_eigs(np.linalg.eigvals(sysb.A[:nu, :nu])) if nu else [], sorted_eigs(eu), rtol=1e-9)
    # Both Gramians of the stable block are diag(g) (SciPy).
    sigma = hankel_sv(As, Bs, Cs, discrete)
    for w in gramians(sysb.A[nu:, nu:], sysb.B[nu:], sysb.C[:, nu:], discrete):
        assert np.allclose(w, np.diag(sigma), atol=1e-8 * sigma[0])


def sweep_error(sys, red, dt):
    """``max_ω σ̄(G − G_r)`` over a dense NumPy grid (a lower bound of the H∞ norm)."""
    A, B, C, D, _ = sys
    _, pts = grid(dt)
    diff = response(A, B, C, D, pts) - response(red.A, red.B, red.C, red.D, pts)
    return max(np.linalg.norm(e, 2) for e in diff)


@pytest.mark.parametrize("method", ["truncate", "matchdc"])
@pytest.mark.parametrize("seed,ns,nu,discrete", CASES)
def test_balred_keeps_unstable_poles_within_the_hankel_bounds(seed, ns, nu, discrete, method):
    sys, (As, Bs, Cs, D), eu = modal_system(seed, ns, nu, discrete=discrete)
    dt = sys[4]
    sigma = hankel_sv(As, Bs, Cs, discrete)
    for keep in range(1, ns):
        r = nu + keep
        red = pl.balred(sys, r, method=method)
        assert red.nstates == r and red.dt == dt
        ev = np.linalg.eigvals(red.A)
        for p in eu:
            assert np.min(np.abs(ev - p)) < 1e-8 * abs(p)
        # G − G_r = G_s − G_{r,s}: its H∞ norm by pendulab's hinfnorm on the stable parts
        # (the difference of the unstable realisations cancels only in the transfer function).
        rs = pl.stabsep(red).stable
        n1, n2 = As.shape[0], rs.nstates
        err = (
            sla.block_diag(As, rs.A),
            np.vstack([Bs, rs.B]),
            np.hstack([Cs, -rs.C]),
            D - rs.D,
            dt,
        )
        assert n1 + n2 == ns + keep
        hinf = pl.hinfnorm(err).ninf
        sweep = sweep_error(sys, red, dt)
        lower, upper = sigma[keep], 2.0 * sigma[keep:].sum()
        # One discarded state attains the upper bound (‖G − G_r‖∞ = 2σₙ); SciPy's σ are good
        # to ~1e-9 σ₁ (see the hsvd test).
        tol = 1e-7 * hinf + 1e-9 * sigma[0]
        assert lower - tol <= hinf <= upper + tol, (keep, lower, hinf, upper)
        assert sweep <= hinf * (1 + 1e-7)
        assert sweep >= 0.99 * hinf, (sweep, hinf)
        if method == "matchdc":
            point = np.array([1.0 if discrete else 0.0])
            g0 = response(*sys[:4], point)
            r0 = response(red.A, red.B, red.C, red.D, point)
            assert np.allclose(r0, g0, atol=1e-8 * np.abs(g0).max())
        else:
            assert np.array_equal(red.D, D)


def test_balred_takes_a_list_of_orders_as_python_control():
    sys, _, _ = modal_system(21, 5, 1)
    out = pl.balred(sys, [2, 4])
    assert [s.nstates for s in out] == [2, 4]
    one = pl.balred(sys, 4)
    assert np.array_equal(out[1].A, one.A)


def test_hinfnorm_of_a_first_order_lag():
    # k/(s + a): the peak k/a at ω = 0.
    r = pl.hinfnorm(pl.tf([3.0], [1.0, 2.0]))
    ninf, fpeak = r
    assert ninf == pytest.approx(1.5, rel=1e-9)
    assert fpeak == pytest.approx(0.0, abs=1e-9)


def boundary_systems():
    return {
        "integrator": (np.diag([0.0, -1.0]), np.ones((2, 1)), np.ones((1, 2)), 0.0),
        "imaginary pair": (np.array([[0.0, 2.0], [-2.0, 0.0]]), np.ones((2, 1)), np.ones((1, 2)), 0.0),
        "unit circle": (np.diag([1.0, 0.5]), np.ones((2, 1)), np.ones((1, 2)), 0.0, 0.1),
    }


@pytest.mark.parametrize("name", list(boundary_systems()))
def test_boundary_eigenvalues_are_refused_by_name(name):
    sys = boundary_systems()[name]
    for f in (pl.stabsep, pl.hsvd, pl.balreal, lambda s: pl.balred(s, 1)):
        with pytest.raises(pl.InvalidArgumentError, match="stability boundary"):
            f(sys)


def test_bad_orders_methods_and_data_raise_typed_errors():
    sys, _, _ = modal_system(31, 4, 2)
    with pytest.raises(pl.InvalidArgumentError, match="exceeds the system's 6 states"):
        pl.balred(sys, 7)
    with pytest.raises(pl.InvalidArgumentError, match="below the system's 2 unstable states"):
        pl.balred(sys, 1)
    with pytest.raises(pl.InvalidArgumentError, match="balred method"):
        pl.balred(sys, 3, method="hankel")
    with pytest.raises(pl.InvalidArgumentError, match="orders"):
        pl.balred(sys, "three")
    with pytest.raises(pl.InvalidArgumentError, match="orders"):
        pl.balred(sys, -1)
    A = np.array(sys[0])
    A[1, 2] = np.nan
    with pytest.raises(pl.NotFiniteError, match="A"):
        pl.hsvd((A, sys[1], sys[2], sys[3]))
    with pytest.raises(pl.InvalidArgumentError, match="tolerance"):
        pl.hinfnorm(sys, tol=2.0)
    # A non-minimal realisation: balreal refuses it (a zero Hankel singular value).
    A2 = np.diag([-1.0, -2.0])
    with pytest.raises(pl.LinAlgError, match="not minimal"):
        pl.balreal((A2, np.array([[1.0], [0.0]]), np.array([[1.0, 1.0]]), 0.0))
