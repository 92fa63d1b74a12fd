#!/usr/bin/env python3
"""Trains a swing-up-and-balance policy for the book's cart rig with pendulab.rl (docs/studies.md, "RL").

Evolution Strategies (Salimans et al. 2017) over a NumPy MLP on the registered env
`pendulab/CartRigSwingUpQuantized-v0`: the cart rig of table 3.5 from hanging, the controller
seeing the positions in whole encoder counts, its voltage through the 16-bit D/A and the ±5 V
saturation, acting every 10 ms (RK4 at 1 ms), 6 s episodes. The rollouts run on the local
cores (`--backend local`) or as Ray Core tasks (`--backend ray [--address HOST:PORT]`); the
result is the same bit for bit. The trained weights are written to `--out` with the seed,
the settings and this command; `cart_swingup_policy.npz` next to this script was made by the
command in its `meta["command"]`.

Usage: target/pyenv/bin/python tools/examples/train_cart_swingup.py [--balance-generations 80]
       [--generations 250] [--seed 0] [--backend local|ray] [--address HOST:PORT] [--out FILE.npz]
Prints one JSON object per 10 generations and a final one: the evaluation of the policy from
the hanging rest and from the env's own reset distribution (success: the env's criterion).
"""

import argparse
import json
import pathlib
import sys
import time

import numpy as np

from pendulab import rl

HERE = pathlib.Path(__file__).resolve().parent


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--balance-generations", type=int, default=80,
                   help="stage 1: ES on the balance task (pendulab/CartRig-v0, same imperfections)")
    p.add_argument("--generations", type=int, default=60, help="stage 2: ES on the swing-up env")
    p.add_argument("--curriculum", type=int, default=0,
                   help="stage 2: generations over which the start angles widen (0: fixed)")
    p.add_argument("--pairs", type=int, default=32)
    p.add_argument("--episodes", type=int, default=4)
    p.add_argument("--anywhere", type=int, default=1, help="stage 2: episodes not from hanging")
    p.add_argument("--anywhere-angle", type=float, default=0.15,
                   help="stage 2: their start angle range about upright (rad; within 12°: balance episodes)")
    p.add_argument("--balance-weight", type=float, default=0.5)
    p.add_argument("--sigma", type=float, default=0.5)
    p.add_argument("--learning-rate", type=float, default=0.2)
    p.add_argument("--swingup-sigma", type=float, default=None, help="stage 2's σ (default --sigma)")
    p.add_argument("--swingup-learning-rate", type=float, default=None,
                   help="stage 2's Adam step (default --learning-rate)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--backend", choices=("local", "ray"), default="local")
    p.add_argument("--address", default=None, help="a Ray cluster's HOST:PORT (default: a local one)")
    p.add_argument("--chunk", type=int, default=None, help="pairs per Ray task")
    p.add_argument("--out", default=str(HERE / "cart_swingup_policy.npz"))
    a = p.parse_args(argv)
    common = dict(pairs=a.pairs, episodes=a.episodes, sigma=a.sigma, learning_rate=a.learning_rate, seed=a.seed)
    # Stage 1: the balance task on the same rig (start within ±0.05 of upright, episodes end
    # beyond 12° or the travel), so that the policy learns to catch before it learns to pump.
    kw = {k: v for k, v in rl.ENV_KWARGS.items() if k not in ("rig", "task")}
    balance = rl.ESConfig(env_id="pendulab/CartRig-v0", env_kwargs=kw, **common)
    # Stage 2: the swing-up env, from the stage-1 policy; `anywhere` of the episodes start
    # within ±anywhere_angle of upright (balance episodes when inside 12°: their fitness stops
    # when the pendulum leaves the window), the others from the env's hanging start.
    stage2 = dict(common, sigma=a.swingup_sigma or a.sigma, learning_rate=a.swingup_learning_rate or a.learning_rate)
    swingup = rl.ESConfig(anywhere=a.anywhere, anywhere_angle=a.anywhere_angle, balance_weight=a.balance_weight,
                          curriculum=a.curriculum, **stage2)

    def progress(stage):
        def report(g, s):
            if g % 10 == 0:
                print(json.dumps({"stage": stage, "generation": g, **{k: round(v, 3) for k, v in s.items()}}),
                      flush=True)
        return report

    t0 = time.perf_counter()
    opts = dict(backend=a.backend, address=a.address, chunk=a.chunk)
    first = rl.train(balance, a.balance_generations, progress=progress("balance"), **opts)
    res = rl.train(swingup, a.generations, initial=first.policy, progress=progress("swing-up"), **opts)
    seconds = time.perf_counter() - t0
    args = list(argv if argv is not None else sys.argv[1:])
    if "--out" in args:  # the output path is not part of the recipe
        i = args.index("--out")
        del args[i:i + 2]
    command = "python tools/examples/train_cart_swingup.py " + " ".join(x for x in args if not x.startswith("--out="))
    res.policy.save(a.out, seed=a.seed, command=command.strip(), train_seconds=round(seconds, 1),
                    balance_stage=balance.to_dict(), balance_generations=a.balance_generations,
                    balance_stage_mean_return=first.history["mean_return"].round(3).tolist(),
                    history_mean_return=res.history["mean_return"].round(3).tolist())
    hanging = rl.evaluate(res.policy, np.array([[0.0, np.pi, 0.0, 0.0]]))
    starts = rl._starts(12345, 0, 16, rl.ENV_ID, {})
    ev = rl.evaluate(res.policy, starts)
    print(json.dumps({
        "out": a.out, "generations": res.generations, "seconds": round(seconds, 1),
        "hanging": {k: np.asarray(v).tolist() for k, v in hanging.items()},
        "reset_distribution": {"n": 16, "success": int(ev["success"].sum()),
                               "mean_return": float(ev["return"].mean()),
                               "time_to_upright_max": float(np.nanmax(ev["time_to_upright"]))
                               if ev["success"].any() else None},
    }, indent=1))


if __name__ == "__main__":
    main()
