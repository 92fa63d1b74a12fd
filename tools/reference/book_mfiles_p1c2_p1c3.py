"""The book's M-files of §2.2.1, §3.2.1 and §3.3 followed line by line, for pendulab-book's tests.

Each function below is a transcription of one M-file of the book (MATLAB's 1-based indices written
out as `i - 1`), run on the rig measurements in data/rig/ (or, for p1c221_id_cart, on the closed-form
response of the book's Simulink model cart_model.slx). Nothing here uses pendulab.

- p1c221_id_cart.m with cartident.m: cart_model.slx is the drive z'' = -a_c z' + b_c v (table 3.5:
  a_c = 6.25, b_c = 4.36; the pendulum does not act on the cart), a step v = ref at t = 0 through the
  ±5 V saturation and the 16-bit D/A quantizer (interval 10/2^16, round to nearest), the cart
  position through the encoder quantizer (2*pi/(4*500) rad of the motor, 4*500*4.8414e-5 m per
  turn, round to nearest), ode4 with a fixed step of 1 ms. The position is taken in closed form,
  z(t) = b_c v (t/a_c - (1 - exp(-a_c t))/a_c^2), instead of the ode4 steps (their error, ~1e-14 m,
  moves no encoder count here).
- p1c321_cdip_id_cart.m: the k_P = 10 record, t >= 1 s, peak plateau, Amax = zmax - zc with zc = 0.2.
- p1c332_adip_id_arm.m: the same on adip_arm_pcont_data_kP_3_ref_1.csv (the M-file's
  adip_pcont_data_kP_3_ref_1), theta1c = 1, k_P = 3.
- p1c332_adip_id_pend.m: adip_pend_data.csv, 50 s <= t <= 66 s, peaks between negative-going zero
  crossings exactly as the M-file finds them (including its `imax(j) + num(j)`, line 57, which
  points one sample after the largest sample).
- p1c332_adip_id_least_square.m: adip_least_square_data.csv, 1 s <= t <= 9 s, three-point derivatives,
  the model adip_least_square_MN_sim.slx: every column through tf(1,[Tf 1])^3 (Tf = 0.075 s) under
  Simulink's ode1 (forward Euler) at 1 ms from a zero state, then p = inv(M'M) M'N (lines 102-103).

Run: python3 tools/reference/book_mfiles_p1c2_p1c3.py   (from the repository root)
Produced with Python 3.11.7, standard library only (no NumPy); prints JSON.
"""

import csv
import json
import math
import pathlib

RIG = pathlib.Path(__file__).resolve().parents[2] / "data" / "rig"


def load(name):
    with open(RIG / name, newline="") as f:
        rows = list(csv.reader(f))
    head = rows[0]
    cols = {h: [float(r[i]) for r in rows[1:] if r] for i, h in enumerate(head)}
    return cols


def mean(x):
    return sum(x) / len(x)


def matlab_round(x):
    # MATLAB's round: half away from zero.
    return math.floor(abs(x) + 0.5) * (1 if x >= 0 else -1)


# ------------------------------------------------------------------ p1c221_id_cart + cartident


def cartident(t, y, ref, ts, tend):
    datasize = int(matlab_round(tend / ts))  # int32(tend/ts)
    n = len(y)
    dy = [0.0] * n
    for i in range(1, n - 1):
        dy[i] = (y[i + 1] - y[i - 1]) / 2 / ts
    dy[0] = (-3 * y[0] + 4 * y[1] - y[2]) / 2 / ts
    dy[n - 1] = (y[n - 3] - 4 * y[n - 2] + 3 * y[n - 1]) / 2 / ts
    init_data = int(matlab_round(1.4 / ts))
    K = mean(dy[init_data - 1 : datasize])  # dy(init_data:datasize)
    k = None
    for i in range(1, datasize + 1):  # i = 1:datasize
        if dy[i - 1] < 0.632 * K and dy[i] > 0.632 * K:
            k = i
            break
    T = t[k - 1]
    return K / ref, T


