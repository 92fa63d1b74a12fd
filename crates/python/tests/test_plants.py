"""pendulab.plants against closed forms (docs/model.md §1, §2) and finite differences.

The independent references: the model equations and linearisations written out here from
docs/model.md (book tables 3.5 and 3.7, eqs 3.7, 3.21), the printed upright eigenvalues
0, −6.25, +5.7543, −5.7867, central differences of the nonlinear right-hand side for the
Jacobians, and the two routes of the arm's linearisation (Jacobian at θ₁ₑ, LPV form at
ρ = 1 − cos θ₁ₑ).
"""

import numpy as np
import pytest

import pendulab
from pendulab import plants

CART_BOOK = dict(a_c=6.25, b_c=4.36, m_p=0.107, l_p=0.230, L_p=0.380, J_p=1.59e-3, mu_p=2.35e-4, g=9.81)
ARM_BOOK = dict(a1=6.20, b1=15.8, L1=0.227, m2=0.096, l2=0.195, L2=0.300, J2=9.06e-4, mu2=1.01e-4, g=9.81)


def cart_f(p, x, v):
    """docs/model.md §1: z̈ = −a_c ż + b_c v, θ̈ = (m g l sin θ − μ θ̇ − m l cos θ z̈)/J."""
    z, th, dz, dth = x
    J = p["J_p"] + p["m_p"] * p["l_p"] ** 2
    ddz = -p["a_c"] * dz + p["b_c"] * v
    ddth = (p["m_p"] * p["g"] * p["l_p"] * np.sin(th) - p["mu_p"] * dth
            - p["m_p"] * p["l_p"] * np.cos(th) * ddz) / J
    return np.array([dz, dth, ddz, ddth])


def arm_f(p, x, v):
    """docs/model.md §2: θ̈₁ = −a₁ θ̇₁ + b₁ v, then
    α₂ θ̈₂ = α₃ θ̇₁² sin(θ₁ − θ₂) + α₅ sin θ₂ + μ₂ (θ̇₁ − θ̇₂) − α₃ cos(θ₁ − θ₂) θ̈₁."""
    t1, t2, d1, d2 = x
    a2 = p["J2"] + p["m2"] * p["l2"] ** 2
    a3 = p["m2"] * p["L1"] * p["l2"]
    a5 = p["m2"] * p["l2"] * p["g"]
    dd1 = -p["a1"] * d1 + p["b1"] * v
    dd2 = (a3 * d1**2 * np.sin(t1 - t2) + a5 * np.sin(t2) + p["mu2"] * (d1 - d2)
           - a3 * np.cos(t1 - t2) * dd1) / a2
    return np.array([d1, d2, dd1, dd2])


def random_points(n, seed):
    rng = np.random.default_rng(seed)
    return [(rng.uniform(-2, 2, 4) * [0.2, 3.0, 1.0, 5.0], rng.uniform(-5, 5)) for _ in range(n)]


def test_book_parameters_are_the_defaults():
    assert plants.CartPendulum().params == CART_BOOK
    assert plants.ArmPendulum().params == ARM_BOOK


@pytest.mark.parametrize("cls,f,book", [(plants.CartPendulum, cart_f, CART_BOOK), (plants.ArmPendulum, arm_f, ARM_BOOK)])
def test_derivative_is_the_model_equation(cls, f, book):
    for custom in ({}, {"g": 9.7, "mu_p" if cls is plants.CartPendulum else "mu2": 0.0}):
        p = {**book, **custom}
        plant = cls(custom)
        for x, v in random_points(200, 1):
            np.testing.assert_allclose(plant.derivative(x, v), f(p, x, v), rtol=1e-13, atol=1e-12)


@pytest.mark.parametrize("cls", [plants.CartPendulum, plants.ArmPendulum])
def test_jacobian_matches_central_differences(cls):
    plant = cls()
    for x, v in random_points(50, 2):
        A, B = plant.jacobian(x, v)
        h = 1e-6
        Afd = np.column_stack([(plant.derivative(x + h * e, v) - plant.derivative(x - h * e, v)) / (2 * h)
                               for e in np.eye(4)])
        Bfd = (plant.derivative(x, v + h) - plant.derivative(x, v - h)) / (2 * h)
        # Central differences: truncation h²·f'''/6 plus rounding ~1e-16·|f|/h, both ≲ 1e-7 here.
        np.testing.assert_allclose(A, Afd, atol=1e-6 * (1 + np.abs(A).max()))
        np.testing.assert_allclose(B[:, 0], Bfd, atol=1e-6 * (1 + np.abs(B).max()))


