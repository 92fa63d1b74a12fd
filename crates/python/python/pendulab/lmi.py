"""LMI syntheses with their certificates (book Part 2 §1), over ``pendulab_lmi::synthesis``.

Every design is solved in Rust by Clarabel (the GIL released) and returns its gain with the
certificate that proves it; the control law is ``u = -K x`` (the book writes ``u = +K̃ x`` with
``K̃ = L X⁻¹ = -K``). A design whose LMIs have no solution raises
:class:`pendulab.InfeasibleError` (``err.status``: the solver's outcome,
``err.certificate_valid``: whether a Farkas certificate of infeasibility checks out).

- :func:`alpha_stability` — ``P ≻ 0``, ``AᵀP + PA + 2αP ≺ 0`` (Part 2 §1.1.2, example 1.1);
- :func:`max_decay_rate` — the largest such α, by bisection (Part 2 §1.2.1);
- :func:`lq` — the LQ guaranteed cost ``J ≤ x₀ᵀX⁻¹x₀``, maximising ``tr X`` (Part 2 §1.2.2);
- :func:`d_stability` — the same with the poles in LMI regions (Chilali–Gahinet; §1.2.2);
- :func:`robust` — one gain for a polytope of plants given by its vertices (§1.3);
- :func:`saturated` — ``|u_i| ≤ u_max_i`` on an invariant ellipsoid around given states (§1.4);
- :func:`state_feedback` — the general specification (any combination of the above);
- :func:`gain_scheduled` — ``K(ρ) = -L(ρ) X(ρ)⁻¹`` for ``A(ρ) = A₀ + ρA₁``, ``|ρ̇| ≤ ν``, by SOS
  multipliers (§1.5, problem (1.62)); the result is callable: ``K = sched(rho)``.

Regions are tuples: ``("decay_rate", α)`` (``Re s < -α``), ``("speed_limit", β)``
(``Re s > -β``), ``("sector", θ)`` (damping ratio ≥ ``cos θ``), ``("disk", q, r)``
(``|s + q| < r``), ``("general", L, M)`` (``L + sM + s̄Mᵀ ≺ 0``).

Results (:class:`LmiFeedback`) carry ``K``, ``X`` (``V(x) = xᵀX⁻¹x``), ``L = -KX``, the
closed-loop ``poles`` of every vertex, ``poles_in_regions``, ``status``, ``objective``,
``iterations`` and ``cost_bound(x0)``; they unpack as ``K, X, L``.
"""

from ._native import InfeasibleError
from ._native import LmiFeedback, Lyapunov, Schedule
from ._native import lmi_alpha_stability as alpha_stability
from ._native import lmi_d_stability as d_stability
from ._native import lmi_gain_scheduled as gain_scheduled
from ._native import lmi_lq as lq
from ._native import lmi_max_decay_rate as max_decay_rate
from ._native import lmi_robust as robust
from ._native import lmi_saturated as saturated
from ._native import lmi_state_feedback as state_feedback

__all__ = [
    "alpha_stability",
    "max_decay_rate",
    "lq",
    "d_stability",
    "robust",
    "saturated",
    "state_feedback",
    "gain_scheduled",
    "LmiFeedback",
    "Lyapunov",
    "Schedule",
    "InfeasibleError",
]
