"""The book's pendulums: the cart-type (table 3.5) and arm-type (table 3.7) rigs as models.

``CartPendulum(params=None)`` and ``ArmPendulum(params=None)`` hold validated parameters (the
book's values, each overridable by its symbol in ``params``; invalid or unknown ones raise
``pendulab.InvalidArgumentError`` naming the parameter) and give, over ``pendulab-plants``:

- ``derivative(x, u)``: the nonlinear right-hand side ``ẋ = f(x, u)``;
- ``jacobian(x, u)``: the analytic ``(A, B)`` at any point;
- ``linearize(posture="upright", z=0.0 | theta1=0.0, measured=False)``: ``(A, B, C, D)`` at a
  rest, in deviation variables, ``C = I`` or the encoder rows;
- ``lpv()`` (arm): ``(A₀, A₁, B₀, B₁)`` with ``A(ρ) = A₀ + ρ A₁``, ``ρ = 1 − cos θ₁``;
- ``energy(x)``, ``upright_energy``: the pendulum's energy (0 hanging at rest).

Conventions (``docs/model.md``): SI units and radians, angles from the **upward** vertical;
cart state ``[z, θ, ż, θ̇]``, arm state ``[θ₁, θ₂, θ̇₁, θ̇₂]`` (``θ₂`` absolute); the input is
the motor voltage ``v`` (V), ±5 V on the rigs. Cart:
``z̈ = −a_c ż + b_c v``, ``J θ̈ + m_p l_p cos θ z̈ = m_p g l_p sin θ − μ_p θ̇``,
``J = J_p + m_p l_p²``.
"""

import json
from typing import Any, Mapping, Optional, Sequence, Union

import numpy as np

from ._native import ArmPendulum, CartPendulum, batch_feedback, batch_simulate_json, simulate_json

__all__ = ["CartPendulum", "ArmPendulum", "Trajectory", "simulate", "simulate_batch", "feedback_batch"]


class Trajectory:
    """A simulated run: ``t`` (s), ``x`` (states, one row per sample), ``u`` (plant input,
    V), ``command`` (controller output before the actuator chain, V), ``y`` (what the
    controller measured), ``reference``, ``ts``, ``switch_times`` and ``summary`` (dict:
    settling time, overshoot, peak input, time in saturation, ...)."""

    def __init__(self, d: Mapping[str, Any]):
        self.t, self.x, self.u = d["t"], d["x"], d["u"]
        self.command, self.y, self.reference = d["command"], d["y"], d["reference"]
        self.ts, self.switch_times, self.summary = d["ts"], d["switch_times"], d["summary"]

    def to_pandas(self):
        """The samples as a ``pandas.DataFrame`` indexed by ``t`` (needs pandas)."""
        import pandas as pd

        cols = {f"x{i}": self.x[:, i] for i in range(self.x.shape[1])}
        cols.update({f"y{i}": self.y[:, i] for i in range(self.y.shape[1])})
        cols.update(u=self.u, command=self.command, reference=self.reference)
        return pd.DataFrame(cols, index=pd.Index(self.t, name="t"))

    def __repr__(self) -> str:
        return f"Trajectory({len(self.t)} samples, ts={self.ts})"


def _plant_json(plant: Union[str, Mapping[str, Any]]) -> str:
    return plant if isinstance(plant, str) else json.dumps(plant)


def _scenario(x0, t_final, imperfections, scenario) -> str:
    spec = dict(scenario)
    spec["initial_state"] = [float(v) for v in np.asarray(x0, dtype=float).reshape(-1)]
    spec["duration"] = float(t_final)
    if imperfections is not None:
        spec["imperfections"] = dict(imperfections)
    return json.dumps(spec)


def simulate(
    plant: Union[str, Mapping[str, Any]],
    controller: Mapping[str, Any],
    x0: Sequence[float],
    t_final: float,
    imperfections: Optional[Mapping[str, Any]] = None,
    **scenario: Any,
) -> Trajectory:
    """The nonlinear sampled-data simulation of ``controller`` on ``plant`` from ``x0`` for
    ``t_final`` seconds, through ``pendulab_control::scenario::simulate`` (the one simulate
    path of the CLI and the other front ends; ``docs/model.md`` §6).

    ``plant``: ``"cart"`` / ``"arm"`` (the book's rig) or a ``PlantSpec`` dict;
    ``controller``: a ``ControllerSpec`` dict (e.g. ``{"kind": "state-feedback", "k_book":
    [...]}``); ``imperfections``: the rig's effects (``quantization``, ``saturation``,
    ``dac``, ``pseudo_differentiator``, ``drive_friction``, ``pivot_friction``,
    ``delay_samples``, ``noise``); further keywords are ``ScenarioSpec`` keys
    (``reference``, ``disturbance``, ``sample_time``, ``substeps``). The specs cross as JSON;
    a spec that does not parse or validate raises ``pendulab.InvalidArgumentError`` naming
    the key.
    """
    spec = _scenario(x0, t_final, imperfections, scenario)
    return Trajectory(simulate_json(_plant_json(plant), json.dumps(controller), spec))


def simulate_batch(plant, controller, x0s, t_final, imperfections=None, workers=None, **scenario):
    """:func:`simulate` from each initial state of ``x0s``, in Rust on ``workers`` threads
    (default: all cores) with the GIL released, a few runs at a time: Ctrl-C raises
    ``KeyboardInterrupt`` between them. Returns the trajectories in order."""
    specs = [_scenario(x0, t_final, imperfections, scenario) for x0 in x0s]
    runs = batch_simulate_json(_plant_json(plant), json.dumps(controller), specs, threads=workers)
    return [Trajectory(r) for r in runs]


def feedback_batch(K, x0s, t_final, params=None, ts=1e-3, substeps=1, stay_within=None, threads=None):
    """The book's cart pendulum (``params`` override table 3.5) under ``u = −K x`` (V, held
    over each sample ``ts``, RK4 with ``substeps`` steps per sample) from every row of ``x0s``
    (``[z, θ, ż, θ̇]``) for ``t_final`` seconds, on all cores (``threads``) by the eight-lane
    kernel of ``pendulab bench sim-batch``; with ``stay_within=(i, bound)`` a run stops at the
    first sample with ``|x_i| > bound``. Ctrl-C raises ``KeyboardInterrupt`` between chunks of
    1024 runs. Returns a dict: ``held`` (bool), ``steps`` (RK4 steps integrated),
    ``final_state`` (runs × 4)."""
    return batch_feedback(K, x0s, t_final, params=params, ts=ts, substeps=substeps,
                          stay_within=stay_within, threads=threads)
