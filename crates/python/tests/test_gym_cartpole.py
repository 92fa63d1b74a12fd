"""pendulab/CartPole-v1 against Gymnasium 1.2.2's CartPole-v1, run in the same test.

Same seeds, same actions: the observations must be identical, the internal float64 states
within 1e-12, and rewards, terminations and truncations equal — for the single environment
(through ``gymnasium.make``'s wrappers, stepping on after termination too) and for the
native vector env against Gymnasium's own ``CartPoleVectorEnv``.
"""

import gymnasium
import numpy as np
import pytest

import pendulab
import pendulab.gym  # noqa: F401  (registers the environments)
from pendulab.gym import CartPoleVectorEnv


def policies(rng):
    """A random policy and a balancing one (long episodes that reach the 500-step limit)."""
    yield lambda obs: int(rng.integers(2))
    yield lambda obs: int(obs[2] + 0.3 * obs[3] + 0.01 * obs[1] > 0)


@pytest.mark.parametrize("sutton_barto", [False, True])
def test_single_env_reproduces_gymnasium_step_for_step(sutton_barto):
    rng = np.random.default_rng(5)
    steps = truncations = beyond = 0
    for seed in range(12):
        for policy in policies(rng):
            ours = gymnasium.make("pendulab/CartPole-v1", sutton_barto_reward=sutton_barto)
            ref = gymnasium.make("CartPole-v1", sutton_barto_reward=sutton_barto)
            o1, _ = ours.reset(seed=seed)
            o2, _ = ref.reset(seed=seed)
            assert o1.dtype == o2.dtype == np.float32
            np.testing.assert_array_equal(o1, o2)
            extra = 0
            while extra < 3:
                a = policy(o2)
                o1, r1, te1, tr1, _ = ours.step(a)
                o2, r2, te2, tr2, _ = ref.step(a)
                steps += 1
                np.testing.assert_array_equal(o1, o2)
                s1, s2 = ours.unwrapped.state, ref.unwrapped.state
                assert np.max(np.abs(s1 - s2)) <= 1e-12
                assert (r1, te1, tr1) == (r2, te2, tr2)
                assert type(r1) is type(r2) is float
                if tr1:
                    truncations += 1
                    break
                if te1:
                    # Gymnasium keeps integrating after termination; so must we.
                    extra += 1
                    beyond += 1
    assert steps > 5000 and truncations > 5 and beyond > 20


def test_reset_options_bounds_as_gymnasium():
    ours = gymnasium.make("pendulab/CartPole-v1")
    ref = gymnasium.make("CartPole-v1")
    opts = {"low": -0.1, "high": 0.1}
    np.testing.assert_array_equal(ours.reset(seed=123, options=opts)[0], ref.reset(seed=123, options=opts)[0])


@pytest.mark.parametrize("num_envs,threads", [(7, 1), (1500, 2)])
def test_vector_env_reproduces_gymnasiums_vector_env(num_envs, threads):
    ours = CartPoleVectorEnv(num_envs=num_envs, threads=threads)
    ref = gymnasium.make_vec("CartPole-v1", num_envs=num_envs, vectorization_mode="vector_entry_point")
    o1, _ = ours.reset(seed=42)
    o2, _ = ref.reset(seed=42)
    np.testing.assert_array_equal(o1, o2)
    rng = np.random.default_rng(0)
    resets = 0
    for _ in range(700):
        a = rng.integers(0, 2, size=num_envs)
        o1, r1, te1, tr1, _ = ours.step(a)
        o2, r2, te2, tr2, _ = ref.step(a)
        np.testing.assert_array_equal(o1, o2)
        assert np.max(np.abs(ours.state - ref.unwrapped.state.T)) <= 1e-12
        np.testing.assert_array_equal(r1, r2)
        assert r1.dtype == r2.dtype
        np.testing.assert_array_equal(te1, te2)
        np.testing.assert_array_equal(tr1, tr2)
        resets += int(te1.sum() + tr1.sum())
    assert resets > num_envs


def test_make_vec_uses_the_native_vector_env():
    envs = gymnasium.make_vec("pendulab/CartPole-v1", num_envs=3, vectorization_mode="vector_entry_point")
    assert isinstance(envs.unwrapped, CartPoleVectorEnv)
    assert envs.metadata["autoreset_mode"] == gymnasium.vector.AutoresetMode.NEXT_STEP


def test_bad_actions_raise_and_step_nothing():
    envs = CartPoleVectorEnv(num_envs=4)
    envs.reset(seed=1)
    before = envs.state.copy()
    with pytest.raises(pendulab.InvalidArgumentError, match=r"actions\[2\] = 2"):
        envs.step(np.array([0, 1, 2, 0]))
    with pytest.raises(pendulab.ShapeError, match="expected 4 actions"):
        envs.step(np.array([0, 1]))
    np.testing.assert_array_equal(envs.state, before)
    env = gymnasium.make("pendulab/CartPole-v1").unwrapped
    with pytest.raises(ValueError, match="reset"):
        env.step(0)
    env.reset(seed=0)
    with pytest.raises(ValueError):
        env.step(3)
    with pytest.raises(pendulab.InvalidArgumentError, match="masspole"):
        pendulab._native.ClassicCartPoleCore(1, autoreset=False, params={"masspole": -1.0})
