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

from ._native import ArmPendulum, CartPendulum

__all__ = ["CartPendulum", "ArmPendulum"]
