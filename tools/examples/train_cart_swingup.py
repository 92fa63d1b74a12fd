#!/usr/bin/env python3
"""Trains a swing-up-and-balance policy for the book's cart rig with pendulab.rl (docs/studies.md, "RL").

The registered env `pendulab/CartRigSwingUpQuantized-v0`: the cart rig of table 3.5 from
hanging, the controller seeing the positions in whole encoder counts, its voltage through the
16-bit D/A and the ±5 V saturation, acting every 10 ms (RK4 at 1 ms); here with 8 s episodes
(`--max-steps 800`). The rollouts run on the local cores (`--backend local`) or as Ray Core
tasks (`--backend ray [--address HOST:PORT]`); the result is the same bit for bit. The trained
weights are written to `--out` with the seed, the settings and this command;
`cart_swingup_policy.npz` next to this script was made by the command in its `meta["command"]`.

`--algorithm cma` (default): CMA-ES (Hansen 2016) over an MLP on the "energy" features (the
basic five and the pendulum's energy relative to upright), from scratch, the fitness being the
shaped reward plus an upright-and-still bonus less a penalty for the steps lost by leaving the
travel, the episodes from hanging with the start offsets `--spread`.
`--algorithm es`: the earlier recipe, Evolution Strategies (Salimans et al. 2017) in two stages
(the balance task, then the swing-up env), which balances but does not swing up.

Usage: target/pyenv/bin/python tools/examples/train_cart_swingup.py [--algorithm cma|es]
       [--generations N] [--seed 0] [--backend local|ray] [--address HOST:PORT] [--out FILE.npz]
Prints one JSON object per 25 generations and a final one: the evaluation of the policy from
the tutorial's six starts over 6 s and 8 s (success: the env's criterion).
"""

import argparse
import json
import pathlib
import sys
import time

import numpy as np

from pendulab import rl

HERE = pathlib.Path(__file__).resolve().parent
#: The tutorial's starts [z, θ, ż, θ̇] (notebook §7).
STARTS = np.array([[0.0, np.pi, 0.0, 0.0], [0.1, np.pi, 0.0, 0.0], [-0.1, np.pi, 0.0, 0.0],
                   [0.0, np.pi - 0.3, 0.0, 0.0], [0.0, np.pi, 0.0, 1.0], [0.05, 2.5, 0.0, -0.5]])


def floats(text):
    return tuple(float(v) for v in text.split(","))


def ints(text):
    return tuple(int(v) for v in text.split(","))


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--algorithm", choices=("cma", "es"), default="cma")
    p.add_argument("--generations", type=int, default=None,
                   help="CMA-ES generations (default 600); ES: stage 2's (default 60)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--episodes", type=int, default=4)
    p.add_argument("--sigma", type=float, default=0.5)
    # CMA-ES
    p.add_argument("--popsize", type=int, default=32)
    p.add_argument("--hidden", type=ints, default=(16,), help="hidden layer widths, e.g. 16 or 16,16")
    p.add_argument("--max-steps", type=int, default=800, help="episode length in 10 ms steps")
    p.add_argument("--spread", type=floats, default=(0.1, 0.5, 0.0, 0.5),
                   help="half-widths of the uniform start offsets of z, θ, ż, θ̇ (SI)")
    p.add_argument("--bonus", type=float, default=2.0, help="weight of the upright-and-still bonus")
    p.add_argument("--termination-penalty", type=float, default=1.0, help="per step lost by leaving the travel")
    # ES (two stages)
    p.add_argument("--balance-generations", type=int, default=80,
                   help="ES stage 1: on the balance task (pendulab/CartRig-v0, same imperfections)")
    p.add_argument("--pairs", type=int, default=32)
    p.add_argument("--anywhere", type=int, default=1, help="ES stage 2: episodes not from hanging")
    p.add_argument("--anywhere-angle", type=float, default=0.15,
                   help="ES stage 2: their start angle range about upright (rad; within 12°: balance episodes)")
    p.add_argument("--balance-weight", type=float, default=0.5)
    p.add_argument("--learning-rate", type=float, default=0.2)
    p.add_argument("--curriculum", type=int, default=0)
    p.add_argument("--backend", choices=("local", "ray"), default="local")
    p.add_argument("--address", default=None, help="a Ray cluster's HOST:PORT (default: a local one)")
    p.add_argument("--chunk", type=int, default=None, help="pairs or candidates per Ray task")
    p.add_argument("--out", default=str(HERE / "cart_swingup_policy.npz"))
    a = p.parse_args(argv)

    def progress(stage):
        def report(g, s):
            if (g + 1) % 25 == 0:
                print(json.dumps({"stage": stage, "generation": g + 1, **{k: round(v, 3) for k, v in s.items()}}),
                      flush=True)
        return report

    t0 = time.perf_counter()
    opts = dict(backend=a.backend, address=a.address, chunk=a.chunk)
    extra = {}
    if a.algorithm == "cma":
        cfg = rl.CMAConfig(popsize=a.popsize, sigma=a.sigma, episodes=a.episodes, hidden=a.hidden,
                           features="energy", env_kwargs={"max_steps": a.max_steps}, bonus=a.bonus,
                           termination_penalty=a.termination_penalty, spread=a.spread, seed=a.seed)
        res = rl.train(cfg, a.generations or 600, progress=progress("cma-es"), **opts)
        extra = {"history_max_fitness": res.history["max_fitness"].round(1).tolist(),
                 "history_sigma": res.history["sigma"].round(4).tolist()}
    else:
        common = dict(pairs=a.pairs, episodes=a.episodes, sigma=a.sigma, learning_rate=a.learning_rate, seed=a.seed)
        kw = {k: v for k, v in rl.ENV_KWARGS.items() if k not in ("rig", "task")}
        balance = rl.ESConfig(env_id="pendulab/CartRig-v0", env_kwargs=kw, **common)
        swingup = rl.ESConfig(anywhere=a.anywhere, anywhere_angle=a.anywhere_angle, balance_weight=a.balance_weight,
                              curriculum=a.curriculum, **common)
        first = rl.train(balance, a.balance_generations, progress=progress("balance"), **opts)
        res = rl.train(swingup, a.generations or 60, initial=first.policy, progress=progress("swing-up"), **opts)
        extra = {"balance_stage": balance.to_dict(), "balance_generations": a.balance_generations,
                 "balance_stage_mean_return": first.history["mean_return"].round(3).tolist()}
    seconds = time.perf_counter() - t0
    args = list(argv if argv is not None else sys.argv[1:])
    if "--out" in args:  # the output path is not part of the recipe
        i = args.index("--out")
        del args[i:i + 2]
    command = "python tools/examples/train_cart_swingup.py " + " ".join(x for x in args if not x.startswith("--out="))
    res.policy.save(a.out, seed=a.seed, command=command.strip(), train_seconds=round(seconds, 1),
                    history_mean_return=res.history["mean_return"].round(3).tolist(), **extra)
    report = {"out": a.out, "generations": res.generations, "seconds": round(seconds, 1)}
    for steps in (600, 800):
        ev = rl.evaluate(res.policy, STARTS, max_steps=steps)
        report[f"{steps // 100} s"] = {"success": int(ev["success"].sum()), "of": len(STARTS),
                                       "time_to_upright": np.round(ev["time_to_upright"], 2).tolist(),
                                       "peak_voltage": np.round(ev["peak_voltage"], 2).tolist(),
                                       "max_travel": np.round(ev["max_travel"], 3).tolist()}
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
