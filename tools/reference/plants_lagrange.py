"""Independent derivation of pendulab-plants' nonlinear models by the Euler-Lagrange equations.

Writes crates/plants/tests/fixtures/lagrange.json. For each model the script

1. writes the positions of the bodies in the plane (x to the right, y up, angles from the
   upward vertical, the book's conventions, docs/model.md §1–2),
2. forms the Lagrangian L = T - V and Rayleigh's dissipation function D (viscous joint friction),
3. derives the Euler-Lagrange equation d/dt dL/dq' - dL/dq + dD/dq' = 0 of every pendulum
   coordinate with sympy,
4. closes the system with the drive law (the cart or the arm is an acceleration source,
   z'' = -a_c z' + b_c v, resp. theta1'' = -a1 theta1' + b1 v, as the book identifies it),
5. solves the resulting linear equations for the accelerations and evaluates
   x' = f(x, u) at a few states and inputs (book parameters and a second, unrelated set) with
   mpmath at 40 significant digits.

It also checks symbolically the closed form of det M_c of the arm model linearised at
theta1e (derived by hand in crates/plants/tests/plants.rs) and prints the result.

Tool: Python 3.11, SymPy 1.14 (with mpmath). Run from the repository root:
    python3 tools/reference/plants_lagrange.py
"""

import json
import math
import pathlib

import mpmath
import sympy as sp

mpmath.mp.dps = 40
t = sp.symbols("t")


def euler_lagrange(lag, diss, q):
    qd = sp.diff(q, t)
    return sp.diff(sp.diff(lag, qd), t) - sp.diff(lag, q) + sp.diff(diss, qd)


def kinetic(m, j, x, y, angle):
    """Kinetic energy of a rigid body of mass m, inertia j about its centre of mass."""
    return m / 2 * (sp.diff(x, t) ** 2 + sp.diff(y, t) ** 2) + j / 2 * sp.diff(angle, t) ** 2


# ----------------------------------------------------------------------------------------------
# Cart-type pendulum: cart position z(t), pendulum angle theta(t) from upright.
def cart_pendulum_model():
    ac, bc, m, l, jp, mu, g, mcart, v = sp.symbols("a_c b_c m_p l_p J_p mu_p g M v", real=True)
    z = sp.Function("z")(t)
    th = sp.Function("theta")(t)
    xc, yc = z + l * sp.sin(th), l * sp.cos(th)
    T = mcart / 2 * sp.diff(z, t) ** 2 + kinetic(m, jp, xc, yc, th)
    V = m * g * yc
    D = mu / 2 * sp.diff(th, t) ** 2
    eq = euler_lagrange(T - V, D, th)
    # State symbols.
    Z, TH, DZ, DTH, DDZ, DDTH = sp.symbols("Z TH DZ DTH DDZ DDTH", real=True)
    subs = {
        sp.diff(z, t, 2): DDZ,
        sp.diff(th, t, 2): DDTH,
        sp.diff(z, t): DZ,
        sp.diff(th, t): DTH,
    }
    eq = eq.subs(subs).subs({z: Z, th: TH})
    ddz = -ac * DZ + bc * v
    ddth = sp.solve(eq.subs(DDZ, ddz), DDTH)[0]
    f = [DZ, DTH, ddz, sp.simplify(ddth)]
    args = (ac, bc, m, l, jp, mu, g, Z, TH, DZ, DTH, v)
    return sp.lambdify(args, f, modules="mpmath"), f


