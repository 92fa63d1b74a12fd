"""pendulab.rl without Ray (``docs/studies.md``, "RL"): the registered env and its D/A, the
MLP's batch independence, the energy feature, the committed policy (swing-up and balance)
judged by the env's own success criterion,
save/load and bad input. The training on Ray is in ``test_rl_ray.py``."""

import math
import pathlib

import gymnasium
import numpy as np
import pytest

import pendulab as pl
from pendulab import rl
from pendulab._native import RigCore

ROOT = pathlib.Path(__file__).resolve().parents[3]
POLICY = ROOT / "tools" / "examples" / "cart_swingup_policy.npz"


def test_the_env_is_registered_with_the_rigs_imperfections():
    env = gymnasium.make(rl.ENV_ID)
    spec = env.spec
    assert spec.kwargs == rl.ENV_KWARGS
    assert spec.kwargs["quantize"] and spec.kwargs["dac"] and spec.kwargs["task"] == "swingup"
    obs, _ = env.reset(seed=3)
    # Quantised observation: whole encoder counts (cart 4.8414e-5 m, pendulum 2π/14400 rad).
    assert obs[0] / 4.8414e-5 == pytest.approx(round(obs[0] / 4.8414e-5), abs=1e-9)
    assert obs[1] / (2 * math.pi / 14400) == pytest.approx(round(obs[1] / (2 * math.pi / 14400)), abs=1e-9)
    vec = rl.make_vec(3)
    assert vec.num_envs == 3 and type(vec.unwrapped).__name__ == "RigVectorEnv"


def test_the_dac_applies_the_16_bit_converter_to_the_voltage():
    # The D/A env with voltage a equals the plain env with a rounded to the converter's grid
    # (10 V / 2^16), and differs from the plain env with a itself.
    q = 10.0 / 2**16
    a = np.array([1.23456789, -4.99999, 0.5 * q + 1e-9, 7.0])
    x0 = np.tile([0.01, 3.0, 0.0, 0.0], (4, 1))
    kw = dict(task="swingup", dt=0.01, substeps=10)
    with_dac, plain, rounded = (RigCore("cart", 4, dac=d, **kw) for d in (True, False, False))
    for c in (with_dac, plain, rounded):
        c.reset_to(x0)
    with_dac.step(a)
    plain.step(a)
    rounded.step(np.clip(np.round(a / q) * q, -5.0, 5.0))
    np.testing.assert_array_equal(with_dac.state, rounded.state)
    assert not np.array_equal(with_dac.state[0], plain.state[0])


def test_the_mlp_gives_each_policy_the_same_bits_in_any_batch():
    rng = np.random.default_rng(7)
    sizes = (5, 16, 16, 1)
    d = rl.MlpPolicy.initial((16, 16)).params.size
    params = rng.standard_normal((3, d)) * 0.5
    obs = rng.standard_normal((3, 5, 4)) * [0.2, 3.0, 1.0, 5.0]
    together = rl._forward(params, sizes, obs, 5.0)
    for p in range(3):
        for e in range(5):
            alone = rl._forward(params[p:p + 1], sizes, obs[p:p + 1, e:e + 1], 5.0)
            assert alone[0, 0] == together[p, e]
    # Against the textbook matrix form (BLAS), to rounding.
    w1 = params[0, :80].reshape(5, 16)
    b1 = params[0, 80:96]
    w2 = params[0, 96:352].reshape(16, 16)
    b2 = params[0, 352:368]
    w3 = params[0, 368:384].reshape(16, 1)
    b3 = params[0, 384:385]
    z, th, dz, dth = obs[0].T
    f = np.stack([z / 0.2, np.sin(th), np.cos(th), dz / 1.0, dth / 3.0], axis=1)
    ref = 5.0 * np.tanh(np.tanh(np.tanh(f @ w1 + b1) @ w2 + b2) @ w3 + b3)[:, 0]
    np.testing.assert_allclose(together[0], ref, rtol=1e-12, atol=1e-12)