def p1c221_id_cart():
    ac, bc = 6.25, 4.36
    q_dac = 10 / 2**16
    g_m_rad = 2 * math.pi / (4 * 500 * 4.8414e-5)
    g_rad_m = 4 * 500 * 4.8414e-5 / (2 * math.pi)
    q_rad = 2 * math.pi / (4 * 500)
    ts = 0.001
    t = [k * ts for k in range(10001)]  # StartTime 0, StopTime 10, FixedStep 0.001
    Ks, Ts = [], []
    for ref in [0.8, 0.9, 1.0, 1.1]:
        v = q_dac * matlab_round(max(-5.0, min(5.0, ref)) / q_dac)
        y = []
        for tk in t:
            z = bc * v * (tk / ac - (1 - math.exp(-ac * tk)) / ac**2)
            y.append(g_rad_m * (q_rad * matlab_round(z * g_m_rad / q_rad)))
        K, T = cartident(t, y, ref, ts, 1.5)
        Ks.append(K)
        Ts.append(T)
    Tave = matlab_round(((Ts[0] + Ts[1] + Ts[2] + Ts[3]) / 4) * 10**3) / 10**3
    Kave = matlab_round(((Ks[0] + Ks[1] + Ks[2] + Ks[3]) / 4) * 10**3) / 10**3
    return {
        "K1": Ks[0], "K2": Ks[1], "K3": Ks[2], "K4": Ks[3],
        "T1": Ts[0], "T2": Ts[1], "T3": Ts[2], "T4": Ts[3],
        "Kave": Kave, "Tave": Tave, "a": 1 / Tave, "b": Kave / Tave,
    }


# ------------------------------------------------------------------ peak-time identification


def peak_feature(t_data, y_data, yc, kP):
    t, y = [], []
    for tk, yk in zip(t_data, y_data):
        if tk >= 1:
            t.append(tk - 1)
            y.append(yk)
    ymax = max(y)
    imax = y.index(ymax)  # first maximum, 0-based
    imax_last = imax
    for i in range(imax, len(t)):
        if y[i] == ymax:
            imax_last = i
        if y[i] < ymax:
            break
    Tp = (t[imax] + t[imax_last]) / 2
    Amax = ymax - yc
    gamma = -(1 / Tp) * math.log(Amax / yc)
    delta = math.pi / Tp
    omega_n = math.sqrt(gamma**2 + delta**2)
    zeta = gamma / omega_n
    return {
        "Tp": Tp, "Amax": Amax, "gamma": gamma, "delta": delta, "omega_n": omega_n,
        "zeta": zeta, "a": 2 * zeta * omega_n, "b": omega_n**2 / kP,
    }


def p1c321_cdip_id_cart():
    d = load("cdip_cart_pcont_data_kP_100_ref_02.csv")
    r = peak_feature(d["t"], d["z"], 0.2, 10)
    r["ac"], r["bc"] = r.pop("a"), r.pop("b")
    return r


def p1c332_adip_id_arm():
    d = load("adip_arm_pcont_data_kP_3_ref_1.csv")
    r = peak_feature(d["t"], d["theta1"], 1.0, 3)
    r["a1"], r["b1"] = r.pop("a"), r.pop("b")
    return r


# ------------------------------------------------------------------ free oscillation


def p1c332_adip_id_pend():
    d = load("adip_pend_data.csv")
    tmin, tmax_ = 50, 50 + 16
    t, phi2 = [], []
    for tk, pk in zip(d["t"], d["theta2"]):
        if tk >= tmin and tk <= tmax_:
            t.append(tk - tmin)
            phi2.append(pk)
    # num holds MATLAB (1-based) indices.
    num, flag = [], 0
    for i in range(1, len(t)):  # i = 1:length(t)-1
        if phi2[i - 1] > 0:
            flag = 1
        if flag == 1 and phi2[i - 1] < 0:
            num.append(i)
            flag = 0
    if phi2[0] < 0:
        num = [1] + num
    Amax, tmax = [], []
    for j in range(len(num) - 1):
        seg = phi2[num[j] - 1 : num[j + 1]]  # phi2(num(j):num(j+1))
        a = max(seg)
        imax = seg.index(a) + 1 + num[j]  # [Amax imax] = max(...); imax = imax + num(j)
        imax_last = imax
        for i in range(imax, num[j + 1] + 1):
            if phi2[i - 1] == a:
                imax_last = i
            if phi2[i - 1] < a:
                break
        Amax.append(a)
        tmax.append((t[imax - 1] + t[imax_last - 1]) / 2)
    T = [tmax[i + 1] - tmax[i] for i in range(len(tmax) - 1)]
    lam = [Amax[i + 1] / Amax[i] for i in range(len(tmax) - 1)]
    T_average, lambda_average = mean(T), mean(lam)
    m2, l2, g = 9.60e-002, 1.95e-001, 9.81e000
    gamma = (1 / T_average) * math.log(1 / lambda_average)
    delta = 2 * math.pi / T_average
    omega_n = math.sqrt(gamma**2 + delta**2)
    zeta = gamma / omega_n
    J2 = m2 * g * l2 / omega_n**2 - m2 * l2**2
    mu2 = 2 * zeta * omega_n * (J2 + m2 * l2**2)
    return {
        "T": T, "lambda": lam, "T_average": T_average, "lambda_average": lambda_average,
        "gamma": gamma, "delta": delta, "zeta": zeta, "omega_n": omega_n, "J2": J2, "mu2": mu2,
        "Amax": Amax, "tmax": tmax,
    }


