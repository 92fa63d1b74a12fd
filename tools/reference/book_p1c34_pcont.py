"""Reference for book example p1c34_cdip_plot_pcont (pendulab-book tests/p1c3.rs).

The nonlinear cart pendulum of docs/model.md §1 (table 3.5), hanging, under P control of the cart
position u = k_P (0.2 - z), k_P = 10, integrated by SciPy's solve_ivp (DOP853, rtol 1e-11,
atol 1e-13) in two variants:
  - "continuous": the controller acts continuously (the book's Simulink picture);
  - "zoh": the controller samples z every 1 ms and holds u (pendulab's sampled loop).
Prints the cart peak, its time, the first three extrema of phi = theta - pi and their times.

Run: python3 tools/reference/book_p1c34_pcont.py
Produced with Python 3.11, NumPy 2.4.6, SciPy 1.17.1.
"""

import numpy as np
from scipy.integrate import solve_ivp

ac, bc, mp, lp, Jp, mup, g = 6.25, 4.36, 0.107, 0.230, 1.59e-3, 2.35e-4, 9.81
J = Jp + mp * lp**2
kp, r = 10.0, 0.2


def f(t, x, v):
    z, th, dz, dth = x
    ddz = -ac * dz + bc * v
    ddth = (mp * g * lp * np.sin(th) - mup * dth - mp * lp * np.cos(th) * ddz) / J
    return [dz, dth, ddz, ddth]


def extrema(t, y):
    d = np.diff(y)
    out = []
    for k in range(1, len(d)):
        if d[k - 1] * d[k] < 0:
            # parabola through three samples
            y0, y1, y2 = y[k - 1], y[k], y[k + 1]
            den = y0 - 2 * y1 + y2
            s = 0.5 * (y0 - y2) / den if den != 0 else 0.0
            h = t[1] - t[0]
            out.append((t[k] + s * h, y1 - 0.25 * (y0 - y2) * s))
    return out


def report(name, t, x):
    z, phi = x[0], x[1] - np.pi
    k = int(np.argmax(z))
    ex = extrema(t, phi)[:3]
    print(f"{name}: z_peak = {z[k]:.6f} at {t[k]:.4f} s; z(4) = {z[-1]:.6f}")
    print("   phi extrema:", ", ".join(f"{v:+.6f} at {tt:.4f} s" for tt, v in ex))


t = np.arange(0, 4.0 + 5e-7, 1e-4)
sol = solve_ivp(lambda t, x: f(t, x, kp * (r - x[0])), (0, 4), [0, np.pi, 0, 0],
                method="DOP853", rtol=1e-11, atol=1e-13, t_eval=t)
report("continuous", sol.t, sol.y)

ts = 1e-3
x = np.array([0.0, np.pi, 0.0, 0.0])
ts_all, xs = [0.0], [x.copy()]
for k in range(4000):
    v = kp * (r - x[0])
    s = solve_ivp(lambda t, x: f(t, x, v), (k * ts, (k + 1) * ts), x, method="DOP853",
                  rtol=1e-11, atol=1e-13)
    x = s.y[:, -1]
    ts_all.append((k + 1) * ts)
    xs.append(x.copy())
report("zoh 1 ms", np.array(ts_all), np.array(xs).T)
