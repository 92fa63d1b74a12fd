"""Reference values for pendulab-lti's loop-analysis, norm, reduction and step-metric tools.

Tools: python-control 0.10.2, SciPy 1.16.3, NumPy, and Slycot 0.7.1 (SLICOT: AB13BD for the
H2 norm, AB13DD for the L∞/H∞ norm, TB01PD inside control.minreal, SB03MD inside the
Gramians of control.hsvd, TB04AD inside the ss → tf conversion of stability_margins).

Writes crates/lti/tests/data/lti_toolbox_reference.json with random systems (fixed seeds)
and, per system,
  - margins (50 SISO loops, orders 1–10, 35 continuous and 15 discrete, some with an
    integrator): every gain crossing (ω, phase margin in degrees) and every phase crossing
    (ω, gain margin) from control.stability_margins(L, returnall=True, method='poly'),
    i.e. the roots of the polynomials |num(jω)|² − |den(jω)|² and Im(num(jω)·den(−jω))
    (z-domain counterparts in discrete time). Each crossing is checked here against the
    state-space frequency response (||L| − 1| ≤ 1e-7, |Im L| ≤ 1e-7·|L|); a loop failing the
    check is not written (the count is printed and stored);
  - norms (50 stable systems, orders 1–12, 1–3 inputs and outputs, 35 continuous and 15
    discrete): the H2 norm (control.norm(sys, 2), AB13BD) and the H∞ norm with its peak
    frequency (control.linfnorm, AB13DD, tol 1e-10);
  - hsvd (50 stable systems, orders 1–12): the singular values of L_oᵀ R_c with the Gramians
    W = F Fᵀ from SciPy's solve_continuous_lyapunov / solve_discrete_lyapunov (Bartels–
    Stewart) factored by numpy's eigh, and, for the continuous ones, control.hsvd
    (√eig(W_c W_o), which control.hsvd does not implement in discrete time) for comparison;
  - minreal (30 non-minimal systems built as a minimal part plus uncontrollable and
    unobservable parts, orders 2–12): the order control.minreal returns;
  - stepinfo (30 stable SISO systems, orders 1–6): control.step_info on a given time grid.

Run (from the repository root), with Slycot installed next to the venv:
    target/pyenv/bin/pip install --no-deps --target target/slycot-site slycot==0.7.1
    PYTHONPATH=target/slycot-site target/pyenv/bin/python tools/reference/lti_toolbox_reference.py
"""

import json
import pathlib
import warnings

import control
import numpy as np
import scipy
import slycot
from fixture_json import mat, sysdict

OUT = pathlib.Path("crates/lti/tests/data/lti_toolbox_reference.json")


def fin(x):
    x = float(x)
    return x if np.isfinite(x) else None


def response(sys, w):
    """L(jω) or L(e^{jωts}) from the state-space matrices (independent of the tf route)."""
    s = 1j * w if sys.dt in (0, None) else np.exp(1j * w * sys.dt)
    n = sys.nstates
    if n == 0:
        return complex(sys.D[0, 0])
    x = np.linalg.solve(s * np.eye(n) - sys.A, sys.B)
    return complex((sys.C @ x + sys.D)[0, 0])


def margins_cases(rng):
    cases, dropped = [], 0
    specs = [(n, False, False) for n in range(1, 11) for _ in range(3)]  # 30 continuous
    specs += [(n, False, True) for n in range(2, 7)]  # 5 continuous with an integrator
    specs += [(n, True, False) for n in range(1, 6) for _ in range(3)]  # 15 discrete
    for n, discrete, integ in specs:
        for _attempt in range(20):
            np.random.seed(rng.integers(2**31))
            if discrete:
                g = control.drss(n, 1, 1, dt=0.05)
            else:
                g = control.rss(n - 1 if integ else n, 1, 1)
                if integ:
                    g = control.series(g, control.tf2ss(control.tf([1.0], [1.0, 0.0])))
            g = control.ss(g.A, g.B, g.C, np.zeros((1, 1)), g.dt)
            dc = np.max(np.abs(control.evalfr(g, 1j * 1.0 if not discrete else np.exp(0.05j))))
            k = 10 ** rng.uniform(0.3, 1.5) / max(dc, 1e-6) * rng.choice([-1.0, 1.0])
            loop = control.ss(g.A, g.B, g.C * k, g.D, g.dt)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                gm, pm, sm, wpc, wgc, wms = control.stability_margins(
                    loop, returnall=True, method="poly"
                )
            wpc, gm = np.atleast_1d(wpc), np.atleast_1d(gm)
            wgc, pm = np.atleast_1d(wgc), np.atleast_1d(pm)
            phase = [
                (float(w), float(m))
                for w, m in zip(wpc, gm)
                if np.isfinite(w) and np.isfinite(m)
            ]
            gain = [(float(w), float(m)) for w, m in zip(wgc, pm)]
            ok = len(gain) > 0
            for w, _ in gain:
                v = response(loop, w)
                ok &= abs(abs(v) - 1.0) <= 1e-7
            for w, _ in phase:
                if w == 0.0:
                    continue
                v = response(loop, w)
                ok &= abs(v.imag) <= 1e-7 * abs(v) and v.real <= 0.0
            if ok:
                d = sysdict(loop)
                d["gain_crossings"] = sorted(gain)
                d["phase_crossings"] = sorted(phase)
                cases.append(d)
                break
            dropped += 1
    return cases, dropped


