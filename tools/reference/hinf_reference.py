"""Reference values for pendulab's H∞ and H2 syntheses (Riccati in pendulab-lti, LMI in
pendulab-lmi).

Tools: python-control 0.10.2, NumPy, SciPy 1.16.3 and Slycot 0.7.1 (SLICOT SB10AD: H∞
γ-iteration and the optimal controller, "modified Glover's and Doyle's 1988 formulas",
called directly with a tight tolerance GTOL; SB10HD through control.h2syn; AB13DD through
control.linfnorm; AB13BD through control.norm(sys, 2)).

Writes crates/lti/tests/data/hinf_reference.json with, per standard plant
P = [A B1 B2; C1 D11 D12; C2 D21 D22] (the whole system A, B, C, D, with nmeas, ncon):
  - gamma_slycot: the level SB10AD returns (its estimate of the optimal γ to GTOL, the
    tightest of 1e-8, 1e-6, 1e-4 whose controller closes a stable loop, stored as gtol: a
    tighter GTOL returns unstable closed loops on some plants);
  - gamma_closed_loop: ‖T_zw‖∞ of SB10AD's controller in closed loop (control.linfnorm,
    tol 1e-10): any stabilising controller's norm bounds the optimum from above;
  - h2_optimal (plants with D11 = 0): ‖T_zw‖₂ of control.h2syn's controller in closed loop,
    control.norm(·, 2) of the lower LFT (P.lft(K)).
Plants:
  - "first_order_unstable": python-control's own hinfsyn example, G = 1/(s − 1) with
    z = u, y = w + G u; the optimum is γ_opt = 2 in closed form (robust stabilisation for
    additive uncertainty, Glover 1986: 1/σ_H of the mirror image 1/(s + 1), whose Hankel
    singular value is 1/2);
  - "cart_lq": the book's cart pendulum (table 3.5; docs/model.md §1, upright), the LQ
    weights of part 2 §2.3.4 (Q = diag(10, 10, 0, 0), R = 1) as z = [√10 z_c; √10 θ; u],
    w = [input disturbance; encoder noise of the two positions × 0.1], y = [z_c; θ] + noise;
  - "random6" and "random6_d22": a random 6-state plant (seed 8), nw = 3, ncon = 2, nz = 4,
    nmeas = 2, D11 = 0, with D22 = 0 and with a random D22 (loop shift); "random6_d11": the
    same with a random D11 (3 × standard normal; the LMI synthesis only);
  - "mixsyn_d11": the mixed-sensitivity plant of control.augw for
    G = 200/((10s + 1)(0.05s + 1)²) (Skogestad & Postlethwaite, Multivariable Feedback
    Control, example 2.11), W1 = (s/M + ω_b)/(s + ω_b A) with M = 1.5, ω_b = 10, A = 1e-4,
    W2 = 1: D11 = 1/M ≠ 0 (the LMI synthesis only; the Riccati synthesis refuses it);
  - "mixsyn": the same G with W1 = 5/(s + 0.1), W2 = 0.1 (D11 = 0).

Run (from the repository root):
    python3 -m venv /tmp/venv-hinf
    /tmp/venv-hinf/bin/pip install control==0.10.2 scipy==1.16.3 slycot==0.7.1
    /tmp/venv-hinf/bin/python tools/reference/hinf_reference.py
"""

import json
import pathlib

import control
import numpy as np
import scipy
import slycot
from book_plants import cdip

OUT = pathlib.Path(__file__).resolve().parents[2] / "crates/lti/tests/data/hinf_reference.json"


def assemble(A, B1, B2, C1, C2, D11, D12, D21, D22):
    B = np.hstack([B1, B2])
    C = np.vstack([C1, C2])
    D = np.block([[D11, D12], [D21, D22]])
    return A, B, C, D


