"""Independent RK4 reference values for pendulab-sim's integrator and sampled-data tests.

Writes crates/sim/tests/fixtures/rk4_reference.json. Everything here is plain Python 3 floats
(IEEE double, no NumPy), written from the textbook formulas, sharing no code with the Rust
crate:

  - classic RK4 (Kutta 1901): k1 = f(t, x), k2 = f(t + h/2, x + h/2 k1),
    k3 = f(t + h/2, x + h/2 k2), k4 = f(t + h, x + h k3), x+ = x + h/6 (k1 + 2k2 + 2k3 + k4),
    on a grid t_k = t0 + k*h;
  - "pendulum": damped pendulum driven by u(t) = 0.5 sin(2t) (the input evaluated at the stage
    times), theta'' = -(g/l) sin(theta) - c theta' + u;
  - "van_der_pol": x'' = mu (1 - x^2) x' - x, mu = 2;
  - "cart_pendulum_loop": the nonlinear cart-type pendulum of docs/model.md §1 (book table 3.5) in a
    sampled-data loop: every ts = 0.01 s the command v_k = sat(-K x_k, +-5 V) is computed from
    the true state and held (zero-order hold) while RK4 takes 4 substeps of 0.0025 s; the time
    of sample k is k*ts (no accumulation).

Run: python3 tools/reference/sim_rk4_reference.py   (from the repository root)
Tool: CPython (version recorded in the fixture), no third-party packages.
"""

import json
import math
import pathlib
import platform


def rk4_step(f, t, x, h):
    k1 = f(t, x)
    k2 = f(t + h / 2, [xi + h / 2 * ki for xi, ki in zip(x, k1)])
    k3 = f(t + h / 2, [xi + h / 2 * ki for xi, ki in zip(x, k2)])
    k4 = f(t + h, [xi + h * ki for xi, ki in zip(x, k3)])
    return [xi + h / 6 * (a + 2 * b + 2 * c + d) for xi, a, b, c, d in zip(x, k1, k2, k3, k4)]


def integrate(f, x0, h, steps, every):
    x = list(x0)
    out = [[0.0] + x]
    for k in range(steps):
        x = rk4_step(f, k * h, x, h)
        if (k + 1) % every == 0:
            out.append([(k + 1) * h] + x)
    return out


def pendulum_case():
    g, l, c = 9.81, 0.5, 0.3

    def f(t, x):
        u = 0.5 * math.sin(2 * t)
        return [x[1], -(g / l) * math.sin(x[0]) - c * x[1] + u]

    x0 = [2.5, 0.0]
    h, steps = 0.01, 500
    return {
        "name": "pendulum",
        "params": {"g": g, "l": l, "c": c, "u_amplitude": 0.5, "u_omega": 2.0},
        "x0": x0,
        "dt": h,
        "steps": steps,
        "samples": integrate(f, x0, h, steps, 25),
    }


def van_der_pol_case():
    mu = 2.0

    def f(t, x):
        return [x[1], mu * (1 - x[0] ** 2) * x[1] - x[0]]

    x0 = [2.0, 0.0]
    h, steps = 0.005, 2000
    return {
        "name": "van_der_pol",
        "params": {"mu": mu},
        "x0": x0,
        "dt": h,
        "steps": steps,
        "samples": integrate(f, x0, h, steps, 100),
    }


def cart_pendulum_loop_case():
    ac, bc, mp, lp, jp, mup, g = 6.25, 4.36, 0.107, 0.230, 1.59e-3, 2.35e-4, 9.81
    J = jp + mp * lp * lp
    K = [-10.0, -45.0, -12.0, -6.0]  # library sign: v = -K x
    vmax = 5.0
    ts, substeps, samples = 0.01, 4, 200
    h = ts / substeps

    def f(v):
        def rhs(t, x):
            z_dd = -ac * x[2] + bc * v
            th_dd = (mp * g * lp * math.sin(x[1]) - mup * x[3] - mp * lp * math.cos(x[1]) * z_dd) / J
            return [x[2], x[3], z_dd, th_dd]

        return rhs

    x = [0.05, 0.3, 0.0, 0.0]
    out = []
    for k in range(samples + 1):
        tk = k * ts
        v = -sum(ki * xi for ki, xi in zip(K, x))
        v = max(-vmax, min(vmax, v))
        out.append([tk] + x + [v])
        if k == samples:
            break
        rhs = f(v)
        for j in range(substeps):
            x = rk4_step(rhs, tk + j * h, x, h)
    return {
        "name": "cart_pendulum_loop",
        "params": {"a_c": ac, "b_c": bc, "m_p": mp, "l_p": lp, "J_p": jp, "mu_p": mup, "g": g,
                   "K": K, "v_max": vmax, "ts": ts, "substeps": substeps},
        "x0": [0.05, 0.3, 0.0, 0.0],
        "samples_layout": "t, z, theta, dz, dtheta, v (v computed at t and held)",
        "samples": out,
    }


def main():
    out = {
        "tool": f"CPython {platform.python_version()} (plain floats, no third-party packages)",
        "script": "tools/reference/sim_rk4_reference.py",
        "cases": [pendulum_case(), van_der_pol_case(), cart_pendulum_loop_case()],
    }
    path = pathlib.Path("crates/sim/tests/fixtures/rk4_reference.json")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