def random_system(rng, k):
    """Case k of 50: order 1 + k mod 12, 1–3 inputs and outputs, discrete (ts = 0.1 s) from 35."""
    discrete = k >= 35
    n = 1 + k % 12
    p, m = 1 + rng.integers(3), 1 + rng.integers(3)
    np.random.seed(rng.integers(2**31))
    g = control.drss(n, p, m, dt=0.1) if discrete else control.rss(n, p, m)
    return g, discrete


def norms_cases(rng):
    cases = []
    for k in range(50):
        g, discrete = random_system(rng, k)
        d = rng.uniform(-1, 1, (g.noutputs, g.ninputs)) * (k % 3 == 0)
        g = control.ss(g.A, g.B, g.C, d, g.dt)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            h2 = control.norm(g, 2, method="slycot")
        hinf, peak = control.linfnorm(g, tol=1e-10)
        e = sysdict(g)
        e["h2"] = fin(h2)
        e["hinf"] = fin(hinf)
        e["hinf_peak"] = fin(peak)
        cases.append(e)
    return cases


def sqrt_hsv(wc, wo):
    """Square-root route: W = F Fᵀ from eigh (negative rounding clipped), σ = svd(L_oᵀ R_c)."""

    def factor(w):
        ev, v = np.linalg.eigh((w + w.T) / 2)
        return v * np.sqrt(np.maximum(ev, 0.0))

    return np.linalg.svd(factor(wo).T @ factor(wc), compute_uv=False)


def hsvd_cases(rng):
    cases = []
    for k in range(50):
        g, discrete = random_system(rng, k)
        e = sysdict(g)
        if discrete:
            wc = scipy.linalg.solve_discrete_lyapunov(g.A, g.B @ g.B.T)
            wo = scipy.linalg.solve_discrete_lyapunov(g.A.T, g.C.T @ g.C)
        else:
            wc = scipy.linalg.solve_continuous_lyapunov(g.A, -g.B @ g.B.T)
            wo = scipy.linalg.solve_continuous_lyapunov(g.A.T, -g.C.T @ g.C)
        e["hsv"] = [float(v) for v in sqrt_hsv(wc, wo)]
        if not discrete:
            # python-control's √eig(W_c W_o) (SB03MD Gramians), kept for comparison: it
            # loses the small values of lightly damped systems (NaN where an eigenvalue of
            # the product comes out negative).
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                e["hsv_control"] = [fin(v) for v in control.hsvd(g)]
        cases.append(e)
    return cases


def minreal_cases(rng):
    cases = []
    for k in range(30):
        nm = 1 + k % 6
        nuc = 1 + rng.integers(3)  # uncontrollable
        nuo = 1 + rng.integers(3)  # unobservable
        p, m = 1 + rng.integers(2), 1 + rng.integers(2)
        np.random.seed(rng.integers(2**31))
        g = control.rss(nm, p, m)
        au = control.rss(nuc, 1, 1).A
        ao = control.rss(nuo, 1, 1).A
        n = nm + nuc + nuo
        a = scipy.linalg.block_diag(g.A, au, ao)
        # uncontrollable block: no input; unobservable block: not seen, driven by the input
        a[nm + nuc :, :nm] = rng.uniform(-1, 1, (nuo, nm))
        a[:nm, nm : nm + nuc] = rng.uniform(-1, 1, (nm, nuc))
        b = np.vstack([g.B, np.zeros((nuc, m)), rng.uniform(-1, 1, (nuo, m))])
        c = np.hstack([g.C, rng.uniform(-1, 1, (p, nuc)), np.zeros((p, nuo))])
        # A random orthogonal change of coordinates hides the structure.
        q, _ = np.linalg.qr(rng.normal(size=(n, n)))
        full = control.ss(q @ a @ q.T, q @ b, c @ q.T, g.D)
        # Keep only cases whose minimal part is well controllable/observable.
        r = control.minreal(full, verbose=False)
        e = sysdict(full)
        e["order"] = int(r.nstates)
        e["minimal_part_order"] = nm
        cases.append(e)
    return cases


def stepinfo_cases(rng):
    cases = []
    for k in range(30):
        n = 1 + k % 6
        np.random.seed(rng.integers(2**31))
        g = control.rss(n, 1, 1)
        g = control.ss(g.A, g.B, g.C, g.D * (k % 2), 0)
        slow = min(abs(p.real) for p in g.poles())
        tf = min(10.0 / slow, 200.0)
        t = np.linspace(0.0, tf, 2001)
        info = control.step_info(g, T=t)
        e = sysdict(g)
        e["t_final"] = tf
        e["samples"] = len(t)
        e["info"] = {key: fin(v) for key, v in info.items()}
        cases.append(e)
    return cases


def main():
    rng = np.random.default_rng(20261206)
    margins, dropped = margins_cases(rng)
    out = {
        "tools": {
            "python-control": control.__version__,
            "scipy": scipy.__version__,
            "numpy": np.__version__,
            "slycot": slycot.__version__,
        },
        "margins_dropped_attempts": dropped,
        "margins": margins,
        "norms": norms_cases(rng),
        "hsvd": hsvd_cases(rng),
        "minreal": minreal_cases(rng),
        "stepinfo": stepinfo_cases(rng),
    }
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps(out, indent=1) + "\n")
    print(
        f"wrote {OUT}: {len(out['margins'])} margin loops ({dropped} attempts dropped), "
        f"{len(out['norms'])} norms, {len(out['hsvd'])} hsvd, {len(out['minreal'])} minreal, "
        f"{len(out['stepinfo'])} stepinfo"
    )


if __name__ == "__main__":
    main()