# ----------------------------------------------------------------------------------------------
# Cart with two parallel pendulums a, b.
def two_pendulum_model():
    ac, bc, g, mcart, v = sp.symbols("a_c b_c g M v", real=True)
    ma, la, ja, mua, mb, lb, jb, mub = sp.symbols("m_a l_a J_a mu_a m_b l_b J_b mu_b", real=True)
    z = sp.Function("z")(t)
    tha = sp.Function("theta_a")(t)
    thb = sp.Function("theta_b")(t)
    T = (
        mcart / 2 * sp.diff(z, t) ** 2
        + kinetic(ma, ja, z + la * sp.sin(tha), la * sp.cos(tha), tha)
        + kinetic(mb, jb, z + lb * sp.sin(thb), lb * sp.cos(thb), thb)
    )
    V = ma * g * la * sp.cos(tha) + mb * g * lb * sp.cos(thb)
    D = mua / 2 * sp.diff(tha, t) ** 2 + mub / 2 * sp.diff(thb, t) ** 2
    Z, A, B, DZ, DA, DB, DDZ, DDA, DDB = sp.symbols("Z A B DZ DA DB DDZ DDA DDB", real=True)
    subs = {
        sp.diff(z, t, 2): DDZ,
        sp.diff(tha, t, 2): DDA,
        sp.diff(thb, t, 2): DDB,
        sp.diff(z, t): DZ,
        sp.diff(tha, t): DA,
        sp.diff(thb, t): DB,
    }
    ddz = -ac * DZ + bc * v
    eqs = [
        euler_lagrange(T - V, D, q).subs(subs).subs({z: Z, tha: A, thb: B}).subs(DDZ, ddz)
        for q in (tha, thb)
    ]
    sol = sp.solve(eqs, [DDA, DDB], dict=True)[0]
    f = [DZ, DA, DB, ddz, sp.simplify(sol[DDA]), sp.simplify(sol[DDB])]
    args = (ac, bc, g, ma, la, ja, mua, mb, lb, jb, mub, Z, A, B, DZ, DA, DB, v)
    return sp.lambdify(args, f, modules="mpmath"), f


# ----------------------------------------------------------------------------------------------
# Arm-type pendulum: arm angle theta1(t), absolute pendulum angle theta2(t), both from upright.
def arm_pendulum_model():
    a1, b1, L1, m2, l2, j2, mu2, g, jarm, v = sp.symbols(
        "a_1 b_1 L_1 m_2 l_2 J_2 mu_2 g J_arm v", real=True
    )
    th1 = sp.Function("theta1")(t)
    th2 = sp.Function("theta2")(t)
    # The arm's own inertia J_arm enters only the arm equation, which the drive law replaces.
    T = jarm / 2 * sp.diff(th1, t) ** 2 + kinetic(
        m2, j2, L1 * sp.sin(th1) + l2 * sp.sin(th2), L1 * sp.cos(th1) + l2 * sp.cos(th2), th2
    )
    V = m2 * g * (L1 * sp.cos(th1) + l2 * sp.cos(th2))
    # Viscous friction in the pendulum's joint acts on the relative angular velocity.
    D = mu2 / 2 * (sp.diff(th2, t) - sp.diff(th1, t)) ** 2
    eq = euler_lagrange(T - V, D, th2)
    P1, P2, D1, D2, DD1, DD2 = sp.symbols("P1 P2 D1 D2 DD1 DD2", real=True)
    subs = {
        sp.diff(th1, t, 2): DD1,
        sp.diff(th2, t, 2): DD2,
        sp.diff(th1, t): D1,
        sp.diff(th2, t): D2,
    }
    dd1 = -a1 * D1 + b1 * v
    eq = eq.subs(subs).subs({th1: P1, th2: P2}).subs(DD1, dd1)
    dd2 = sp.solve(eq, DD2)[0]
    f = [D1, D2, dd1, sp.simplify(dd2)]
    args = (a1, b1, L1, m2, l2, j2, mu2, g, P1, P2, D1, D2, v)
    return sp.lambdify(args, f, modules="mpmath"), f, (a1, b1, L1, m2, l2, j2, mu2, g)


def arm_det_check(arm_syms):
    """det M_c of the arm model linearised at theta1e versus the hand-derived closed form."""
    a1, b1, L1, m2, l2, j2, mu2, g = arm_syms
    th1e = sp.symbols("theta_1e", real=True)
    al2 = j2 + m2 * l2**2
    al3 = m2 * L1 * l2
    al5 = m2 * l2 * g
    c = sp.cos(th1e)
    A = sp.Matrix(
        [
            [0, 0, 1, 0],
            [0, 0, 0, 1],
            [0, 0, -a1, 0],
            [0, al5 / al2, (mu2 + a1 * al3 * c) / al2, -mu2 / al2],
        ]
    )
    B = sp.Matrix([0, 0, b1, -b1 * al3 * c / al2])
    Mc = B.row_join(A * B).row_join(A * A * B).row_join(A**3 * B)
    closed = al5 * b1**4 / al2**4 * (mu2**2 * (al2 + al3 * c) - al5 * al3**2 * c**2)
    return sp.simplify(Mc.det() - closed) == 0


