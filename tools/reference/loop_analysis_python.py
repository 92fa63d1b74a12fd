"""Reference values for pendulab-lti's Nyquist, root-locus, disk-margin and sigma tools.

Tools: python-control 0.10.2 (NumPy, SciPy 1.16.3 underneath; no Slycot, so
control.disk_margins takes its SISO path |S + (skew − 1)/2| on the grid).

Writes crates/lti/tests/data/loop_analysis_reference.json (fixed seeds):
  - nyquist: SISO loops (random stable and unstable continuous loops, loops with one or two
    integrators, an undamped pole pair, open-loop unstable loops, discrete loops, one with
    an integrator z = 1): control.nyquist_response(L) with its defaults (indent_radius
    1e-4, indent_direction 'right') gives the clockwise encirclement count N; P counts the
    open-loop poles with Re p > 0 (|z| > 1) and Z the closed-loop poles with Re >= 0
    (|z| >= 1) of control.feedback(L). Only loops where python-control's own count
    satisfies Z = N + P are written (the number dropped is stored);
  - rlocus: SISO transfer functions and a gain list; control.root_locus_map(L, gains).loci
    (closed-loop poles per gain, python-control's order);
  - disk: stable closed loops and a skew; control.disk_margins(L, omega, skew,
    returnall=True) on a log grid
    (301 points over 1e-3 … 1e3 rad/s, stored once as disk_omega): the frequency-wise disk margin, gain margin (dB) and
    phase margin (deg), and the worst case (returnall=False);
  - sigma: MIMO systems; control.singular_values_response(G, omega) (checked here against
    numpy.linalg.svd of the frequency response).

Run from the repository root:
    python3 -m venv /tmp/venv && /tmp/venv/bin/pip install control==0.10.2 scipy==1.16.3
    /tmp/venv/bin/python tools/reference/loop_analysis_python.py
"""

import json
import pathlib
import warnings

import control
import numpy as np
import scipy
from fixture_json import mat, sysdict

OUT = pathlib.Path("crates/lti/tests/data/loop_analysis_reference.json")
# The disk-margin grid (stored once in the fixture as "disk_omega").
OMEGA_DISK = np.logspace(-3, 3, 301)


def cplx(v):
    return [[float(np.real(x)), float(np.imag(x))] for x in v]


def nyquist_cases(rng):
    loops = []
    tf = control.tf
    # Hand-made loops: integrators, an undamped pair, open-loop unstable.
    loops += [
        tf([2.0], [1.0, 1.0]),
        tf([10.0], [1.0, 3.0, 3.0, 1.0]),  # 1/(s+1)^3, gain 10: unstable closed loop
        tf([4.0], [1.0, 3.0, 3.0, 1.0]),
        tf([1.0], [1.0, 1.0, 0.0]),  # integrator
        tf([3.0, 1.0], [1.0, 0.0, 0.0]),  # double integrator with a lead zero
        tf([1.0], [1.0, 0.0, 0.0]),  # double integrator: closed loop on the axis
        tf([1.0, 0.2], [1.0, 0.0, 1.0]),  # undamped pole pair at ±j
        tf([1.0], [1.0, 0.5, 0.0, 4.0, 0.0]),
        tf([5.0, 10.0], [1.0, 2.0, -3.0]),  # (s+2)/((s-1)(s+3)), stable closed loop
        tf([0.5, 1.0], [1.0, 2.0, -3.0]),  # gain too small: unstable
        tf([1.0, 1.0], [1.0, -1.0, 0.0]),  # unstable pole and an integrator
        tf([-2.0], [1.0, 1.0]),
        tf([1.0, -1.0], [1.0, 3.0, 2.0]),  # non-minimum phase
    ]
    for n in range(1, 7):
        for _ in range(3):
            np.random.seed(rng.integers(2**31))
            g = control.rss(n, 1, 1)
            g = control.ss(g.A, g.B, g.C, np.zeros((1, 1)))
            dc = abs(control.evalfr(g, 1j))
            k = 10 ** rng.uniform(-0.3, 1.3) / max(dc, 1e-6) * rng.choice([-1.0, 1.0])
            loops.append(control.ss(g.A, g.B, g.C * k, g.D))
    for n in range(1, 5):
        for _ in range(2):
            np.random.seed(rng.integers(2**31))
            g = control.drss(n, 1, 1, dt=0.05)
            g = control.ss(g.A, g.B, g.C, np.zeros((1, 1)), 0.05)
            dc = abs(control.evalfr(g, np.exp(0.05j)))
            k = 10 ** rng.uniform(-0.3, 1.0) / max(dc, 1e-6) * rng.choice([-1.0, 1.0])
            loops.append(control.ss(g.A, g.B, g.C * k, g.D, 0.05))
    loops.append(tf([0.1], [1.0, -1.0], 0.1))  # discrete integrator
    loops.append(tf([0.5, 0.2], [1.0, -1.5, 0.5], 0.1))  # integrator and a pole at 0.5
    loops.append(tf([1.0], [1.0, -1.2], 0.1))  # unstable discrete pole, gain 1
    cases, dropped = [], 0
    for L in loops:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = control.nyquist_response(L)
        dt = L.dt not in (0, None)
        poles = L.poles()
        clp = control.feedback(L).poles()
        if dt:
            P = int((np.abs(poles) > 1).sum())
            Z = int((np.abs(clp) >= 1).sum())
        else:
            P = int((poles.real > 0).sum())
            Z = int((clp.real >= 0).sum())
        if Z != r.count + P:
            dropped += 1
            continue
        cases.append(dict(sysdict(L), count=int(r.count), P=P, Z=Z))
    return cases, dropped


