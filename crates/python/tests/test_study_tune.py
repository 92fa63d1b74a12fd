"""The Ray Tune example `tools/examples/tune_cart_servo.py` (docs/studies.md), run briefly:
three trials on a local 2-CPU cluster; the best trial's objective is the smallest of the
trials', and rescoring its weights through `plants.simulate` in this process gives the same
numbers as the Tune worker reported. Skipped without Ray Tune."""

import importlib.util
import pathlib

import pytest

pytest.importorskip("ray.tune")
import ray  # noqa: E402

EXAMPLE = pathlib.Path(__file__).resolve().parents[3] / "tools" / "examples" / "tune_cart_servo.py"


def load_example():
    spec = importlib.util.spec_from_file_location("tune_cart_servo", EXAMPLE)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_tune_example_finds_and_reports_a_reproducible_best(tmp_path):
    ex = load_example()
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        cfg, metrics, n, objectives = ex.tune_weights(samples=3, duration=4.0, storage_path=str(tmp_path))
    finally:
        ray.shutdown()
    assert n == 3 and metrics["objective"] == min(objectives)
    again = ex.score(cfg, 4.0)
    assert again["objective"] == metrics["objective"]
    assert again["peak_command"] == metrics["peak_command"]
    book = ex.score(ex.BOOK, 4.0)
    assert book["feasible"] and book["peak_command"] <= 5.0