def plants():
    out = {}
    # python-control's hinfsyn docstring example.
    out["first_order_unstable"] = (
        np.array([[1.0]]),
        np.array([[0.0, 1.0]]),
        np.array([[0.0], [1.0]]),
        np.array([[0.0, 1.0], [1.0, 0.0]]),
        1,
        1,
    )
    A, Bu = cdip()
    sigma = 0.1
    C1 = np.vstack([np.diag(np.sqrt([10.0, 10.0, 0.0, 0.0]))[:2], np.zeros((1, 4))])
    D12 = np.array([[0.0], [0.0], [1.0]])
    C2 = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    B1 = np.hstack([Bu, np.zeros((4, 2))])
    D21 = np.hstack([np.zeros((2, 1)), sigma * np.eye(2)])
    out["cart_lq"] = (
        *assemble(A, B1, Bu, C1, C2, np.zeros((3, 3)), D12, D21, np.zeros((2, 1))),
        2,
        1,
    )
    rng = np.random.default_rng(8)
    n, nw, nu, nz, ny = 6, 3, 2, 4, 2
    A = rng.standard_normal((n, n))
    B1 = rng.standard_normal((n, nw))
    B2 = rng.standard_normal((n, nu))
    C1 = rng.standard_normal((nz, n))
    C2 = rng.standard_normal((ny, n))
    D12 = rng.standard_normal((nz, nu))
    D21 = rng.standard_normal((ny, nw))
    D22 = rng.standard_normal((ny, nu))
    Z11 = np.zeros((nz, nw))
    out["random6"] = (*assemble(A, B1, B2, C1, C2, Z11, D12, D21, np.zeros((ny, nu))), ny, nu)
    out["random6_d22"] = (*assemble(A, B1, B2, C1, C2, Z11, D12, D21, D22), ny, nu)
    D11 = 3.0 * rng.standard_normal((nz, nw))
    out["random6_d11"] = (*assemble(A, B1, B2, C1, C2, D11, D12, D21, np.zeros((ny, nu))), ny, nu)
    s = control.tf("s")
    G = 200 / ((10 * s + 1) * (0.05 * s + 1) ** 2)
    M, wb, Aw = 1.5, 10.0, 1e-4
    W1 = (s / M + wb) / (s + wb * Aw)
    W2 = control.tf([1.0], [1.0])
    P = control.augw(control.ss(G), control.ss(W1), control.ss(W2))
    out["mixsyn_d11"] = (P.A, P.B, P.C, P.D, 1, 1)
    W1s = 5 / (s + 0.1)
    W2s = control.tf([0.1], [1.0])
    P = control.augw(control.ss(G), control.ss(W1s), control.ss(W2s))
    out["mixsyn"] = (P.A, P.B, P.C, P.D, 1, 1)
    return out


def main():
    cases = []
    for name, (A, B, C, D, nmeas, ncon) in plants().items():
        A, B, C, D = (np.atleast_2d(np.asarray(m, dtype=float)) for m in (A, B, C, D))
        n, m, np_ = A.shape[0], B.shape[1], C.shape[0]
        # The tightest GTOL of 1e-8, 1e-6, 1e-4 whose controller closes a stable loop.
        for gtol in (1e-8, 1e-6, 1e-4):
            gam, Ak, Bk, Ck, Dk, Ac, Bc, Cc, Dc, rcond = slycot.sb10ad(
                n, m, np_, ncon, nmeas, 1e6, A, B, C, D, job=3, gtol=gtol
            )
            if np.all(np.linalg.eigvals(Ac).real < 0):
                break
        assert np.all(np.linalg.eigvals(Ac).real < 0), name
        cl = control.ss(Ac, Bc, Cc, Dc)
        norm_cl = float(control.linfnorm(cl, tol=1e-10)[0])
        case = {
            "name": name,
            "a": A.tolist(),
            "b": B.tolist(),
            "c": C.tolist(),
            "d": D.tolist(),
            "nmeas": nmeas,
            "ncon": ncon,
            "gamma_slycot": float(gam),
            "gtol": gtol,
            "gamma_closed_loop": norm_cl,
        }
        nz, nw = np_ - nmeas, m - ncon
        if not np.any(D[:nz, :nw]):
            P = control.ss(A, B, C, D)
            K = control.h2syn(P, nmeas, ncon)
            # lower LFT with u = K y (python-control's lft is the positive-feedback LFT).
            cl2 = P.lft(K)
            assert np.all(cl2.poles().real < 0), name
            case["h2_optimal"] = float(control.norm(cl2, 2))
        print(f"{name}: γ_slycot = {gam:.10g}, ‖T_zw‖∞ = {norm_cl:.10g}, H2 = {case.get('h2_optimal')}")
        cases.append(case)
    doc = {
        "tools": {
            "python-control": control.__version__,
            "scipy": scipy.__version__,
            "numpy": np.__version__,
            "slycot": slycot.__version__,
        },
        "script": "tools/reference/hinf_reference.py",
        "cases": cases,
    }
    OUT.write_text(json.dumps(doc, indent=1) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
