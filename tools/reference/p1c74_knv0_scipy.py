"""Observer gain L of book example 7.1 (p1c74_ex1_cdip_ob_design.m, line 42) by SciPy's robust
pole placement, an implementation independent of pendulab-lti's Kautsky-Nichols-Van Dooren
method 0 (the robust assignment MATLAB's `place` documents). SciPy's own KNV0 refuses complex
poles (the script tries it and records the refusal), so its Tits-Yang method is run.

The M-file: the cart pendulum of cdip_para.m (ac = 6.25, bc = 4.36, mp = 0.107, lp = 0.23,
Jp = 1.59e-3, mup = 2.35e-4, g = 9.81), two outputs C = [I2 0], controller poles
pc = [-6.5 +- 1.5j, -4, -2.5], observer poles po = 4 pc, L = -(place(A', C', po))'.
With two outputs the L that places the poles is not unique; this prints the L of SciPy's Tits-Yang
and its properties (eig(A + LC), the 2-norm condition number of the observer's eigenvector
matrix, the departure from normality sqrt(||A+LC||_F^2 - sum |lambda|^2)), and writes them to
crates/book/tests/fixtures/p1c74_knv0_scipy.json.

Tool: Python 3.11, SciPy 1.16.3, NumPy. Run from the repository root:
    python3 tools/reference/p1c74_knv0_scipy.py
"""

import json
import pathlib

import numpy as np
import scipy
from scipy.signal import place_poles

ac, bc = 6.25, 4.36
mp, lp, Jp, mup, g = 1.07e-1, 2.30e-1, 1.59e-3, 2.35e-4, 9.81
J = Jp + mp * lp**2
a1, a2, a3, b1 = mp * g * lp / J, ac * mp * lp / J, -mup / J, -bc * mp * lp / J
A = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [0, 0, -ac, 0], [0, a1, a2, a3]], dtype=float)
C = np.array([[1, 0, 0, 0], [0, 1, 0, 0]], dtype=float)
pc = np.array([-6.5 + 1.5j, -6.5 - 1.5j, -4, -2.5])
po = 4 * pc

# SciPy's KNV0 refuses complex poles ("Complex poles are not supported by KNV0"), and po has
# a complex pair: its other robust method, Tits-Yang (which maximises |det V| of the
# normalised eigenvector matrix V, the measure KNV's method 0 also drives up), is run instead.
try:
    place_poles(A.T, C.T, po, method="KNV0")
    knv0_note = "KNV0 ran"
except ValueError as e:
    knv0_note = f"KNV0 refused: {e}"
print(knv0_note)
res = place_poles(A.T, C.T, po, method="YT", rtol=1e-12, maxiter=1000)
L = -res.gain_matrix.T  # the book's sign: observer A + L C
Acl = A + L @ C
lam = np.linalg.eigvals(Acl)
_, V = np.linalg.eig(Acl)
cond = np.linalg.cond(V)
dep = np.sqrt(max(np.linalg.norm(Acl, "fro") ** 2 - np.sum(np.abs(lam) ** 2), 0.0))
out = {
    "tool": f"SciPy {scipy.__version__} place_poles(method='YT', rtol=1e-12, maxiter=1000)",
    "knv0": knv0_note,
    "L": L.tolist(),
    "eig_re_im": sorted([[z.real, z.imag] for z in lam]),
    "eigenvector_condition": cond,
    "departure_from_normality": dep,
    "rtol_reached": res.rtol,
    "nb_iter": int(res.nb_iter),
}
np.set_printoptions(precision=10, suppress=False)
print("L =\n", L)
print("eig(A + L C) =", np.sort_complex(lam))
print("cond(V) =", cond, " departure from normality =", dep, " iterations =", res.nb_iter)
path = pathlib.Path("crates/book/tests/fixtures/p1c74_knv0_scipy.json")
path.write_text(json.dumps(out, indent=1) + "\n")
print("wrote", path)