def test_cart_upright_linearization_is_the_closed_form_with_its_eigenvalues():
    p = CART_BOOK
    J = p["J_p"] + p["m_p"] * p["l_p"] ** 2
    mgl, ml = p["m_p"] * p["g"] * p["l_p"], p["m_p"] * p["l_p"]
    A_ref = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [0, 0, -p["a_c"], 0],
                      [0, mgl / J, p["a_c"] * ml / J, -p["mu_p"] / J]])
    B_ref = np.array([[0], [0], [p["b_c"]], [-p["b_c"] * ml / J]])
    A, B, C, D = plants.CartPendulum().linearize()
    np.testing.assert_allclose(A, A_ref, rtol=1e-14, atol=0)
    np.testing.assert_allclose(B, B_ref, rtol=1e-14, atol=0)
    np.testing.assert_array_equal(C, np.eye(4))
    np.testing.assert_array_equal(D, np.zeros((4, 1)))
    # Block triangular: 0, −a_c and the roots of s² + (μ/J) s − m g l/J.
    mu = p["mu_p"] / J
    disc = np.sqrt(mu**2 + 4 * mgl / J)
    closed = np.sort([0.0, -p["a_c"], (-mu + disc) / 2, (-mu - disc) / 2])
    eig = np.sort(np.linalg.eigvals(A).real)
    np.testing.assert_allclose(eig, closed, atol=1e-12)
    # docs/model.md prints them to 4 decimals.
    np.testing.assert_allclose(eig, [-6.25, -5.7867, 0.0, 5.7543], atol=5e-5)


def test_cart_hanging_and_measured_linearizations():
    A_up, *_ = plants.CartPendulum().linearize("upright")
    A_dn, B_dn, C_m, D_m = plants.CartPendulum().linearize("hanging", z=0.3, measured=True)
    # cos π = −1 flips the m g l and m l entries of the last row (docs/model.md §1).
    np.testing.assert_allclose(A_dn[3, 1:3], -A_up[3, 1:3], rtol=1e-15)
    assert A_dn[3, 3] == A_up[3, 3]
    np.testing.assert_array_equal(C_m, [[1, 0, 0, 0], [0, 1, 0, 0]])
    assert D_m.shape == (2, 1)


def test_arm_linearization_closed_form_and_lpv_agree():
    p = ARM_BOOK
    a2 = p["J2"] + p["m2"] * p["l2"] ** 2
    a3 = p["m2"] * p["L1"] * p["l2"]
    a5 = p["m2"] * p["l2"] * p["g"]
    plant = plants.ArmPendulum()
    np.testing.assert_allclose(plant.alphas, (a2, a3, a5), rtol=1e-15)
    A0, A1, B0, B1 = plant.lpv()
    for th1 in np.linspace(-np.pi, np.pi, 13):
        c = np.cos(th1)
        A_ref = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [0, 0, -p["a1"], 0],
                          [0, a5 / a2, (p["mu2"] + p["a1"] * a3 * c) / a2, -p["mu2"] / a2]])
        B_ref = np.array([[0], [0], [p["b1"]], [-p["b1"] * a3 * c / a2]])
        A, B, _, _ = plant.linearize("upright", theta1=th1)
        np.testing.assert_allclose(A, A_ref, rtol=1e-13, atol=1e-15)
        np.testing.assert_allclose(B, B_ref, rtol=1e-13, atol=1e-15)
        rho = 1 - c
        np.testing.assert_allclose(A0 + rho * A1, A, rtol=1e-13, atol=1e-14)
        np.testing.assert_allclose(B0 + rho * B1, B, rtol=1e-13, atol=1e-14)


