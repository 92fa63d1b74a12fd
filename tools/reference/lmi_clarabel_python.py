#!/usr/bin/env python3
"""Solve the exact conic problems pendulab-lmi hands Clarabel with the Python build of Clarabel.

Input: the JSON written by the ignored test `export_benchmark_problems` in
crates/lmi/tests/conic_export.rs (one file per benchmark workload: `lmi_servo.json`,
`sos_gain_schedule.json`), each holding, per Clarabel solve, A (CSC), b, q, the cones, the
settings pendulab sets (all others at Clarabel's defaults, which are the same in both
builds of the same version) and what the Rust build returned.

    PENDULAB_CONIC_DIR=$PWD/target/conic cargo test --release -p pendulab-lmi \
        --test conic_export -- --ignored
    python3 tools/reference/lmi_clarabel_python.py target/conic

For each solve it prints Clarabel's own `solve_time` (median and minimum of `--repeats`
solves), iterations, status, objective and final residuals of the Python build next to the
Rust build's. The Python wheel ships its own BLAS/LAPACK; the Rust build runs on
crates/lapack. Each problem is solved with both KKT factorisations, QDLDL (Clarabel's
simplicial LDLᵀ) and faer's supernodal LDLᵀ; pendulab's `KktSolver::Auto` uses QDLDL below
a KKT dimension of 500 (the servo: 101) and faer from there on (the SOS program: 2 752).

Figures recorded with clarabel 0.11.1 (PyPI wheel), NumPy 2.4.6, SciPy 1.17.1, Python
3.11.7, on the 2-core shared development machine under other builds (load average 2.6–3.2),
2026-11-27; pendulab-lmi settings: Clarabel defaults except at most one iterative-refinement
step (`SolveOptions::refinement_steps = 1`) and unmerged chordal cliques
(`SolveOptions::merge_cliques = false`); Clarabel `solve_time`, min / median:

    problem (n vars, m rows)                  python qdldl      python qdldl,     python faer
                                              same settings     default refine.   (info only)
    lmi-servo (20, 81)                        3.42 / 3.90 ms    4.06 / 5.37 ms    3.19 / 5.17 ms
                                              (12 it)           (12 it)           (12 it)
    sos γ minimisation (1081, 1671)           1507 / 1526 ms    1490 / 1580 ms    537 / 570 ms
                                              (27 it)           (28 it)           (22 it)
    sos re-solve γ ≤ 1.06 γ* (1081, 1672)     889 / 1010 ms     859 / 871 ms      516 / 545 ms
                                              (17 it)           (17 it)           (17 it)

Same machine and hour, `pendulab bench <workload> --json` (whole design: build, Clarabel
setup and solve with QDLDL on crates/lapack, rechecks): lmi-servo min 2.89 ms, median
3.26–4.32 ms (12 it); sos-gain-schedule median 2157–2416 ms for both solves (24 + 17 it;
Clarabel solve_time 1384–1516 + 874–1024 ms). Iteration counts of the degenerate γ
minimisation differ between builds and settings (22–28) because their dense kernels round
differently; it ends `AlmostSolved` in every build and setting tried.

Quiet machine (load average ≈ 1), 2026-11-27, pendulab with `KktSolver::Auto` (QDLDL for the
servo, faer for the SOS program), Clarabel `solve_time` median:

    problem                          python qdldl    python faer     rust (export run)
    lmi-servo                        4.93 ms         5.33 ms         3.32 ms (qdldl)
    sos γ minimisation               1514 ms (27 it) 896 ms (22 it)  774 ms (faer, 25 it)
    sos re-solve γ ≤ 1.06 γ*         1003 ms (17 it) 645 ms (17 it)  559 ms (faer, 17 it)

and `pendulab bench sos-gain-schedule` 1465 ms median for the whole design (both solves);
`tools/reference/lmi_perf_cvxpy.py` in the same minutes: cvxpy's single γ minimisation 4240 ms
total median (Clarabel auto/faer, 34 it), 6074 ms with QDLDL.
"""

