"""Gymnasium environments stepped in Rust, registered on ``import pendulab.gym``.

=============================== =====================================================
id                              what
=============================== =====================================================
``pendulab/CartPole-v1``        drop-in ``CartPole-v1``: Gymnasium's own cart-pole
                                (Barto, Sutton & Anderson 1983; Euler steps of 0.02 s,
                                ±10 N, ±2.4 m / ±12°, reward 1 per step, 500 steps),
                                the same trajectories as Gymnasium's for the same seed
                                and actions; ``make_vec`` gives the native vector env
``pendulab/CartRig-v0``         the book's cart rig (table 3.5), balance: motor
                                voltage in (``Box(±5 V)``), state ``[z, θ, ż, θ̇]``
                                out, RK4 over 0.02 s, reward 1 per step, ends beyond
                                12° or the 0.4 m travel, 500 steps
``pendulab/CartRigSwingUp-v0``  the cart rig from hanging, reward ``(1 + cos θ)/2``,
                                ends beyond the travel only
``pendulab/ArmRig-v0``          the book's arm rig (table 3.7), balance, travel 3 rad
``pendulab/ArmRigSwingUp-v0``   the arm rig from hanging
=============================== =====================================================

Every environment has a native vector version (:class:`CartPoleVectorEnv`,
:class:`RigVectorEnv`, a ``gymnasium.vector.VectorEnv``) that steps all its environments in
one call into Rust with the GIL released, on several threads for large batches, with
Gymnasium 1.x's default autoreset (``AutoresetMode.NEXT_STEP``: the step after an episode's
end returns the new episode's first observation with reward 0).

Seeding: the cart-pole draws its initial states from the environment's ``np_random`` exactly
as Gymnasium does; the rigs' initial states come from the Rust environment's own ChaCha8
generator, re-seeded by ``reset(seed=s)`` (a vector env seeds environment ``i`` with
``s + i``, as ``SyncVectorEnv`` does).
"""

from __future__ import annotations

import os
from typing import Any, Optional

import gymnasium
import numpy as np
from gymnasium import logger, spaces
from gymnasium.envs.classic_control import utils
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from . import _native

__all__ = ["CartPoleEnv", "CartPoleVectorEnv", "RigEnv", "RigVectorEnv"]

_THETA_THRESHOLD = 12 * 2 * np.pi / 360
_X_THRESHOLD = 2.4


def _cartpole_spaces():
    high = np.array(
        [_X_THRESHOLD * 2, np.inf, _THETA_THRESHOLD * 2, np.inf], dtype=np.float32
    )
    return spaces.Discrete(2), spaces.Box(-high, high, dtype=np.float32)


def _render_mode(render_mode: Optional[str]) -> Optional[str]:
    """``None`` or ``"rgb_array"``; ``"human"`` (a window) is not provided."""
    if render_mode not in (None, "rgb_array"):
        raise _native.InvalidArgumentError(
            f"render_mode {render_mode!r}: only 'rgb_array' is provided (no window); "
            "show the frames with matplotlib or save them"
        )
    return render_mode


def _threads(threads: Optional[int]) -> int:
    return max(1, os.cpu_count() or 1) if threads is None else int(threads)