def test_energy_is_the_closed_form():
    cart, arm = plants.CartPendulum(), plants.ArmPendulum()
    J = CART_BOOK["J_p"] + CART_BOOK["m_p"] * CART_BOOK["l_p"] ** 2
    mgl = CART_BOOK["m_p"] * CART_BOOK["g"] * CART_BOOK["l_p"]
    a2, _, a5 = arm.alphas
    for x, _ in random_points(100, 3):
        assert cart.energy(x) == pytest.approx(0.5 * J * x[3] ** 2 + mgl * (1 + np.cos(x[1])), rel=1e-14, abs=1e-15)
        assert arm.energy(x) == pytest.approx(0.5 * a2 * x[3] ** 2 + a5 * (1 + np.cos(x[1])), rel=1e-14, abs=1e-15)
    assert cart.upright_energy == pytest.approx(2 * mgl, rel=1e-15)
    assert cart.energy([0, np.pi, 0, 0]) == pytest.approx(0, abs=1e-16)


def test_bad_inputs_raise_with_the_rust_message():
    with pytest.raises(pendulab.InvalidArgumentError, match="m_p"):
        plants.CartPendulum({"m_p": -0.1})
    with pytest.raises(ValueError, match="J2"):
        plants.ArmPendulum({"J2": float("nan")})
    with pytest.raises(pendulab.InvalidArgumentError, match="unknown parameter"):
        plants.CartPendulum({"mass": 1.0})
    with pytest.raises(pendulab.ShapeError):
        plants.CartPendulum().derivative([0, 0, 0], 0.0)
    with pytest.raises(pendulab.NotFiniteError):
        plants.CartPendulum().derivative([0, np.nan, 0, 0], 0.0)
    with pytest.raises(pendulab.NotFiniteError):
        plants.ArmPendulum().derivative([0, 0, 0, 0], np.inf)
    with pytest.raises(pendulab.InvalidArgumentError, match="posture"):
        plants.CartPendulum().linearize("sideways")
    with pytest.raises(ValueError, match="z"):
        plants.CartPendulum().linearize(z=np.nan)


K_BOOK = [3.16228, 13.47175, 4.48137, 2.26289]


def test_simulate_is_the_library_run_and_the_model_between_samples():
    """The book's cart gain from 5° with the rig's quantisers (the example the Rust library
    tests in control::scenario), and every sample of a plain run against SciPy integrating
    docs/model.md's equations with the recorded input held over the sample."""
    x0 = [0.0, np.radians(5), 0.0, 0.0]
    ctrl = {"kind": "state-feedback", "k_book": K_BOOK}
    run = plants.simulate("cart", ctrl, x0, 5.0, imperfections={"quantization": True})
    assert run.t.shape == (5001,) and run.x.shape == (5001, 4)
    assert run.summary["left_angle_window"] is False
    assert abs(run.summary["final_state"][1]) < 1e-2

    from scipy.integrate import solve_ivp

    plain = plants.simulate("cart", ctrl, x0, 0.5)
    for k in range(0, 500, 7):
        ref = solve_ivp(lambda t, x: cart_f(CART_BOOK, x, plain.u[k]), (0, plain.ts), plain.x[k],
                        rtol=1e-12, atol=1e-14, method="DOP853").y[:, -1]
        # One RK4 step of 1 ms: (|λ| h)⁵/120 · X ≈ 1e-13 · 12, far below 1e-9.
        np.testing.assert_allclose(plain.x[k + 1], ref, atol=1e-9)


def test_simulate_batch_and_bad_specs():
    ctrl = {"kind": "state-feedback", "k_book": K_BOOK}
    x0s = [[0.0, np.radians(a), 0.0, 0.0] for a in (-4, 2, 6)]
    runs = plants.simulate_batch("cart", ctrl, x0s, 1.0)
    for x0, r in zip(x0s, runs):
        np.testing.assert_array_equal(r.x, plants.simulate("cart", ctrl, x0, 1.0).x)
    with pytest.raises(pendulab.InvalidArgumentError, match="controller"):
        plants.simulate("cart", {"kind": "nonsense"}, x0s[0], 1.0)
    with pytest.raises(ValueError):
        plants.simulate("cart", ctrl, [0.0, 0.1], 1.0)
    with pytest.raises(ValueError):
        plants.simulate("boat", ctrl, x0s[0], 1.0)
