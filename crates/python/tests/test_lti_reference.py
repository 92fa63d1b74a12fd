"""pendulab's LTI functions against SciPy 1.16.3 and python-control 0.10.2, computed in the
same run, on 200 random systems of sizes 1–60 each (``conftest.sizes``).

Tolerances are relative to each problem's conditioning, from first-order perturbation
theory for a backward-stable solver (backward error ``c·n·ε`` times the equation's terms),
with ``c = 1000`` for the constant neither bound states; both the reference and pendulab
carry an error of that size:

- Lyapunov / Riccati: ``‖X − X_ref‖ ≤ c·n·ε·‖L⁻¹‖·Σ‖terms‖``, where ``L`` is the
  (closed-loop) Lyapunov or Stein operator. For a stable ``F``, ``‖L⁻¹‖₂`` over symmetric
  matrices equals ``‖L⁻¹(I)‖₂`` (``L⁻¹`` is a positive map), computed here by SciPy.
- eigenvalues (``place``): Bauer–Fike, ``|δλ| ≤ cond(V)·‖δM‖``; the gain is formed from the
  eigenvector matrix (``K = Z⁻¹U₀ᵀ(A − VΛV⁻¹)``), so ``‖δM‖ = ‖B‖‖δK‖`` carries a second
  ``cond(V)``: ``|δλ| ≤ c·n·ε·cond(V)²·(‖A‖ + ‖B‖‖K‖)``.
- ``c2d``: ``c·n·ε·(1 + ‖A Ts‖)·e^{‖A Ts‖}`` (the block exponential's rounding).
- time responses: ``c·len·ε·max|y|`` (rounding accumulated over the recursion of a stable
  system).
- frequency responses: ``c·n·ε·κ₂(jωI − A)`` relative to ``‖C‖‖(jωI − A)⁻¹B‖ + ‖D‖``.
"""

import control as ct
import numpy as np
import pytest
import scipy
import scipy.linalg as sl
import scipy.signal as ss
from scipy.optimize import linear_sum_assignment

import pendulab as pl
from conftest import EPS, psd_weights, sizes, stable_matrix

C = 1e3

assert scipy.__version__ == "1.16.3", scipy.__version__
assert ct.__version__ == "0.10.2", ct.__version__


def norm2(m):
    return np.linalg.norm(m, 2) if np.size(m) else 0.0


def inputs(rng, n):
    """1–4 inputs (outputs) for responses and discretisation."""
    return int(rng.integers(1, min(n, 4) + 1))


