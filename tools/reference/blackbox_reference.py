"""NumPy reference for pendulab-ident's ARX identification on the cart rig's records.

ARX [na nb nk] = [2 2 1] of the cart drive from the P-control records
data/rig/cdip_cart_pcont_data_kP_{025,050,200}_ref_02.csv (k_P = 2.5, 5, 20; voltage rebuilt as
v = k_P (r - z), r stepping 0 -> 0.2 m at t = 1 s; samples 0.5 s <= t <= 4 s; every 10th sample,
Ts = 10 ms), the three records merged without crossing their boundaries. Solved by
`numpy.linalg.lstsq` (an SVD, independent of the crate's Householder QR); the continuous poles as
log(z_i)/Ts of `numpy.roots` of A (the ZOH map, independent of the crate's d2c by a matrix
logarithm).

Writes crates/ident/tests/data/blackbox_reference.json (read by crates/ident/tests/blackbox_rig.rs).
Run: target/pyenv/bin/python tools/reference/blackbox_reference.py   (from the repository root)
The versions used are recorded in the output (committed fixture: Python 3, NumPy from target/pyenv).
"""

import json
import pathlib
import platform

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
Q = 10
TS = 1e-3 * Q


def record(stem, kp):
    d = np.genfromtxt(ROOT / "data" / "rig" / f"{stem}.csv", delimiter=",", names=True)
    keep = (d["t"] >= 0.5 - 1e-9) & (d["t"] <= 4.0 + 1e-9)
    t, z = d["t"][keep], d["z"][keep]
    v = kp * (np.where(t >= 1.0 - 1e-9, 0.2, 0.0) - z)
    return v[::Q], z[::Q]


rows, target = [], []
for stem, kp in [
    ("cdip_cart_pcont_data_kP_025_ref_02", 2.5),
    ("cdip_cart_pcont_data_kP_050_ref_02", 5.0),
    ("cdip_cart_pcont_data_kP_200_ref_02", 20.0),
]:
    v, z = record(stem, kp)
    for k in range(2, len(z)):
        rows.append([-z[k - 1], -z[k - 2], v[k - 1], v[k - 2]])
        target.append(z[k])
phi, y = np.array(rows), np.array(target)
theta, *_ = np.linalg.lstsq(phi, y, rcond=None)
a = [1.0, float(theta[0]), float(theta[1])]
poles = sorted(float(np.log(p.real) / TS) for p in np.roots(a))
out = {
    "tool": f"NumPy {np.__version__}, Python {platform.python_version()}",
    "decimation": Q,
    "ts": TS,
    "samples": len(y),
    "a": a,
    "b": [float(theta[2]), float(theta[3])],
    "continuous_poles": poles,
}
path = ROOT / "crates" / "ident" / "tests" / "data" / "blackbox_reference.json"
path.write_text(json.dumps(out, indent=1) + "\n")
print(json.dumps(out, indent=1))