def rlocus_cases():
    tf = control.tf
    specs = [
        (tf([1.0], [1.0, 3.0, 2.0, 0.0]), [0, 0.1, 0.3849, 1, 2, 6, 10, 100]),
        (tf([1.0, 1.0], [1.0, 3.0, -4.0, 0.0]), [0, 0.5, 1, 3, 10, 50]),
        (tf([1.0, 2.0, 5.0], [1.0, 9.0, 26.0, 24.0, 0.0]), [0, 0.2, 1, 5, 25, 125]),
        (tf([2.0, 1.0], [1.0, 2.0, 1.0]), [0, 0.3, 1.5, 7]),  # biproper? no: m = 1, n = 2
        (tf([1.0, 0.5], [1.0, -1.6, 0.8, -0.1], 0.1), [0, 0.05, 0.2, 0.7, 1.5]),
        (tf([1.0, -1.0], [1.0, 4.0, 5.0]), [0, 0.5, 2, 4.9]),
    ]
    out = []
    for L, gains in specs:
        m = control.root_locus_map(L, gains)
        num = np.atleast_1d(np.squeeze(L.num[0][0])).tolist()
        den = np.atleast_1d(np.squeeze(L.den[0][0])).tolist()
        out.append(
            {
                "num": num,
                "den": den,
                "dt": None if L.dt in (0, None) else float(L.dt),
                "gains": [float(k) for k in gains],
                "loci": [cplx(row) for row in m.loci],
            }
        )
    return out


def disk_cases(rng):
    omega = OMEGA_DISK
    tf = control.tf
    loops = [
        (tf([2.0], [1.0, 1.0]), 0.0),
        (tf([1.0], [1.0, 1.0, 0.0]), 0.0),
        (tf([4.0], [1.0, 3.0, 3.0, 1.0]), 0.0),
        (tf([4.0], [1.0, 3.0, 3.0, 1.0]), 0.5),
        (tf([4.0], [1.0, 3.0, 3.0, 1.0]), -0.5),
        (tf([5.0, 10.0], [1.0, 2.0, -3.0]), 0.0),
        (tf([25.0], [1.0, 1.0, 25.0]), 0.0),
        (tf([0.8, 0.4], [1.0, 0.3, 1.0, 0.0]), 0.2),
    ]
    while len(loops) < 16:
        np.random.seed(rng.integers(2**31))
        n = int(rng.integers(1, 7))
        g = control.rss(n, 1, 1)
        g = control.ss(g.A, g.B, g.C, np.zeros((1, 1)))
        dc = abs(control.evalfr(g, 1j))
        k = 10 ** rng.uniform(-0.3, 0.7) / max(dc, 1e-6) * rng.choice([-1.0, 1.0])
        L = control.ss(g.A, g.B, g.C * k, g.D)
        if np.all(control.feedback(L).poles().real < -1e-6):
            loops.append((L, float(rng.choice([0.0, 0.0, 0.3, -0.3]))))
    cases = []
    for L, skew in loops:
        assert np.all(control.feedback(L).poles().real < 0), "closed loop must be stable"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            dm, dgm, dpm = control.disk_margins(L, omega, skew=skew, returnall=True)
            wdm, wdgm, wdpm = control.disk_margins(L, omega, skew=skew)
        fin = lambda v: [float(x) if np.isfinite(x) else None for x in v]
        cases.append(
            dict(
                sysdict(L),
                skew=skew,
                dm=fin(dm),
                dgm=fin(dgm),
                dpm=fin(dpm),
                worst=[float(wdm), float(wdgm) if np.isfinite(wdgm) else None,
                       float(wdpm) if np.isfinite(wdpm) else None],
            )
        )
    return cases


def sigma_cases(rng):
    omega = np.logspace(-2, 2, 41)
    cases = []
    for ny, nu, dt in [(2, 3, None), (3, 2, None), (3, 3, None), (2, 2, 0.1), (1, 3, None)]:
        np.random.seed(rng.integers(2**31))
        n = int(rng.integers(2, 7))
        g = control.rss(n, ny, nu) if dt is None else control.drss(n, ny, nu, dt=dt)
        w = omega if dt is None else omega[omega < np.pi / dt]
        r = control.singular_values_response(g, w)
        sv = np.abs(np.asarray(r.frdata))[:, 0, :].T  # (nω, k)
        for k, wk in enumerate(w):
            x = np.exp(1j * wk * dt) if dt else 1j * wk
            ref = np.linalg.svd(g(x), compute_uv=False)
            assert np.allclose(ref, sv[k], rtol=1e-12, atol=0), (ref, sv[k])
        cases.append(dict(sysdict(g), omega=w.tolist(), sv=sv.tolist()))
    return cases


def main():
    rng = np.random.default_rng(20260608)
    nyq, dropped = nyquist_cases(rng)
    out = {
        "tool": f"python-control {control.__version__}, SciPy {scipy.__version__}, NumPy {np.__version__}",
        "nyquist": nyq,
        "nyquist_dropped": dropped,
        "rlocus": rlocus_cases(),
        "disk_omega": OMEGA_DISK.tolist(),
        "disk": disk_cases(rng),
        "sigma": sigma_cases(rng),
    }
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps(out, indent=None, separators=(",", ":")) + "\n")
    print(
        f"{len(nyq)} nyquist ({dropped} dropped), {len(out['rlocus'])} rlocus, "
        f"{len(out['disk'])} disk, {len(out['sigma'])} sigma -> {OUT}"
    )


if __name__ == "__main__":
    main()
