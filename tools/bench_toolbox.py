"""Side-by-side timing of pendulab's loop-analysis and H∞ workloads and python-control's.

Tools: python-control 0.10.2 (stability_margins, poly method through an ss → tf
conversion), Slycot 0.7.1 (AB13DD behind control.linfnorm / control.norm(sys, 'inf',
method='slycot')), NumPy, SciPy 1.16.3 (control.norm(sys, 'inf', method='scipy')).

The systems are the ones of crates/cli/src/bench/toolbox.rs, built here with the same
SplitMix64 stream filled row by row: A₀ uniform in [−1, 1), A = A₀ − (max Re λ(A₀) + 0.1) I,
B and C uniform, D = 0; margin-n10: seed 10, n = 10, SISO, L = k·G with k = 10/G(0);
hinf-n50: seed 50, n = 50, 2 inputs, 2 outputs, tolerance 1e-8. In the same run it calls
`pendulab bench margin-n10 --json` and `pendulab bench hinf-n50 --json` (release binary)
and prints one JSON object with both sides' figures and the values each side computed.

Run (from the repository root, after `cargo build --release -p pendulab`):
    target/pyenv/bin/pip install --no-deps --target target/slycot-site slycot==0.7.1
    PYTHONPATH=target/slycot-site target/pyenv/bin/python tools/bench_toolbox.py
"""

import json
import subprocess
import sys
import time
import warnings

import control
import numpy as np

try:
    import slycot
except ImportError:  # the scipy method is still timed
    slycot = None

MASK = (1 << 64) - 1


class SplitMix64:
    def __init__(self, seed):
        self.s = seed & MASK

    def uniform(self):
        self.s = (self.s + 0x9E3779B97F4A7C15) & MASK
        z = self.s
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
        z ^= z >> 31
        return (z >> 11) * (2.0 / (1 << 53)) - 1.0

    def matrix(self, r, c):
        return np.array([[self.uniform() for _ in range(c)] for _ in range(r)])


def random_stable(seed, n, p, m):
    g = SplitMix64(seed)
    a0 = g.matrix(n, n)
    b = g.matrix(n, m)
    c = g.matrix(p, n)
    shift = np.max(np.linalg.eigvals(a0).real)
    return control.ss(a0 - (shift + 0.1) * np.eye(n), b, c, np.zeros((p, m)))


def timeit(f, min_time=1.0):
    """Median seconds per call over batches of ~10 ms for at least min_time seconds."""
    t0 = time.perf_counter()
    f()
    once = max(time.perf_counter() - t0, 1e-7)
    batch = max(1, int(np.ceil(0.01 / once)))
    per_call = []
    start = time.perf_counter()
    while time.perf_counter() - start < min_time or len(per_call) < 3:
        s = time.perf_counter()
        for _ in range(batch):
            f()
        per_call.append((time.perf_counter() - s) / batch)
    return float(np.median(per_call))


def pendulab(workload):
    out = subprocess.run(
        ["target/release/pendulab", "bench", workload, "--json"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return json.loads(out)


def main():
    g = random_stable(10, 10, 1, 1)
    k = 10.0 / control.dcgain(g)
    loop = control.ss(g.A, g.B, g.C * k, g.D)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        gm, pm, sm, wpc, wgc, wms = control.stability_margins(loop, returnall=True)
        t_margin = timeit(lambda: control.stability_margins(loop, returnall=True))
    h = random_stable(50, 50, 2, 2)
    result = {
        "versions": {
            "python-control": control.__version__,
            "slycot": slycot.__version__ if slycot else None,
        },
        "margin-n10": {
            "python_control_us": t_margin * 1e6,
            "gain_crossings": [[float(w), float(p)] for w, p in zip(np.atleast_1d(wgc), np.atleast_1d(pm))],
            "phase_crossings": [[float(w), float(m)] for w, m in zip(np.atleast_1d(wpc), np.atleast_1d(gm))],
        },
        "hinf-n50": {},
    }
    if slycot:
        val, peak = control.linfnorm(h, tol=1e-8)
        result["hinf-n50"]["slycot_ab13dd_ms"] = timeit(lambda: control.linfnorm(h, tol=1e-8)) * 1e3
        result["hinf-n50"]["slycot_norm"] = float(val)
        result["hinf-n50"]["slycot_peak"] = float(peak)
    else:
        result["hinf-n50"]["slycot"] = "not installed"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        val = control.norm(h, "inf", tol=1e-8, method="scipy")
        result["hinf-n50"]["scipy_method_ms"] = (
            timeit(lambda: control.norm(h, "inf", tol=1e-8, method="scipy"), 3.0) * 1e3
        )
    result["hinf-n50"]["scipy_method_norm"] = float(val)
    for name in ("margin-n10", "hinf-n50"):
        try:
            r = pendulab(name)
            result[name]["pendulab"] = {"figure": r["figure"], "unit": r["unit"], "check": r["check"]}
        except (OSError, subprocess.CalledProcessError) as e:
            result[name]["pendulab"] = f"not run: {e}"
    json.dump(result, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