def design_inputs(rng, n):
    """n/4 to n/2 inputs (at least one): enough actuation for the design problems to stay
    well-conditioned at every size, so that both solvers answer."""
    return int(rng.integers(max(1, n // 4), max(1, n // 2) + 1))


def riccati_tolerance(a, b, q, r, x, gain, discrete):
    """Relative forward-error bound of a Riccati solution (module docstring)."""
    n = a.shape[0]
    acl = a - b @ gain
    if discrete:
        y = sl.solve_discrete_lyapunov(acl.T, np.eye(n))
        terms = norm2(a) ** 2 * norm2(x) + norm2(x) + norm2(q) + norm2(b) ** 2 * norm2(x) * norm2(gain)
    else:
        y = sl.solve_continuous_lyapunov(acl.T, -np.eye(n))
        g = b @ np.linalg.solve(r, b.T)
        terms = 2 * norm2(a) * norm2(x) + norm2(q) + norm2(x) ** 2 * norm2(g)
    return C * n * EPS * norm2(y) * terms / max(norm2(x), 1e-300)


def relerr(x, ref):
    return np.linalg.norm(x - ref) / max(np.linalg.norm(ref), 1e-300)


@pytest.mark.parametrize("discrete", [False, True], ids=["care", "dare"])
def test_riccati_with_cross_term_against_scipy(discrete):
    rng = np.random.default_rng(1 + discrete)
    for k, n in enumerate(sizes(10 + discrete)):
        m = design_inputs(rng, n)
        a = stable_matrix(rng, n, margin=-0.5, discrete=discrete)
        b = rng.standard_normal((n, m))
        q, r, nn = psd_weights(rng, n, m, cross=k % 2 == 0)
        solve = pl.dare if discrete else pl.care
        ref = sl.solve_discrete_are if discrete else sl.solve_continuous_are
        res = solve(a, b, q, r, nn)
        x_ref = ref(a, b, q, r, s=nn)
        if discrete:
            g_ref = np.linalg.solve(b.T @ x_ref @ b + r, b.T @ x_ref @ a + (0 if nn is None else nn.T))
        else:
            g_ref = np.linalg.solve(r, b.T @ x_ref + (0 if nn is None else nn.T))
        tol = riccati_tolerance(a, b, q, r, x_ref, g_ref, discrete)
        x, poles, g = res
        assert relerr(x, x_ref) <= tol, (k, n, m, relerr(x, x_ref), tol)
        gain_tol = tol * (1 + norm2(b) * norm2(x_ref) / max(norm2(r), 1e-300)) * norm2(x_ref) / max(norm2(g_ref), 1e-300)
        assert relerr(g, g_ref) <= gain_tol, (k, n, relerr(g, g_ref), gain_tol)
        stab = np.abs(poles) < 1 if discrete else poles.real < 0
        assert stab.all()


@pytest.mark.parametrize("discrete", [False, True], ids=["lqr", "dlqr"])
def test_lqr_against_python_control(discrete):
    rng = np.random.default_rng(3 + discrete)
    for k, n in enumerate(sizes(20 + discrete)):
        m = design_inputs(rng, n)
        a = stable_matrix(rng, n, margin=-0.5, discrete=discrete)
        b = rng.standard_normal((n, m))
        q, r, nn = psd_weights(rng, n, m, cross=discrete or k % 2 == 0)
        if discrete:
            K, S, E = pl.dlqr(a, b, q, r, nn)
            K_ref, S_ref, E_ref = ct.dlqr(a, b, q, r, nn)
        else:
            args = (a, b, q, r) if nn is None else (a, b, q, r, nn)
            K, S, E = pl.lqr(*args)
            K_ref, S_ref, E_ref = ct.lqr(*args)
        tol = riccati_tolerance(a, b, q, r, S_ref, K_ref, discrete)
        assert relerr(S, S_ref) <= tol, (k, n, relerr(S, S_ref), tol)
        gain_tol = tol * (1 + norm2(b) * norm2(S_ref) / norm2(r)) * norm2(S_ref) / max(norm2(K_ref), 1e-300)
        assert relerr(K, K_ref) <= gain_tol, (k, n, relerr(K, K_ref), gain_tol)
        # Closed-loop poles: the eigenvalues of A − BK as NumPy computes them (Bauer–Fike).
        ev, v = np.linalg.eig(a - b @ K)
        i, j = linear_sum_assignment(np.abs(ev[:, None] - E[None, :]))
        ev_tol = C * n * EPS * np.linalg.cond(v) * (norm2(a) + norm2(b) * norm2(K))
        assert np.max(np.abs(ev[i] - E[j])) <= ev_tol, (k, n)


@pytest.mark.parametrize("discrete", [False, True], ids=["lyap", "dlyap"])
def test_lyapunov_against_scipy(discrete):
    rng = np.random.default_rng(5 + discrete)
    for k, n in enumerate(sizes(30 + discrete)):
        a = stable_matrix(rng, n, discrete=discrete)
        w = rng.standard_normal((n, n))
        q = w @ w.T
        if discrete:
            res = pl.dlyap(a, q)
            x_ref = sl.solve_discrete_lyapunov(a, q)
            y = sl.solve_discrete_lyapunov(a, np.eye(n))
            terms = norm2(a) ** 2 * norm2(x_ref) + norm2(x_ref) + norm2(q)
        else:
            res = pl.lyap(a, q)
            x_ref = sl.solve_continuous_lyapunov(a, -q)
            y = sl.solve_continuous_lyapunov(a, -np.eye(n))
            terms = 2 * norm2(a) * norm2(x_ref) + norm2(q)
        tol = C * n * EPS * norm2(y) * terms / norm2(x_ref)
        x = np.asarray(res)
        assert relerr(x, x_ref) <= tol, (k, n, relerr(x, x_ref), tol)


def place_problem(rng, n, m):
    a = rng.standard_normal((n, n)) / np.sqrt(n)
    b = rng.standard_normal((n, m))
    npairs = int(rng.integers(0, n // 2 + 1))
    re = -rng.uniform(0.5, 3.0, n - npairs)
    pairs = -rng.uniform(0.5, 3.0, npairs) + 1j * rng.uniform(0.1, 2.0, npairs)
    return a, b, np.concatenate([re[: n - 2 * npairs], pairs, pairs.conj()])


def test_place_achieves_the_requested_poles():
    """Sizes 1–20 (pendulab-lti's KNV sweeps take seconds per system beyond n ≈ 40)."""
    rng = np.random.default_rng(7)
    for k, n in enumerate(sizes(40, largest=20)):
        # Enough inputs (n/3 to n − 1) for the assignment to be well-posed.
        m = int(rng.integers(max(1, n // 3), max(n // 3, n - 1) + 1)) if n > 1 else 1
        a, b, p = place_problem(rng, n, m)
        res = pl.place(a, b, p)
        K = np.asarray(res)
        acl = a - b @ K
        ev, v = np.linalg.eig(acl)
        i, j = linear_sum_assignment(np.abs(ev[:, None] - p[None, :]))
        err = np.abs(ev[i] - p[j])
        tol = C * n * EPS * np.linalg.cond(v) ** 2 * (norm2(a) + norm2(b) * norm2(K))
        assert err.max() <= tol, (k, n, m, err.max(), tol)
        if m == 1 and n <= 8:
            # Single input: the gain is unique, so python-control's (SciPy's) must agree.
            K_ref = ct.place(a, b, p)
            assert relerr(K, K_ref) <= tol * np.linalg.cond(ct.ctrb(a, b)), (k, n)


def test_place_with_square_b_and_complex_poles():
    # Closed form: with B = I any K = A − M assigns eig(M); M = [[-1, 1], [-1, -1]] has -1 ± j.
    a, b, p = np.zeros((2, 2)), np.eye(2), np.array([-1 + 1j, -1 - 1j])
    assert np.allclose(np.sort_complex(np.linalg.eigvals([[-1, 1], [-1, -1]])), np.sort_complex(p))
    K = np.asarray(pl.place(a, b, p))
    assert np.allclose(np.sort_complex(np.linalg.eigvals(a - b @ K)), np.sort_complex(p))


@pytest.mark.parametrize("method", ["zoh", "foh", "tustin"])
def test_c2d_against_scipy(method):
    rng = np.random.default_rng({"zoh": 51, "foh": 52, "tustin": 53}[method])
    for k, n in enumerate(sizes(50)):
        m, p = inputs(rng, n), inputs(rng, n)
        a = rng.standard_normal((n, n)) / np.sqrt(n)
        b = rng.standard_normal((n, m))
        c = rng.standard_normal((p, n))
        d = rng.standard_normal((p, m))
        ts = float(rng.uniform(0.01, 0.5))
        sysd = pl.c2d(pl.ss(a, b, c, d), ts, method)
        ad, bd, cd, dd, _ = ss.cont2discrete((a, b, c, d), ts, method="bilinear" if method == "tustin" else method)
        at = norm2(a) * ts
        tol = C * n * EPS * (1 + at) * np.exp(at)
        if method == "foh":
            # Realisations may differ; the transfer function may not: compare G(z) on the
            # unit circle.
            z = np.exp(1j * np.linspace(0.1, 3.0, 7))
            for zk in z:
                g = sysd.C @ np.linalg.solve(zk * np.eye(n) - sysd.A, sysd.B) + sysd.D
                g_ref = cd @ np.linalg.solve(zk * np.eye(n) - ad, bd) + dd
                kap = np.linalg.cond(zk * np.eye(n) - ad)
                assert relerr(g, g_ref) <= tol * kap, (k, n, relerr(g, g_ref), tol * kap)
        else:
            for x, ref in ((sysd.A, ad), (sysd.B, bd), (sysd.C, cd), (sysd.D, dd)):
                assert np.linalg.norm(x - ref) <= tol * max(1.0, np.linalg.norm(ref)), (k, n, method)
        assert sysd.dt == ts


@pytest.mark.parametrize("hold", ["foh", "zoh"])
def test_lsim_against_scipy(hold):
    rng = np.random.default_rng(11 + (hold == "zoh"))
    for k, n in enumerate(sizes(60 + (hold == "zoh"))):
        m, p = inputs(rng, n), inputs(rng, n)
        a = stable_matrix(rng, n)
        b = rng.standard_normal((n, m))
        c = rng.standard_normal((p, n))
        d = rng.standard_normal((p, m))
        t = np.linspace(0, 5, 101)
        u = rng.standard_normal((101, m))
        x0 = rng.standard_normal(n)
        y, tt, x = pl.lsim((a, b, c, d), u, t, x0, hold=hold)
        _, y_ref, x_ref = ss.lsim((a, b, c, d), u, t, X0=x0, interp=hold == "foh")
        y_ref = y_ref.reshape(len(t), -1) if p > 1 else y_ref.reshape(-1)
        scale = max(np.abs(y_ref).max(), 1.0)
        tol = C * len(t) * EPS * (1 + norm2(a) * 0.05) * scale
        assert np.abs(y - y_ref).max() <= tol, (k, n, np.abs(y - y_ref).max(), tol)
        assert np.abs(x - x_ref.reshape(len(t), n)).max() <= tol * max(1.0, np.abs(x_ref).max()) / scale
        assert np.array_equal(tt, t)


def test_step_against_python_control():
    rng = np.random.default_rng(13)
    for k, n in enumerate(sizes(70)):
        m, p = inputs(rng, n), inputs(rng, n)
        a = stable_matrix(rng, n)
        b = rng.standard_normal((n, m))
        c = rng.standard_normal((p, n))
        d = rng.standard_normal((p, m))
        t = np.linspace(0, 5, 51)
        y, _ = pl.step((a, b, c, d), t)
        ref = ct.step_response(ct.ss(a, b, c, d), t, squeeze=False).outputs  # (p, m, len)
        y3 = np.reshape(y, (len(t), p, m))
        scale = max(np.abs(ref).max(), 1.0)
        tol = C * len(t) * EPS * (1 + norm2(a) * 0.1) * scale
        assert np.abs(y3 - ref.transpose(2, 0, 1)).max() <= tol, (k, n)


def test_freqresp_against_python_control():
    rng = np.random.default_rng(17)
    for k, n in enumerate(sizes(80)):
        m, p = inputs(rng, n), inputs(rng, n)
        a = stable_matrix(rng, n)
        b = rng.standard_normal((n, m))
        c = rng.standard_normal((p, n))
        d = rng.standard_normal((p, m))
        w = np.logspace(-2, 2, 9)
        g, omega = pl.freqresp((a, b, c, d), w)
        g3 = np.reshape(g, (p, m, len(w)))
        ref = ct.ss(a, b, c, d)(1j * w, squeeze=False)  # (p, m, len)
        for i, wi in enumerate(w):
            r = 1j * wi * np.eye(n) - a
            kap = np.linalg.cond(r)
            size = norm2(c) * norm2(np.linalg.solve(r, b)) + norm2(d)
            err = norm2(g3[:, :, i] - ref[:, :, i])
            assert err <= C * n * EPS * kap * size, (k, n, wi, err)
        assert np.array_equal(omega, w)
