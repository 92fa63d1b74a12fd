#!/usr/bin/env python3
"""Tunes the weights Q, R of the cart's LQ integral servo with Ray Tune (docs/studies.md).

Each trial designs the servo `lq-servo` with `lqr = {q = [q_z, q_θ, 0, 0, q_w], r}` (book
part 1 ch. 6, `cdip_lqr_servo_sim`) and runs it through the one simulate path on the book's
cart rig with its imperfections (encoder quantisation, ±5 V saturation, D/A, the
pseudo-differentiator) for a 0.1 m step of the cart position. The objective is the settling
time of `z`, subject to `|v| ≤ 5 V` before saturation (`peak_command`) and the rig's track
limit (`left_travel`); a trial that breaks a constraint or does not settle scores
`duration + penalty`. The book's weights Q = diag(1, 5, 0, 0, 100), R = 1 are scored the same
way and printed next to the best trial.

Usage: target/pyenv/bin/python tools/examples/tune_cart_servo.py [--samples 24] [--duration 6]
Prints one JSON object: the book's score, the best weights and their score, the trials run.
"""

import argparse
import json
import math

from pendulab import plants

IMPERFECTIONS = {"quantization": True, "saturation": True, "dac": True, "pseudo_differentiator": True}
STEP = 0.1  # m, the servo reference of the cart position
BOOK = {"q_z": 1.0, "q_theta": 5.0, "q_w": 100.0, "r": 1.0}


def score(weights, duration=6.0):
    """Settling time (s) of the servo with `weights`, or `duration + 10` (+ the violation) when
    |v| exceeds 5 V, the cart leaves the track or z does not settle."""
    ctrl = {"kind": "lq-servo", "reference": [STEP],
            "lqr": {"q": [weights["q_z"], weights["q_theta"], 0.0, 0.0, weights["q_w"]], "r": weights["r"]}}
    run = plants.simulate("cart", ctrl, [0.0, 0.0, 0.0, 0.0], duration, imperfections=IMPERFECTIONS)
    s = run.summary
    over = max(0.0, s["peak_command"] - 5.0)
    if s["left_travel"] or over > 0 or s["settling_time"] is None:
        return {"objective": duration + 10.0 + over, "settling_time": s["settling_time"],
                "peak_command": s["peak_command"], "feasible": False}
    return {"objective": s["settling_time"], "settling_time": s["settling_time"],
            "peak_command": s["peak_command"], "feasible": True}


def trainable(config):
    from ray import tune

    tune.report(score(config, config.get("duration", 6.0)))


def tune_weights(samples=24, duration=6.0, seed=0, storage_path=None):
    """Ray Tune's random search (`BasicVariantGenerator`, seeded) over log-uniform weights,
    trial results under `storage_path` (Tune's default `~/ray_results` if None); returns
    (best weights, the best trial's metrics, the number of trials, every trial's objective)."""
    from ray import tune

    space = {
        "q_z": tune.loguniform(0.1, 100.0),
        "q_theta": tune.loguniform(0.1, 100.0),
        "q_w": tune.loguniform(1.0, 1000.0),
        "r": tune.loguniform(0.1, 10.0),
        "duration": duration,
        "seed": seed,
    }
    tuner = tune.Tuner(
        trainable,
        param_space=space,
        tune_config=tune.TuneConfig(metric="objective", mode="min", num_samples=samples,
                                    search_alg=tune.search.BasicVariantGenerator(random_state=seed)),
        run_config=tune.RunConfig(storage_path=storage_path, verbose=0),
    )
    grid = tuner.fit()
    best = grid.get_best_result()
    cfg = {k: best.config[k] for k in ("q_z", "q_theta", "q_w", "r")}
    objectives = [r.metrics["objective"] for r in grid]
    return cfg, best.metrics, len(grid), objectives


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=24)
    ap.add_argument("--duration", type=float, default=6.0)
    args = ap.parse_args()
    import ray

    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        cfg, metrics, n, _ = tune_weights(args.samples, args.duration)
    finally:
        ray.shutdown()
    book = score(BOOK, args.duration)
    print(json.dumps({"book": {"weights": BOOK, **book},
                      "best": {"weights": cfg, **{k: metrics[k] for k in book}},
                      "trials": n}, indent=1, default=lambda v: None if v is None or math.isnan(v) else v))


if __name__ == "__main__":
    main()
