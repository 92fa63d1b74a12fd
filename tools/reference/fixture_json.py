"""How the reference scripts write matrices and systems into their JSON fixtures: the one
encoding the Rust tests read back (a matrix as a list of rows; a system as its state-space
matrices with dt, nx, nu, ny). numpy and python-control only.

Imported by the scripts beside it (`python3 tools/reference/<script>.py` puts this folder on
the import path).
"""

import control
import numpy as np


def mat(m):
    """A matrix (or a scalar or vector, as one row) as a list of rows of floats."""
    return np.atleast_2d(np.asarray(m, dtype=float)).tolist()


def sysdict(sys):
    """A system as {dt, a, b, c, d, nx, nu, ny}: its state-space form (control.ss), dt None
    in continuous time, a, b, c empty lists for a static gain."""
    sys = control.ss(sys)
    return {
        "dt": None if sys.dt in (0, None) else float(sys.dt),
        "a": mat(sys.A) if sys.nstates else [],
        "b": mat(sys.B) if sys.nstates else [],
        "c": mat(sys.C) if sys.nstates else [],
        "d": mat(sys.D),
        "nx": int(sys.nstates),
        "nu": int(sys.ninputs),
        "ny": int(sys.noutputs),
    }
