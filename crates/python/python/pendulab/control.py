"""Controllers beyond a static gain (book Part 2 §2–§3), over ``pendulab-control``.

Designs return their results as dicts of arrays; run-time controllers come back as
:class:`Controller` objects with ``update(t, y) -> u`` (the measurement ``y`` at time ``t`` in
seconds to the command ``u``, as the sampled-data loop calls them), ``reset()``, ``ny``,
``nu``, ``sample_time``. Library sign: ``u = −K x`` (the book's ``u = +K x`` has
``K_book = −K``).

- :func:`sliding_surface`, :func:`sliding_mode` — the LQ-optimal switching surface and the
  sliding-mode law ``u = −(SᵀA x + K₂ σ/(|σ| + δ)) / (SᵀB)``, ``σ = Sᵀx`` (Part 2 §3.2.3);
- :func:`energy_pumping`, :func:`energy_shaping` — swing-up from the hanging rest (Part 2
  §3.2.3; the energy-shaping gains are tuned for the rigs, not from the book);
- :func:`nmpc_arm_swing_up` — the C/GMRES NMPC swing-up of the arm pendulum (Part 2 §3.3);
- :func:`odq` — the optimal dynamic quantizer, closed form or LP (Part 2 §2.3.4);
- :func:`kalman` — the steady-state Kalman filter (MATLAB ``kalman``);
- :func:`build` — the controller a ``ControllerSpec`` describes (``docs/model.md`` §6), from the
  factory the CLI and :func:`pendulab.plants.simulate` use.
"""

import json
from typing import Any, Mapping, Union

from . import _native
from ._native import Controller
from ._native import control_energy_pumping as energy_pumping
from ._native import control_energy_shaping as energy_shaping
from ._native import control_kalman as kalman
from ._native import control_nmpc_arm_swing_up as nmpc_arm_swing_up
from ._native import control_odq as odq
from ._native import control_sliding_mode as sliding_mode
from ._native import control_sliding_surface as sliding_surface

__all__ = [
    "Controller",
    "sliding_surface",
    "sliding_mode",
    "energy_pumping",
    "energy_shaping",
    "nmpc_arm_swing_up",
    "odq",
    "kalman",
    "build",
]


def build(spec: Mapping[str, Any], plant: Union[str, Mapping[str, Any]] = "cart", ts: float = 1e-3) -> Controller:
    """The controller ``spec`` (a ``ControllerSpec`` dict such as ``{"kind": "state-feedback",
    "k_book": [...]}``) describes for ``plant`` (``"cart"``, ``"arm"`` or a ``PlantSpec`` dict),
    running at loop period ``ts`` (s)."""
    p = plant if isinstance(plant, str) else json.dumps(plant)
    return _native.control_build(json.dumps(spec), p, float(ts))
