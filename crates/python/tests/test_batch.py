"""Batch runs on all cores: ``feedback_batch`` against an independent RK4 written here over
the plant's own right-hand side, ``simulate_batch`` against ``simulate``, and Ctrl-C: a SIGINT
sent to a process running a long batch (or stepping a vector env of 2¹⁸ rigs) raises
``KeyboardInterrupt`` within 1 s."""

import os
import pathlib
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import pendulab as pl
from pendulab import plants

K = None


def lqr_gain():
    global K
    if K is None:
        a, b, _, _ = plants.CartPendulum().linearize("upright")
        K = pl.lqr(a, b, np.diag([10.0, 10.0, 0.0, 0.0]), 1.0).K[0]
    return K


def rk4_zoh(plant, k, x0, ts, steps):
    """u = −K x held over each sample, one classic RK4 step per sample (the reference)."""
    x = np.array(x0, dtype=float)
    for _ in range(steps):
        u = -k @ x
        k1 = plant.derivative(x, u)
        k2 = plant.derivative(x + ts / 2 * k1, u)
        k3 = plant.derivative(x + ts / 2 * k2, u)
        k4 = plant.derivative(x + ts * k3, u)
        x = x + ts / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return x


def test_feedback_batch_equals_an_independent_rk4():
    k = lqr_gain()
    x0s = np.array([[0.0, th, 0.0, om] for th in (-0.3, 0.1, 0.25) for om in (-0.5, 0.4)])
    out = plants.feedback_batch(k, x0s, 0.5)
    assert out["held"].all() and (out["steps"] == 500).all()
    cart = plants.CartPendulum()
    for x0, xf in zip(x0s, out["final_state"]):
        # The kernel's sines are within 2 ulp of libm's; over 500 stable closed-loop steps
        # the states agree to ~1e-14 of their size.
        np.testing.assert_allclose(xf, rk4_zoh(cart, k, x0, 1e-3, 500), rtol=0, atol=1e-12)


def test_feedback_batch_stops_runs_that_fall():
    k = lqr_gain()
    x0s = np.array([[0.0, 0.05, 0.0, 0.0], [0.0, 1.2, 0.0, 3.0]])
    out = plants.feedback_batch(k, x0s, 10.0, stay_within=(1, np.pi / 2), threads=1)
    assert out["held"].tolist() == [True, False]
    assert out["steps"][0] == 10_000 and out["steps"][1] < 10_000
    assert abs(out["final_state"][1, 1]) > np.pi / 2
    with pytest.raises(pl.ShapeError):
        plants.feedback_batch(k[:3], x0s, 1.0)
    with pytest.raises(pl.ShapeError):
        plants.feedback_batch(k, x0s[:, :3], 1.0)
    with pytest.raises(pl.InvalidArgumentError):
        plants.feedback_batch(k, x0s, 1.0, threads=0)
    with pytest.raises(pl.NotFiniteError):
        plants.feedback_batch(k, [[0, np.nan, 0, 0]], 1.0)


def test_simulate_batch_equals_simulate():
    ctrl = {"kind": "state-feedback", "k_book": [3.16228, 13.47175, 4.48137, 2.26289]}
    x0s = [[0, 0.05, 0, 0], [0, -0.08, 0, 0.1], [0.02, 0.0, 0, 0]]
    runs = plants.simulate_batch("cart", ctrl, x0s, 1.0, imperfections={"quantization": True})
    for x0, r in zip(x0s, runs):
        one = plants.simulate("cart", ctrl, x0, 1.0, imperfections={"quantization": True})
        np.testing.assert_array_equal(r.x, one.x)
        np.testing.assert_array_equal(r.u, one.u)
    with pytest.raises(pl.InvalidArgumentError, match="scenario 0"):
        plants.simulate_batch("cart", ctrl, x0s, 1.0, sample_time="fast")


SCRIPT = """
import signal, sys, time
# A process started with SIGINT ignored (a background job of a non-interactive shell, as CI
# may start the tests) keeps it ignored and Python then installs no KeyboardInterrupt handler;
# Ctrl-C at a terminal always has one, so the test puts Python's own handler in place.
signal.signal(signal.SIGINT, signal.default_int_handler)
import numpy as np
from pendulab import plants
which = sys.argv[1]
if which == "vector":
    import pendulab.gym
    envs = pendulab.gym.RigVectorEnv(num_envs=1 << 18, rig="cart")
    envs.reset(seed=0)
    actions = np.zeros(1 << 18)
    def call():
        while True:
            envs.step(actions)
elif which == "feedback":
    x0s = np.zeros((4_000_000, 4)); x0s[:, 1] = 0.1
    call = lambda: plants.feedback_batch([-3.2, -13.5, -4.5, -2.3], x0s, 2.0)
else:
    ctrl = {"kind": "state-feedback", "k_book": [3.16228, 13.47175, 4.48137, 2.26289]}
    call = lambda: plants.simulate_batch("cart", ctrl, [[0, 0.05, 0, 0]] * 100_000, 10.0)
print("ready", flush=True)
try:
    call()
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", time.monotonic(), flush=True)
"""


@pytest.mark.skipif(os.name != "posix", reason="SIGINT delivery is POSIX")
@pytest.mark.parametrize("which", ["feedback", "simulate", "vector"])
def test_ctrl_c_interrupts_a_long_batch(which):
    p = subprocess.Popen(
        [sys.executable, "-c", SCRIPT, which], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        assert p.stdout.readline().strip() == "ready"
        time.sleep(0.5)  # well inside the batch, which takes minutes (a chunk: tens of ms)
        sent = time.monotonic()
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=30)
    finally:
        p.kill()
    words = out.split()
    assert words[:1] == ["interrupted"], (out, err)
    assert float(words[1]) - sent < 1.0
