"""Studies on the local backend (``pendulab.study``, ``docs/studies.md``): the grid's initial
states against ``numpy.meshgrid``, chunking invariance, the cart's odd symmetry of the region
of attraction, the counter-based draws against their distributions' moments, a Monte Carlo
sample with a point distribution against ``pendulab.plants.simulate``, resume from the
chunk cache, bad input, and the figures."""

import math
import os

import numpy as np
import pytest

import pendulab as pl
from pendulab import plants, study
from test_batch import lqr_gain  # the LQR gain of pendulab bench sim-batch

GRID = {"theta": (-1.2, 1.2, 9), "dtheta": (-3.0, 3.0, 7)}
BOOK_K = {"kind": "state-feedback", "k_book": [3.16228, 13.47175, 4.48137, 2.26289]}


def test_grid_initial_states_are_the_meshgrid_in_c_order():
    r = study.roa("cart", lqr_gain(), GRID, 0.01, x0=(0.01, 0, 0.02, 0))
    th, om = np.meshgrid(np.linspace(-1.2, 1.2, 9), np.linspace(-3.0, 3.0, 7), indexing="ij")
    x = study.roa_initial_states(r.study.spec, 0, r.study.n)
    np.testing.assert_allclose(x[:, 1], th.reshape(-1), rtol=0, atol=1e-15)
    np.testing.assert_allclose(x[:, 3], om.reshape(-1), rtol=0, atol=1e-15)
    assert (x[:, 0] == 0.01).all() and (x[:, 2] == 0.02).all()


def test_roa_is_the_same_for_every_chunking_and_thread_count():
    a = study.roa("cart", lqr_gain(), GRID, 3.0, chunk=5, threads=1)
    b = study.roa("cart", lqr_gain(), GRID, 3.0, chunk=1000)
    for k in a.arrays:
        np.testing.assert_array_equal(a.arrays[k], b.arrays[k])
    assert 0 < a.stats["caught"] < a.stats["n"] == 63


def test_roa_of_the_cart_is_symmetric_under_x_to_minus_x():
    # f(−x, −u) = −f(x, u) for the cart pendulum (docs/model.md) and u = −K x is odd, so a
    # run from −x₀ is the mirror of the run from x₀: the map of a grid symmetric about 0 is
    # symmetric under the point reflection.
    r = study.roa("cart", lqr_gain(), {"theta": (-1.2, 1.2, 25), "dtheta": (-3.0, 3.0, 21)}, 5.0)
    cube = r.caught.reshape(25, 21)
    np.testing.assert_array_equal(cube, cube[::-1, ::-1])
    _, _, cells = r.roa_slice()
    np.testing.assert_array_equal(cells, cube.T)
    # Small states are caught (the linear closed loop is stable), the grid's corners
    # (leaning and spinning the same way) fall.
    assert cube[12, 10] and not cube[0, 0] and not cube[-1, -1]
    fell = ~r.held
    assert np.isfinite(r.time_to_fall[fell]).all() and np.isnan(r.time_to_fall[~fell]).all()


def test_draws_have_their_distributions_moments_and_depend_only_on_the_index():
    n = 20000
    d = study.draws({"a": ("uniform", 2.0, 5.0), "b": ("normal", -1.0, 0.5)}, n, seed=11)
    u, g = d[:, 0], d[:, 1]
    assert u.min() >= 2.0 and u.max() < 5.0
    # Uniform on [2, 5): mean 3.5, variance (b−a)²/12 = 0.75, fourth central moment
    # (b−a)⁴/80 = 81/80; normal(−1, 0.5²). Each estimate within 5 standard errors: σ/√n for
    # a mean, √((μ₄ − σ⁴)/n) for a variance (σ²·√(2/(n−1)) for the normal's).
    assert abs(u.mean() - 3.5) < 5 * math.sqrt(0.75 / n)
    assert abs(u.var() - 0.75) < 5 * math.sqrt((81 / 80 - 0.75**2) / n)
    assert abs(g.mean() + 1.0) < 5 * 0.5 / math.sqrt(n)
    assert abs(g.var() - 0.25) < 5 * 0.25 * math.sqrt(2 / (n - 1))
    np.testing.assert_array_equal(study.draws({"a": ("uniform", 2.0, 5.0), "b": ("normal", -1.0, 0.5)},
                                              100, seed=11, start=n - 100), d[-100:])
    assert not np.array_equal(study.draws({"a": ("uniform", 2.0, 5.0)}, 10, seed=12)[:, 0], u[:10])


def test_a_point_distribution_reproduces_simulate():
    # A uniform distribution of zero width draws the book's value itself, so every sample is
    # the run of plants.simulate (the single-run path) on the book's plant.
    imp = {"quantization": True, "saturation": True}
    one = plants.simulate("cart", BOOK_K, (0.0, 0.1, 0.0, 0.0), 3.0, imperfections=imp)
    a_c = plants.CartPendulum().params["a_c"]
    mc = study.monte_carlo("cart", BOOK_K, {"a_c": ("uniform", a_c, a_c)}, imp, 3, seed=1,
                           x0=(0.0, 0.1, 0.0, 0.0), duration=3.0)
    assert (mc.params[:, 0] == a_c).all()
    s = one.summary
    assert mc.caught.all() and s["settling_time"] is not None
    np.testing.assert_array_equal(mc.settling_time, np.full(3, s["settling_time"]))
    np.testing.assert_array_equal(mc.peak_input, np.full(3, s["peak_input"]))
    np.testing.assert_array_equal(mc.max_angle_deviation, np.full(3, s["max_angle_deviation"]))


