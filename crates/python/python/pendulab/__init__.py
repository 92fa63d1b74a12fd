"""pendulab — the inverted-pendulum control laboratory, from Python.

The numerics are pendulab's Rust crates (``pendulab._native``); this package gives them
python-control's and MATLAB's names. Linear-systems functions live at the top level
(``pendulab.lqr``, ``pendulab.StateSpace``, ...); the pendulums and their simulation in
``pendulab.plants``; the LMI syntheses in ``pendulab.lmi``; identification in
``pendulab.ident``; sliding mode, swing-up, NMPC, quantizers and Kalman filters in
``pendulab.control``; the book's examples and the lab report in ``pendulab.book``; the
Gymnasium environments in ``pendulab.gym``; regions of attraction and Monte Carlo studies,
cut into deterministic chunks run locally or on Ray, in ``pendulab.study`` and
``pendulab.ray``; a swing-up policy trained by Evolution Strategies with its rollouts as Ray
tasks on the native vector env in ``pendulab.rl`` (``docs/studies.md``).
"""

from ._native import __version__
from .lti import *  # noqa: F401,F403
from .lti import __all__ as _lti_all
from .errors import *  # noqa: F401,F403
from .errors import __all__ as _errors_all

__all__ = ["__version__", *_lti_all, *_errors_all]
