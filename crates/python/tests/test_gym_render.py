"""render_mode="rgb_array": the environments draw the rig at their state (the drawing of
``pendulab-plot``'s rig animations) as H × W × 3 uint8 frames; the pendulum's bob is where the
state puts it; Gymnasium's ``check_env`` passes with rendering; "human" is refused clearly."""

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import pendulab as pl
import pendulab.gym  # noqa: F401
from pendulab import _native


def bob_x(frame):
    """Column of the centroid of the bob's (red) pixels."""
    r, g, b = (frame[..., i].astype(int) for i in range(3))
    ys, xs = np.nonzero((r > 150) & (g < 90) & (b < 90))
    assert xs.size > 20
    return xs.mean()


def test_the_bob_follows_the_pendulum_angle():
    w = 480
    upright = _native.render_rig("cart", [0.0, 0.0, 0.0, 0.0], 0.4)
    right = _native.render_rig("cart", [0.0, 0.3, 0.0, 0.0], 0.4)
    left = _native.render_rig("cart", [0.0, -0.3, 0.0, 0.0], 0.4)
    assert upright.shape == (320, w, 3) and upright.dtype == np.uint8
    # θ from the upward vertical, positive to the right; the picture is mirror-symmetric
    # about the cart's centre (to a pixel of anti-aliasing).
    assert bob_x(left) < bob_x(upright) < bob_x(right)
    assert abs((bob_x(right) - bob_x(upright)) - (bob_x(upright) - bob_x(left))) < 1.5
    # The cart moves with z: half the rail (0.2 of ±0.4 m) moves everything right.
    moved = _native.render_rig("cart", [0.2, 0.0, 0.0, 0.0], 0.4)
    assert bob_x(moved) > bob_x(upright) + 50
    arm = _native.render_rig("arm", [0.5, 0.2, 0.0, 0.0], 3.0)
    assert arm.shape == (320, w, 3) and not np.array_equal(arm, upright)
    with pytest.raises(pl.InvalidArgumentError):
        _native.render_rig("boat", [0.0] * 4, 1.0)


@pytest.mark.parametrize("id", ["pendulab/CartPole-v1", "pendulab/CartRig-v0", "pendulab/ArmRigSwingUp-v0"])
def test_envs_render_rgb_arrays(id):
    env = gymnasium.make(id, render_mode="rgb_array")
    env.reset(seed=3)
    first = env.render()
    assert first.shape == (320, 480, 3) and first.dtype == np.uint8
    for _ in range(5):
        env.step(env.action_space.sample())
    assert not np.array_equal(env.render(), first)
    check_env(env.unwrapped, skip_render_check=False)


def test_human_mode_is_refused_with_a_reason():
    with pytest.raises(pl.InvalidArgumentError, match="rgb_array"):
        pendulab.gym.RigEnv(render_mode="human")
    with pytest.raises(pl.InvalidArgumentError, match="rgb_array"):
        pendulab.gym.CartPoleEnv(render_mode="human")