# ------------------------------------------------------------------ least squares


def three_point(x, ts):
    n = len(x)
    d = [0.0] * n
    d[0] = (-3 * x[0] + 4 * x[1] - x[2]) / (2 * ts)
    for i in range(1, n - 1):
        d[i] = (-x[i - 1] + x[i + 1]) / (2 * ts)
    d[n - 1] = (x[n - 3] - 4 * x[n - 2] + 3 * x[n - 1]) / (2 * ts)
    return d


def euler_lag3(u, tf, ts):
    # tf(1,[Tf 1])^3 under ode1: x_{k+1} = x_k + ts (A x_k + B u_k), y_k = C x_k, x_0 = 0, which for
    # any realisation is three stages y_{k+1} = y_k + (ts/Tf)(u_k - y_k).
    c = ts / tf
    x = u
    for _ in range(3):
        y = [0.0] * len(x)
        for k in range(len(x) - 1):
            y[k + 1] = y[k] + c * (x[k] - y[k])
        x = y
    return x


def normal_equations(c1, c2, n):
    # p = inv(M'M) M'N for M = [c1, c2], by Cramer's rule on the 2x2 normal equations.
    s11 = sum(a * a for a in c1)
    s12 = sum(a * b for a, b in zip(c1, c2))
    s22 = sum(b * b for b in c2)
    r1 = sum(a * y for a, y in zip(c1, n))
    r2 = sum(b * y for b, y in zip(c2, n))
    det = s11 * s22 - s12 * s12
    return (s22 * r1 - s12 * r2) / det, (s11 * r2 - s12 * r1) / det


def p1c332_adip_id_least_square():
    d = load("adip_least_square_data.csv")
    t, phi1, phi2, v = [], [], [], []
    for k in range(len(d["t"])):
        if d["t"][k] >= 1 and d["t"][k] <= 9:
            t.append(d["t"][k] - 1)
            phi1.append(d["phi1"][k])
            phi2.append(d["phi2"][k])
            v.append(d["v"][k])
    ts = 0.001
    dphi1 = three_point(phi1, ts)
    ddphi1 = three_point(dphi1, ts)
    dphi2 = three_point(phi2, ts)
    ddphi2 = three_point(dphi2, ts)
    Tf = 0.075
    L1, m2, l2, g = 2.27e-001, 9.60e-002, 1.95e-001, 9.81e000
    alpha3 = m2 * L1 * l2
    alpha5 = m2 * l2 * g
    f = lambda x: euler_lag3(x, Tf, ts)
    Mf1 = (f([-x for x in dphi1]), f(v))
    Nf1 = f(ddphi1)
    Mf2 = (f(ddphi2), f([b - a for a, b in zip(dphi1, dphi2)]))
    N2 = [
        alpha3 * math.cos(p1 - p2) * dd1 - alpha3 * d1**2 * math.sin(p1 - p2) - alpha5 * math.sin(p2)
        for p1, p2, d1, dd1 in zip(phi1, phi2, dphi1, ddphi1)
    ]
    Nf2 = f(N2)
    a1, b1 = normal_equations(Mf1[0], Mf1[1], Nf1)
    alpha2, mu2 = normal_equations(Mf2[0], Mf2[1], Nf2)
    return {"n": len(t), "a1": a1, "b1": b1, "alpha2": alpha2, "mu2": mu2, "J2": alpha2 - m2 * l2**2}


if __name__ == "__main__":
    out = {
        "p1c221_id_cart": p1c221_id_cart(),
        "p1c321_cdip_id_cart": p1c321_cdip_id_cart(),
        "p1c332_adip_id_arm": p1c332_adip_id_arm(),
        "p1c332_adip_id_pend": p1c332_adip_id_pend(),
        "p1c332_adip_id_least_square": p1c332_adip_id_least_square(),
    }
    print(json.dumps(out, indent=1))
