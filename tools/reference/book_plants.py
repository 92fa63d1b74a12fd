"""The book's two plants as the reference scripts use them, written from docs/model.md (not from
pendulab's code): the cart-type pendulum linearised upright (docs/model.md §1, book table 3.5)
and the arm-type pendulum linearised at an arm angle (docs/model.md §2, book table 3.7), with
the integral-servo augmentation of book eq. 6.40. numpy only.

Imported by the scripts beside it (`python3 tools/reference/<script>.py` puts this folder on
the import path).
"""

import numpy as np


def cdip():
    """(A, B) of the cart pendulum upright, state [z, phi, z', phi'], input the voltage."""
    ac, bc, mp, lp, Jp, mup, g = 6.25, 4.36, 0.107, 0.230, 1.59e-3, 2.35e-4, 9.81
    J = Jp + mp * lp**2
    A = np.array(
        [
            [0, 0, 1, 0],
            [0, 0, 0, 1],
            [0, 0, -ac, 0],
            [0, mp * g * lp / J, ac * mp * lp / J, -mup / J],
        ]
    )
    B = np.array([[0], [0], [bc], [-bc * mp * lp / J]])
    return A, B


# Arm pendulum, table 3.7.
a1n, b1n, L1, m2, l2, J2, mu2, g = 6.20, 15.8, 0.227, 0.096, 0.195, 9.06e-4, 1.01e-4, 9.81
al2, al3, al5 = J2 + m2 * l2**2, m2 * L1 * l2, m2 * l2 * g


def arm(a1=a1n, b1=b1n, th=0.0):
    """(A, B) of the arm pendulum upright with the arm at th (rad), drive pole a1, gain b1."""
    c = np.cos(th)
    A = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [0, 0, -a1, 0],
                  [0, al5 / al2, (mu2 + a1 * al3 * c) / al2, -mu2 / al2]])
    B = np.array([[0], [0], [b1], [-b1 * al3 * c / al2]])
    return A, B


def augment(A, B):
    """The plant augmented with w = integral of (r - theta1) (book eq. 6.40)."""
    At = np.zeros((5, 5))
    At[:4, :4] = A
    At[4, 0] = -1.0
    Bt = np.vstack([B, [[0.0]]])
    return At, Bt