class CartPoleEnv(gymnasium.Env):
    """Gymnasium's ``CartPole-v1`` with the dynamics stepped in Rust.

    State ``[x, ẋ, θ, θ̇]`` (m, m/s, rad, rad/s; float64 inside, float32 observations);
    action 0 pushes the cart with −10 N, 1 with +10 N, for one Euler step of 0.02 s. Reward
    1 per step including the terminating one (0 afterwards), or with
    ``sutton_barto_reward`` 0 per step and −1 from termination on. Terminates at
    ``|x| > 2.4`` or ``|θ| > 12°``; truncation at 500 steps comes from ``TimeLimit`` when
    made with ``gymnasium.make("pendulab/CartPole-v1")``, as for Gymnasium's.
    ``reset(options={"low": ..., "high": ...})`` changes the initial-state bounds.
    ``render_mode="rgb_array"``: ``render()`` returns the cart and pole as an ``(320, 480, 3)``
    ``uint8`` picture (pole drawn 1 m long, track ±2.4 m).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 50}

    def __init__(self, sutton_barto_reward: bool = False, render_mode: Optional[str] = None):
        self._core = _native.ClassicCartPoleCore(
            1, autoreset=False, sutton_barto_reward=sutton_barto_reward
        )
        self.action_space, self.observation_space = _cartpole_spaces()
        self.render_mode = _render_mode(render_mode)
        self.state: Optional[np.ndarray] = None
        self._beyond: Optional[int] = None

    def step(self, action):
        if self.state is None:
            raise _native.InvalidArgumentError("call reset before step")
        if not self.action_space.contains(action):
            raise _native.InvalidArgumentError(
                f"{action!r} ({type(action)}) is not an action of {self.action_space}"
            )
        obs, reward, terminated, _ = self._core.step(np.array([int(action)], dtype=np.int64))
        if terminated[0]:
            if self._beyond is None:
                self._beyond = 0
            else:
                if self._beyond == 0:
                    logger.warn(
                        "You are calling 'step()' even though this environment has already "
                        "returned terminated = True. You should always call 'reset()' once you "
                        "receive 'terminated = True' -- any further steps are undefined behavior."
                    )
                self._beyond += 1
        self.state = self._core.state[0]
        return obs[0], float(reward[0]), bool(terminated[0]), False, {}

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        low, high = utils.maybe_parse_reset_bounds(options, -0.05, 0.05)
        self.state = self.np_random.uniform(low=low, high=high, size=(4,))
        obs = self._core.reset_to(self.state[None, :])
        self._beyond = None
        return obs[0], {}

    def render(self):
        if self.render_mode == "rgb_array" and self.state is not None:
            x, x_dot, theta, theta_dot = (float(v) for v in self.state)
            return _native.render_rig("cart", [x, theta, x_dot, theta_dot], 2.4, pendulum_length=1.0)
        return None


class CartPoleVectorEnv(VectorEnv):
    """``num_envs`` cart-poles (:class:`CartPoleEnv`'s dynamics) stepped in one Rust call.

    The same trajectories as Gymnasium's ``CartPoleVectorEnv`` (``gymnasium.make_vec(
    "CartPole-v1", vectorization_mode="vector_entry_point")``) for the same seed and actions:
    initial states from ``np_random`` in the same order, autoreset on the next step, truncation
    at ``max_episode_steps``, float32 observations and rewards. ``threads`` (default: all
    cores) rayon threads step batches larger than 512 environments.
    """

    metadata = {
        "render_modes": [],
        "render_fps": 50,
        "autoreset_mode": AutoresetMode.NEXT_STEP,
    }

    def __init__(
        self,
        num_envs: int = 1,
        max_episode_steps: int = 500,
        render_mode: Optional[str] = None,
        sutton_barto_reward: bool = False,
        threads: Optional[int] = None,
    ):
        self.num_envs = num_envs
        self.max_episode_steps = max_episode_steps
        self.render_mode = render_mode
        self._core = _native.ClassicCartPoleCore(
            num_envs,
            autoreset=True,
            max_episode_steps=max_episode_steps,
            sutton_barto_reward=sutton_barto_reward,
            threads=_threads(threads),
        )
        self.single_action_space, self.single_observation_space = _cartpole_spaces()
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.low, self.high = -0.05, 0.05
        self._reset_done = False

    @property
    def state(self) -> np.ndarray:
        """The states, ``(num_envs, 4)`` float64."""
        return self._core.state

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        self.low, self.high = utils.maybe_parse_reset_bounds(options, -0.05, 0.05)
        state = self.np_random.uniform(low=self.low, high=self.high, size=(4, self.num_envs))
        obs = self._core.reset_to(state.T)
        self._reset_done = True
        return obs, {}

    def step(self, actions):
        if not self._reset_done:
            raise _native.InvalidArgumentError("call reset before step")
        actions = np.ascontiguousarray(actions, dtype=np.int64).reshape(-1)
        k = self._core.pending_resets
        fresh = (
            self.np_random.uniform(low=self.low, high=self.high, size=(4, k)) if k else None
        )
        obs, reward, terminated, truncated = self._core.step(actions, fresh)
        return obs, reward, terminated, truncated, {}


class RigEnv(gymnasium.Env):
    """The book's cart or arm rig as a Gymnasium environment, stepped in Rust.

    Parameters
    ----------
    rig : ``"cart"`` (state ``[z, θ, ż, θ̇]``: m, rad, m/s, rad/s) or ``"arm"``
        (``[θ₁, θ₂, θ̇₁, θ̇₂]``: rad, rad/s); angles from the upward vertical.
    task : ``"balance"`` (start uniform in ±0.05 around upright, reward 1 per step, ends
        beyond 12° or the travel) or ``"swingup"`` (start around hanging, reward
        ``(1 + cos θ)/2`` of the pendulum angle, ends beyond the travel only).
    dt : control period (s); the voltage is held over it and the plant integrated by
        ``substeps`` classic RK4 steps.
    max_steps : steps before truncation (default 500).
    travel : drive travel (default: the rig's ``RigSpec::travel_limit``, 0.4 m for the cart and
        3 rad for the arm; ``docs/model.md``).
    quantize : observe the positions quantised by the rig's encoders (cart
        4.8414·10⁻⁵ m and 2π/14400 rad per count; arm 2π/200000 and 2π/14400 rad).
    dac : the voltage quantised by the rig's 16-bit D/A converter over ±5 V (steps of
        10/2¹⁶ V, round to nearest; ``RigSpec::dac``).
    params : the plant's parameters by the book's symbols (others from tables 3.5 / 3.7).

    The action is the motor voltage, ``Box(-5, 5, (1,), float32)``, clipped to ±5 V.
    ``render_mode="rgb_array"``: ``render()`` returns the rig at its state as an
    ``(320, 480, 3)`` ``uint8`` picture (the drawing of the book's figures).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 50}

    def __init__(self, rig: str = "cart", task: str = "balance", render_mode: Optional[str] = None, **options: Any):
        self._core = _native.RigCore(rig, 1, task=task, autoreset=False, **options)
        self.rig, self.task, self.dt, self.travel = rig, task, self._core.dt, self._core.travel
        self.render_mode = _render_mode(render_mode)
        self.metadata = {**self.metadata, "render_fps": round(1.0 / self.dt)}
        self.action_space = spaces.Box(-5.0, 5.0, shape=(1,), dtype=np.float32)
        self.observation_space = spaces.Box(-np.inf, np.inf, shape=(4,), dtype=np.float64)
        self._seeded = False

    @property
    def state(self) -> np.ndarray:
        """The plant's state (not quantised), float64."""
        return self._core.state[0]

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        if seed is not None:
            seeds = [int(seed)]
        elif not self._seeded:
            seeds = [int(self.np_random.integers(0, 2**63))]
        else:
            seeds = None
        self._seeded = True
        return self._core.reset(seeds)[0], {}

    def render(self):
        if self.render_mode == "rgb_array":
            return _native.render_rig(self.rig, self.state.tolist(), self.travel)
        return None

    def step(self, action):
        a = np.asarray(action, dtype=np.float64).reshape(-1)
        if a.shape != (1,):
            raise _native.ShapeError(f"action must hold one voltage, got shape {np.shape(action)}")
        obs, reward, terminated, truncated = self._core.step(a)
        return obs[0], float(reward[0]), bool(terminated[0]), bool(truncated[0]), {}


class RigVectorEnv(VectorEnv):
    """``num_envs`` :class:`RigEnv` environments stepped in one Rust call.

    Step for step the same as ``SyncVectorEnv`` over ``num_envs`` :class:`RigEnv` with the
    same arguments (environment ``i`` seeded with ``seed + i``, autoreset on the next step,
    each environment's generator continuing). ``threads`` (default: all cores) rayon threads
    step batches larger than 512 environments. Other arguments (``dt``, ``substeps``,
    ``max_steps``, ``travel``, ``quantize``, ``dac``, ``params``) as :class:`RigEnv`.
    """

    metadata = {"render_modes": [], "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(
        self,
        num_envs: int = 1,
        rig: str = "cart",
        task: str = "balance",
        render_mode: Optional[str] = None,
        threads: Optional[int] = None,
        **options: Any,
    ):
        self.num_envs = num_envs
        self.render_mode = render_mode
        self._core = _native.RigCore(
            rig, num_envs, task=task, autoreset=True, threads=_threads(threads), **options
        )
        self.travel = self._core.travel
        self.single_action_space = spaces.Box(-5.0, 5.0, shape=(1,), dtype=np.float32)
        self.single_observation_space = spaces.Box(
            -np.inf, np.inf, shape=(4,), dtype=np.float64
        )
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self._seeded = False

    @property
    def state(self) -> np.ndarray:
        """The plants' states, ``(num_envs, 4)`` float64 (not quantised)."""
        return self._core.state

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        if seed is not None:
            seeds = [int(seed) + i for i in range(self.num_envs)]
        elif not self._seeded:
            base = int(self.np_random.integers(0, 2**62))
            seeds = [base + i for i in range(self.num_envs)]
        else:
            seeds = None
        self._seeded = True
        return self._core.reset(seeds), {}

    def step(self, actions):
        a = np.ascontiguousarray(actions, dtype=np.float64).reshape(-1)
        obs, reward, terminated, truncated = self._core.step(a)
        return obs, reward, terminated, truncated, {}


def _register() -> None:
    def reg(id: str, entry: str, vector: str, **kw: Any) -> None:
        if id not in gymnasium.registry:
            gymnasium.register(
                id=id,
                entry_point=f"pendulab.gym:{entry}",
                vector_entry_point=f"pendulab.gym:{vector}",
                **kw,
            )

    reg(
        "pendulab/CartPole-v1",
        "CartPoleEnv",
        "CartPoleVectorEnv",
        max_episode_steps=500,
        reward_threshold=475.0,
    )
    for rig in ("cart", "arm"):
        for task, suffix in (("balance", ""), ("swingup", "SwingUp")):
            reg(
                f"pendulab/{rig.capitalize()}Rig{suffix}-v0",
                "RigEnv",
                "RigVectorEnv",
                kwargs={"rig": rig, "task": task},
            )


_register()
