"""Reference values for the book examples of part 2 ch. 2 (crates/book/tests/p2c2.rs).

Independent of pendulab: the cart-pendulum model of docs/model.md §1 written out here, SciPy's
matrix exponential and discrete Riccati solver.

- p2c244_ex3: Van Loan discretisation of the cost ∫(xᵀQx + uᵀRu)dt for a held input at
  ts = 0.1 s (Q = diag(10, 10, 0, 0), R = 1), checked against Simpson quadrature of
  e^{Fᵀs} W e^{Fs}, and K_d from scipy.linalg.solve_discrete_are with the cross term.
- p2c242_ex2: the I–PD loop at ts = 0.025 s on the exact ZOH sampling of
  P(s) = b_c/(s² + a_c s): Tustin integral I_k = I_{k−1} + k_I ts (e_k + e_{k−1})/2, pure
  derivative k_D s by Tustin, D_k = −D_{k−1} + (2 k_D/ts)(s_k − s_{k−1}) with s_k = −z_k (first
  sample s_{−1} = s_0, D_{−1} = 0), u_k = −k_P z_k + I_k + D_k; overshoot of the samples
  z_k over r = 0.1 m for 1 s (samples k = 0..40), and the spectral radius of the discrete loop.

Run: python3 tools/reference/book_p2c2.py   (prints the numbers the test asserts)
Tool versions used for the committed numbers: Python 3.11, NumPy 2.x, SciPy 1.17.1.
"""

import numpy as np
import scipy
from scipy.linalg import expm, solve_discrete_are

ac, bc, mp, lp, Jp, mup, g = 6.25, 4.36, 0.107, 0.230, 1.59e-3, 2.35e-4, 9.81


def cdip():
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


def sampled_data_lqr():
    A, B = cdip()
    n, m = B.shape
    Q = np.diag([10.0, 10.0, 0.0, 0.0])
    R = np.array([[1.0]])
    h = 0.1
    F = np.zeros((n + m, n + m))
    F[:n, :n] = A
    F[:n, n:] = B
    W = np.zeros((n + m, n + m))
    W[:n, :n] = Q
    W[n:, n:] = R
    H = np.zeros((2 * (n + m), 2 * (n + m)))
    H[: n + m, : n + m] = -F.T
    H[: n + m, n + m :] = W
    H[n + m :, n + m :] = F
    E = expm(H * h)
    G22 = E[n + m :, n + m :]
    G12 = E[: n + m, n + m :]
    Wd = G22.T @ G12
    # Simpson check of the same integral.
    N = 2000
    s = np.linspace(0, h, N + 1)
    acc = np.zeros_like(W)
    for k, sk in enumerate(s):
        c = 1 if k in (0, N) else (4 if k % 2 else 2)
        Ek = expm(F * sk)
        acc += c * Ek.T @ W @ Ek
    acc *= (h / N) / 3
    assert np.abs(acc - Wd).max() < 1e-10 * np.abs(Wd).max(), np.abs(acc - Wd).max()
    Ad = G22[:n, :n]
    Bd = G22[:n, n:]
    Qd, Sd, Rd = Wd[:n, :n], Wd[:n, n:], Wd[n:, n:]
    P = solve_discrete_are(Ad, Bd, Qd, Rd, s=Sd)
    Kd = np.linalg.solve(Rd + Bd.T @ P @ Bd, Bd.T @ P @ Ad + Sd.T)
    return Kd, Rd


def ipd_discrete():
    wn = 25.0
    ki, kp, kd = wn**3 / bc, 3 * wn**2 / bc, (3 * wn - ac) / bc
    ts, r = 0.025, 0.1
    A = np.array([[0, 1], [0, -ac]])
    B = np.array([[0], [bc]])
    M = np.zeros((3, 3))
    M[:2, :2] = A
    M[:2, 2:] = B
    E = expm(M * ts)
    Ad, Bd = E[:2, :2], E[:2, 2:]
    x = np.zeros((2, 1))
    integ, e_prev, s_prev, d = 0.0, 0.0, None, 0.0
    zs = []
    for k in range(41):
        z = x[0, 0]
        zs.append(z)
        e = r - z
        integ += ki * ts * (e + e_prev) / 2
        e_prev = e
        sk = -z
        if s_prev is None:
            s_prev = sk
        d = -d + 2 * kd / ts * (sk - s_prev)
        s_prev = sk
        u = -kp * z + integ + d
        x = Ad @ x + Bd * u
    zs = np.array(zs)
    # Homogeneous closed loop on ξ_k = [x_k, I_{k−1}, z_{k−1}, D_{k−1}]:
    # I_k = I_{k−1} − (k_I ts/2)(z_k + z_{k−1}), D_k = −D_{k−1} − (2k_D/ts)(z_k − z_{k−1}),
    # u_k = −k_P z_k + I_k + D_k, x_{k+1} = A_d x_k + B_d u_k.
    c = np.array([1.0, 0.0])
    rows_i = np.concatenate([-ki * ts / 2 * c, [1.0, -ki * ts / 2, 0.0]])
    rows_d = np.concatenate([-2 * kd / ts * c, [0.0, 2 * kd / ts, -1.0]])
    rows_u = -kp * np.concatenate([c, [0, 0, 0]]) + rows_i + rows_d
    M = np.zeros((5, 5))
    M[:2, :] = np.hstack([Ad, np.zeros((2, 3))]) + Bd @ rows_u[None, :]
    M[2, :] = rows_i
    M[3, :] = np.concatenate([c, [0, 0, 0]])
    M[4, :] = rows_d
    rho = np.abs(np.linalg.eigvals(M)).max()
    return (zs.max() - r) / r * 100, (ki, kp, kd), rho


if __name__ == "__main__":
    Kd, Rd = sampled_data_lqr()
    print("scipy", scipy.__version__, "numpy", np.__version__)
    print("Kd (library sign u = -Kd x):", repr(Kd.ravel().tolist()))
    print("Rd:", repr(float(Rd[0, 0])))
    os_d, gains, rho = ipd_discrete()
    print("I-PD gains [kI, kP, kD]:", gains)
    print("overshoot_discrete % (samples):", repr(float(os_d)))
    print("spectral radius of the discrete loop:", repr(float(rho)))