def test_the_energy_feature_is_the_books_pendulum_energy_relative_to_upright():
    # Book part 2 §3.2 / docs/model.md: E = ½ J θ̇² + m_p g l_p (1 + cos θ) with table 3.5's
    # m_p = 0.107 kg, l_p = 0.23 m, J_p = 1.59e-3 kg m², J = J_p + m_p l_p², g = 9.81 m/s²;
    # the feature is (E − 2 m_p g l_p) / (m_p g l_p).
    m_p, l_p, J_p, g = 0.107, 0.23, 1.59e-3, 9.81
    J = J_p + m_p * l_p**2
    obs = np.array([[0.0, math.pi, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0], [0.1, 2.0, -0.3, 4.0], [0.0, -0.4, 0.2, -7.0]])
    E = 0.5 * J * obs[:, 3] ** 2 + m_p * g * l_p * (1 + np.cos(obs[:, 1]))
    f = rl._features(obs, "energy")
    assert len(f) == rl.FEATURES["energy"] == 6
    np.testing.assert_allclose(f[5], (E - 2 * m_p * g * l_p) / (m_p * g * l_p), rtol=2e-4, atol=1e-12)
    assert f[5][0] == -2.0 and f[5][1] == 0.0
    # The first five are the basic features, bit for bit.
    for a, b in zip(f[:5], rl._features(obs)):
        np.testing.assert_array_equal(a, b)
    p = rl.MlpPolicy.initial((8,), seed=1, features="energy")
    assert p.sizes == (6, 8, 1) and p.params.size == 7 * 8 + 9


def test_the_cma_fitness_bonus_and_termination_penalty():
    # The bonus is cos⁴⁰(θ/2) / (1 + (θ̇/2)²), evaluated by repeated squaring.
    x = np.array([[0.0, 0.0, 0.0, 0.0], [0.0, math.radians(12), 0.0, 0.0], [0.0, 0.5, 0.0, 2.0], [0.0, 3.0, 0.0, 0.0]])
    ref = [math.cos(th / 2) ** 40 / (1 + (w / 2) ** 2) for th, w in x[:, [1, 3]]]
    np.testing.assert_allclose(rl._upright_still(x), ref, rtol=1e-13, atol=1e-300)
    # A policy pinned at +5 V leaves the travel at step k of 300; with the penalty its fitness
    # is the one without less penalty × (300 − 1 − k) (the steps it did not run), and with
    # bonus b it gains b × the bonus summed over the steps it ran.
    d = rl.MlpPolicy.initial((4,), features="energy").params.size
    params = np.zeros((1, d))
    params[0, -1] = 10.0  # the output bias: u = 5 tanh(10)
    starts = np.array([[0.0, math.pi, 0.0, 0.0]])
    kw = {"max_steps": 300}
    runs = [rl._run(params, (6, 4, 1), 5.0, starts, rl.ENV_ID, kw, record=True, features="energy", bonus=b,
                    termination_penalty=c) for b, c in ((0.0, 0.0), (0.0, 1.5), (0.5, 0.0))]
    k = runs[0]["x"].shape[0] - 1  # the terminating step (the loop stops after it)
    assert runs[0]["terminated"][0, 0] and 0 < k < 299
    assert runs[1]["fitness"][0, 0] == pytest.approx(runs[0]["fitness"][0, 0] - 1.5 * (300 - 1 - k), rel=1e-12)
    bonus = rl._upright_still(runs[0]["x"][:, 0, 0]).sum()
    assert runs[2]["fitness"][0, 0] == pytest.approx(runs[0]["fitness"][0, 0] + 0.5 * bonus, rel=1e-12)