def test_monte_carlo_is_the_same_for_every_chunking_with_noise():
    imp = {"quantization": True, "noise": {"std": [1e-4, 1e-3, 1e-3, 1e-2], "seed": 0}}
    dist = {"m_p": ("uniform", 0.07, 0.11), "a_c": ("normal", 8.0, 0.5)}
    a = study.monte_carlo("cart", BOOK_K, dist, imp, 10, seed=3, duration=1.0, chunk=3, threads=1)
    b = study.monte_carlo("cart", BOOK_K, dist, imp, 10, seed=3, duration=1.0, chunk=16)
    for k in a.arrays:
        np.testing.assert_array_equal(a.arrays[k], b.arrays[k])
    np.testing.assert_array_equal(a.params, study.draws(dist, 10, seed=3))
    # Another seed draws other parameters and other noise.
    c = study.monte_carlo("cart", BOOK_K, dist, imp, 10, seed=4, duration=1.0)
    assert not np.array_equal(a.peak_input, c.peak_input)


class CountingStudy(study.Study):
    computed = []

    def chunk(self, start, count, threads=None):
        CountingStudy.computed.append(start)
        return super().chunk(start, count, threads)


def test_resume_computes_only_the_missing_chunks(tmp_path):
    first = study.roa("cart", lqr_gain(), GRID, 1.0, chunk=10, cache_dir=tmp_path)
    spec = first.study.spec
    files = sorted(os.listdir(tmp_path / first.study.key))
    assert "spec.json" in files and "20-10.npz" in files and len(files) == 8  # 7 chunks + spec
    os.remove(tmp_path / first.study.key / "20-10.npz")
    os.remove(tmp_path / first.study.key / "60-3.npz")
    CountingStudy.computed = []
    seen = []
    again = study.run(CountingStudy(spec), chunk=10, cache_dir=tmp_path, progress=lambda d, t: seen.append((d, t)))
    assert CountingStudy.computed == [20, 60]
    assert seen[-1] == (63, 63) and len(seen) == 7
    for k in first.arrays:
        np.testing.assert_array_equal(first.arrays[k], again.arrays[k])


def test_bad_input_raises_clear_errors():
    k = lqr_gain()
    with pytest.raises(pl.InvalidArgumentError, match="grid is empty"):
        study.roa("cart", k, {}, 1.0)
    with pytest.raises(pl.InvalidArgumentError, match="grid is empty"):
        study.roa("cart", k, {"theta": (-1, 1, 0)}, 1.0)
    with pytest.raises(pl.NotFiniteError, match="theta"):
        study.roa("cart", k, {"theta": (float("nan"), 1, 3)}, 1.0)
    with pytest.raises(pl.InvalidArgumentError, match="unknown state"):
        study.roa("cart", k, {"phi": (-1, 1, 3)}, 1.0)
    with pytest.raises(pl.InvalidArgumentError, match="gain K"):
        study.roa("cart", {"kind": "state-feedback"}, GRID, 1.0)
    with pytest.raises(pl.InvalidArgumentError, match="4 entries"):
        study.roa("cart", k[:3], GRID, 1.0)
    with pytest.raises(pl.InvalidArgumentError, match="cart"):
        study.roa("arm", k, GRID, 1.0)
    with pytest.raises(pl.InvalidArgumentError, match="seed"):
        study.roa("cart", k, GRID, 1.0, seed=-1)
    with pytest.raises(pl.InvalidArgumentError, match="backend"):
        study.roa("cart", k, GRID, 1.0, backend="dask")
    with pytest.raises(pl.InvalidArgumentError, match="not a parameter"):
        study.monte_carlo("cart", BOOK_K, {"mass": ("uniform", 0.1, 0.2)}, None, 4, seed=0)
    with pytest.raises(pl.NotFiniteError):
        study.monte_carlo("cart", BOOK_K, {"m_p": ("uniform", 0.1, float("inf"))}, None, 4, seed=0)
    with pytest.raises(pl.InvalidArgumentError, match="low"):
        study.monte_carlo("cart", BOOK_K, {"m_p": ("uniform", 0.2, 0.1)}, None, 4, seed=0)
    with pytest.raises(pl.InvalidArgumentError, match="m_p"):
        study.monte_carlo("cart", BOOK_K, {"m_p": ("normal", -5.0, 0.0)}, None, 4, seed=0)
    with pytest.raises(pl.InvalidArgumentError, match="at least one"):
        study.monte_carlo("cart", BOOK_K, {}, None, 0, seed=0)


def test_figures_are_saved_as_svg_and_png(tmp_path):
    r = study.roa("cart", lqr_gain(), {"theta": (-1.2, 1.2, 13), "dtheta": (-3.0, 3.0, 11)}, 2.0)
    r.save_figure(tmp_path / "roa.svg")
    r.save_figure(tmp_path / "roa.png")
    svg = (tmp_path / "roa.svg").read_text()
    assert svg.lstrip().startswith("<svg") and "stabilised" in svg and "theta(0)" in svg
    assert (tmp_path / "roa.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    mc = study.monte_carlo("cart", BOOK_K, {"m_p": ("uniform", 0.07, 0.11)}, {"quantization": True}, 8,
                           seed=0, duration=2.0)
    mc.save_figure(tmp_path / "mc.svg", field="peak_input", bins=4)
    assert "peak_input" in (tmp_path / "mc.svg").read_text()
    with pytest.raises(pl.InvalidArgumentError, match=".svg or .png"):
        mc.save_figure(tmp_path / "mc.pdf", field="peak_input")