import argparse
import json
import pathlib
import statistics
import time

import clarabel
import numpy as np
import scipy.sparse as sp


def cones_of(spec):
    out = []
    for kind, d in spec:
        if kind == "zero":
            out.append(clarabel.ZeroConeT(d))
        elif kind == "nonneg":
            out.append(clarabel.NonnegativeConeT(d))
        elif kind == "psd_triangle":
            out.append(clarabel.PSDTriangleConeT(d))
        else:
            raise ValueError(f"unknown cone {kind}")
    return out


def settings_of(spec):
    s = clarabel.DefaultSettings()
    s.verbose = False
    for name, v in spec.items():
        if name in ("max_iter", "iterative_refinement_max_iter"):
            v = int(v)
        elif name in ("chordal_decomposition_enable", "iterative_refinement_enable"):
            v = bool(v)
        setattr(s, name, v)
    return s


def solve(prob, repeats, clarabel_refinement=False, method="qdldl"):
    m, n = prob["m"], prob["n"]
    A = sp.csc_matrix(
        (prob["A"]["nzval"], prob["A"]["rowval"], prob["A"]["colptr"]), shape=(m, n)
    )
    P = sp.csc_matrix((n, n))
    q = np.array(prob["q"], dtype=float)
    b = np.array(prob["b"], dtype=float)
    cones = cones_of(prob["cones"])
    times, wall = [], []
    sol = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        settings = settings_of(prob["settings"])
        settings.chordal_decomposition_merge_method = prob.get("merge_method", "clique_graph")
        # Forced either way (the wheel's "auto" would pick faer on dense-fill KKT systems).
        settings.direct_solve_method = method
        if clarabel_refinement:
            # Clarabel's own defaults for iterative refinement (up to 10 steps).
            settings.iterative_refinement_enable = True
            settings.iterative_refinement_max_iter = 10
        solver = clarabel.DefaultSolver(P, q, A, b, cones, settings)
        sol = solver.solve()
        wall.append(time.perf_counter() - t0)
        times.append(sol.solve_time)
    return sol, times, wall


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir", help="directory with lmi_servo.json and sos_gain_schedule.json")
    ap.add_argument("--repeats", type=int, default=0, help="solves per problem (0: auto)")
    args = ap.parse_args()
    print(f"clarabel (python) {clarabel.__version__}")
    for name in ["lmi_servo", "sos_gain_schedule"]:
        path = pathlib.Path(args.dir) / f"{name}.json"
        if not path.exists():
            print(f"{name}: {path} missing")
            continue
        data = json.loads(path.read_text())
        for k, prob in enumerate(data["solves"]):
            repeats = args.repeats or (50 if prob["n"] < 200 else 5)
            rust = prob["rust"]
            cones = ",".join(f"{c}{d}" for c, d in prob["cones"])
            print(f"{name} solve {k}: n={prob['n']} m={prob['m']} nnz(A)={len(prob['A']['nzval'])} cones=[{cones}]")
            for label, default_ir, method in [
                ("python, same settings (qdldl)", False, "qdldl"),
                ("python, Clarabel's default refinement (qdldl)", True, "qdldl"),
                ("python, same settings, faer", False, "faer"),
            ]:
                sol, times, wall = solve(prob, repeats, default_ir, method)
                print(
                    f"  {label}: status={sol.status} it={sol.iterations} "
                    f"solve_time median={statistics.median(times)*1e3:.3f} ms min={min(times)*1e3:.3f} ms "
                    f"(setup+solve wall median {statistics.median(wall)*1e3:.3f} ms) "
                    f"obj={sol.obj_val:.12e} r_prim={sol.r_prim:.2e} r_dual={sol.r_dual:.2e}"
                )
            print(
                f"  rust (export run): status={rust['status']} it={rust['iterations']} "
                f"solve_time={rust['solve_time']*1e3:.3f} ms (one solve) "
                f"obj={rust['obj_val']:.12e} r_prim={rust['r_prim']:.2e} r_dual={rust['r_dual']:.2e}"
            )


if __name__ == "__main__":
    main()
