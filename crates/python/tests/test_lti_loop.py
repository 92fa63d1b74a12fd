"""Loop analysis (``nyquist``, ``nichols``, ``rlocus``, ``rlocfind``, ``disk_margin``, ``sigma``)
against python-control 0.10.2 computed in the same run, and closed forms."""

import control as ct
import numpy as np
import pytest

import pendulab as pl

assert ct.__version__ == "0.10.2", ct.__version__

LOOPS = [
    ([2.0], [1.0, 1.0]),
    ([10.0], [1.0, 3.0, 3.0, 1.0]),  # two closed-loop RHP poles
    ([1.0], [1.0, 1.0, 0.0]),  # integrator
    ([1.0, 0.2], [1.0, 0.0, 1.0]),  # undamped pair
    ([5.0, 10.0], [1.0, 2.0, -3.0]),  # open-loop unstable, stable closed loop
    ([1.0, 1.0], [1.0, -1.0, 0.0]),
]


@pytest.mark.parametrize("num,den", LOOPS)
def test_nyquist_count_matches_python_control(num, den):
    r = pl.nyquist(pl.tf(num, den))
    ref = ct.nyquist_response(ct.tf(num, den))
    assert r.count == ref.count
    assert r.criterion_holds
    count, response, omega = r
    assert response.shape == omega.shape and omega[0] >= 0.0


def test_rlocus_matches_python_control_and_rlocfind():
    num, den = [1.0, 1.0], [1.0, 3.0, -4.0, 0.0]
    gains = np.array([0.0, 0.5, 3.0, 10.0])
    roots, k = pl.rlocus(pl.tf(num, den), gains)
    ref = ct.root_locus_map(ct.tf(num, den), gains).loci
    assert np.array_equal(k, gains)
    for ours, theirs in zip(roots, ref):
        for p in theirs:
            assert np.min(np.abs(ours - p)) < 1e-9 * max(1.0, abs(p))
    # 1/(s(s + 1)(s + 2)): break-away −1 + 1/√3, j√2 at K = 6.
    r = pl.rlocus(pl.tf([1.0], [1.0, 3.0, 2.0, 0.0]))
    assert r.break_points[0].real == pytest.approx(-1 + 1 / np.sqrt(3), abs=1e-12)
    assert r.centroid == pytest.approx(-1.0, abs=1e-14)
    f = pl.rlocfind(pl.tf([1.0], [1.0, 3.0, 2.0, 0.0]), 1j * np.sqrt(2))
    assert f.gain == pytest.approx(6.0, rel=1e-10)
    assert f.distance < 1e-8


@pytest.mark.parametrize("skew", [0.0, 0.4, -0.4])
def test_disk_margin_against_python_control_grid(skew):
    num, den = [4.0], [1.0, 3.0, 3.0, 1.0]
    m = pl.disk_margin(pl.tf(num, den), skew)
    omega = np.logspace(-3, 3, 3001)
    dm, dgm, dpm = ct.disk_margins(ct.tf(num, den), omega, skew=skew)
    # Our α is the exact peak: at most the grid minimum, and close to it on a fine grid.
    assert m.alpha <= dm * (1 + 1e-9)
    assert m.alpha >= dm * (1 - 1e-4)
    assert m.phase_margin_deg == pytest.approx(dpm, rel=1e-3)
    assert m.closed_loop_stable


def test_disk_margin_closed_form_and_unstable_loop():
    # −0.5/(s + 1): α = 2(1 + k)/(1 − k) = 2/3 at ω = 0.
    alpha, gm_db, pm = pl.disk_margin(pl.tf([-0.5], [1.0, 1.0]))
    assert alpha == pytest.approx(2.0 / 3.0, rel=1e-9)
    assert pm == pytest.approx(np.degrees(2 * np.arctan(1.0 / 3.0)), rel=1e-9)
    assert gm_db == pytest.approx(20 * np.log10(2.0), rel=1e-8)
    m = pl.disk_margin(pl.tf([0.5], [1.0, -1.0]))
    assert m.alpha == 0.0 and not m.closed_loop_stable


def test_sigma_and_nichols():
    np.random.seed(7)
    g = ct.rss(4, 2, 3)
    omega = np.logspace(-2, 2, 30)
    sv, w = pl.sigma((g.A, g.B, g.C, g.D), omega)
    ref = np.abs(np.asarray(ct.singular_values_response(g, omega).frdata))[:, 0, :]
    assert sv.shape == ref.shape == (2, 30)
    assert np.allclose(sv, ref, rtol=1e-10, atol=0)
    mag, ph, w = pl.nichols(pl.tf([1.0], [1.0, 1.0, 0.0]), [0.1, 1.0, 10.0])
    assert np.allclose(ph, -90 - np.degrees(np.arctan([0.1, 1.0, 10.0])), atol=1e-9)


def test_mimo_loop_is_rejected():
    with pytest.raises(pl.Error):
        pl.nyquist((np.array([[-1.0]]), np.array([[1.0, 1.0]]), np.array([[1.0]]), np.zeros((1, 2))))
