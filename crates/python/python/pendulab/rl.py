"""Policy training on Ray without a deep-learning framework (``docs/studies.md``, "RL").

Two trainers, each with its rollouts as Ray tasks: **CMA-ES** (Hansen, "The CMA Evolution
Strategy: A Tutorial", 2016; :class:`CMAConfig`, which trained the committed swing-up policy:
candidates ``m + σ B D zₖ`` from the adapted covariance ``C = B D² Bᵀ``, computed in the
driver and shipped to the workers in chunks) and **Evolution Strategies** as in Salimans,
Ho, Chen, Sidor & Sutskever, "Evolution Strategies as a Scalable Alternative to
Reinforcement Learning" (2017; :class:`ESConfig`): a population of
``pairs`` antithetic perturbations ``θ ± σ εᵢ`` of the policy's parameters (``εᵢ`` standard
normal), each scored by its episodes' return on the native vector env, fitness shaped by
centred ranks (ranks scaled to ``[−0.5, 0.5]``), the gradient estimate
``g = Σᵢ (s⁺ᵢ − s⁻ᵢ) εᵢ / (2 · pairs · σ)`` followed by an Adam step (Kingma & Ba 2015) with
L2 weight decay. The policy is a small NumPy MLP (:class:`MlpPolicy`).

**Rollouts on Ray.** A generation's ``2 · pairs`` policies are cut into chunks of pairs; each
chunk is one Ray Core task (:func:`train` with ``backend="ray"``) that makes the registered
env by id (``gymnasium.make_vec(..., vectorization_mode="vector_entry_point")``: the native
:class:`pendulab.gym.RigVectorEnv`, one Rust call per step for all its environments) and
returns the chunk's returns. What is shipped per generation: the parameter vector (``ray.put``
once, a few kB) and each task's ``(generation, first pair, count)``; the perturbations are
regenerated on the worker from counter-based seeds ``(seed, generation, pair)``.

**Determinism.** Pair ``i`` of generation ``k`` draws its perturbation from
``numpy.random.default_rng([seed, k, i])``; the generation's episodes start from states drawn
from ``default_rng([seed, k])`` (the same for every policy of the generation: common random
numbers); the MLP is evaluated with element-wise NumPy operations only (no BLAS, whose
summation order may depend on the batch), so a policy's return does not depend on which
other policies share its batch. Hence training gives the same parameters bit for bit
whatever the chunking and the backend (local or Ray; ``tests/test_rl_ray.py`` checks it).

**The environment** :data:`ENV_ID` (registered on import, with RLlib's registry by
:func:`register_rllib`) is the book's cart rig swinging up from hanging with the rig's
imperfections: the controller sees the positions in whole encoder counts (4.8414·10⁻⁵ m,
2π/14400 rad), its voltage is quantised by the 16-bit D/A and saturated at ±5 V
(``docs/model.md`` §3); the policy acts every 10 ms, the plant is integrated by RK4 at 1 ms;
episodes of 6 s; reward ``(1 + cos θ)/2`` per step; the episode ends if the cart leaves its
0.4 m travel. :func:`swingup_success` is its success criterion.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import time
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Tuple, Union

import gymnasium
import numpy as np

from . import gym as _gym  # noqa: F401  (registers pendulab's base ids)
from ._native import __version__
from .errors import InvalidArgumentError

__all__ = [
    "ENV_ID",
    "ENV_KWARGS",
    "CMAConfig",
    "ESConfig",
    "FEATURES",
    "MlpPolicy",
    "TrainResult",
    "evaluate",
    "make_vec",
    "register_rllib",
    "rollout",
    "swingup_success",
    "time_to_upright",
    "train",
]

#: The cart rig's swing-up with the rig's imperfections (see the module documentation).
ENV_ID = "pendulab/CartRigSwingUpQuantized-v0"
#: Its keyword arguments of :class:`pendulab.gym.RigEnv` / :class:`~pendulab.gym.RigVectorEnv`.
ENV_KWARGS: Dict[str, Any] = {
    "rig": "cart",
    "task": "swingup",
    "dt": 0.01,
    "substeps": 10,
    "max_steps": 600,
    "quantize": True,
    "dac": True,
}
#: Success (:func:`swingup_success`): within this angle of upright (rad; the balance task's
#: window, 12°) ...
UPRIGHT_WINDOW = math.radians(12.0)
#: ... for every step of the episode's last this many seconds, never beyond the travel.
HOLD_SECONDS = 2.0


def _register() -> None:
    if ENV_ID not in gymnasium.registry:
        gymnasium.register(
            id=ENV_ID,
            entry_point="pendulab.gym:RigEnv",
            vector_entry_point="pendulab.gym:RigVectorEnv",
            kwargs=dict(ENV_KWARGS),
        )


_register()


def register_rllib(env_id: str = ENV_ID) -> str:
    """Registers ``env_id`` with Ray Tune's registry (``ray.tune.register_env``) so that
    RLlib's algorithms make it by name (``config.environment(env_id)``; RLlib itself needs
    PyTorch, which pendulab does not install). The creator takes RLlib's ``env_config`` as
    keyword arguments of ``gymnasium.make``. Returns ``env_id``."""
    from ray.tune.registry import register_env

    def creator(env_config: Optional[Mapping[str, Any]] = None):
        import pendulab.rl  # noqa: F401  (registers the id in the worker's gymnasium)

        return gymnasium.make(env_id, **dict(env_config or {}))

    register_env(env_id, creator)
    return env_id


def make_vec(num_envs: int, env_id: str = ENV_ID, **kwargs: Any):
    """The native vector env of ``env_id`` (``gymnasium.make_vec`` with the vector entry
    point), single-threaded unless ``threads`` is given."""
    kwargs.setdefault("threads", 1)
    return gymnasium.make_vec(env_id, num_envs=int(num_envs), vectorization_mode="vector_entry_point", **kwargs)


# ----------------------------------------------------------------------------------------
# The policy


#: Observation features of the MLP: ``[z/0.2, sin θ, cos θ, ż/1, θ̇/3]`` (SI states divided
#: by these scales, so that a balancing gain like the book's LQR is of order one per feature).
FEATURE_SCALE = (0.2, 1.0, 3.0)
#: The cart rig's pendulum frequency ``ω_np = √(m_p g l_p / J)`` (rad/s; book table 3.5,
#: ``docs/model.md`` §"Linearisation"), the scale of the ``"energy"`` feature.
OMEGA_NP = 5.7705
#: The observation feature sets of :class:`MlpPolicy`: ``"basic"`` the five above;
#: ``"energy"`` adds the pendulum's energy relative to the upright rest in units of
#: ``m_p g l_p``, ``e = (θ̇/ω_np)²/2 + cos θ − 1`` (−2 at the hanging rest, 0 at the upright
#: rest; book part 2 §3.2's ``E`` minus its upright value, divided by ``m_p g l_p``).
FEATURES = {"basic": 5, "energy": 6}


def _features(obs: np.ndarray, kind: str = "basic") -> list:
    z, th, dz, dth = obs[..., 0], obs[..., 1], obs[..., 2], obs[..., 3]
    c = np.cos(th)
    f = [z / FEATURE_SCALE[0], np.sin(th), c, dz / FEATURE_SCALE[1], dth / FEATURE_SCALE[2]]
    if kind == "energy":
        w = dth / OMEGA_NP
        f.append(0.5 * w * w + c - 1.0)
    return f


def _n_params(sizes: Sequence[int]) -> int:
    return sum((a + 1) * b for a, b in zip(sizes[:-1], sizes[1:]))


def _forward(params: np.ndarray, sizes: Sequence[int], obs: np.ndarray, u_max: float,
             features: str = "basic") -> np.ndarray:
    """The voltages of ``P`` policies (``params``: ``(P, D)``) for ``obs`` ``(P, E, 4)``:
    ``(P, E)``. Layer ``ℓ``: ``a ← tanh(b + Σₖ aₖ W[k, :])`` (the last layer without tanh),
    output ``u_max · tanh(·)``. Written with element-wise operations in a fixed order (the
    sum over ``k`` one input at a time), so each entry is the same bits whatever ``P`` and
    ``E`` are."""
    params = np.ascontiguousarray(params, dtype=np.float64)
    a = np.ascontiguousarray(np.stack(_features(np.asarray(obs, dtype=np.float64), features), axis=-1))
    o = 0
    nl = len(sizes) - 1
    for layer, (m, n) in enumerate(zip(sizes[:-1], sizes[1:])):
        W = params[:, o:o + m * n].reshape(-1, 1, m, n)
        o += m * n
        acc = np.empty(a.shape[:-1] + (n,))
        acc[...] = params[:, None, o:o + n]
        o += n
        for k in range(m):
            acc += a[:, :, k:k + 1] * W[:, :, k, :]
        a = np.tanh(acc) if layer < nl - 1 else acc
    return u_max * np.tanh(a[..., 0])


class MlpPolicy:
    """A multilayer perceptron ``u = u_max · tanh(MLP(features(obs)))`` (V) of the cart's
    observation ``[z, θ, ż, θ̇]`` (m, rad, m/s, rad/s): ``features`` (:data:`FEATURES`:
    ``"basic"`` ``[z/0.2, sin θ, cos θ, ż/1, θ̇/3]``, ``"energy"`` these and the pendulum's
    energy relative to upright), ``hidden`` layers of tanh units, one linear output.
    ``params`` is the flat vector of every layer's ``W`` (``m × n``, row-major) then ``b``,
    layer by layer."""

    def __init__(self, params: Sequence[float], hidden: Sequence[int] = (16,), u_max: float = 5.0,
                 meta: Optional[Mapping[str, Any]] = None, features: str = "basic"):
        if features not in FEATURES:
            raise InvalidArgumentError(f"rl: features {features!r}; expected one of {sorted(FEATURES)}")
        self.features = features
        self.hidden = tuple(int(h) for h in hidden)
        self.sizes = (FEATURES[features], *self.hidden, 1)
        self.params = np.array(params, dtype=np.float64).reshape(-1)
        self.u_max = float(u_max)
        self.meta = dict(meta or {})
        if self.params.size != _n_params(self.sizes):
            raise InvalidArgumentError(
                f"rl: {self.params.size} parameters for layers {self.sizes}; expected {_n_params(self.sizes)}")
        if not np.all(np.isfinite(self.params)):
            raise InvalidArgumentError("rl: the policy's parameters must be finite")

    @classmethod
    def initial(cls, hidden: Sequence[int] = (16,), seed: int = 0, u_max: float = 5.0,
                features: str = "basic") -> "MlpPolicy":
        """Hidden weights ``N(0, 1/m)`` for a layer of ``m`` inputs, drawn from
        ``default_rng([seed])``; biases and the output layer 0 (the initial policy commands
        0 V everywhere, as in Salimans et al.'s implementation, whose output layer starts
        near 0)."""
        if features not in FEATURES:
            raise InvalidArgumentError(f"rl: features {features!r}; expected one of {sorted(FEATURES)}")
        rng = np.random.default_rng([int(seed)])
        sizes = (FEATURES[features], *hidden, 1)
        parts = []
        for layer, (m, n) in enumerate(zip(sizes[:-1], sizes[1:])):
            w = rng.standard_normal(m * n) / math.sqrt(m)
            parts += [w if layer < len(sizes) - 2 else np.zeros(m * n), np.zeros(n)]
        return cls(np.concatenate(parts), hidden, u_max, features=features)

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        """The voltages ``(n,)`` for observations ``(n, 4)`` (or one ``(4,)``: a float)."""
        o = np.asarray(obs, dtype=np.float64)
        u = _forward(self.params[None, :], self.sizes, o.reshape(1, -1, 4), self.u_max, self.features)[0]
        return float(u[0]) if o.ndim == 1 else u

    def save(self, path: Union[str, os.PathLike], **meta: Any) -> None:
        """Writes ``params``, the layer sizes, ``u_max``, the feature set and ``meta`` (JSON:
        e.g. the seed and the command that trained it) to a ``.npz`` file."""
        m = {**self.meta, **meta}
        np.savez(os.fspath(path), params=self.params, hidden=np.array(self.hidden, dtype=np.int64),
                 u_max=np.float64(self.u_max), features=np.array(self.features),
                 meta=np.array(json.dumps(m, sort_keys=True)))

    @classmethod
    def load(cls, path: Union[str, os.PathLike]) -> "MlpPolicy":
        """Reads a file written by :meth:`save` (a file without a feature set: ``"basic"``)."""
        with np.load(os.fspath(path), allow_pickle=False) as z:
            features = str(z["features"]) if "features" in z.files else "basic"
            return cls(z["params"], tuple(int(h) for h in z["hidden"]), float(z["u_max"]),
                       json.loads(str(z["meta"])), features)

    def __repr__(self) -> str:
        return f"MlpPolicy(sizes={self.sizes}, features={self.features!r}, {self.params.size} parameters)"


# ----------------------------------------------------------------------------------------
# Rollouts


def _wrap(theta: np.ndarray) -> np.ndarray:
    return np.mod(theta + np.pi, 2 * np.pi) - np.pi


def swingup_success(theta: np.ndarray, terminated: Union[bool, np.ndarray], dt: float) -> np.ndarray:
    """The success criterion of :data:`ENV_ID`: the episode did not end beyond the travel and
    the pendulum stayed within :data:`UPRIGHT_WINDOW` (12°, the balance task's window) of
    upright at every step of its last :data:`HOLD_SECONDS` seconds. ``theta``: the angles
    after each step, ``(steps,)`` or ``(steps, n)``."""
    th = np.asarray(theta, dtype=np.float64)
    k = int(round(HOLD_SECONDS / dt))
    if th.shape[0] < k:  # an episode that ended before lasting that long did not succeed
        return np.zeros(th.shape[1:], dtype=bool)
    held = np.all(np.abs(_wrap(th[-k:])) <= UPRIGHT_WINDOW, axis=0)
    return held & ~np.asarray(terminated, dtype=bool)


def time_to_upright(theta: np.ndarray, dt: float) -> np.ndarray:
    """The time (s) from the start to the first sample after which the pendulum stays within
    :data:`UPRIGHT_WINDOW` of upright to the end, sample ``k`` (0-based) being at time
    ``(k + 1)·dt``; NaN where the last sample is outside. ``theta``: ``(steps,)`` or
    ``(steps, n)``."""
    th = np.asarray(theta, dtype=np.float64)
    inside = np.abs(_wrap(th)) <= UPRIGHT_WINDOW
    n = th.shape[0]
    # The last sample outside the window (−1 if none).
    last_out = np.where(inside.all(axis=0), -1, n - 1 - np.argmax(~inside[::-1], axis=0))
    return np.where(last_out < n - 1, (last_out + 2) * dt, np.nan)


def _starts(seed: int, generation: int, episodes: int, env_id: str, env_kwargs: Mapping[str, Any],
            anywhere: int = 0, angle: float = math.pi) -> np.ndarray:
    """The true initial states of a generation's episodes: the env's own reset distribution
    (uniform ±0.05 around hanging), the env of episode ``e`` seeded from
    ``default_rng([seed, generation])``; the last ``anywhere`` episodes instead with the
    pendulum angle uniform in ``[−angle, angle]`` about upright (drawn from the same
    generator)."""
    rng = np.random.default_rng([int(seed), int(generation)])
    seeds = rng.integers(0, 2**62, size=episodes)
    env = make_vec(1, env_id, **env_kwargs)
    out = []
    for s in seeds:
        env.reset(seed=int(s))
        out.append(env.state[0].copy())
    env.close()
    x = np.array(out)
    if anywhere:
        x[episodes - anywhere:, 1] = rng.uniform(-angle, angle, size=anywhere)
    return x


def _upright_still(x: np.ndarray) -> np.ndarray:
    """The upright-and-still bonus ``cos⁴⁰(θ/2) / (1 + (θ̇/2)²)`` of states ``x`` ``(n, 4)``:
    1 at the upright rest, 0.8 at 12° from upright, 0.26 at 30°, 0.003 at 60°; halved at
    ``|θ̇| = 2`` rad/s."""
    h = (1.0 + np.cos(x[:, 1])) * 0.5
    h2 = h * h
    h4 = h2 * h2
    h20 = h4 * h4 * h4 * h4 * h4
    return h20 / (1.0 + (x[:, 3] * 0.5) ** 2)


def _run(params: np.ndarray, sizes: Sequence[int], u_max: float, starts: np.ndarray, env_id: str,
         env_kwargs: Mapping[str, Any], record: bool = False, balance: bool = False, features: str = "basic",
         bonus: float = 0.0, termination_penalty: float = 0.0) -> Dict[str, np.ndarray]:
    """``P`` policies (``params`` ``(P, D)``) each from every row of ``starts`` ``(E, 4)`` on
    one native vector env of ``P·E`` environments for a whole episode (``max_steps``).
    Returns ``return`` (env reward summed up to the episode's end) and ``fitness`` (the
    shaped reward of :class:`ESConfig` plus ``bonus`` times the upright-and-still bonus of
    :class:`CMAConfig`, less ``termination_penalty`` per step an episode ended early by the
    travel did not run; with ``balance``, for the episodes that start within
    :data:`UPRIGHT_WINDOW` of upright it stops at the first step beyond it) as ``(P, E)``,
    ``terminated``, and with ``record``
    ``theta`` (``(steps, P, E)``, true angles), ``u`` (applied voltages) and ``x`` (states)."""
    P, E = params.shape[0], starts.shape[0]
    env = make_vec(P * E, env_id, **env_kwargs)
    core = env.unwrapped._core
    steps = int(core.max_steps)
    obs = core.reset_to(np.ascontiguousarray(np.tile(starts, (P, 1))))
    alive = np.ones(P * E, dtype=bool)
    ret = np.zeros(P * E)
    fit = np.zeros(P * E)
    terminated = np.zeros(P * E, dtype=bool)
    scoring = np.ones(P * E, dtype=bool)
    is_balance = np.tile(_is_balance(starts), P)
    rec_x, rec_u = [], []
    last_x, last_u = core.state.copy(), np.zeros(P * E)
    for k in range(steps):
        u = _forward(params, sizes, obs.reshape(P, E, 4), u_max, features).reshape(-1)
        obs, r, term, trunc, _ = env.step(u)
        x = core.state
        if record:
            # A finished episode keeps its last state (the env has moved on to a new one).
            last_x[alive] = x[alive]
            last_u[alive] = np.clip(u[alive], -5.0, 5.0)
            rec_x.append(last_x.copy())
            rec_u.append(last_u.copy())
        shaped = r * 0.25 * (1.0 + 1.0 / (1.0 + (x[:, 3] / 5.0) ** 2)) * (1.0 + 1.0 / (1.0 + (x[:, 0] / 0.2) ** 2))
        if bonus:
            shaped = shaped + bonus * _upright_still(x)
        ret += np.where(alive, r, 0.0)
        if balance:
            scoring &= ~(is_balance & (np.abs(_wrap(x[:, 1])) > UPRIGHT_WINDOW))
        fit += np.where(alive & scoring, shaped, 0.0)
        if termination_penalty:
            fit -= np.where(alive & term, termination_penalty * (steps - 1 - k), 0.0)
        terminated |= alive & term
        alive &= ~(term | trunc)
        if not alive.any():
            break
    env.close()
    out = {"return": ret.reshape(P, E), "fitness": fit.reshape(P, E), "terminated": terminated.reshape(P, E)}
    if record:
        xs = np.array(rec_x).reshape(len(rec_x), P, E, 4)
        out.update(x=xs, theta=xs[..., 1], u=np.array(rec_u).reshape(len(rec_u), P, E))
    return out


# ----------------------------------------------------------------------------------------
# Evolution Strategies


@dataclasses.dataclass(frozen=True)
class ESConfig:
    """Evolution Strategies' settings (Salimans et al. 2017; see the module documentation).

    ``pairs`` antithetic pairs per generation with noise scale ``sigma`` (on the parameters),
    each policy scored over ``episodes`` episodes; Adam with ``learning_rate`` (β₁ = 0.9,
    β₂ = 0.999, ε = 10⁻⁸) on ``−g + weight_decay · θ``; the MLP's ``hidden`` layers; the
    env ``env_id`` with ``env_kwargs`` overriding its registered arguments; ``seed`` fixes
    everything. ``fitness``: ``"shaped"`` ranks the env's reward ``r`` weighted per step by
    ``(1 + 1/(1 + (θ̇/5)²))/2 · (1 + 1/(1 + (z/0.2)²))/2`` (a spinning pendulum or a cart far
    from the centre earns less; after Tassa et al. 2018's cart-pole swing-up reward) and
    ``"return"`` ranks the env's return itself. ``anywhere``: of the ``episodes`` of a
    generation, this many start with the pendulum angle uniform in ``±anywhere_angle`` about
    upright instead of hanging. An episode that starts within 12° of upright (the balance
    task's window) is a balance episode: its fitness stops at the first step beyond the
    window. A policy's fitness is the weighted mean over its episodes, balance episodes
    weighted by ``balance_weight``, the others by 1. ``curriculum``: over this many
    generations the angle range grows linearly from 0.2 rad to ``anywhere_angle`` (the region
    the policy must catch the pendulum from widens as it learns)."""

    pairs: int = 32
    sigma: float = 0.5
    learning_rate: float = 0.2
    weight_decay: float = 0.005
    episodes: int = 4
    hidden: Tuple[int, ...] = (16,)
    u_max: float = 5.0
    env_id: str = ENV_ID
    env_kwargs: Mapping[str, Any] = dataclasses.field(default_factory=dict)
    fitness: str = "shaped"
    anywhere: int = 0
    anywhere_angle: float = math.pi
    balance_weight: float = 1.0
    curriculum: int = 0
    seed: int = 0

    def to_dict(self) -> Dict[str, Any]:
        """The settings as a JSON-able dict (tuples as lists)."""
        return _config_dict(self)

    def check(self) -> None:
        """Raises :class:`InvalidArgumentError` naming the first bad setting."""
        if self.pairs < 1:
            raise InvalidArgumentError("rl: pairs must be at least 1")
        _check_common(self)
        for name in ("sigma", "learning_rate"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise InvalidArgumentError(f"rl: {name} = {v}; it must be finite and positive")
        if not (math.isfinite(self.weight_decay) and self.weight_decay >= 0):
            raise InvalidArgumentError(f"rl: weight_decay = {self.weight_decay}; it must be ≥ 0")
        if self.fitness not in ("shaped", "return"):
            raise InvalidArgumentError(f"rl: fitness {self.fitness!r}; expected \"shaped\" or \"return\"")


def _config_dict(cfg: Any) -> Dict[str, Any]:
    d = dataclasses.asdict(cfg)
    return {k: (list(v) if isinstance(v, tuple) else dict(v) if k == "env_kwargs" else v) for k, v in d.items()}


def _check_common(cfg: Any) -> None:
    """The checks :class:`ESConfig` and :class:`CMAConfig` share: episodes, anywhere, seed."""
    if cfg.episodes < 1:
        raise InvalidArgumentError("rl: episodes must be at least 1")
    if not 0 <= cfg.anywhere <= cfg.episodes:
        raise InvalidArgumentError(f"rl: anywhere = {cfg.anywhere}; must be between 0 and episodes")
    if isinstance(cfg.seed, bool) or not 0 <= int(cfg.seed) < 2**63:
        raise InvalidArgumentError(f"rl: seed must be an integer in [0, 2⁶³), got {cfg.seed!r}")


def _is_balance(starts: np.ndarray) -> np.ndarray:
    return np.abs(_wrap(starts[:, 1])) <= UPRIGHT_WINDOW


def _noise(seed: int, generation: int, pair: int, d: int) -> np.ndarray:
    return np.random.default_rng([int(seed), int(generation), int(pair)]).standard_normal(d)


def _pairs_task(cfg: Mapping[str, Any], theta: np.ndarray, generation: int, start: int, count: int,
                starts: np.ndarray) -> Dict[str, np.ndarray]:
    """What a worker runs: pairs ``start .. start + count`` of a generation, each ``θ ± σ ε``
    over the generation's episodes. Returns ``fitness`` and ``return`` as ``(count, 2)``
    (``+``, ``−``), the mean over the episodes."""
    sizes = (5, *cfg["hidden"], 1)
    d = theta.size
    eps = np.array([_noise(cfg["seed"], generation, i, d) for i in range(start, start + count)])
    params = np.concatenate([theta + cfg["sigma"] * eps, theta - cfg["sigma"] * eps])
    out = _run(params, sizes, cfg["u_max"], starts, cfg["env_id"], cfg["env_kwargs"], balance=True)
    key = "fitness" if cfg["fitness"] == "shaped" else "return"
    w = np.where(_is_balance(starts), cfg["balance_weight"], 1.0)
    f = (out[key] * w).sum(axis=1).reshape(2, count).T / w.sum()
    r = out["return"].mean(axis=1).reshape(2, count).T
    return {"fitness": np.ascontiguousarray(f), "return": np.ascontiguousarray(r)}


def _centred_ranks(x: np.ndarray) -> np.ndarray:
    """Salimans et al.'s fitness shaping: the ranks of ``x`` (ties by index) scaled to
    ``[−0.5, 0.5]``."""
    flat = x.reshape(-1)
    r = np.empty(flat.size)
    r[np.argsort(flat, kind="stable")] = np.arange(flat.size)
    return (r / max(flat.size - 1, 1) - 0.5).reshape(x.shape)


class TrainResult:
    """A finished training: ``policy`` (:class:`MlpPolicy`), ``config`` (:class:`ESConfig`),
    ``history`` (per generation: ``mean_return`` and ``max_return`` of the population's
    policies, ``mean_fitness``, ``seconds``; CMA-ES also ``max_fitness`` and ``sigma``),
    ``generations``; ``adam`` the optimiser's state (Adam's for ES, the mean, step size,
    covariance and paths for CMA-ES; to continue with ``train(..., resume=result)``)."""

    def __init__(self, policy: MlpPolicy, config: Union[ESConfig, "CMAConfig"], history: Dict[str, np.ndarray],
                 adam: Dict[str, Any]):
        self.policy, self.config, self.history, self.adam = policy, config, history, adam
        self.generations = int(adam["t"])

    def __repr__(self) -> str:
        last = self.history["mean_return"][-1] if len(self.history["mean_return"]) else math.nan
        return f"TrainResult({self.generations} generations, last mean return {last:.1f})"


def _ray_task(fn: Callable, address: Optional[str], timeout: float, num_cpus: float, max_retries: int,
              resources: Optional[Dict[str, float]]):
    """``ray`` connected to ``address`` (:func:`pendulab.ray.connect`) and ``fn`` as a Ray task
    with these options."""
    from . import ray as pray

    ray = pray._ray()
    pray.connect(address, timeout=timeout)
    return ray, ray.remote(fn).options(num_cpus=num_cpus, resources=resources or {}, max_retries=int(max_retries))


def _chunks(n: int, chunk: int):
    if int(chunk) < 1:
        raise InvalidArgumentError(f"rl: chunk = {chunk}; needs at least 1")
    return [(s, min(chunk, n - s)) for s in range(0, n, chunk)]


def train(
    config: Union[ESConfig, "CMAConfig", None] = None,
    generations: int = 100,
    *,
    backend: str = "local",
    chunk: Optional[int] = None,
    initial: Optional[MlpPolicy] = None,
    resume: Optional[TrainResult] = None,
    progress: Optional[Callable[[int, Dict[str, float]], None]] = None,
    address: Optional[str] = None,
    timeout: float = 10.0,
    num_cpus: float = 1,
    max_retries: int = 3,
    resources: Optional[Dict[str, float]] = None,
) -> TrainResult:
    """Trains an :class:`MlpPolicy` by Evolution Strategies (an :class:`ESConfig`) or CMA-ES
    (a :class:`CMAConfig`) for ``generations`` generations.

    ``backend="local"`` evaluates the pairs (CMA-ES: the candidates) in this process in
    chunks of ``chunk`` pairs (candidates; default all); ``"ray"`` submits one Ray task per
    chunk (default ``ceil(pairs / 2)``-pair, ``ceil(popsize / 2)``-candidate chunks; each task asks for ``num_cpus`` CPUs and ``resources``
    and is retried up to ``max_retries`` times if its worker dies) after
    :func:`pendulab.ray.connect` to ``address`` (an unreachable one raises
    ``ConnectionError`` within ``timeout`` s). Same ``config`` (seed included) → same
    result bit for bit on either backend and for any ``chunk``. ``initial``: the starting
    policy (default :meth:`MlpPolicy.initial` of the seed; CMA-ES: the initial mean);
    ``resume``: continue a previous result (its policy and optimiser state; generation
    numbers continue). ``progress(generation,
    stats)`` after each generation."""
    cfg = config or ESConfig()
    cfg.check()
    if int(generations) < 0:
        raise InvalidArgumentError(f"rl: generations = {generations}; must be ≥ 0")
    if backend not in ("local", "ray"):
        raise InvalidArgumentError(f"rl: backend {backend!r}; expected \"local\" or \"ray\"")
    if isinstance(cfg, CMAConfig):
        return _train_cma(cfg, int(generations), backend, chunk, initial, resume, progress,
                          dict(address=address, timeout=timeout, num_cpus=num_cpus, max_retries=max_retries,
                               resources=resources))
    cd = cfg.to_dict()
    cd["env_kwargs"] = dict(cfg.env_kwargs)
    if resume is not None:
        policy = resume.policy
        adam = {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in resume.adam.items()}
        history = {k: list(v) for k, v in resume.history.items()}
    else:
        policy = initial or MlpPolicy.initial(cfg.hidden, cfg.seed, cfg.u_max)
        d = policy.params.size
        adam = {"m": np.zeros(d), "v": np.zeros(d), "t": 0}
        history = {"mean_return": [], "max_return": [], "mean_fitness": [], "seconds": []}
    if policy.hidden != tuple(cfg.hidden):
        raise InvalidArgumentError(f"rl: the initial policy's layers {policy.hidden} differ from the config's {cfg.hidden}")
    theta = policy.params.copy()
    ranges = _chunks(cfg.pairs, chunk or (cfg.pairs if backend == "local" else max(1, -(-cfg.pairs // 2))))
    if backend == "ray":
        ray, task = _ray_task(_pairs_task, address=address, timeout=timeout, num_cpus=num_cpus,
                              max_retries=max_retries, resources=resources)
        cfg_ref = ray.put(cd)
    b1, b2, eps_adam = 0.9, 0.999, 1e-8
    for _ in range(int(generations)):
        t0 = time.perf_counter()
        g = adam["t"]
        angle = cfg.anywhere_angle
        if cfg.curriculum > 0:
            angle = min(angle, 0.2 + (angle - 0.2) * g / cfg.curriculum)
        starts = _starts(cfg.seed, g, cfg.episodes, cfg.env_id, cfg.env_kwargs, cfg.anywhere, angle)
        if backend == "local":
            parts = [_pairs_task(cd, theta, g, s, c, starts) for s, c in ranges]
        else:
            th_ref = ray.put(theta)
            refs = [task.remote(cfg_ref, th_ref, g, s, c, starts) for s, c in ranges]
            parts = ray.get(refs)
        fit = np.concatenate([p["fitness"] for p in parts])
        ret = np.concatenate([p["return"] for p in parts])
        s = _centred_ranks(fit)
        grad = np.zeros_like(theta)
        for i in range(cfg.pairs):
            grad += (s[i, 0] - s[i, 1]) * _noise(cfg.seed, g, i, theta.size)
        grad /= 2 * cfg.pairs * cfg.sigma
        step = -grad + cfg.weight_decay * theta
        adam["t"] = g + 1
        adam["m"] = b1 * adam["m"] + (1 - b1) * step
        adam["v"] = b2 * adam["v"] + (1 - b2) * step * step
        mh = adam["m"] / (1 - b1 ** adam["t"])
        vh = adam["v"] / (1 - b2 ** adam["t"])
        theta = theta - cfg.learning_rate * mh / (np.sqrt(vh) + eps_adam)
        stats = {"mean_return": float(ret.mean()), "max_return": float(ret.max()),
                 "mean_fitness": float(fit.mean()), "seconds": time.perf_counter() - t0}
        for k, v in stats.items():
            history[k].append(v)
        if progress:
            progress(g, stats)
    meta = {"algorithm": "evolution strategies (Salimans et al. 2017)", "config": cd,
            "generations": int(adam["t"]), "pendulab_version": __version__}
    final = MlpPolicy(theta, cfg.hidden, cfg.u_max, meta)
    return TrainResult(final, cfg, {k: np.array(v) for k, v in history.items()}, adam)


# ----------------------------------------------------------------------------------------
# CMA-ES


@dataclasses.dataclass(frozen=True)
class CMAConfig:
    """CMA-ES's settings (Hansen, "The CMA Evolution Strategy: A Tutorial", 2016, with its
    default constants; see :func:`train`).

    Each generation samples ``popsize`` candidates ``m + σ B D zₖ`` (``zₖ`` standard normal
    from ``default_rng([seed, generation, k])``, ``C = B D² Bᵀ``), scores each over
    ``episodes`` episodes and moves the mean to the weighted mean of the best
    ``popsize // 2`` (log-linear weights), adapting ``C`` (rank-one and rank-μ updates) and
    ``σ`` (cumulative step-size adaptation); initial step size ``sigma`` (on the
    parameters), initial ``C = I``. The policy: an :class:`MlpPolicy` with ``hidden`` tanh
    layers on the ``features`` (:data:`FEATURES`). The fitness of an episode is the shaped
    reward of :class:`ESConfig` plus ``bonus`` times the upright-and-still bonus
    ``cos⁴⁰(θ/2) / (1 + (θ̇/2)²)`` per step, less ``termination_penalty`` for every step the
    episode did not run because the cart left its travel; a candidate's fitness is the
    weighted mean over its episodes (balance episodes, those starting within 12° of upright,
    weighted by ``balance_weight`` and scored only until they first leave the window). The
    episodes start from the env's reset distribution with uniform offsets within
    ``±spread`` (``[z, θ, ż, θ̇]``: m, rad, m/s, rad/s) added, drawn from
    ``default_rng([seed, generation, 2⁶²])``; of them, the last ``anywhere`` start with the
    angle uniform in ``±anywhere_angle`` about upright instead (no offsets). ``env_id`` with
    ``env_kwargs`` overriding its registered arguments; ``seed`` fixes everything."""

    popsize: int = 32
    sigma: float = 0.5
    episodes: int = 4
    hidden: Tuple[int, ...] = (16,)
    features: str = "energy"
    u_max: float = 5.0
    env_id: str = ENV_ID
    env_kwargs: Mapping[str, Any] = dataclasses.field(default_factory=dict)
    bonus: float = 2.0
    termination_penalty: float = 1.0
    spread: Tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
    anywhere: int = 0
    anywhere_angle: float = 0.15
    balance_weight: float = 1.0
    seed: int = 0

    def to_dict(self) -> Dict[str, Any]:
        """The settings as a JSON-able dict (tuples as lists)."""
        return _config_dict(self)

    def check(self) -> None:
        """Raises :class:`InvalidArgumentError` naming the first bad setting."""
        if self.popsize < 4:
            raise InvalidArgumentError("rl: popsize must be at least 4")
        _check_common(self)
        if not (math.isfinite(self.sigma) and self.sigma > 0):
            raise InvalidArgumentError(f"rl: sigma = {self.sigma}; it must be finite and positive")
        if self.features not in FEATURES:
            raise InvalidArgumentError(f"rl: features {self.features!r}; expected one of {sorted(FEATURES)}")
        vals = [self.bonus, self.termination_penalty, self.balance_weight, self.anywhere_angle]
        if len(self.spread) != 4 or not all(math.isfinite(v) and v >= 0 for v in [*self.spread, *vals]):
            raise InvalidArgumentError("rl: spread (4 values), bonus, termination_penalty, balance_weight and "
                                       "anywhere_angle must be finite and ≥ 0")


def _cma_starts(cfg: "CMAConfig", generation: int) -> np.ndarray:
    x = _starts(cfg.seed, generation, cfg.episodes, cfg.env_id, cfg.env_kwargs, cfg.anywhere, cfg.anywhere_angle)
    n = cfg.episodes - cfg.anywhere
    if n and any(cfg.spread):
        rng = np.random.default_rng([int(cfg.seed), int(generation), 2**62])
        x[:n] += rng.uniform(-1.0, 1.0, size=(n, 4)) * np.asarray(cfg.spread, dtype=np.float64)
    return x


def _candidates_task(cfg: Mapping[str, Any], params: np.ndarray, starts: np.ndarray) -> Dict[str, np.ndarray]:
    """What a worker runs for CMA-ES: the candidates ``params`` ``(count, D)`` over the
    generation's episodes. Returns ``fitness`` (weighted mean) and ``return`` (mean) as
    ``(count,)``."""
    sizes = (FEATURES[cfg["features"]], *cfg["hidden"], 1)
    out = _run(params, sizes, cfg["u_max"], starts, cfg["env_id"], cfg["env_kwargs"], balance=True,
               features=cfg["features"], bonus=cfg["bonus"], termination_penalty=cfg["termination_penalty"])
    w = np.where(_is_balance(starts), cfg["balance_weight"], 1.0)
    return {"fitness": (out["fitness"] * w).sum(axis=1) / w.sum(), "return": out["return"].mean(axis=1)}


def _train_cma(cfg: CMAConfig, generations: int, backend: str, chunk: Optional[int], initial: Optional[MlpPolicy],
               resume: Optional[TrainResult], progress, ray_opts: Dict[str, Any]) -> TrainResult:
    cd = cfg.to_dict()
    if resume is not None:
        st = {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in resume.adam.items()}
        history = {k: list(v) for k, v in resume.history.items()}
        policy = resume.policy
    else:
        policy = initial or MlpPolicy.initial(cfg.hidden, cfg.seed, cfg.u_max, cfg.features)
        d = policy.params.size
        st = {"mean": policy.params.copy(), "sigma": float(cfg.sigma), "C": np.eye(d), "pc": np.zeros(d),
              "ps": np.zeros(d), "t": 0}
        history = {k: [] for k in ("mean_return", "max_return", "mean_fitness", "max_fitness", "sigma", "seconds")}
    if policy.hidden != tuple(cfg.hidden) or policy.features != cfg.features:
        raise InvalidArgumentError(f"rl: the initial policy's layers {policy.sizes} differ from the config's "
                                   f"{(FEATURES[cfg.features], *cfg.hidden, 1)}")
    n, lam = policy.params.size, int(cfg.popsize)
    mu = lam // 2
    w = np.log(mu + 0.5) - np.log(np.arange(1, mu + 1))
    w /= w.sum()
    mueff = 1.0 / float(np.sum(w * w))
    cc = (4 + mueff / n) / (n + 4 + 2 * mueff / n)
    cs = (mueff + 2) / (n + mueff + 5)
    c1 = 2 / ((n + 1.3) ** 2 + mueff)
    cmu = min(1 - c1, 2 * (mueff - 2 + 1 / mueff) / ((n + 2) ** 2 + mueff))
    damps = 1 + 2 * max(0.0, math.sqrt((mueff - 1) / (n + 1)) - 1) + cs
    chi_n = math.sqrt(n) * (1 - 1 / (4 * n) + 1 / (21 * n * n))
    ranges = _chunks(lam, chunk or (lam if backend == "local" else max(1, -(-lam // 2))))
    if backend == "ray":
        ray, task = _ray_task(_candidates_task, **ray_opts)
        cfg_ref = ray.put(cd)
    for _ in range(generations):
        t0 = time.perf_counter()
        g = st["t"]
        m, sigma, C = st["mean"], st["sigma"], st["C"]
        evals, B = np.linalg.eigh(C)
        D = np.sqrt(np.maximum(evals, 1e-20))
        Z = np.array([_noise(cfg.seed, g, k, n) for k in range(lam)])
        Y = (Z * D) @ B.T
        X = m + sigma * Y
        starts = _cma_starts(cfg, g)
        if backend == "local":
            parts = [_candidates_task(cd, X[s:s + c], starts) for s, c in ranges]
        else:
            refs = [task.remote(cfg_ref, X[s:s + c], starts) for s, c in ranges]
            parts = ray.get(refs)
        fit = np.concatenate([p["fitness"] for p in parts])
        ret = np.concatenate([p["return"] for p in parts])
        order = np.argsort(-fit, kind="stable")[:mu]
        ysel = Y[order]
        yw = w @ ysel
        m = m + sigma * yw
        ps = (1 - cs) * st["ps"] + math.sqrt(cs * (2 - cs) * mueff) * (B @ ((B.T @ yw) / D))
        hsig = float(np.linalg.norm(ps) / math.sqrt(1 - (1 - cs) ** (2 * (g + 1))) / chi_n < 1.4 + 2 / (n + 1))
        pc = (1 - cc) * st["pc"] + hsig * math.sqrt(cc * (2 - cc) * mueff) * yw
        c1a = c1 * (1 - (1 - hsig) * cc * (2 - cc))
        C = (1 - c1a - cmu) * C + c1 * np.outer(pc, pc) + cmu * (ysel.T * w) @ ysel
        C = (C + C.T) * 0.5
        sigma = sigma * math.exp((cs / damps) * (float(np.linalg.norm(ps)) / chi_n - 1))
        st = {"mean": m, "sigma": sigma, "C": C, "pc": pc, "ps": ps, "t": g + 1}
        stats = {"mean_return": float(ret.mean()), "max_return": float(ret.max()), "mean_fitness": float(fit.mean()),
                 "max_fitness": float(fit.max()), "sigma": sigma, "seconds": time.perf_counter() - t0}
        for k, v in stats.items():
            history[k].append(v)
        if progress:
            progress(g, stats)
    meta = {"algorithm": "CMA-ES (Hansen 2016)", "config": cd, "generations": int(st["t"]),
            "pendulab_version": __version__}
    final = MlpPolicy(st["mean"], cfg.hidden, cfg.u_max, meta, cfg.features)
    return TrainResult(final, cfg, {k: np.array(v) for k, v in history.items()}, st)


# ----------------------------------------------------------------------------------------
# Evaluation


def rollout(policy: MlpPolicy, x0: Sequence[float], env_id: str = ENV_ID, **env_kwargs: Any) -> Dict[str, Any]:
    """One episode of ``policy`` from the true state ``x0`` on ``env_id``: ``t`` (s, after
    each step), ``x`` (states), ``u`` (voltages applied, V), ``return``, ``terminated``,
    ``success`` (:func:`swingup_success`)."""
    x0 = np.asarray(x0, dtype=np.float64).reshape(1, 4)
    out = _run(policy.params[None, :], policy.sizes, policy.u_max, x0, env_id, env_kwargs, record=True,
               features=policy.features)
    dt = float(make_vec(1, env_id, **env_kwargs).unwrapped._core.dt)
    x = out["x"][:, 0, 0]
    n = x.shape[0]
    term = bool(out["terminated"][0, 0])
    return {"t": dt * np.arange(1, n + 1), "x": x, "u": out["u"][:, 0, 0], "return": float(out["return"][0, 0]),
            "terminated": term, "success": bool(swingup_success(x[:, 1], term, dt)) if n >= HOLD_SECONDS / dt else False}


def evaluate(policy: MlpPolicy, states: np.ndarray, env_id: str = ENV_ID, **env_kwargs: Any) -> Dict[str, np.ndarray]:
    """``policy`` from each row of ``states`` (true states ``[z, θ, ż, θ̇]``) for one episode
    on ``env_id``, all in one native vector env. Per episode: ``return``, ``terminated``,
    ``success`` (:func:`swingup_success`), ``time_to_upright`` (s, :func:`time_to_upright`;
    NaN unless successful),
    ``peak_voltage`` (V, the largest |command|; within ±5 V by the policy's ``u_max``),
    ``max_travel`` (m, the largest |z|)."""
    st = np.asarray(states, dtype=np.float64).reshape(-1, 4)
    out = _run(policy.params[None, :], policy.sizes, policy.u_max, st, env_id, env_kwargs, record=True,
               features=policy.features)
    dt = float(make_vec(1, env_id, **env_kwargs).unwrapped._core.dt)
    th = out["theta"][:, 0, :]
    tu = time_to_upright(th, dt)
    term = out["terminated"][0]
    success = swingup_success(th, term, dt)
    return {"return": out["return"][0], "terminated": term, "success": success,
            "time_to_upright": np.where(success, tu, np.nan),
            "peak_voltage": np.abs(out["u"][:, 0, :]).max(axis=0),
            "max_travel": np.abs(out["x"][:, 0, :, 0]).max(axis=0)}
