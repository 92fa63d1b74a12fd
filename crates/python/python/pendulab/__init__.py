"""pendulab — the inverted-pendulum control laboratory, from Python.

The numerics are pendulab's Rust crates (``pendulab._native``); this package gives them
python-control's and MATLAB's names. Linear-systems functions live at the top level
(``pendulab.lqr``, ``pendulab.StateSpace``, ...); the pendulums and their simulation in
``pendulab.plants``; the LMI syntheses in ``pendulab.lmi``; identification in
``pendulab.ident``; sliding mode, swing-up, NMPC, quantizers and Kalman filters in
``pendulab.control``; the book's examples and the lab report in ``pendulab.book``; the
Gymnasium environments in ``pendulab.gym``.
"""

from ._native import __version__
from .lti import *  # noqa: F401,F403
from .lti import __all__ as _lti_all
from .errors import *  # noqa: F401,F403
from .errors import __all__ as _errors_all

__all__ = ["__version__", *_lti_all, *_errors_all]
