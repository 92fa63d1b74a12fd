"""pendulab.rl on a local Ray cluster of 2 CPUs (``docs/studies.md``, "RL"): a short
Evolution Strategies training and a short CMA-ES training each improve on the initial policy
and give the same parameters bit for bit on Ray (two chunkings) as locally, and resumed
halfway; the env is in RLlib's registry; an unreachable cluster fails fast. Skipped without
Ray."""

import math

import numpy as np
import pytest

ray = pytest.importorskip("ray")

from pendulab import rl  # noqa: E402

#: A short problem: 6 pairs, 2 episodes of 2 s (200 steps of 10 ms) from near hanging.
SHORT = rl.ESConfig(pairs=6, episodes=2, seed=3, env_kwargs={"max_steps": 200})
GENERATIONS = 6
#: A short CMA-ES problem: 8 candidates, 2 episodes of 2 s from near hanging, energy feature.
SHORT_CMA = rl.CMAConfig(popsize=8, episodes=2, seed=3, env_kwargs={"max_steps": 200}, spread=(0.05, 0.3, 0.0, 0.3))


@pytest.fixture(scope="module")
def cluster():
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield
    ray.shutdown()


def test_training_on_ray_improves_the_return_and_equals_the_local_run(cluster):
    local = rl.train(SHORT, GENERATIONS)
    # The mean return over fixed evaluation episodes, before and after (the env's return).
    starts = rl._starts(99, 0, 8, rl.ENV_ID, SHORT.env_kwargs)
    before = rl.evaluate(rl.MlpPolicy.initial(SHORT.hidden, SHORT.seed), starts, **SHORT.env_kwargs)["return"].mean()
    after = rl.evaluate(local.policy, starts, **SHORT.env_kwargs)["return"].mean()
    assert after > before + 5.0, (before, after)
    for chunk in (1, 4):
        seen = []
        on_ray = rl.train(SHORT, GENERATIONS, backend="ray", chunk=chunk, progress=lambda g, s: seen.append(g))
        assert seen == list(range(GENERATIONS))
        np.testing.assert_array_equal(on_ray.policy.params, local.policy.params)
        for k in ("mean_return", "max_return", "mean_fitness"):
            np.testing.assert_array_equal(on_ray.history[k], local.history[k])
    # Resuming for the remaining generations gives the uninterrupted run's parameters.
    half = rl.train(SHORT, GENERATIONS // 2, backend="ray")
    rest = rl.train(SHORT, GENERATIONS - GENERATIONS // 2, resume=half)
    np.testing.assert_array_equal(rest.policy.params, local.policy.params)


def test_cma_es_on_ray_improves_the_fitness_and_equals_the_local_run(cluster):
    local = rl.train(SHORT_CMA, GENERATIONS)
    h = local.history
    # The population's best fitness rises from the first generations to the last ones.
    assert h["max_fitness"][-2:].mean() > h["max_fitness"][:2].mean() + 5.0, h["max_fitness"]
    # The mean's return over fixed evaluation episodes rises from the initial policy's (0 V).
    starts = rl._starts(99, 0, 8, rl.ENV_ID, SHORT_CMA.env_kwargs)
    before = rl.evaluate(rl.MlpPolicy.initial(SHORT_CMA.hidden, SHORT_CMA.seed, features="energy"), starts,
                         **SHORT_CMA.env_kwargs)["return"].mean()
    after = rl.evaluate(local.policy, starts, **SHORT_CMA.env_kwargs)["return"].mean()
    assert after > before + 5.0, (before, after)
    assert local.policy.features == "energy" and local.policy.meta["algorithm"].startswith("CMA-ES")
    for chunk in (1, 3):
        on_ray = rl.train(SHORT_CMA, GENERATIONS, backend="ray", chunk=chunk)
        np.testing.assert_array_equal(on_ray.policy.params, local.policy.params)
        for k in ("mean_return", "max_return", "mean_fitness", "max_fitness", "sigma"):
            np.testing.assert_array_equal(on_ray.history[k], local.history[k])
    half = rl.train(SHORT_CMA, GENERATIONS // 2, backend="ray")
    rest = rl.train(SHORT_CMA, GENERATIONS - GENERATIONS // 2, resume=half)
    np.testing.assert_array_equal(rest.policy.params, local.policy.params)
    np.testing.assert_array_equal(rest.adam["C"], local.adam["C"])


def test_the_env_is_in_rllibs_registry(cluster):
    from ray.tune.registry import ENV_CREATOR, _global_registry

    rl.register_rllib()
    env = _global_registry.get(ENV_CREATOR, rl.ENV_ID)({"max_steps": 10})
    obs, _ = env.reset(seed=1)
    assert abs(abs(obs[1]) - math.pi) < 0.06  # starts near hanging
    assert env.unwrapped._core.max_steps == 10


def test_an_unreachable_cluster_fails_fast():
    import socket
    import time

    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    t0 = time.monotonic()
    with pytest.raises(ConnectionError, match=str(port)):
        rl.train(SHORT, 1, backend="ray", address=f"127.0.0.1:{port}", timeout=2)
    assert time.monotonic() - t0 < 10
