#!/usr/bin/env python3
"""The 100 × 100 grid of initial conditions from Python against ``pendulab bench sim-batch``,
in the same run.

Workload (as ``crates/cli/src/bench/sim.rs`` describes ``sim-batch``): the book's cart pendulum
(table 3.5) under the LQR gain of its upright linearisation with ``Q = diag(10, 10, 0, 0)``,
``R = 1``, from θ₀ ∈ [−1.2, 1.2] rad × θ̇₀ ∈ [−3, 3] rad/s (100 × 100), 10 s each at 1 kHz
(zero-order hold, one RK4 step per sample), a run stopping at the first sample with
``|θ| > π/2``; both cores. The figure is RK4 steps integrated per wall second; the Python side
is ``pendulab.plants.feedback_batch`` (the same lane kernel, chunked so that Ctrl-C is
honoured between chunks of 1024 runs), timed from the NumPy grid to the result arrays, median of the repeats.

Usage: ``target/pyenv/bin/python crates/python/tools/bench_grid.py [--seconds S]`` from the
repository root, after ``cargo build --release -p pendulab`` and ``maturin develop --release``.
Tools: pendulab (this checkout), NumPy (version printed).
"""

import argparse
import json
import os
import pathlib
import subprocess
import time

import numpy as np

import pendulab as pl
from pendulab import plants

ROOT = pathlib.Path(__file__).resolve().parents[3]
CLI = ROOT / "target" / "release" / "pendulab"


def grid(n=100):
    th, om = np.linspace(-1.2, 1.2, n), np.linspace(-3.0, 3.0, n)
    x0s = np.zeros((n * n, 4))
    x0s[:, 1] = np.repeat(th, n)
    x0s[:, 3] = np.tile(om, n)
    return x0s


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=3.0, help="minimum measuring time per side")
    args = ap.parse_args()
    a, b, _, _ = plants.CartPendulum().linearize("upright")
    k = pl.lqr(a, b, np.diag([10.0, 10.0, 0.0, 0.0]), 1.0).K[0]
    x0s = grid()

    def run():
        return plants.feedback_batch(k, x0s, 10.0, stay_within=(1, np.pi / 2))

    run()  # warm-up (thread pool, pages)
    times, out = [], None
    start = time.perf_counter()
    while len(times) < 3 or time.perf_counter() - start < args.seconds:
        t0 = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - t0)
    median = float(np.median(times))
    steps = int(out["steps"].sum())
    py = {"steps_per_s": steps / median, "grid_seconds_median": median, "grids": len(times),
          "executed_steps": steps, "upright_fraction": float(out["held"].mean())}

    cli = subprocess.run([str(CLI), "bench", "sim-batch", "--json", "--seconds", str(args.seconds)],
                         check=True, capture_output=True, text=True).stdout.strip().splitlines()[-1]
    cli = json.loads(cli)
    ref = {"steps_per_s": cli["figure"], "grid_seconds_median": cli["check"]["grid_seconds_median"],
           "executed_steps": cli["check"]["executed_steps"], "upright_fraction": cli["check"]["upright_fraction"]}
    print(json.dumps({
        "workload": "grid 100x100, 10 s at 1 kHz, LQR, stop at |theta| > pi/2",
        "cores": os.cpu_count(), "numpy": np.__version__,
        "python": py, "cli_bench_sim_batch": ref,
        "python_time_over_cli": py["grid_seconds_median"] / ref["grid_seconds_median"],
        "same_outcomes": py["executed_steps"] == ref["executed_steps"] and py["upright_fraction"] == ref["upright_fraction"],
    }, indent=1))


if __name__ == "__main__":
    main()
