"""Reference values for the Part 1 ch. 5-8 and IP Toolbox examples of pendulab-book.

Tools: Python 3.11, NumPy 2.4.6, SciPy 1.17.1 (solve_continuous_are, place_poles,
cont2discrete), python-control 0.10.2 (lqr cross-check), SymPy 1.14.0 (exact determinants).
Plant data: docs/model.md §1–2 (book tables 3.5 and 3.7).

Run: python3 tools/reference/book_p1c5_reference.py   (prints the numbers the tests
crates/book/tests/{p1c5,p1c6,p1c8,toolbox}.rs quote).
"""

import numpy as np
import scipy
import scipy.linalg as sla
import scipy.signal as sig
import sympy as sp
import control

# Cart pendulum (table 3.5).
ac, bc, mp, lp, Jp, mup, g = 6.25, 4.36, 0.107, 0.230, 1.59e-3, 2.35e-4, 9.81
J = Jp + mp * lp**2
A_c = np.array(
    [
        [0, 0, 1, 0],
        [0, 0, 0, 1],
        [0, 0, -ac, 0],
        [0, mp * g * lp / J, ac * mp * lp / J, -mup / J],
    ]
)
B_c = np.array([[0], [0], [bc], [-bc * mp * lp / J]])

# Arm pendulum (table 3.7).
a1, b1, L1, m2, l2, J2, mu2 = 6.20, 15.8, 0.227, 0.096, 0.195, 9.06e-4, 1.01e-4
al2, al3, al5 = J2 + m2 * l2**2, m2 * L1 * l2, m2 * l2 * g


def arm(th, mu=mu2, lib=np):
    c = lib.cos(th)
    A = [
        [0, 0, 1, 0],
        [0, 0, 0, 1],
        [0, 0, -a1, 0],
        [0, al5 / al2, (mu + a1 * al3 * c) / al2, -mu / al2],
    ]
    B = [[0], [0], [b1], [-b1 * al3 * c / al2]]
    return A, B


def lqr_book(A, B, Q, R):
    X = sla.solve_continuous_are(np.array(A, float), np.array(B, float), Q, R)
    K = np.linalg.solve(R, np.array(B, float).T @ X)
    K2, _, _ = control.lqr(np.array(A, float), np.array(B, float), Q, R)
    assert np.allclose(K, K2, rtol=1e-9, atol=1e-12)
    return -K  # book convention u = +K x


def fmt(v):
    return "[" + ", ".join(f"{x:.12g}" for x in np.ravel(v)) + "]"


print("versions", np.__version__, scipy.__version__, control.__version__, sp.__version__)

# p1c511_ex3_adip: det M_c(theta1e), exact arithmetic on the float data.
th = sp.symbols("th")
for name, val in [("0", 0), ("pi/2", sp.pi / 2)]:
    A, B = arm(val, sp.Float(mu2, 30), sp)
    A, B = sp.Matrix(A), sp.Matrix(B)
    Mc = B.row_join(A * B).row_join(A * A * B).row_join(A**3 * B)
    print(f"p1c511_ex3 det_Mc at {name}:", sp.N(Mc.det(), 15))
    A0, B0 = arm(val, 0, sp)
    A0, B0 = sp.Matrix(A0), sp.Matrix(B0)
    Mc0 = B0.row_join(A0 * B0).row_join(A0 * A0 * B0).row_join(A0**3 * B0)
    print(f"p1c511_ex3 det_Mc (mu2 = 0) at {name}:", sp.N(Mc0.det(), 15))

# p1c522_ex7: place at theta1e = pi/4.
A, B = arm(np.pi / 4)
A, B = np.array(A, float), np.array(B, float)
K = sig.place_poles(A, B, [-2, -2.5, -3, -3.5]).gain_matrix
print("p1c522_ex7 K (book):", fmt(-K))

# p1c523_ex8: LQR at theta1e = pi/4.
for name, q, r in [
    ("case1", [10, 10, 1, 1], 1.0),
    ("case2", [10, 10, 1, 1], 10.0),
    ("case3", [20, 10, 1, 1], 1.0),
]:
    print(f"p1c523_ex8 K_{name}:", fmt(lqr_book(A, B, np.diag(q), np.array([[r]]))))

# p1c63_ex5: LQ integral servo of the cart pendulum, Q = C~' diag(q1, q2) C~ on [x; w].
Aa = np.block([[A_c, np.zeros((4, 1))], [-np.array([[1, 0, 0, 0]]), np.zeros((1, 1))]])
Ba = np.vstack([B_c, [[0]]])
Ka = lqr_book(Aa, Ba, np.diag([800, 0, 0, 0, 20000.0]), np.array([[1.0]]))
print("p1c63_ex5 K1:", fmt(Ka[0, :4]), "K2:", fmt(Ka[0, 4:]))

# adip_lqr_sim (theta1e = 0).
A0, B0 = arm(0.0)
for q1 in [1, 5, 20]:
    print(f"adip_lqr_sim K_q{q1}:", fmt(lqr_book(A0, B0, np.diag([q1, 10, 0.1, 0.1]), np.array([[1.0]]))))

# adip_lqr_servo_sim: y = theta1.
A0, B0 = np.array(A0, float), np.array(B0, float)
Aa = np.block([[A0, np.zeros((4, 1))], [-np.array([[1, 0, 0, 0]]), np.zeros((1, 1))]])
Ba = np.vstack([B0, [[0]]])
Ka = lqr_book(Aa, Ba, np.diag([0.1, 10, 0, 0, 25.0]), np.array([[1.0]]))
print("adip_lqr_servo_sim K1:", fmt(Ka[0, :4]), "K2:", fmt(Ka[0, 4:]))

# p1c83 / p1c84: C(s) = 1/(s^2 + s + 1), ts = 1.
for method in ["zoh", "bilinear"]:
    num, den, _ = sig.cont2discrete(([1.0], [1.0, 1.0, 1.0]), 1.0, method=method)
    print(f"p1c8 {method}: num", fmt(num), "den", fmt(den))
