"""Which simulation setting reproduces the book's printed digits of p1c34_cdip_plot_pcont.

The book's p1c34 example (part 1 §3.4): cart P control v = k_P (0.2 - z), k_P = 10, pendulum hanging, 4 s; z peaks 0.237 m
at 0.54 s and settles at 0.200 m; phi = theta - pi has extrema +0.394 rad at 0.30 s, -0.701 at
0.79 s, +0.755 at 1.35 s.

This script integrates the nonlinear cart pendulum of docs/model.md §1 (book table 3.5) with a
plain-Python classic RK4 (Kutta 1901; shares no code with pendulab) in four settings and prints
z's first peak and phi's first three extrema on the 1 ms grid:

  continuous  - the P law inside the ODE (acts continuously), RK4 at 1 ms and at 0.1 ms;
  zoh 1 kHz   - the P law sampled every 1 ms and held (zero-order hold), RK4 at 1 ms;
  zoh 10 kHz  - sampled every 0.1 ms.

Result (CPython 3.11.7, no third-party packages):
  continuous 1 ms:  z 0.2370 @ 0.540; phi +0.3944 @ 0.298, -0.7009 @ 0.792, +0.7546 @ 1.346
  zoh 1 kHz:        z 0.2373 @ 0.540; phi +0.3950 @ 0.298, -0.7026 @ 0.792, +0.7567 @ 1.346
Only the continuous law rounds to every printed digit; the 1 kHz ZOH (an effective delay of
ts/2) is off in the third decimal of phi. The P law reads only z, so the velocity estimate
(derivative + 1/(0.02 s + 1)) does not enter. crates/plants/tests/acceptance.rs asserts the
book's digits on pendulab's continuous-loop run (these printed numbers are not asserted).

Run: python3 tools/reference/sim_p1c34.py
"""

import math
import platform

AC, BC, MP, LP, JP, MUP, G = 6.25, 4.36, 0.107, 0.230, 1.59e-3, 2.35e-4, 9.81
J = JP + MP * LP * LP
KP, R = 10.0, 0.2


def f(x, v):
    z, th, zd, thd = x
    zdd = -AC * zd + BC * v
    thdd = (MP * G * LP * math.sin(th) - MUP * thd - MP * LP * math.cos(th) * zdd) / J
    return [zd, thd, zdd, thdd]


def rk4(g, x, h):
    k1 = g(x)
    k2 = g([a + h / 2 * b for a, b in zip(x, k1)])
    k3 = g([a + h / 2 * b for a, b in zip(x, k2)])
    k4 = g([a + h * b for a, b in zip(x, k3)])
    return [a + h / 6 * (p + 2 * q + 2 * r + s) for a, p, q, r, s in zip(x, k1, k2, k3, k4)]


def run(continuous, ts, h):
    """Samples of (t, z, phi) every 1 ms; controller period ts (ZOH) or continuous; RK4 step h."""
    x = [0.0, math.pi, 0.0, 0.0]
    out = []
    n_per_ms = round(1e-3 / h)
    n_per_sample = round(ts / h) if ts else 1
    v = 0.0
    for k in range(4000 * n_per_ms + 1):
        if k % n_per_ms == 0:
            out.append((k * h, x[0], x[1] - math.pi))
        if continuous:
            x = rk4(lambda y: f(y, KP * (R - y[0])), x, h)
        else:
            if k % n_per_sample == 0:
                v = KP * (R - x[0])
            x = rk4(lambda y: f(y, v), x, h)
    return out


def extrema(samples, i):
    v = [s[i] for s in samples]
    return [
        (samples[k][0], v[k])
        for k in range(1, len(v) - 1)
        if (v[k] > v[k - 1] and v[k] >= v[k + 1]) or (v[k] < v[k - 1] and v[k] <= v[k + 1])
    ]


def main():
    print(f"CPython {platform.python_version()}")
    for name, cont, ts, h in [
        ("continuous 1 ms", True, None, 1e-3),
        ("continuous 0.1 ms", True, None, 1e-4),
        ("zoh 1 kHz", False, 1e-3, 1e-3),
        ("zoh 10 kHz", False, 1e-4, 1e-4),
    ]:
        s = run(cont, ts, h)
        tz, zp = extrema(s, 1)[0]
        ph = ", ".join(f"{v:+.4f} @ {t:.3f}" for t, v in extrema(s, 2)[:3])
        print(f"{name:18s} z {zp:.4f} @ {tz:.3f}; z(4 s) {s[-1][1]:.4f}; phi {ph}")


if __name__ == "__main__":
    main()
