"""pendulab.control.find_operating_point on the shipped plants and on user callables.

References are closed forms: the rigs rest upright (θ = 0) and hanging (θ = π) at zero input
with zero velocities; a cart rolling at constant speed ż needs v = a_c ż / b_c (from
z̈ = −a_c ż + b_c v = 0); a damped pendulum m l² θ̈ = τ − m g l sin θ − c θ̇ rests at
θ* = asin(τ / (m g l)).
"""

import math

import numpy as np
import pytest

import pendulab as pl
from pendulab.control import OperatingPoint, find_operating_point
from pendulab.plants import ArmPendulum, CartPendulum

M, L, G, C = 0.2, 0.3, 9.81, 0.05


def pendulum(x, u):
    """Damped pendulum with a torque u (N m): θ̈ = (u − m g l sin θ − c θ̇) / (m l²)."""
    return [x[1], (u[0] - M * G * L * math.sin(x[0]) - C * x[1]) / (M * L * L)]


@pytest.mark.parametrize("plant", [CartPendulum(), "cart"])
def test_cart_upright_and_hanging(plant):
    up = find_operating_point(plant, [0.1, 0.05, 0.02, -0.03], 0.0, ix=[0])
    assert isinstance(up, OperatingPoint)
    np.testing.assert_allclose(up.x, [0.1, 0.0, 0.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(up.u, [0.0], atol=0)
    assert up.residual <= 1e-10 and np.abs(up.dx).max() <= 1e-10
    assert up.status == "isolated" and up.converged
    down = find_operating_point(plant, [0.0, 2.9, 0.1, 0.0])
    assert abs(down.x[1] - math.pi) < 1e-9 and np.abs(down.x[2:]).max() < 1e-9
    # The cart's position is free at every equilibrium: a one-dimensional family.
    assert down.status == "family" and down.family_dimension == 1
    x, u = down  # python-control's unpacking
    np.testing.assert_array_equal(x, down.x)


def test_arm_upright_and_hanging():
    arm = ArmPendulum()
    up = find_operating_point(arm, [0.4, 0.1, 0.0, 0.2], ix=[0])
    np.testing.assert_allclose(up.x, [0.4, 0.0, 0.0, 0.0], atol=1e-9)
    down = find_operating_point(arm, [0.4, 3.3, 0.0, 0.0], ix=[0])
    np.testing.assert_allclose(down.x, [0.4, math.pi, 0.0, 0.0], atol=1e-9)
    assert down.residual <= 1e-10


def test_cart_rolling_at_constant_speed_needs_a_c_zdot_over_b_c():
    cart = CartPendulum({"a_c": 9.5})  # the object's own parameters are used
    p = cart.params
    assert p["a_c"] == 9.5
    op = find_operating_point(cart, [0.0, 0.0, 0.2, 0.0], [0.0], ix=[2], iu=[], idx=[1, 2, 3])
    assert abs(op.u[0] - p["a_c"] * 0.2 / p["b_c"]) < 1e-9
    assert abs(op.dx[0] - 0.2) < 1e-12 and np.abs(op.dx[1:]).max() < 1e-10


def test_callable_pendulum_held_by_a_torque():
    tau = 0.3
    op = find_operating_point(pendulum, [0.2, 0.1], [tau])
    assert abs(op.x[0] - math.asin(tau / (M * G * L))) < 1e-10
    assert abs(op.x[1]) < 1e-10 and op.status == "isolated"
    # The inverse problem with an output map: hold y = θ at θ*, find the torque.
    theta = 0.7
    op = find_operating_point(pendulum, [0.5, 0.0], [0.0], y0=[theta], h=lambda x, u: [x[0]])
    assert abs(op.u[0] - M * G * L * math.sin(theta)) < 1e-10
    np.testing.assert_allclose(op.y, [theta], atol=1e-10)


def test_callable_errors_name_the_function_and_propagate():
    with pytest.raises(pl.ShapeError, match=r"f\(x, u\) returned 3 values"):
        find_operating_point(lambda x, u: [0.0, 0.0, 0.0], [0.1, 0.0], [0.0])
    with pytest.raises(pl.NotFiniteError, match=r"f\(x, u\)"):
        find_operating_point(lambda x, u: [float("nan"), 0.0], [0.1, 0.0], [0.0])
    with pytest.raises(pl.InvalidArgumentError, match="callable"):
        find_operating_point(42, [0.1, 0.0])

    calls = []

    def fails_later(x, u):
        calls.append(1)
        if len(calls) > 3:
            raise RuntimeError("model broke")
        return pendulum(x, u)

    with pytest.raises(RuntimeError, match="model broke"):
        find_operating_point(fails_later, [0.2, 0.1], [0.3])

    def wrong_length_later(x, u):
        calls.append(1)
        return pendulum(x, u) if len(calls) < 8 else [1.0]

    calls.clear()
    with pytest.raises(pl.ShapeError, match=r"f\(x, u\) returned 1 values at x = "):
        find_operating_point(wrong_length_later, [0.2, 0.1], [0.3])


def test_bad_inputs_raise_typed_errors():
    cart = CartPendulum()
    with pytest.raises(pl.ShapeError):
        find_operating_point(cart, [0.0, 0.1, 0.0])
    with pytest.raises(pl.NotFiniteError):
        find_operating_point(cart, [0.0, float("nan"), 0.0, 0.0])
    with pytest.raises(pl.InvalidArgumentError, match="fixed state index 7 is out of range"):
        find_operating_point(cart, [0.0, 0.1, 0.0, 0.0], ix=[7])
    with pytest.raises(pl.InvalidArgumentError, match="output map"):
        find_operating_point(cart, [0.0, 0.1, 0.0, 0.0], h=lambda x, u: x)
    with pytest.raises(pl.InvalidArgumentError, match="y0"):
        find_operating_point(pendulum, [0.1, 0.0], [0.0], iy=[0])
    with pytest.raises(pl.ShapeError, match="y0"):
        find_operating_point(pendulum, [0.1, 0.0], [0.0], y0=[1.0, 2.0], h=lambda x, u: [x[0]])
    # ẋ = x² + 1 has no zero: the search stalls at x = 0 with residual 1.
    with pytest.raises(pl.LinAlgError) as e:
        find_operating_point(lambda x, u: [x[0] ** 2 + 1.0], [0.5])
    assert e.value.variant == "NoConvergence"


def test_derivative_targets_dx0_against_closed_form_and_python_control():
    """``dx0``: the damped pendulum at θ = 0.6 rad (held), turning at θ̇ = 0.4 rad/s and
    accelerating at θ̈ = 1.5 rad/s² (the held derivatives' values) needs
    u = m l² · 1.5 + m g l sin 0.6 + c · 0.4; python-control 0.10's ``find_operating_point``
    with the same keywords finds the same point."""
    import control as ct

    op = find_operating_point(pendulum, [0.6, 0.0], [0.0], ix=[0], iu=[], dx0=[0.4, 1.5])
    u = M * L * L * 1.5 + M * G * L * math.sin(0.6) + C * 0.4
    np.testing.assert_allclose(op.x, [0.6, 0.4], rtol=0, atol=1e-10)
    assert abs(op.u[0] - u) <= 1e-10
    np.testing.assert_allclose(op.dx, [0.4, 1.5], rtol=0, atol=1e-10)
    sys = ct.nlsys(lambda t, x, u, params: np.array(pendulum(x, u)), None, inputs=1, states=2, outputs=2)
    with pytest.warns(UserWarning):  # python-control counts the held entries as constraints
        ref = ct.find_operating_point(sys, [0.6, 0.0], [0.0], ix=[0], iu=[], dx0=[0.4, 1.5], return_result=True)
    assert ref.result.success
    np.testing.assert_allclose(op.x, ref.states, rtol=0, atol=1e-8)
    np.testing.assert_allclose(op.u, ref.inputs, rtol=0, atol=1e-8)
    # A freed derivative's value is ignored (θ̈ free: any u holds θ̇ = 0.4).
    free = find_operating_point(pendulum, [0.6, 0.0], [0.0], ix=[0], idx=[0], dx0=[0.4, 99.0])
    assert abs(free.x[1] - 0.4) <= 1e-10 and free.u[0] == 0.0
    with pytest.raises(pl.ShapeError, match="dx0"):
        find_operating_point(pendulum, [0.6, 0.0], [0.0], dx0=[0.4])
    with pytest.raises(pl.NotFiniteError):
        find_operating_point(pendulum, [0.6, 0.0], [0.0], dx0=[0.4, math.nan])
