#!/usr/bin/env python3
"""Throughput of pendulab's studies (docs/studies.md), printed as one JSON object.

1. Local backend: the region of attraction on the 100 × 100 grid of `pendulab bench
   sim-batch` (θ₀ ∈ [−1.2, 1.2] rad × θ̇₀ ∈ [−3, 3] rad/s, 10 s at 1 kHz, |θ| ≤ π/2, the LQR
   gain of Q = diag(10, 10, 0, 0), R = 1) through `pendulab.study.roa`, against
   `target/release/pendulab bench sim-batch --json` run in the same process tree, both as
   RK4 steps integrated per second.
2. Ray backend with 2 worker CPUs against the local backend on a larger grid (`--ray-points`
   per axis, the same 10 s runs), both timed here; the overhead is 1 − rate(Ray)/rate(local),
   with the time of `ray.init` quoted separately, and the bytes shipped per chunk (the
   pickled spec and one chunk's result).

Usage: target/pyenv/bin/python tools/bench_study.py [--ray-points 200] [--chunk 1024]
Needs the package built (`maturin develop --release`) and, for part 2, Ray installed.
"""

import argparse
import json
import os
import pickle
import subprocess
import sys
import time

import numpy as np

import pendulab as pl
from pendulab import plants, study

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def gain():
    a, b, _, _ = plants.CartPendulum().linearize("upright")
    return pl.lqr(a, b, np.diag([10.0, 10.0, 0.0, 0.0]), 1.0).K[0]


def grid(points):
    return {"theta": (-1.2, 1.2, points), "dtheta": (-3.0, 3.0, points)}


def timed(fn, repeat=1):
    best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ray-points", type=int, default=200)
    ap.add_argument("--chunk", type=int, default=1024)
    ap.add_argument("--no-ray", action="store_true")
    args = ap.parse_args()
    k = gain()
    res = {"machine": {"cpus": os.cpu_count()}}

    exe = os.path.join(ROOT, "target", "release", "pendulab")
    cli = json.loads(subprocess.run([exe, "bench", "sim-batch", "--json"], check=True,
                                    capture_output=True, text=True).stdout.strip().splitlines()[-1])
    secs, r = timed(lambda: study.roa("cart", k, grid(100), 10.0), repeat=3)
    steps = int(r.steps.sum())
    res["local_100x100"] = {
        "seconds_min_of_3": secs, "steps": steps, "steps_per_s": steps / secs,
        "caught_fraction": r.stats["caught_fraction"],
        "cli_sim_batch_steps_per_s": cli["figure"], "cli_executed_steps": cli["check"]["executed_steps"],
        "cli_upright_fraction": cli["check"]["upright_fraction"],
        # Like for like: the CLI's fastest grid against this one's fastest of 3.
        "cli_grid_seconds_min": cli["check"]["grid_seconds_min"],
        "cli_steps_per_s_min_grid": cli["check"]["executed_steps"] / cli["check"]["grid_seconds_min"],
        "ratio_to_cli_min_grid": cli["check"]["grid_seconds_min"] / secs,
    }

    if not args.no_ray:
        import ray

        t0 = time.perf_counter()
        ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
        init_s = time.perf_counter() - t0
        g = grid(args.ray_points)
        n = args.ray_points**2
        # Warm the workers (process start, import) once, as a long study would amortise.
        study.roa("cart", k, grid(8), 0.01, backend="ray", chunk=32)
        ray_s, rr = timed(lambda: study.roa("cart", k, g, 10.0, backend="ray", chunk=args.chunk))
        loc_s, lr = timed(lambda: study.roa("cart", k, g, 10.0, chunk=args.chunk))
        same = all(np.array_equal(rr.arrays[key], lr.arrays[key], equal_nan=True) for key in lr.arrays)
        steps = int(lr.steps.sum())
        spec_bytes = len(pickle.dumps(lr.study.spec))
        chunk_bytes = len(pickle.dumps(lr.study.chunk(0, args.chunk)))
        res["ray_vs_local"] = {
            "trajectories": n, "steps": steps, "chunk": args.chunk,
            "chunks": -(-n // args.chunk), "ray_init_s": init_s,
            "ray_s": ray_s, "local_s": loc_s,
            "ray_steps_per_s": steps / ray_s, "local_steps_per_s": steps / loc_s,
            "ray_over_local": loc_s / ray_s, "overhead": 1 - loc_s / ray_s,
            "identical": same, "spec_bytes": spec_bytes, "chunk_result_bytes": chunk_bytes,
            "seconds_per_chunk_local": loc_s / -(-n // args.chunk) * os.cpu_count(),
        }
        ray.shutdown()
    json.dump(res, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