def num(x):
    return float(mpmath.mpf(x))


BOOK_CART = dict(a_c=6.25, b_c=4.36, m_p=0.107, l_p=0.230, J_p=1.59e-3, mu_p=2.35e-4, g=9.81)
OTHER_CART = dict(a_c=3.1, b_c=2.7, m_p=0.42, l_p=0.51, J_p=7.3e-3, mu_p=4.4e-3, g=9.78)
BOOK_ARM = dict(
    a1=6.20, b1=15.8, L1=0.227, m2=0.096, l2=0.195, J2=9.06e-4, mu2=1.01e-4, g=9.81
)
OTHER_ARM = dict(a1=4.3, b1=9.1, L1=0.31, m2=0.21, l2=0.26, J2=2.2e-3, mu2=7.0e-4, g=9.80)

CART_POINTS = [
    ([0.1, 0.3, -0.2, 0.5], 0.7),
    ([-0.05, 2.5, 0.4, -1.3], -1.2),
    ([0.0, math.pi - 0.2, 0.0, 0.0], 0.0),
    ([0.3, -4.0, 1.1, 6.0], 4.5),
]
ARM_POINTS = [
    ([0.2, 0.1, -0.3, 0.8], 0.5),
    ([1.3, -0.4, 2.0, -1.5], -2.0),
    ([math.pi / 4, 0.0, 0.0, 0.0], 0.0),
    ([-2.0, 3.0, -4.0, 7.0], 4.9),
]
TWO_POINTS = [
    ([0.1, 0.2, -0.3, 0.4, 0.5, -0.6], 0.8),
    ([-0.2, 3.0, 2.9, -0.1, -2.0, 1.0], -3.0),
]


def main():
    out = {
        "tool": "Python 3.11 / SymPy %s / mpmath %s (40 digits)" % (sp.__version__, mpmath.__version__),
        "cart_pendulum": [],
        "arm_pendulum": [],
        "two_pendulum_cart": [],
    }
    cart, cart_f = cart_pendulum_model()
    print("cart pendulum theta'' =", cart_f[3])
    for params in (BOOK_CART, OTHER_CART):
        p = params
        for x, v in CART_POINTS:
            f = cart(p["a_c"], p["b_c"], p["m_p"], p["l_p"], p["J_p"], p["mu_p"], p["g"], *x, v)
            out["cart_pendulum"].append(
                {"params": p, "x": x, "u": v, "f": [num(fi) for fi in f]}
            )

    arm, arm_f, arm_syms = arm_pendulum_model()
    print("arm pendulum theta2'' =", arm_f[3])
    for p in (BOOK_ARM, OTHER_ARM):
        for x, v in ARM_POINTS:
            f = arm(p["a1"], p["b1"], p["L1"], p["m2"], p["l2"], p["J2"], p["mu2"], p["g"], *x, v)
            out["arm_pendulum"].append({"params": p, "x": x, "u": v, "f": [num(fi) for fi in f]})

    two, _ = two_pendulum_model()
    b = BOOK_CART
    pa = dict(m=b["m_p"], l=b["l_p"], J=b["J_p"], mu=b["mu_p"])
    pb = dict(m=1.2 * b["m_p"], l=1.2 * b["l_p"], J=1.2**3 * b["J_p"], mu=b["mu_p"])
    for x, v in TWO_POINTS:
        f = two(
            b["a_c"], b["b_c"], b["g"],
            pa["m"], pa["l"], pa["J"], pa["mu"],
            pb["m"], pb["l"], pb["J"], pb["mu"],
            *x, v,
        )
        out["two_pendulum_cart"].append(
            {
                "params": {"a_c": b["a_c"], "b_c": b["b_c"], "g": b["g"], "a": pa, "b": pb},
                "x": x,
                "u": v,
                "f": [num(fi) for fi in f],
            }
        )

    ok = arm_det_check(arm_syms)
    print("arm det M_c closed form verified symbolically:", ok)
    out["arm_det_closed_form_verified"] = bool(ok)

    path = pathlib.Path("crates/plants/tests/fixtures/lagrange.json")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=1) + "\n")
    print("wrote", path)


if __name__ == "__main__":
    main()
