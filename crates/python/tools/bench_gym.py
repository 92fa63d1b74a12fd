"""Env-steps per second of pendulab's native vector envs against Gymnasium's CartPole-v1.

Run from the checkout with the package installed (``target/pyenv``):

    target/pyenv/bin/python crates/python/tools/bench_gym.py [--num-envs 4096] [--seconds 2]

Measures, in one run, random actions (a pool of pre-drawn action arrays, cycled, the same for
every contender) through ``step``, autoreset included:

- ``pendulab.gym.CartPoleVectorEnv`` (the drop-in CartPole-v1 dynamics in Rust), 1 thread and
  all cores;
- ``pendulab.gym.RigVectorEnv`` (the book's cart rig, RK4, voltage actions), all cores;
- Gymnasium 1.2.2's ``CartPole-v1`` as ``SyncVectorEnv`` (``make_vec(vectorization_mode="sync")``)
  and as its NumPy ``CartPoleVectorEnv`` (``vectorization_mode="vector_entry_point"``).

Prints one JSON line per contender (env-steps/s) and the ratios to SyncVectorEnv.
"""

import argparse
import json
import os
import time

import gymnasium
import numpy as np

import pendulab
from pendulab.gym import CartPoleVectorEnv, RigVectorEnv


def rate(envs, actions, seconds):
    envs.reset(seed=0)
    n = envs.num_envs
    k = 0
    for _ in range(3):  # warm-up
        envs.step(actions[k % len(actions)])
        k += 1
    steps, t0 = 0, time.perf_counter()
    while True:
        for _ in range(10):
            envs.step(actions[k % len(actions)])
            k += 1
        steps += 10
        dt = time.perf_counter() - t0
        if dt >= seconds:
            return steps * n / dt


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--num-envs", type=int, default=4096)
    ap.add_argument("--sync-envs", type=int, default=16)
    ap.add_argument("--seconds", type=float, default=2.0)
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    cores = os.cpu_count() or 1
    n, m = args.num_envs, args.sync_envs
    discrete = [rng.integers(0, 2, size=n) for _ in range(16)]
    discrete_sync = [rng.integers(0, 2, size=m) for _ in range(16)]
    volts = [rng.uniform(-5, 5, size=(n, 1)) for _ in range(16)]
    results = {}

    def report(name, num_envs, r, **extra):
        results[name] = r
        print(json.dumps({"bench": name, "num_envs": num_envs, "env_steps_per_s": round(r), **extra}), flush=True)

    report("pendulab CartPoleVectorEnv, 1 thread", n, rate(CartPoleVectorEnv(n, threads=1), discrete, args.seconds))
    report(f"pendulab CartPoleVectorEnv, {cores} threads", n, rate(CartPoleVectorEnv(n, threads=cores), discrete, args.seconds))
    report(f"pendulab RigVectorEnv cart, {cores} threads", n, rate(RigVectorEnv(n, rig="cart", threads=cores), volts, args.seconds))
    sync = gymnasium.make_vec("CartPole-v1", num_envs=m, vectorization_mode="sync")
    report("gymnasium CartPole-v1 SyncVectorEnv", m, rate(sync, discrete_sync, args.seconds))
    vec = gymnasium.make_vec("CartPole-v1", num_envs=n, vectorization_mode="vector_entry_point")
    report("gymnasium CartPole-v1 CartPoleVectorEnv (NumPy)", n, rate(vec, discrete, args.seconds))
    base = results["gymnasium CartPole-v1 SyncVectorEnv"]
    print(json.dumps({
        "versions": {"pendulab": pendulab.__version__, "gymnasium": gymnasium.__version__, "numpy": np.__version__},
        "ratio_to_sync": {k: round(v / base, 1) for k, v in results.items()},
    }))


if __name__ == "__main__":
    main()
