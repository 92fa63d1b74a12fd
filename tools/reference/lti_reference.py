"""Reference values from python-control for pendulab-lti's discretisation, Bode and zeros tests.

Writes crates/lti/tests/fixtures/lti_reference.json with
  - c2d by FOH and by Tustin with prewarp of SISO transfer functions (num/den, den monic) and
    the frequency response of a MIMO FOH discretisation at a few frequencies,
  - Bode points (complex response; magnitude dB; phase deg) of continuous and discrete systems,
  - transmission zeros of non-minimum-phase systems (among them the linearised cart pendulum of
    docs/model.md §1 with the cart position as output).

Run: python3 tools/reference/lti_reference.py   (from the repository root)
"""

import json
import pathlib

import control
import numpy as np
import scipy

from book_plants import cdip


def monic(num, den):
    num = np.atleast_1d(np.squeeze(num)).astype(float)
    den = np.atleast_1d(np.squeeze(den)).astype(float)
    return (num / den[0]).tolist(), (den / den[0]).tolist()


def tfdata(sys):
    n, d = control.tfdata(sys)
    return monic(n[0][0], d[0][0])


def response(sys, w):
    r = control.frequency_response(sys, w)
    fresp = np.asarray(r.fresp)  # shape (ny, nu, nw)
    return fresp


def main():
    out = {
        "tool": f"python-control {control.__version__}, scipy {scipy.__version__}, numpy {np.__version__}",
        "script": "tools/reference/lti_reference.py",
    }

    # --- c2d of SISO transfer functions --------------------------------------------------
    c2d = []
    g1 = control.tf([1.0, 3.0], [1.0, 2.0, 5.0])
    g2 = control.tf([2.0, -1.0, 4.0], [1.0, 3.0, 6.0, 2.0])
    for name, g in [("g1", g1), ("g2", g2)]:
        num, den = tfdata(g)
        for ts in [0.1, 0.5]:
            gd = control.sample_system(g, ts, method="foh")
            dn, dd = tfdata(gd)
            c2d.append({"name": name, "num": num, "den": den, "ts": ts, "method": "foh",
                        "num_d": dn, "den_d": dd})
            w0 = 2.0
            gd = control.sample_system(g, ts, method="tustin", prewarp_frequency=w0)
            dn, dd = tfdata(gd)
            c2d.append({"name": name, "num": num, "den": den, "ts": ts, "method": "tustin",
                        "prewarp": w0, "num_d": dn, "den_d": dd})
    out["c2d_tf"] = c2d

    # --- MIMO FOH: frequency response of the discretisation ----------------------------------
    rng = np.random.default_rng(7)
    A = rng.standard_normal((3, 3)) - 2.0 * np.eye(3)
    B = rng.standard_normal((3, 2))
    C = rng.standard_normal((2, 3))
    D = rng.standard_normal((2, 2))
    ts = 0.2
    sd = control.sample_system(control.ss(A, B, C, D), ts, method="foh")
    w = [0.1, 1.0, 5.0, 12.0]
    fr = response(sd, w)
    out["c2d_mimo_foh"] = {
        "a": A.tolist(), "b": B.tolist(), "c": C.tolist(), "d": D.tolist(), "ts": ts,
        "w": w,
        "re": [[[float(fr[i, j, k].real) for k in range(len(w))] for j in range(2)] for i in range(2)],
        "im": [[[float(fr[i, j, k].imag) for k in range(len(w))] for j in range(2)] for i in range(2)],
    }

    # --- Bode points ----------------------------------------------------------------------
    bode = []
    A, B = cdip()
    Cz = np.array([[1.0, 0.0, 0.0, 0.0]])
    sys_c = control.ss(A, B, Cz, [[0.0]])
    w = np.logspace(-1, 2, 13)
    for name, sys in [("cdip_cart_position", sys_c),
                      ("g1", g1),
                      ("g1_zoh_0.1", control.sample_system(g1, 0.1, method="zoh"))]:
        r = control.frequency_response(sys, w)
        f = np.asarray(r.fresp)[0, 0, :]
        entry = {"name": name, "w": w.tolist(),
                 "re": f.real.tolist(), "im": f.imag.tolist(),
                 "mag_db": (20 * np.log10(np.abs(f))).tolist(),
                 "phase_deg": np.degrees(np.unwrap(np.angle(f))).tolist()}
        if name == "g1":
            entry["num"], entry["den"] = tfdata(g1)
        if name == "g1_zoh_0.1":
            entry["ts"] = 0.1
        bode.append(entry)
    out["bode"] = bode
    out["cdip"] = {"a": A.tolist(), "b": B.tolist()}

    # --- zeros of non-minimum-phase systems ------------------------------------------------
    zeros = []
    z = control.zeros(sys_c)
    zeros.append({"name": "cdip_cart_position", "c": Cz.tolist(), "d": [[0.0]],
                  "zeros_re": np.real(z).tolist(), "zeros_im": np.imag(z).tolist()})
    g3 = control.tf(np.polymul([1.0, -1.0], [1.0, 4.0]), np.polymul(np.polymul([1.0, 1.0], [1.0, 2.0]), [1.0, 5.0]))
    s3 = control.ss(g3)
    z = control.zeros(s3)
    zeros.append({"name": "g3_nmp", "a": np.asarray(s3.A).tolist(), "b": np.asarray(s3.B).tolist(),
                  "c": np.asarray(s3.C).tolist(), "d": np.asarray(s3.D).tolist(),
                  "zeros_re": np.real(z).tolist(), "zeros_im": np.imag(z).tolist()})
    # Square MIMO systems (python-control computes these from the generalised eigenvalues
    # of the system pencil).
    rng = np.random.default_rng(3)
    for name, (n, m, with_d) in [("mimo_2x2_d0", (4, 2, False)), ("mimo_3x3_d_singular", (5, 3, True))]:
        A = rng.standard_normal((n, n))
        B = rng.standard_normal((n, m))
        C = rng.standard_normal((m, n))
        if with_d:
            u = rng.standard_normal((m, 1))
            D = u @ u.T  # rank one: a mix of finite and infinite zero structure
        else:
            D = np.zeros((m, m))
        z = control.zeros(control.ss(A, B, C, D))
        zeros.append({"name": name, "a": A.tolist(), "b": B.tolist(), "c": C.tolist(),
                      "d": D.tolist(), "zeros_re": np.real(z).tolist(),
                      "zeros_im": np.imag(z).tolist()})
    out["zeros"] = zeros

    path = pathlib.Path("crates/lti/tests/fixtures/lti_reference.json")
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