def test_the_committed_policy_swings_up_and_balances_from_hanging():
    """A property of the committed weights, judged by the env's own success criterion
    (within 12° of upright for the episode's last 2 s, never beyond the travel) on the env's
    own 6 s episodes: from the hanging rest, from ten draws of the env's reset distribution
    (±0.05 about hanging), from the tutorial's five other starts, and (catching) from the
    upright rest and the reset distribution moved to upright."""
    policy = rl.MlpPolicy.load(POLICY)
    assert policy.meta["seed"] == 0 and "train_cart_swingup.py" in policy.meta["command"]
    assert policy.meta["algorithm"].startswith("CMA-ES") and policy.features == "energy"
    env = rl.make_vec(10)
    env.reset(seed=2024)
    hanging = env.state.copy()
    others = np.array([[0.1, math.pi, 0, 0], [-0.1, math.pi, 0, 0], [0, math.pi - 0.3, 0, 0], [0, math.pi, 0, 1],
                       [0.05, 2.5, 0, -0.5]])
    upright = np.vstack([np.zeros(4), hanging - [0.0, math.pi, 0.0, 0.0]])
    ev = rl.evaluate(policy, np.vstack([[0.0, math.pi, 0.0, 0.0], hanging, others, upright]))
    assert ev["success"].all(), ev
    assert (ev["max_travel"] <= 0.4).all() and (ev["peak_voltage"] <= 5.0).all()
    # The swing-ups are upright within the episode's first 4 s (else the last 2 s could not
    # all be inside the window).
    assert (ev["time_to_upright"][:16] < 4.0).all()
    # The same episode from the hanging rest, stepped by hand through gymnasium.make with
    # float32 actions (the Box's dtype): the env's criterion on its own trajectory.
    one = gymnasium.make(rl.ENV_ID)
    one.reset(seed=0)
    obs = one.unwrapped._core.reset_to(np.array([[0.0, math.pi, 0.0, 0.0]]))[0]
    thetas, terminated, truncated = [], False, False
    for _ in range(rl.ENV_KWARGS["max_steps"]):
        obs, r, terminated, truncated, _ = one.step(np.array([policy(obs)], dtype=np.float32))
        thetas.append(one.unwrapped.state[1])
        if terminated or truncated:
            break
    assert truncated and not terminated
    assert rl.swingup_success(np.array(thetas), terminated, rl.ENV_KWARGS["dt"])
    # ... and it did swing up: the pendulum started hanging.
    assert abs(abs(thetas[0]) - math.pi) < 0.2


def test_save_load_round_trip_and_bad_input(tmp_path):
    p = rl.MlpPolicy.initial(seed=4)
    p.save(tmp_path / "p.npz", seed=4, note="x")
    q = rl.MlpPolicy.load(tmp_path / "p.npz")
    np.testing.assert_array_equal(p.params, q.params)
    assert q.meta == {"seed": 4, "note": "x"} and q.sizes == (5, 16, 1)
    with pytest.raises(pl.InvalidArgumentError, match="parameters"):
        rl.MlpPolicy(np.zeros(3))
    with pytest.raises(pl.InvalidArgumentError, match="finite"):
        rl.MlpPolicy(np.full(p.params.size, np.nan))
    with pytest.raises(pl.InvalidArgumentError, match="sigma"):
        rl.train(rl.ESConfig(sigma=0.0), 1)
    with pytest.raises(pl.InvalidArgumentError, match="pairs"):
        rl.train(rl.ESConfig(pairs=0), 1)
    with pytest.raises(pl.InvalidArgumentError, match="backend"):
        rl.train(rl.ESConfig(), 1, backend="mpi")
    with pytest.raises(pl.InvalidArgumentError, match="fitness"):
        rl.train(rl.ESConfig(fitness="reward"), 1)
    with pytest.raises(pl.InvalidArgumentError, match="layers"):
        rl.train(rl.ESConfig(hidden=(8,)), 1, initial=p)
    with pytest.raises(pl.InvalidArgumentError, match="anywhere"):
        rl.train(rl.ESConfig(anywhere=5), 1)
    with pytest.raises(pl.InvalidArgumentError, match="popsize"):
        rl.train(rl.CMAConfig(popsize=2), 1)
    with pytest.raises(pl.InvalidArgumentError, match="features"):
        rl.train(rl.CMAConfig(features="pixels"), 1)
    with pytest.raises(pl.InvalidArgumentError, match="spread"):
        rl.train(rl.CMAConfig(spread=(0.0, math.nan, 0.0, 0.0)), 1)
    with pytest.raises(pl.InvalidArgumentError, match="layers"):
        rl.train(rl.CMAConfig(features="energy"), 1, initial=p)  # a "basic" policy
    e = rl.MlpPolicy.initial((4,), seed=2, features="energy")
    e.save(tmp_path / "e.npz")
    assert rl.MlpPolicy.load(tmp_path / "e.npz").features == "energy"
    assert not rl.swingup_success(np.zeros(300), True, 0.01)
    assert rl.swingup_success(np.full(300, 2 * math.pi + 0.1), False, 0.01)  # one turn more is upright
    assert not rl.swingup_success(np.r_[np.zeros(299), 0.3], False, 0.01)
    assert not rl.swingup_success(np.zeros(150), False, 0.01)  # shorter than 2 s
    th = np.r_[np.full(100, 1.0), np.zeros(250)]
    assert rl.time_to_upright(th, 0.01) == pytest.approx(1.01)  # sample 100 is at t = 1.01 s
    assert math.isnan(float(rl.time_to_upright(np.r_[np.zeros(10), 1.0], 0.01)))
